// The page: loads the core (WebAssembly) and shows the built-in example part at once.
import init, { partSummary, version } from './pkg/testpiece.js';

const $ = (id) => document.getElementById(id);

function showError(err) {
  const status = $('status');
  status.className = 'error';
  status.textContent = `Error: ${err && err.message ? err.message : err}`;
}

async function main() {
  await init();
  $('version').textContent = version();
  const summary = partSummary();
  const tbody = $('curves').querySelector('tbody');
  for (const c of summary.curves) {
    const tr = document.createElement('tr');
    tr.dataset.curve = c.curve;
    for (const [text, cls] of [[c.curve, ''], [c.z.toFixed(1), 'num'], [c.length.toFixed(4), 'num']]) {
      const td = document.createElement('td');
      td.textContent = text;
      if (cls) td.className = cls;
      tr.appendChild(td);
    }
    tbody.appendChild(tr);
  }
  $('curves').hidden = false;
  $('status').textContent = 'Computed by the testpiece core in this browser.';
  document.body.dataset.ready = 'true';
}

main().catch(showError);
