// Exports: every table as CSV, every chart as SVG and PNG, the whole analysis as JSON.
// Everything is made in the browser and saved through a download link; nothing is uploaded.
import { svgText, pngBlob } from './plot.js';

/** Saves `data` (string or Blob) as a file named `name`. */
export function download(name, data, type = 'text/plain') {
  const blob = data instanceof Blob ? data : new Blob([data], { type });
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}

function csvCell(v) {
  const s = v === null || v === undefined ? '' : String(v);
  return /[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}

/** CSV text from a header and rows (numbers written in full precision). */
export function toCsv(header, rows) {
  return [header, ...rows].map((r) => r.map(csvCell).join(',')).join('\n') + '\n';
}

/** CSV text of an HTML table (header row from <thead>, data from data-value or text). */
export function tableCsv(table) {
  const rowOf = (tr) => [...tr.children].map((td) => td.dataset.value ?? td.textContent.trim());
  const head = table.tHead ? [...table.tHead.rows].map(rowOf).slice(-1) : [];
  const body = [...table.tBodies].flatMap((b) => [...b.rows].map(rowOf));
  return toCsv(head[0] || [], body);
}

/** Buttons "SVG" and "PNG" for a chart ("PNG" alone for a canvas chart: `png()` a Promise of
 * its Blob) and "CSV" for a table, appended to `bar`. */
export function exportButtons(bar, { name, svg, png, table, csv }) {
  const add = (label, title, fn) => {
    const b = document.createElement('button');
    b.type = 'button';
    b.className = 'export';
    b.textContent = label;
    b.title = title;
    b.dataset.export = `${name}.${label.toLowerCase()}`;
    b.addEventListener('click', fn);
    bar.appendChild(b);
  };
  if (svg) {
    add('SVG', `Save this chart as ${name}.svg`, () => download(`${name}.svg`, svgText(svg()), 'image/svg+xml'));
    add('PNG', `Save this chart as ${name}.png`, async () => download(`${name}.png`, await pngBlob(svg())));
  } else if (png) {
    add('PNG', `Save this chart as ${name}.png`, async () => download(`${name}.png`, await png()));
  }
  if (table || csv) {
    add('CSV', `Save this table as ${name}.csv`, () => download(`${name}.csv`, csv ? csv() : tableCsv(table()), 'text/csv'));
  }
}

/** SHA-256 of bytes, as hex (for the report: the file's checksum). */
export async function sha256Hex(bytes) {
  if (!globalThis.crypto || !crypto.subtle) return 'unavailable (this browser context has no Web Crypto)';
  const d = await crypto.subtle.digest('SHA-256', bytes);
  return [...new Uint8Array(d)].map((b) => b.toString(16).padStart(2, '0')).join('');
}
