// What every view shares: the DOM helper, tables and charts with their export buttons, the
// per-point layout, and what the core sent when the page opened (`start()` of src/wasm/page.rs:
// the machines, the measurement curves, the words for the tags the results carry, the
// thresholds). No result is computed here.
import { chart, xNameOf } from './plot.js';
import { denseChart } from './densechart.js';
import { exportButtons, toCsv } from './export.js';

/** Files of more points than this (a scan) get their per-point charts and the plan view on a
 * canvas (densechart.js, plancanvas.js) and their points table a page of TABLE_ROWS rows at a
 * time: an SVG element or a table row per point stops being fluid at a few thousand. */
export const DENSE_POINTS = 3000;
/** Rows of a page of a points table of more than DENSE_POINTS points (pagedTable; its CSV has
 * every row). 100: the browser lays a page out in a few ms, where the 500 rows shown before had
 * taken one task of 150-260 ms of style and layout after a 20,000-point upload (a Chromium
 * trace: issue 31's bound on a task is 200 ms). */
export const TABLE_ROWS = 100;

/** What the core's `start()` answered (set once by app.js before the first view is drawn). */
export const core = { machines: [], curves: [], words: {}, thresholds: {}, paths: { cones: [], cone_offsets: [], surfaces: [] } };

/** The core's description of the machine `id`. */
export const machineName = (id) => (core.machines.find((m) => m.id === id) || { name: id }).name;
/** Whether the machine `id` uses the pivot length L0 (the core's `uses_l0`). */
export const machineUsesL0 = (id) => (core.machines.find((m) => m.id === id) || { uses_l0: true }).uses_l0;
/** The core's word for the tag `tag` of the kind `kind` (`groups`, `parameter_status`, …). */
export const word = (kind, tag) => (core.words[kind] && core.words[kind][tag]) || tag;

/** The gap diagnosis of an analysis when it was made (`diagnosis.status` of the core). */
export const diagnosisOf = (a) => (a && a.diagnosis && a.diagnosis.status === 'made' ? a.diagnosis.report : null);
/** What the final answer was fitted with, in the core's words (analysis.correction). */
export const fittedWith = (a) => (a.correction ? a.correction.fitted_with_words : '');
/** The export's `fitted_with` column, as the core writes it (identify::export). */
export const fittedWithId = (a) => a.correction.fitted_with;

export function h(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (k === 'dataset') Object.assign(e.dataset, v);
    else e.setAttribute(k, v === true ? '' : v);
  }
  for (const c of children.flat()) if (c !== null && c !== undefined && c !== false) e.append(c instanceof Node ? c : String(c));
  return e;
}

/** The parts of the views left for later (`later`), in order. */
const parts = [];
/** A part of a view drawn later, in a task of its own (app.js `render` takes them after each
 * view): returns a placeholder that `make()`'s element replaces, unless the view was drawn again
 * in the meantime. */
export function later(make) {
  const slot = h('div', { class: 'later' });
  parts.push(() => { if (slot.isConnected) slot.replaceWith(make()); });
  return slot;
}
/** The first part left for later (app.js draws each in a task of its own), or undefined. */
export const nextLater = () => parts.shift();

/** A number with a sensible precision for its unit. */
export function fmtNum(v, unit) {
  if (v === null || v === undefined || !Number.isFinite(v)) return '—';
  if (unit === 'rad') return v.toExponential(3);
  if (unit === 'µm') return v.toFixed(2);
  if (unit === 'mm') return Math.abs(v) >= 0.1 ? v.toFixed(4) : v.toFixed(5);
  return String(Number(v.toPrecision(4)));
}

/** A table with a caption, header and rows of [text, {num, value}] cells, plus a CSV button
 * (of the rows shown, or `csv()` when given: the whole table of which only some rows are shown). */
export function table(name, caption, header, rows, csv) {
  const t = h('table', { 'data-table': name },
    h('caption', {}, caption),
    h('thead', {}, h('tr', {}, header.map((c) => h('th', { scope: 'col' }, c)))),
    h('tbody', {}, rows.map(tableRow)));
  const bar = h('div', { class: 'bar' });
  exportButtons(bar, csv ? { name, csv } : { name, table: () => t });
  return h('div', {}, bar, h('div', { class: 'scroll' }, t));
}

/** A table row of [text, {num, value}] cells. */
const tableRow = (r) => h('tr', {}, r.map((c) => (typeof c === 'object' && c !== null && !(c instanceof Node)
  ? h('td', { class: c.num ? 'num' : c.class, 'data-value': c.value ?? undefined }, c.text)
  : h('td', {}, c))));

/** A table of `count` rows shown a page of `pageRows` at a time (`rowAt(i)`: row i's cells, as
 * for `table`): First, Previous, Next and Last, a row number to go to, "rows a–b of count"
 * (`data-rows` on the table: `a-b`); the CSV button saves every row (`csv()`). */
export function pagedTable(name, caption, header, count, rowAt, csv, pageRows = TABLE_ROWS) {
  const body = h('tbody', {});
  const t = h('table', { 'data-table': name }, h('caption', {}, caption),
    h('thead', {}, h('tr', {}, header.map((c) => h('th', { scope: 'col' }, c)))), body);
  const pages = Math.max(1, Math.ceil(count / pageRows));
  const where = h('span', { class: 'page-where', 'aria-live': 'polite' });
  const go = h('input', { type: 'number', min: 1, max: Math.max(1, count), step: 1, 'aria-label': `row to show (1 to ${count})`, class: 'page-go' });
  const buttons = {};
  let page = 0;
  const show = (k) => {
    page = Math.min(pages - 1, Math.max(0, k));
    const from = page * pageRows, to = Math.min(count, from + pageRows);
    body.replaceChildren(...Array.from({ length: to - from }, (_, i) => tableRow(rowAt(from + i))));
    t.dataset.rows = `${from + 1}-${to}`;
    where.textContent = `rows ${from + 1}–${to} of ${count} (page ${page + 1} of ${pages})`;
    buttons.first.disabled = buttons.prev.disabled = page === 0;
    buttons.next.disabled = buttons.last.disabled = page === pages - 1;
  };
  const nav = (key, label, to) => {
    buttons[key] = h('button', { type: 'button', class: 'page', 'data-page': key, onclick: () => show(to()) }, label);
    return buttons[key];
  };
  go.addEventListener('change', () => {
    const row = Math.round(Number(go.value));
    if (Number.isFinite(row) && row >= 1) show(Math.floor((Math.min(row, count) - 1) / pageRows));
  });
  const bar = h('div', { class: 'bar' },
    nav('first', 'First', () => 0), nav('prev', 'Previous', () => page - 1), nav('next', 'Next', () => page + 1),
    nav('last', 'Last', () => pages - 1), h('label', {}, 'row ', go), where, h('span', { class: 'spacer' }));
  exportButtons(bar, { name, csv });
  show(0);
  return h('div', {}, bar, h('div', { class: 'scroll' }, t));
}

/** x positions and groups for points laid out curve by curve (the core's curve order, then any
 * other curve in order of appearance), the indices in order of x (`order`) and the name of each
 * point (`xNames(i)`); `ids`: a list, or a function of the index. */
export function layout(curves, ids) {
  const x = [];
  const order = []; // the indices in order of x
  const groups = [];
  let pos = 0;
  const of = new Map(core.curves.map((c) => [c, []])); // one pass: a scan has hundreds of lines
  curves.forEach((k, i) => { if (!of.has(k)) of.set(k, []); of.get(k).push(i); });
  for (const [c, idx] of of) {
    if (!idx.length) continue;
    const from = pos + 1;
    for (const i of idx) { x[i] = ++pos; order.push(i); }
    groups.push({ label: c, from, to: pos });
    pos += 2;
  }
  const idOf = typeof ids === 'function' ? ids : (i) => ids[i];
  return { x, groups, order, xNames: (i) => `point ${idOf(i)} (${curves[i]})` };
}

/** A chart with its export buttons (SVG, PNG, CSV of the series) and `extra` controls. */
export function chartBlock(name, spec, extra) {
  const holder = h('div', {});
  const dense = spec.x.length > DENSE_POINTS;
  const c = (dense ? denseChart : chart)(holder, spec);
  const bar = h('div', { class: 'bar' }, extra || '', h('span', { class: 'spacer' }));
  exportButtons(bar, { name, ...(dense ? { png: c.png } : { svg: () => c.svg }), csv: () => toCsv(['x', 'label', ...spec.series.map((s) => s.name)],
    spec.x.map((x, i) => [x, spec.xNames ? xNameOf(spec, i) : '', ...spec.series.map((s) => s.y[i])])) });
  return { el: h('div', { class: 'chart-block', 'data-chart': name }, bar, holder), chart: c };
}
