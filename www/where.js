// The gap diagnosis drawn on the per-point plots and the plan view, shared by the Identification
// and Sim-to-real gap views: a chosen where-group as shaded bands and ringed points, the axis
// reversals the core marks at their nearest point, and the control that chooses the group.
import { h, layout, chartBlock, diagnosisOf, word, core, DENSE_POINTS } from './ui.js';
import { planCanvas } from './plancanvas.js';
import { exportButtons } from './export.js';

// The diagnosis (src/gap/location.rs) reports typed groups: `group` is curve, region, lean or
// reversal (a reversal with its `axis`, path position `s` in mm and `nearest` point id), each
// with the points of the group (`ids`), its residual RMS and its concentration (share of the
// residual sum of squares over share of points). The core decides what is notable: `concentrated`,
// `structure.concentrated_entry` (the default highlight) and, for reversals, `of_verdict` and
// `marked`. These helpers only draw: the chosen group as shaded bands on the per-point plots
// and ringed points on the plan view, the marked reversals at their nearest point. The choice
// is shared by the views; changing it redraws every figure that shows it.
const where = { choice: 'auto', figures: new Set() };

const entryKey = (e) => `${e.group}:${e.name}`;

/** The where report of an analysis: entries, reversals, and the entry to highlight for `choice`. */
export function whereOf(a) {
  const d = diagnosisOf(a);
  if (!d) return null;
  const entries = d.where;
  const reversals = entries.filter((e) => e.group === 'reversal');
  const auto = () => (d.structure.concentrated_entry === null ? null : entries[d.structure.concentrated_entry]);
  // The tool path reverses some axis dozens of times: the core marks those of a named
  // backlash's axis and those where the residual is concentrated; the chosen one is marked too.
  const verdictAxes = d.structure.verdict_axes;
  const isChosen = (e) => where.choice === entryKey(e);
  const marked = reversals.filter((e) => isChosen(e) || e.marked);
  const chosen = where.choice === 'auto' ? auto() : where.choice === 'none' ? null : entries.find((e) => entryKey(e) === where.choice) || null;
  // One mark per point: reversals of several axes can share the nearest point.
  const marks = [];
  for (const e of marked) {
    const m = marks.find((k) => String(k.id) === String(e.nearest));
    if (m) m.entries.push(e); else marks.push({ id: e.nearest, entries: [e] });
  }
  for (const m of marks) {
    m.short = [...new Set(m.entries.map((e) => e.axis))].join(',');
    m.label = m.entries.map(describeReversal).join('; ');
  }
  return { d, entries, reversals, marked, marks, verdictAxes, chosen, auto: auto() };
}

const um1 = (x) => `${(x * 1000).toFixed(1)} µm`;
function describeEntry(e) {
  return `${word('groups', e.group)} ${e.name}: ${e.n} points, baseline residual RMS ${um1(e.rms)}, ` +
    `max |r| ${um1(e.max_abs)}, ${Number(e.concentration.toFixed(2))}× its share of the residual`;
}
function describeReversal(e) {
  return `${e.axis}-axis reversal at ${e.s.toFixed(1)} mm of tool path (point ${e.nearest}); ±${core.thresholds.reversal_window_mm} mm window: ${e.n} points, RMS ${um1(e.rms)}, ${Number(e.concentration.toFixed(2))}× its share`;
}

/** Why the marked reversals are marked, in words (from the core's flags). */
function markedWhy(w) {
  const axes = w.verdictAxes.length ? `those of the named backlash's ${w.verdictAxes.join(', ')} axis and ` : '';
  return `${axes}those where the residual is concentrated near the reversal, and the one chosen above`;
}

/** The marked reversals as a compact table inside a collapsible block. */
function reversalList(w) {
  if (!w.marked.length) return h('span', {}, `None of the ${w.reversals.length} axis reversals of the tool path is marked (none of a named backlash's axis nor with the residual concentrated near it; each can be chosen above).`);
  const rows = w.marked.map((e) => h('tr', {}, h('td', {}, e.axis), h('td', { class: 'num' }, e.s.toFixed(1)), h('td', { class: 'num' }, String(e.nearest)),
    h('td', { class: 'num' }, String(e.n)), h('td', { class: 'num' }, (e.rms * 1000).toFixed(1)), h('td', { class: 'num' }, e.concentration.toFixed(2)),
    h('td', {}, e.of_verdict ? 'named backlash axis' : e.concentrated ? 'residual concentrated' : 'chosen')));
  return h('details', { class: 'reversal-list' },
    h('summary', {}, `${w.marked.length} of ${w.reversals.length} axis reversals marked (${[...new Set(w.marked.map((e) => e.axis))].join(', ')}): ${markedWhy(w)}`),
    h('table', {}, h('thead', {}, h('tr', {}, ...['axis', 'at (mm of tool path)', 'nearest point', `points in ±${core.thresholds.reversal_window_mm} mm`, 'RMS (µm)', 'share ×', 'why marked'].map((t) => h('th', { scope: 'col' }, t)))),
      h('tbody', {}, ...rows)));
}

/** The legend of the highlight in words and units (also drawn inside the exported figures):
 * two lines, what is shaded and what the marks are. */
function whereNote(w) {
  if (!w) return '';
  const s = w.d.structure;
  const what = s.structured ? `structure (RMS ${um1(s.structure_rms)} above noise σ ${um1(s.noise.used)})` : `noise (σ ${um1(s.noise.used)}; no structure above the detection limit ${um1(w.d.verdict.detection_limit)})`;
  const shade = w.chosen ? `Shaded: ${word('groups', w.chosen.group)} ${w.chosen.name} (RMS ${um1(w.chosen.rms)}, ${Number(w.chosen.concentration.toFixed(2))}× its share).` : 'Nothing shaded.';
  const axes = [...new Set(w.marked.map((e) => e.axis))].join(', ');
  const rev = w.marked.length ? `▼ ${w.marked.length} of ${w.reversals.length} axis reversals (${axes}) at the nearest point; ` : `▼ none of ${w.reversals.length} axis reversals marked; `;
  return `${shade}\nBaseline residual of the diagnosis: ${what}.\n${rev}units µm, tool path in mm.`;
}

/** Each point's index by its id (as text) in the per-point tables of the analysis `a` (all in
 * the order of `file.points`), made once per analysis: the where-groups name their points by id. */
const indexes = new WeakMap();
export function pointIndex(a) {
  if (!indexes.has(a)) {
    const ids = a.identification.points.col('id'), index = new Map();
    for (let i = 0; i < ids.length; i++) index.set(String(ids.at(i)), i);
    indexes.set(a, index);
  }
  return indexes.get(a);
}

/** The indices of the points named by `ids` (those of the analysis `a`). */
export function pointsOf(a, ids) {
  const index = pointIndex(a), out = [];
  for (const id of ids) { const i = index.get(String(id)); if (i !== undefined) out.push(i); }
  return out;
}

/** Runs of consecutive x positions of the points `rows` (indices; for shaded bands): {from, to,
 * rows} with the rows in order of x. */
function runsOf(rows, x) {
  const sorted = rows.slice().sort((p, q) => x[p] - x[q]);
  const runs = [];
  for (const i of sorted) {
    const last = runs[runs.length - 1];
    if (last && x[i] === last.to + 1) { last.to = x[i]; last.rows.push(i); } else runs.push({ from: x[i], to: x[i], rows: [i] });
  }
  return runs;
}

/** highlight / markers / note for a per-point chart laid out by `layout` (`x`), its points named
 * by `idOf(i)`. A dense chart's bands carry no list of their points (densechart.js draws none). */
function whereChartPatch(a, x, idOf) {
  const w = whereOf(a);
  if (!w) return { highlight: [], markers: [], note: undefined };
  const index = pointIndex(a);
  const dense = x.length > DENSE_POINTS;
  const highlight = w.chosen ? runsOf(pointsOf(a, w.chosen.ids), x).map((r) => (dense ? { from: r.from, to: r.to, label: describeEntry(w.chosen) } : {
    from: r.from, to: r.to, ids: r.rows.map((i) => String(idOf(i))),
    label: `${describeEntry(w.chosen)}; points ${r.rows.map((i) => String(idOf(i))).join(', ')}` })) : [];
  const markers = w.marks.filter((k) => index.has(String(k.id))).map((k) => ({ x: x[index.get(String(k.id))], id: k.id, short: k.short, label: k.label }));
  return { highlight, markers, note: whereNote(w) };
}

/** Registers a figure drawn elsewhere (surfacemap.js) to be redrawn when the choice changes,
 * while `isConnected()`. */
export function onWhereChange(isConnected, redraw) {
  where.figures.add({ isConnected, redraw });
}

/** The control that chooses what is highlighted, and the legend in words (HTML). */
export function whereControl(a, idSuffix) {
  const w = whereOf(a);
  if (!w) return h('p', { class: 'where-legend' }, 'No gap diagnosis: nothing to highlight.');
  // the points' index by id, made here with the view (0.1 s for 200,000 points) rather than
  // with the first figure that needs it (app.js draws the figures each in a task of its own)
  pointIndex(a);
  const sel = h('select', { id: `where-choice-${idSuffix}`, class: 'where-choice', 'aria-describedby': `where-legend-${idSuffix}` },
    h('option', { value: 'auto' }, w.auto ? `where the residual is concentrated (${w.auto.name})` : 'where the residual is concentrated (nowhere markedly: nothing)'),
    h('option', { value: 'none' }, 'nothing'),
    ...w.entries.map((e) => h('option', { value: entryKey(e) }, `${word('groups', e.group)} ${e.name} (${Number(e.concentration.toFixed(2))}×, RMS ${um1(e.rms)})`)));
  sel.value = where.choice;
  if (sel.value !== where.choice) sel.value = 'auto';
  const legend = h('p', { class: 'where-legend', id: `where-legend-${idSuffix}` });
  const fill = () => {
    const x = whereOf(a);
    legend.textContent = '';
    legend.append(h('span', { class: 'swatch', 'aria-hidden': 'true' }), ' ',
      x.chosen ? `Shaded / ringed: ${describeEntry(x.chosen)}.` : 'Nothing shaded.', ' ',
      whereNote(x).split('\n')[1], ' ',
      h('span', { class: 'rev-swatch', 'aria-hidden': 'true' }, '▼'), ' ', reversalList(x));
  };
  fill();
  sel.addEventListener('change', () => {
    where.choice = sel.value;
    for (const f of [...where.figures]) { if (!f.isConnected()) where.figures.delete(f); else f.redraw(); }
    for (const o of document.querySelectorAll('select.where-choice')) if (o !== sel) o.value = sel.value;
  });
  where.figures.add({ isConnected: () => legend.isConnected, redraw: fill });
  return h('div', { class: 'where-control' }, h('label', { for: `where-choice-${idSuffix}` }, 'Highlight on the plots and the plan view: '), sel, legend);
}

/** The measured / simulated / residual chart with the where highlight. */
export function residualChart(a, name, id = a.identification) {
  const P = id.points, n = P.length;
  const curves = P.col('curve').toArray(), ids = P.col('id');
  const idOf = (i) => ids.at(i);
  const L = layout(curves, idOf);
  // the read-out names the point, its line and where it is: tool-path position and height
  const s = a.path_position, z = a.points.num('z');
  const xNames = s && s.length === n ? (i) => `${L.xNames(i)}, s ${s[i].toFixed(1)} mm, z ${z[i].toFixed(2)} mm` : L.xNames;
  const um = (key) => { const v = P.num(key), y = new Float64Array(n); for (let i = 0; i < n; i++) y[i] = v[i] * 1000; return y; };
  const spec = { title: 'Measured, simulated (identified model) and residual', x: L.x, order: L.order, xNames, groups: L.groups,
    series: [
      { name: 'measured', y: um('measured'), points: true },
      { name: 'simulated', y: um('fitted') },
      { name: 'residual', y: um('residual'), dashed: true },
    ], xLabel: 'measurement point (grouped by curve)', yLabel: 'normal deviation (µm)', yUnit: 'µm', ...whereChartPatch(a, L.x, idOf) };
  const block = chartBlock(name, spec);
  where.figures.add({ isConnected: () => block.el.isConnected, redraw: () => block.chart.update(whereChartPatch(a, L.x, idOf)) });
  return block.el;
}


/** Plan view of the part (x–y) with the residual drawn as coloured arrows along the normal, the
 * points of the highlighted where-group ringed and the axis reversals marked. */
/** Heights further apart than this (mm) are on different scan lines (the reader's rule). */
const LINE_GAP_MM = 0.05;

/** What the plan view draws, in its frame: points (x, y mm), the arrows' ends, the lines. */
function planOf(a, id) {
  const pts = a.file.points, n = pts.length;
  const res = id.points.num('residual');
  const foot = pts.vec('foot').v, normal = pts.vec('normal').v;
  const xs = new Float64Array(n), ys = new Float64Array(n), zs = new Float64Array(n);
  let maxr = 1e-9, x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity; // (no spread: 100,000 arguments overflow)
  for (let i = 0; i < n; i++) {
    maxr = Math.max(maxr, Math.abs(res[i]));
    const x = xs[i] = foot[3 * i], y = ys[i] = foot[3 * i + 1];
    zs[i] = foot[3 * i + 2];
    x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
  }
  const W = 640, H = 570, pad = 30;
  x0 -= 15; x1 += 15; y0 -= 15; y1 += 15;
  const k = Math.min((W - 2 * pad) / (x1 - x0), (H - 2 * pad - 44) / (y1 - y0));
  const X = (x) => pad + (x - x0) * k, Y = (y) => H - pad - 44 - (y - y0) * k;
  const arrowMm = 12; // the largest residual is drawn 12 mm long
  // the arrows' ends (mm)
  const tx = new Float64Array(n), ty = new Float64Array(n);
  for (let i = 0; i < n; i++) {
    const len = (res[i] / maxr) * arrowMm;
    tx[i] = xs[i] + normal[3 * i] * len; ty[i] = ys[i] + normal[3 * i + 1] * len;
  }
  // one line per measured line: a curve's points in file order, cut where the height jumps by
  // more than the reader's scan-line gap (LINE_GAP_MM, src/measurement/scan_lines.rs), so that a
  // scan's lines are not joined across the part; on a surface whose heights form no lines (the
  // core's `scan.banded`) one line per height band (the identification's group of the point)
  // along the tool path, uncut: a band's heights are its own
  const byCurve = new Map(core.curves.map((c) => [c, []])), byBand = new Map();
  const curves = a.points.col('curve'), surfaces = a.points.col('surface'), groups = id.points.col('curve');
  const banded = new Set(a.scan?.banded ?? []), path = a.path_position;
  for (let i = 0; i < n; i++) {
    if (path && banded.has(surfaces.at(i))) {
      const g = groups.at(i);
      if (!byBand.has(g)) byBand.set(g, []);
      byBand.get(g).push(i);
    } else byCurve.get(curves.at(i))?.push(i);
  }
  const lines = [...byBand.values()].map((idx) => idx.sort((p, q) => path[p] - path[q]));
  for (const idx of byCurve.values()) {
    idx.forEach((i, j) => {
      if (j === 0 || Math.abs(zs[i] - zs[idx[j - 1]]) > LINE_GAP_MM) lines.push([]);
      lines[lines.length - 1].push(i);
    });
  }
  const ids = pts.table('file').col('id');
  return { n, res, maxr, W, H, pad, X, Y, xs, ys, tx, ty, lines, arrowMm, idOf: (i) => ids.at(i),
    title: `Plan view: residual along the outward normal (largest ${(maxr * 1000).toFixed(1)} µm = ${arrowMm} mm arrow)`,
    legend: 'blue: material left (+), red: overcut (−); dashed red ring: outlier; x, y in mm' };
}

/** The plan view on a canvas (plancanvas.js), for files of more than DENSE_POINTS points. */
function densePlanView(a, name, plan) {
  const byId = pointIndex(a);
  const outliers = ((a.outliers && a.outliers.points) || []).filter((o) => o.row !== undefined && o.row < plan.n).map((o) => ({ i: o.row }));
  const overlay = () => {
    const w = whereOf(a);
    const rings = w && w.chosen ? pointsOf(a, w.chosen.ids) : [];
    const marks = w ? w.marks.filter((m) => byId.has(String(m.id))).map((m) => ({ i: byId.get(String(m.id)), short: m.short, label: m.label })) : [];
    return { rings, marks, note: whereNote(w) };
  };
  const c = planCanvas({ ...plan, outliers }, overlay);
  const holder = h('div', { 'data-chart': name, class: 'dense-plan' });
  where.figures.add({ isConnected: () => holder.isConnected, redraw: c.redraw });
  const bar = h('div', { class: 'bar' }, h('span', { class: 'spacer' }));
  exportButtons(bar, { name, png: () => new Promise((resolve, reject) => c.canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png')) });
  holder.append(bar, c.el);
  return holder;
}

export function planView(a, name, id = a.identification) {
  const plan = planOf(a, id);
  if (plan.n > DENSE_POINTS) return densePlanView(a, name, plan);
  const { n, res, W, H, pad, X, Y, xs, ys, idOf } = plan;
  const NS = 'http://www.w3.org/2000/svg';
  const svg = document.createElementNS(NS, 'svg');
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`); svg.setAttribute('class', 'chart'); svg.setAttribute('role', 'img');
  svg.setAttribute('aria-label', 'plan view with residual arrows'); svg.setAttribute('xmlns', NS);
  svg.setAttribute('font-family', 'system-ui, sans-serif'); svg.setAttribute('font-size', '11');
  const add = (tag, attrs, parent = svg) => { const e = document.createElementNS(NS, tag); for (const [kk, v] of Object.entries(attrs)) e.setAttribute(kk, v); parent.appendChild(e); return e; };
  add('rect', { x: 0, y: 0, width: W, height: H, fill: '#fff' });
  add('text', { x: pad, y: 18, 'font-weight': 600, 'font-size': 13 }).textContent = plan.title;
  for (const run of plan.lines) {
    add('polyline', { class: 'plan-line', points: run.map((i) => `${X(xs[i]).toFixed(1)},${Y(ys[i]).toFixed(1)}`).join(' '), fill: 'none', stroke: '#bbb' });
  }
  const layer = add('g', { class: 'where-layer' });
  for (let i = 0; i < n; i++) {
    const r = res[i];
    const color = r >= 0 ? '#1f77b4' : '#d62728';
    const xa = X(xs[i]), ya = Y(ys[i]);
    const xb = X(plan.tx[i]), yb = Y(plan.ty[i]);
    add('line', { x1: xa, y1: ya, x2: xb, y2: yb, stroke: color, 'stroke-width': 2 });
    add('circle', { cx: xb, cy: yb, r: 2, fill: color }).appendChild(document.createElementNS(NS, 'title')).textContent = `point ${idOf(i)}: residual ${(r * 1000).toFixed(2)} µm`;
  }
  for (const o of (a.outliers && a.outliers.points) || []) {
    const i = o.row;
    if (i === undefined || !(i < n)) continue;
    const ring = add('circle', { cx: X(xs[i]), cy: Y(ys[i]), r: 9, fill: 'none', stroke: '#d62728', 'stroke-width': 2.5, 'stroke-dasharray': '3 2',
      class: 'outlier-ring', 'data-id': o.id, role: 'img', 'aria-label': `outlier: point ${o.id}, ${(o.size * 1000).toFixed(1)} µm` });
    add('title', {}, ring).textContent = `outlier: point ${o.id}, ${(o.size * 1000).toFixed(1)} µm from the fit without it (|t| = ${o.statistic.toFixed(1)}); ${a.outliers.excluded ? 'left out' : 'kept'}`;
  }
  add('text', { x: W - pad, y: H - 8, 'text-anchor': 'end', fill: '#555' }).textContent = plan.legend;
  const note = add('text', { x: pad, y: H - 52, fill: '#7a4b00', class: 'note' });
  const byId = pointIndex(a);
  function drawWhere() {
    layer.textContent = '';
    const w = whereOf(a);
    note.textContent = '';
    whereNote(w).split('\n').forEach((line, j) => { const t = add('tspan', { x: pad, dy: j ? 14 : 0 }, note); t.textContent = line; });
    if (!w) return;
    if (w.chosen) {
      for (const id of w.chosen.ids) {
        const i = byId.get(String(id));
        if (i === undefined) continue;
        const ring = add('circle', { cx: X(xs[i]), cy: Y(ys[i]), r: 7, fill: '#ffd54f', 'fill-opacity': 0.5, stroke: '#b8860b', 'stroke-width': 1.5,
          class: 'highlight', 'data-id': id, tabindex: 0, role: 'img', 'aria-label': `point ${id}, in ${word('groups', w.chosen.group)} ${w.chosen.name}: residual ${(res[i] * 1000).toFixed(2)} µm` }, layer);
        add('title', {}, ring).textContent = `point ${id}: ${describeEntry(w.chosen)}`;
      }
    }
    for (const k of w.marks) {
      const i = byId.get(String(k.id));
      if (i === undefined) continue;
      const cx = X(xs[i]), cy = Y(ys[i]);
      const g = add('g', { class: 'marker', 'data-id': k.id, tabindex: 0, role: 'img', 'aria-label': k.label }, layer);
      add('path', { d: `M${cx - 6},${cy - 15} L${cx + 6},${cy - 15} L${cx},${cy - 5} Z`, fill: '#6a3d9a' }, g);
      add('text', { x: cx + 7, y: cy - 8, fill: '#6a3d9a', 'font-weight': 600, 'font-size': 10 }, g).textContent = k.short;
      add('title', {}, g).textContent = k.label;
    }
  }
  drawWhere();
  const holder = h('div', { 'data-chart': name });
  where.figures.add({ isConnected: () => holder.isConnected, redraw: drawWhere });
  const bar = h('div', { class: 'bar' }, h('span', { class: 'spacer' }));
  exportButtons(bar, { name, svg: () => svg });
  holder.append(bar, svg);
  return holder;
}
