// The page: settings and files in, the core's results out. All computation is in the core
// (WebAssembly, in a Web Worker when served; on the main thread in the single-file build).
import { startCore, call, cancel } from './core.js';
import { BUILD } from './pkg/build.js';
import { download, sha256Hex } from './export.js';
import { h, dataView, fig19View, identifyView, gapView, reportView } from './views.js';
import { setupBudget } from './budget.js';

const $ = (id) => document.getElementById(id);

const st = {
  files: [],          // {name, bytes, analysis?, error?, sha256?}
  current: 0,
  settings: {},
  sensitivity: null,
  fig19Visible: null,
  select(i) { st.current = i; render(); },
  excludeAndRetry() { $('exclude').checked = true; readSettings(); analyseAll(); },
  exportJson() {
    const f = st.files[st.current];
    if (!f || !f.analysis) return;
    download(`${f.name.replace(/\.[^.]*$/, '')}.testpiece.json`, JSON.stringify({ file: f.name, sha256: f.sha256, analysis: f.analysis }, null, 1), 'application/json');
  },
};

function readSettings() {
  const sigmaUm = parseFloat($('sigma').value);
  st.settings = {
    mode: $('mode').value,
    branch: $('branch').value,
    l0: parseFloat($('l0').value),
    tool_radius: $('toolRadius').checked,
    exclude_bad_rows: $('exclude').checked,
    noise_sigma: Number.isFinite(sigmaUm) && sigmaUm > 0 ? sigmaUm / 1000 : null,
  };
}

// ---------------------------------------------------------------- progress
let busy = 0;
let busyTimer = null;
async function withProgress(text, fn) {
  busy++;
  $('progress-text').textContent = text;
  // Show the indication for anything that takes longer than 200 ms.
  if (!busyTimer) busyTimer = setTimeout(() => { $('progress').hidden = false; }, 200);
  try { return await fn(); } finally {
    if (--busy === 0) { clearTimeout(busyTimer); busyTimer = null; $('progress').hidden = true; }
  }
}

// ---------------------------------------------------------------- computing
async function analyseFile(f) {
  f.error = null;
  try {
    f.analysis = await withProgress(`Analysing ${f.name}…`, () => call('analyse', f.bytes, f.name, st.settings));
  } catch (e) {
    f.analysis = null;
    f.error = e.message;
  }
  if (!f.sha256) f.sha256 = await sha256Hex(f.bytes);
}

async function analyseAll() {
  for (const f of st.files) await analyseFile(f);
  render();
}

async function loadSensitivity() {
  try {
    st.sensitivity = await withProgress('Computing the sensitivity curves…', () => call('sensitivity', st.settings.mode, st.settings.branch));
  } catch (e) {
    st.sensitivity = { error: e.message };
  }
}

async function addFiles(list) {
  const added = [];
  for (const file of list) {
    const bytes = new Uint8Array(await file.arrayBuffer());
    added.push({ name: file.name, bytes });
  }
  if (!added.length) return;
  // A newly chosen set of files replaces the example part.
  st.files = st.files.filter((f) => !f.example).concat(added);
  st.current = st.files.length - added.length;
  for (const f of added) await analyseFile(f);
  render();
}

async function loadExample(name) {
  const bytes = await call('exampleBytes', name);
  st.files = [{ name, bytes: new Uint8Array(bytes), example: true }];
  st.current = 0;
  await analyseFile(st.files[0]);
  render();
}

// ---------------------------------------------------------------- rendering
function summaryText() {
  const f = st.files[st.current];
  const box = $('summary');
  box.textContent = '';
  if (!f) { box.textContent = 'Load a measured part.'; return; }
  if (f.error) {
    box.append(h('div', { class: 'verdict' }, `${f.name} could not be analysed.`), h('div', {}, f.error.split('\n')[0]));
    return;
  }
  const a = f.analysis;
  if (!a) { box.textContent = 'Computing…'; return; }
  const id = a.identification;
  const weak = id.groups.map((g) => g.parameters.join('/')).join('; ');
  const strong = Object.entries(id.parameters).filter(([, p]) => p.status === 'identified' && p.t !== null && p.t >= 3)
    .map(([n, p]) => `${n} = ${p.unit === 'rad' ? p.value.toExponential(2) : p.value.toFixed(4)} ${p.unit}`);
  const d = a.diagnosis.Ok;
  box.append(
    h('div', { class: 'verdict', id: 'verdict-line' }, d ? d.summary.split('\n')[0] : `Verdict: not available (${a.diagnosis.Err})`),
    h('div', {}, `${f.name}: identification of ${Object.keys(id.parameters).length} parameters from ${id.points_used} points.`),
    h('div', {}, `Clearly non-zero (|value| ≥ 3 std): ${strong.length ? strong.join(', ') : 'none'}.`),
    h('div', {}, `Residual after the fit: RMS ${(id.residual.rms * 1000).toFixed(2)} µm, max ${(id.residual.max_abs * 1000).toFixed(2)} µm.`),
    h('div', {}, weak ? `Not separable or weakly determined by this part: ${weak}.` : 'Every parameter is separately determined by this part.'),
  );
}

function render() {
  summaryText();
  dataView($('view-data'), st);
  if (st.sensitivity && !st.sensitivity.error) fig19View($('view-fig19'), st.sensitivity, st);
  else $('view-fig19').textContent = st.sensitivity ? st.sensitivity.error : '';
  const f = st.files[st.current];
  identifyView($('view-identify'), f && f.analysis);
  gapView($('view-gap'), f && f.analysis);
  reportView($('view-report'), st);
  document.body.dataset.ready = 'true';
}

// ---------------------------------------------------------------- tabs (arrow keys move between them)
function setupTabs() {
  const tabs = [...document.querySelectorAll('[role=tab]')];
  const show = (t) => {
    for (const o of tabs) {
      const on = o === t;
      o.setAttribute('aria-selected', String(on));
      o.tabIndex = on ? 0 : -1;
      $(o.getAttribute('aria-controls')).hidden = !on;
    }
  };
  tabs.forEach((t, i) => {
    t.tabIndex = i === 0 ? 0 : -1;
    t.addEventListener('click', () => show(t));
    t.addEventListener('keydown', (e) => {
      const d = e.key === 'ArrowRight' ? 1 : e.key === 'ArrowLeft' ? -1 : 0;
      if (!d) return;
      const n = tabs[(i + d + tabs.length) % tabs.length];
      show(n); n.focus(); e.preventDefault();
    });
  });
}

function setupInputs() {
  $('file').addEventListener('change', (e) => addFiles([...e.target.files]));
  const drop = $('drop');
  drop.addEventListener('dragover', (e) => { e.preventDefault(); drop.classList.add('over'); });
  drop.addEventListener('dragleave', () => drop.classList.remove('over'));
  drop.addEventListener('drop', (e) => { e.preventDefault(); drop.classList.remove('over'); addFiles([...e.dataTransfer.files]); });
  drop.addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); $('file').click(); } });
  $('example').addEventListener('change', () => loadExample($('example').value));
  for (const id of ['mode', 'branch', 'l0', 'toolRadius', 'exclude', 'sigma']) {
    $(id).addEventListener('change', async () => {
      readSettings();
      if (id === 'mode' || id === 'branch') await loadSensitivity();
      await analyseAll();
    });
  }
  $('cancel').addEventListener('click', () => { cancel(); });
}

async function main() {
  const runner = await startCore(globalThis.__TESTPIECE_INLINE__);
  $('runner').textContent = runner;
  $('version').textContent = await call('version');
  setupTabs();
  setupInputs();
  setupBudget($('view-budget'), { call, st, withProgress }); // issue 10
  readSettings();
  const examples = await call('exampleList');
  for (const e of examples) $('example').append(h('option', { value: e.name }, `${e.name}: ${e.description}`));
  await loadSensitivity();
  await loadExample(examples[0].name);
  if ('serviceWorker' in navigator && location.protocol.startsWith('http')) {
    navigator.serviceWorker.register(`sw.js?build=${BUILD}`).catch(() => {});
  }
}

main().catch((e) => {
  $('summary').className = 'summary error';
  $('summary').textContent = `The page could not start: ${e && e.message ? e.message : e}`;
});
