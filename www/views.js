// The page's views: pure functions from the core's results to DOM. No computation of results
// here: every number shown comes from the core (src/analysis.rs, src/sensitivity/ …).
import { chart } from './plot.js';
import { exportButtons, toCsv } from './export.js';

export const CURVES = ['A_Z11', 'A_Z25', 'B_Z11', 'B_Z25'];

/** The machines the core offers (`machines()`: id, name, whether L0 is used), set at start. */
export const machines = { list: [] };
/** The core's description of the machine `id`. */
export const machineName = (id) => (machines.list.find((m) => m.id === id) || { name: id }).name;
const machineUsesL0 = (id) => (machines.list.find((m) => m.id === id) || { uses_l0: true }).uses_l0;

/** The gap diagnosis of an analysis when it was made (`diagnosis.status` of the core). */
export const diagnosisOf = (a) => (a && a.diagnosis && a.diagnosis.status === 'made' ? a.diagnosis.report : null);

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

/** A number with a sensible precision for its unit. */
export function fmtNum(v, unit) {
  if (v === null || v === undefined || !Number.isFinite(v)) return '—';
  if (unit === 'rad') return v.toExponential(3);
  if (unit === 'µm') return v.toFixed(2);
  if (unit === 'mm') return Math.abs(v) >= 0.1 ? v.toFixed(4) : v.toFixed(5);
  return String(Number(v.toPrecision(4)));
}

/** A table with a caption, header and rows of [text, {num, value}] cells, plus a CSV button. */
export function table(name, caption, header, rows) {
  const t = h('table', { 'data-table': name },
    h('caption', {}, caption),
    h('thead', {}, h('tr', {}, header.map((c) => h('th', { scope: 'col' }, c)))),
    h('tbody', {}, rows.map((r) => h('tr', {}, r.map((c) => (typeof c === 'object' && c !== null && !(c instanceof Node)
      ? h('td', { class: c.num ? 'num' : c.class, 'data-value': c.value ?? undefined }, c.text)
      : h('td', {}, c)))))));
  const bar = h('div', { class: 'bar' });
  exportButtons(bar, { name, table: () => t });
  return h('div', {}, bar, h('div', { class: 'scroll' }, t));
}

/** x positions and groups for points laid out curve by curve. */
function layout(curves, ids) {
  const x = [];
  const groups = [];
  let pos = 0;
  for (const c of [...CURVES, ...new Set(curves.filter((k) => !CURVES.includes(k)))]) {
    const idx = curves.map((k, i) => (k === c ? i : -1)).filter((i) => i >= 0);
    if (!idx.length) continue;
    const from = pos + 1;
    for (const i of idx) x[i] = ++pos;
    groups.push({ label: c, from, to: pos });
    pos += 2;
  }
  return { x, groups, xNames: ids.map((id, i) => `point ${id} (${curves[i]})`) };
}

export function chartBlock(name, spec, extra) {
  const holder = h('div', {});
  const c = chart(holder, spec);
  const bar = h('div', { class: 'bar' }, extra || '', h('span', { class: 'spacer' }));
  exportButtons(bar, { name, svg: () => c.svg, csv: () => toCsv(['x', 'label', ...spec.series.map((s) => s.name)],
    spec.x.map((x, i) => [x, spec.xNames ? spec.xNames[i] : '', ...spec.series.map((s) => s.y[i])])) });
  return { el: h('div', { class: 'chart-block', 'data-chart': name }, bar, holder), chart: c };
}

// ---------------------------------------------------------------- Data
export function dataView(root, st) {
  root.textContent = '';
  root.append(h('h2', {}, 'Files'));
  root.append(h('ul', { class: 'files' }, st.files.map((f, i) => h('li', { class: i === st.current ? 'active' : '' },
    h('button', { type: 'button', class: 'link-button', onclick: () => st.select(i) }, f.name),
    ` · ${f.bytes.length} bytes · `, f.error ? h('span', { class: 'warn' }, 'not analysed') : f.analysis ? `${f.analysis.file.points.length} points` : 'computing…'))));
  const f = st.files[st.current];
  if (!f) return;
  if (f.error) {
    root.append(h('h2', {}, `Problems in ${f.name}`), h('pre', { class: 'error', id: 'file-error' }, f.error));
    if (/line \d+/.test(f.error) && !st.settings.exclude_bad_rows) {
      root.append(h('button', { type: 'button', id: 'exclude-rows', onclick: () => st.excludeAndRetry() },
        'Exclude the listed rows and analyse the rest'));
    }
    return;
  }
  const a = f.analysis;
  if (!a) return;
  const file = a.file;
  root.append(h('h2', {}, `${f.name}`),
    h('p', {}, `Format: ${file.format.description}. ${file.points.length} points used.`),
    h('p', {}, `SHA-256: `, h('code', { id: 'checksum' }, f.sha256 || '…')));
  if (file.excluded.length) {
    root.append(h('h2', {}, `Rows excluded at your request (${file.excluded.length})`),
      table('excluded-rows', 'These rows are left out of every result.', ['line', 'column', 'found', 'expected'],
        file.excluded.map((p) => [{ text: p.line, num: true }, p.column ? (p.column.name || p.column.index) : '', p.found, p.expected])));
  }
  if (file.warnings.length) {
    root.append(h('h2', {}, 'Warnings'), h('ul', { id: 'warnings' }, file.warnings.map((w) => h('li', { class: 'warn' }, w.line ? `line ${w.line}: ${w.message}` : w.message))));
  }
  root.append(table('points', 'Matched points: nominal foot on the surface, outward normal, measured normal deviation (+ = material left, − = overcut)',
    ['id', 'line', 'curve', 'u', 'x (mm)', 'y (mm)', 'z (mm)', 'nx', 'ny', 'nz', 'deviation (µm)'],
    file.points.map((p, i) => [p.file.id, { text: p.file.line, num: true }, a.points[i].curve, { text: p.u.toFixed(5), num: true, value: p.u },
      ...p.foot.map((v) => ({ text: v.toFixed(4), num: true, value: v })), ...p.normal.map((v) => ({ text: v.toFixed(5), num: true, value: v })),
      { text: (p.deviation * 1000).toFixed(2), num: true, value: p.deviation * 1000 }])));
}

// ---------------------------------------------------------------- Figure 19
/** Figure-19 curves: `sens` = {ids, curves, params, rows, cols, values (column-major, mm per unit)}. */
export function fig19View(root, sens, st) {
  root.textContent = '';
  const scaleOf = (p) => (/^E[XYZ]/.test(p) ? 0.01 : 1e-4);
  root.append(h('h2', {}, 'Machined defect per error at the 100 built-in points (Figure 19 of paper 000, for the chosen machine)'),
    h('p', {}, `Machine: ${machineName(st.settings.machine)}. Mode ${st.settings.mode}, ${st.settings.branch} B. Each curve: the normal defect (µm) that one error alone leaves at each point, for 1e-4 rad (angles) or 0.01 mm (position errors such as EX0B). Points are grouped by measurement curve; hover for the value.`));
  const L = layout(sens.curves, sens.ids);
  const series = sens.params.map((p, k) => ({
    name: p,
    y: Array.from({ length: sens.rows }, (_, i) => sens.values[k * sens.rows + i] * scaleOf(p) * 1000),
    visible: st.fig19Visible ? st.fig19Visible[p] !== false : true,
  }));
  const spec = { title: 'Figure 19: defect per error', x: L.x, xNames: L.xNames, groups: L.groups, series,
    xLabel: 'measurement point (grouped by curve)', yLabel: 'defect (µm per 1e-4 rad; per 0.01 mm for E[XYZ]..)', yUnit: 'µm' };
  const toggles = h('div', { class: 'toggles', role: 'group', 'aria-label': 'parameters shown' });
  const block = chartBlock('figure19', spec, toggles);
  for (const s of series) {
    const cb = h('input', { type: 'checkbox', 'data-param': s.name });
    cb.checked = s.visible !== false;
    cb.addEventListener('change', () => { s.visible = cb.checked; st.fig19Visible = { ...(st.fig19Visible || {}), [s.name]: cb.checked }; block.chart.update({}); });
    toggles.append(h('label', {}, cb, ` ${s.name}`));
  }
  root.append(block.el);
  root.append(table('figure19-ranges', 'Range of each curve (µm per 1e-4 rad; per 0.01 mm for position errors)', ['parameter', 'min (µm)', 'max (µm)'],
    series.map((s) => [s.name, { text: Math.min(...s.y).toFixed(1), num: true, value: Math.min(...s.y) }, { text: Math.max(...s.y).toFixed(1), num: true, value: Math.max(...s.y) }])));
}


// ---------------------------------------------------------------- Where (the gap diagnosis on the plots)
// The diagnosis (src/gap/location.rs) reports typed groups: `group` is curve, region, lean or
// reversal (a reversal with its `axis`, path position `s` in mm and `nearest` point id), each
// with the points of the group (`ids`), its residual RMS and its concentration (share of the
// residual sum of squares over share of points). The core decides what is notable: `concentrated`,
// `structure.concentrated_entry` (the default highlight) and, for reversals, `of_verdict` and
// `marked`. These helpers only draw: the chosen group as shaded bands on the per-point plots
// and ringed points on the plan view, the marked reversals at their nearest point. The choice
// is shared by the views; changing it redraws every figure that shows it.
const where = { choice: 'auto', figures: new Set() };

const GROUP_WORDS = { curve: 'curve', region: 'region of the S', lean: 'lean of the wall', reversal: 'axis reversal' };
const entryKey = (e) => `${e.group}:${e.name}`;

/** The where report of an analysis: entries, reversals, and the entry to highlight for `choice`. */
function whereOf(a) {
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
  return `${GROUP_WORDS[e.group] || e.group} ${e.name}: ${e.n} points, baseline residual RMS ${um1(e.rms)}, ` +
    `max |r| ${um1(e.max_abs)}, ${Number(e.concentration.toFixed(2))}× its share of the residual`;
}
function describeReversal(e) {
  return `${e.axis}-axis reversal at ${e.s.toFixed(1)} mm of tool path (point ${e.nearest}); ±10 mm window: ${e.n} points, RMS ${um1(e.rms)}, ${Number(e.concentration.toFixed(2))}× its share`;
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
    h('table', {}, h('thead', {}, h('tr', {}, ...['axis', 'at (mm of tool path)', 'nearest point', 'points in ±10 mm', 'RMS (µm)', 'share ×', 'why marked'].map((t) => h('th', { scope: 'col' }, t)))),
      h('tbody', {}, ...rows)));
}

/** The legend of the highlight in words and units (also drawn inside the exported figures):
 * two lines, what is shaded and what the marks are. */
function whereNote(w) {
  if (!w) return '';
  const s = w.d.structure;
  const what = s.structured ? `structure (RMS ${um1(s.structure_rms)} above noise σ ${um1(s.noise.used)})` : `noise (σ ${um1(s.noise.used)}; no structure above the detection limit ${um1(w.d.verdict.detection_limit)})`;
  const shade = w.chosen ? `Shaded: ${GROUP_WORDS[w.chosen.group]} ${w.chosen.name} (RMS ${um1(w.chosen.rms)}, ${Number(w.chosen.concentration.toFixed(2))}× its share).` : 'Nothing shaded.';
  const axes = [...new Set(w.marked.map((e) => e.axis))].join(', ');
  const rev = w.marked.length ? `▼ ${w.marked.length} of ${w.reversals.length} axis reversals (${axes}) at the nearest point; ` : `▼ none of ${w.reversals.length} axis reversals marked; `;
  return `${shade}\nBaseline residual of the diagnosis: ${what}.\n${rev}units µm, tool path in mm.`;
}

/** Runs of consecutive x positions of the points `ids` (for shaded bands). */
function runsOf(ids, idToX) {
  const xs = ids.map((id) => idToX.get(String(id))).filter((x) => x !== undefined).sort((p, q) => p - q);
  const runs = [];
  for (const x of xs) {
    const last = runs[runs.length - 1];
    if (last && x === last.to + 1) { last.to = x; last.xs.push(x); } else runs.push({ from: x, to: x, xs: [x] });
  }
  return runs;
}

/** highlight / markers / note for a per-point chart laid out by `layout`. */
function whereChartPatch(a, ids, x) {
  const w = whereOf(a);
  if (!w) return { highlight: [], markers: [], note: undefined };
  const idToX = new Map(ids.map((id, i) => [String(id), x[i]]));
  const xToId = new Map(ids.map((id, i) => [x[i], String(id)]));
  const highlight = w.chosen ? runsOf(w.chosen.ids, idToX).map((r) => ({ from: r.from, to: r.to, ids: r.xs.map((v) => xToId.get(v)),
    label: `${describeEntry(w.chosen)}; points ${r.xs.map((v) => xToId.get(v)).join(', ')}` })) : [];
  const markers = w.marks.filter((k) => idToX.has(String(k.id))).map((k) => ({ x: idToX.get(String(k.id)), id: k.id, short: k.short, label: k.label }));
  return { highlight, markers, note: whereNote(w) };
}

/** The control that chooses what is highlighted, and the legend in words (HTML). */
function whereControl(a, idSuffix) {
  const w = whereOf(a);
  if (!w) return h('p', { class: 'where-legend' }, 'No gap diagnosis: nothing to highlight.');
  const sel = h('select', { id: `where-choice-${idSuffix}`, class: 'where-choice', 'aria-describedby': `where-legend-${idSuffix}` },
    h('option', { value: 'auto' }, w.auto ? `where the residual is concentrated (${w.auto.name})` : 'where the residual is concentrated (nowhere markedly: nothing)'),
    h('option', { value: 'none' }, 'nothing'),
    ...w.entries.map((e) => h('option', { value: entryKey(e) }, `${GROUP_WORDS[e.group]} ${e.name} (${Number(e.concentration.toFixed(2))}×, RMS ${um1(e.rms)})`)));
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
function residualChart(a, name, id = a.identification) {
  const curves = id.points.map((p) => p.curve);
  const ids = id.points.map((p) => p.id);
  const L = layout(curves, ids);
  const spec = { title: 'Measured, simulated (identified model) and residual', x: L.x, xNames: L.xNames, groups: L.groups,
    series: [
      { name: 'measured', y: id.points.map((p) => p.measured * 1000), points: true },
      { name: 'simulated', y: id.points.map((p) => p.fitted * 1000) },
      { name: 'residual', y: id.points.map((p) => p.residual * 1000), dashed: true },
    ], xLabel: 'measurement point (grouped by curve)', yLabel: 'normal deviation (µm)', yUnit: 'µm', ...whereChartPatch(a, ids, L.x) };
  const block = chartBlock(name, spec);
  where.figures.add({ isConnected: () => block.el.isConnected, redraw: () => block.chart.update(whereChartPatch(a, ids, L.x)) });
  return block.el;
}

// ---------------------------------------------------------------- Identification
/** What the final answer was fitted with, in the core's words (analysis.correction). */
export const fittedWith = (a) => (a.correction ? a.correction.fitted_with_words : '');

/** The single-point outliers the core named (a.outliers), with the rule, as a table. */
function outlierBlock(a) {
  const o = a.outliers;
  if (!o || !o.tested) return h('p', { id: 'outliers' }, 'Outlier test: not made (no diagnosis model for this part).');
  const pts = o.points || [];
  if (!pts.length) return h('p', { id: 'outliers' }, `Outliers: none (${o.rule}).`);
  return h('div', { id: 'outliers' }, h('h2', {}, 'Single-point outliers'), h('p', { class: 'warn' }, o.summary),
    table('outlier-points', `Points whose deviation the fit without them does not explain (|t| above ${Number(o.threshold).toFixed(2)}, Bonferroni α = ${o.alpha} over the points; σ = ${(o.sigma * 1000).toFixed(2)} µm, ${o.sigma_source}); ${o.excluded ? 'left out of the identification and the diagnosis' : 'kept (setting)'}`,
      ['point', 'curve', 'size (µm)', '|t|'],
      pts.map((p) => [String(p.id), p.curve, { text: (p.size * 1000).toFixed(1), num: true, value: p.size * 1000 }, { text: p.statistic.toFixed(1), num: true, value: p.statistic }])));
}

/** A parameters table: value, unit, std, t, status, and the shift from the baseline when given. */
function parameterTable(name, caption, id, shift, fitted) {
  const header = ['parameter', 'value', 'unit', 'std', 't', 'status'];
  if (shift) header.push('shift from baseline (std)');
  header.push('fitted with');
  return table(name, caption, header, Object.entries(id.parameters).map(([n, p]) => {
    const row = [n, { text: fmtNum(p.value, p.unit), num: true, value: p.value }, p.unit,
      { text: fmtNum(p.std, p.unit), num: true, value: p.std ?? '' }, { text: p.t === null || p.t === undefined ? '—' : p.t.toFixed(1), num: true, value: p.t ?? '' },
      { text: p.status.replace('_', ' '), class: `status-${p.status}` }];
    if (shift) {
      const v = shift[n];
      row.push(v === undefined ? { text: n.includes('.') ? 'effect' : '—', value: '' }
        : { text: v === null ? '—' : (v >= 0 ? '+' : '') + v.toFixed(1), num: true, value: v ?? '' });
    }
    row.push(fitted);
    return row;
  }));
}

export function identifyView(root, a) {
  root.textContent = '';
  if (!a) { root.append(h('p', {}, 'Load a measured part to identify the machine.')); return; }
  const id = a.identification;
  const c = a.correction;
  const params = Object.entries(id.parameters);
  root.append(h('h2', {}, 'Identified parameters: the final answer'),
    h('p', { id: 'correction-summary', class: `correction correction-${c.basis}` }, c.summary),
    h('p', {}, `${id.points_used} points, rank ${id.rank} of ${params.length}, condition number ${fmtNum(id.condition)} (unit-scaled design), σ ${id.sigma ? (id.sigma * 1000).toFixed(2) + ' µm' : '—'} (${id.sigma_source}). Residual RMS ${(id.residual.rms * 1000).toFixed(2)} µm, max ${(id.residual.max_abs * 1000).toFixed(2)} µm.`));
  root.append(parameterTable('parameters', `ISO 230-1 location errors (rad; EX0B, dR and lengths in mm), ${fittedWith(a)}${c.effect_parameters.length ? '; the effect\'s own parameters are named <effect>.<parameter>' : ''}. std: one standard deviation${c.std_includes_structure ? ' (includes the unexplained structure)' : ''}; t = |value|/std; shift = (final − baseline)/std.`, id, c.basis === 'baseline' ? null : c.shift, fittedWithId(a)));
  if (c.alternatives && c.alternatives.length) {
    root.append(h('ul', { id: 'alternatives' }, c.alternatives.map((x) => h('li', {}, x.same_answer
      ? `With the equivalent ${x.effect} instead: the same location errors (largest difference ${x.difference_std.toFixed(2)} std, ${x.parameter}).`
      : `With the equivalent ${x.effect} instead: ${x.parameter} differs by ${x.difference_std.toFixed(1)} std; the part cannot choose.`))));
  }
  const base = a.baseline.identification;
  root.append(h('details', { id: 'baseline-details' }, h('summary', {}, 'Baseline identification: the location errors alone, before the diagnosis'),
    h('p', {}, `Residual RMS ${(base.residual.rms * 1000).toFixed(2)} µm, σ ${base.sigma ? (base.sigma * 1000).toFixed(2) + ' µm' : '—'} (${base.sigma_source}).`),
    parameterTable('baseline-parameters', 'Baseline location errors (rad; lengths in mm), without any unmodelled effect', base, null, 'none')));
  root.append(outlierBlock(a));
  if (a.error_set) root.append(errorSetBlock(a.error_set));
  root.append(h('h2', {}, 'What this part cannot separate'));
  if (!id.groups.length) root.append(h('p', {}, 'Every parameter is separately determined by this part.'));
  root.append(h('ul', { id: 'groups' }, id.groups.map((g) => h('li', {}, h('strong', {}, `${g.kind.replace('_', ' ')}: ${g.parameters.join(', ')}. `), g.explanation))));
  if (id.notes && id.notes.length) root.append(h('ul', {}, id.notes.map((n) => h('li', {}, n))));
  // measured vs simulated vs residual, and the plan view, with where the gap diagnosis lies
  root.append(h('h2', {}, 'Residual per point and on the part (final answer)'), whereControl(a, 'identify'));
  root.append(residualChart(a, 'measured-simulated-residual'));
  root.append(planView(a, 'plan-view'));
  root.append(table('residual-per-curve', 'Residual per curve (paper 001 eq. 15-17)', ['curve', 'n', 'RMS (µm)', 'max |r| (µm)', 'MAD (µm)', 'RMSE (µm)', 'MAPE (%)'],
    id.per_curve.map((cv) => [cv.curve, { text: cv.n, num: true }, ...[cv.rms, cv.max_abs, cv.mad, cv.rmse].map((v) => ({ text: (v * 1000).toFixed(2), num: true, value: v * 1000 })),
      { text: cv.mape === null ? '—' : cv.mape.toFixed(1), num: true, value: cv.mape ?? '' }])));
}

const STATUS_WORDS = { kept: 'identified', absorbed: 'absorbed by the identified ones', invisible: 'invisible on a flank-milled wall', index: 'angular zero (not fitted)' };

/** The machine's location errors: which ISO 230-1 errors the part sees and is identified with,
 * which it cannot tell from them or cannot see at all, and the machine's coordinate convention. */
function errorSetBlock(s) {
  const um = (v) => ({ text: (v * 1000).toFixed(3), num: true, value: v * 1000 });
  return h('details', { id: 'error-set' },
    h('summary', {}, `This machine's location errors: ${s.kept.join(', ')} (${s.kept.length} of the ${s.rows.length} ISO 230-1 location errors of ${s.code})`),
    h('p', {}, `Derived from what the part sees, not listed: each error's defect at the ${s.points} built-in points is kept when at least ${(s.visible_fraction * 100).toFixed(1)} % of its RMS is left after the errors kept before it (condition index 30, where the identification calls parameters not separable).`),
    table('error-set-rows', 'ISO 230-1 location errors of the chain (RMS in µm of deviation per 1e-4 rad or per 0.01 mm)',
      ['error', 'status', 'RMS (µm)', 'left beyond the ones before (µm)', 'looks like', 'why'],
      s.rows.map((r) => [r.name, STATUS_WORDS[r.status] || r.status, um(r.rms), um(r.unabsorbed), r.looks_like ? r.looks_like.text : '—', r.reason])),
    h('h3', {}, 'Coordinate convention'),
    h('ul', { id: 'error-set-conventions' }, s.conventions.map((c) => h('li', {}, c))),
    h('h3', {}, 'This machine\'s effects (candidates of the gap diagnosis)'),
    h('ul', { id: 'machine-effects' }, (s.effects || []).map((e) => h('li', {}, e.status === 'offered'
      ? `${e.effect}: offered`
      : `${e.effect}: ${e.status.replace('_', ' ')}: ${e.reason}`))));
}

/** Plan view of the part (x–y) with the residual drawn as coloured arrows along the normal, the
 * points of the highlighted where-group ringed and the axis reversals marked. */
function planView(a, name, id = a.identification) {
  const pts = a.file.points;
  const res = id.points.map((p) => p.residual);
  const maxr = Math.max(1e-9, ...res.map(Math.abs));
  const W = 640, H = 570, pad = 30;
  const xs = pts.map((p) => p.foot[0]), ys = pts.map((p) => p.foot[1]);
  const x0 = Math.min(...xs) - 15, x1 = Math.max(...xs) + 15, y0 = Math.min(...ys) - 15, y1 = Math.max(...ys) + 15;
  const k = Math.min((W - 2 * pad) / (x1 - x0), (H - 2 * pad - 44) / (y1 - y0));
  const X = (x) => pad + (x - x0) * k, Y = (y) => H - pad - 44 - (y - y0) * k;
  const arrowMm = 12; // the largest residual is drawn 12 mm long
  const NS = 'http://www.w3.org/2000/svg';
  const svg = document.createElementNS(NS, 'svg');
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`); svg.setAttribute('class', 'chart'); svg.setAttribute('role', 'img');
  svg.setAttribute('aria-label', 'plan view with residual arrows'); svg.setAttribute('xmlns', NS);
  svg.setAttribute('font-family', 'system-ui, sans-serif'); svg.setAttribute('font-size', '11');
  const add = (tag, attrs, parent = svg) => { const e = document.createElementNS(NS, tag); for (const [kk, v] of Object.entries(attrs)) e.setAttribute(kk, v); parent.appendChild(e); return e; };
  add('rect', { x: 0, y: 0, width: W, height: H, fill: '#fff' });
  add('text', { x: pad, y: 18, 'font-weight': 600, 'font-size': 13 }).textContent = `Plan view: residual along the outward normal (largest ${(maxr * 1000).toFixed(1)} µm = ${arrowMm} mm arrow)`;
  for (const c of CURVES) {
    const idx = a.points.map((p, i) => (p.curve === c ? i : -1)).filter((i) => i >= 0);
    add('polyline', { points: idx.map((i) => `${X(xs[i]).toFixed(1)},${Y(ys[i]).toFixed(1)}`).join(' '), fill: 'none', stroke: '#bbb' });
  }
  const layer = add('g', { class: 'where-layer' });
  pts.forEach((p, i) => {
    const r = res[i], len = (r / maxr) * arrowMm;
    const color = r >= 0 ? '#1f77b4' : '#d62728';
    const xa = X(p.foot[0]), ya = Y(p.foot[1]);
    const xb = X(p.foot[0] + p.normal[0] * len), yb = Y(p.foot[1] + p.normal[1] * len);
    add('line', { x1: xa, y1: ya, x2: xb, y2: yb, stroke: color, 'stroke-width': 2 });
    add('circle', { cx: xb, cy: yb, r: 2, fill: color }).appendChild(document.createElementNS(NS, 'title')).textContent = `point ${p.file.id}: residual ${(r * 1000).toFixed(2)} µm`;
  });
  for (const o of (a.outliers && a.outliers.points) || []) {
    const i = o.row;
    if (i === undefined || !pts[i]) continue;
    const ring = add('circle', { cx: X(xs[i]), cy: Y(ys[i]), r: 9, fill: 'none', stroke: '#d62728', 'stroke-width': 2.5, 'stroke-dasharray': '3 2',
      class: 'outlier-ring', 'data-id': o.id, role: 'img', 'aria-label': `outlier: point ${o.id}, ${(o.size * 1000).toFixed(1)} µm` });
    add('title', {}, ring).textContent = `outlier: point ${o.id}, ${(o.size * 1000).toFixed(1)} µm from the fit without it (|t| = ${o.statistic.toFixed(1)}); ${a.outliers.excluded ? 'left out' : 'kept'}`;
  }
  add('text', { x: W - pad, y: H - 8, 'text-anchor': 'end', fill: '#555' }).textContent = 'blue: material left (+), red: overcut (−); dashed red ring: outlier; x, y in mm';
  const note = add('text', { x: pad, y: H - 52, fill: '#7a4b00', class: 'note' });
  const byId = new Map(pts.map((p, i) => [String(p.file.id), i]));
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
          class: 'highlight', 'data-id': id, tabindex: 0, role: 'img', 'aria-label': `point ${id}, in ${GROUP_WORDS[w.chosen.group]} ${w.chosen.name}: residual ${(res[i] * 1000).toFixed(2)} µm` }, layer);
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

// ---------------------------------------------------------------- Report
export function reportView(root, st) {
  root.textContent = '';
  const f = st.files[st.current];
  const a = f && f.analysis;
  root.append(h('h2', {}, 'Report'),
    h('div', { class: 'bar no-print' },
      h('button', { type: 'button', id: 'print', onclick: () => window.print() }, 'Print / save as PDF'),
      h('button', { type: 'button', id: 'export-json', onclick: () => st.exportJson() }, 'Export the whole analysis (JSON)')));
  if (!a) { root.append(h('p', {}, f && f.error ? 'The file could not be analysed: see Data.' : 'No analysis yet.')); return; }
  const s = a.settings;
  root.append(table('report-inputs', 'Inputs and settings', ['item', 'value'], [
    ['software', `testpiece ${a.version}`],
    ['file', f.name], ['SHA-256', f.sha256 || ''], ['format', a.file.format.description],
    ['points used', String(a.identification.points_used)], ['rows excluded', a.file.excluded.map((p) => p.line).join(' ') || 'none'],
    ['machine', machineName(s.machine)], ['L0', machineUsesL0(s.machine) ? `${s.l0} mm` : 'not used by this machine'], ['mode', s.mode], ['branch', s.branch],
    ['tool-radius term', s.tool_radius ? 'fitted (dR)' : 'not fitted'], ['CMM σ', a.noise ? a.noise.summary : (s.noise_sigma ? `${(s.noise_sigma * 1000).toFixed(2)} µm` : 'from the residual')],
    ['outliers', a.outliers && a.outliers.summary ? a.outliers.summary : 'none found'], ['errors reported', fittedWith(a)],
  ]));
  const id = a.identification;
  root.append(h('p', { id: 'report-correction' }, a.correction.summary));
  root.append(table('report-parameters', `Identified parameters, final answer (value ± 1 std), ${fittedWith(a)}`, ['parameter', 'value', 'std', 'unit', 'status', 'fitted with'],
    Object.entries(id.parameters).map(([n, p]) => [n, { text: fmtNum(p.value, p.unit), num: true, value: p.value }, { text: fmtNum(p.std, p.unit), num: true, value: p.std ?? '' }, p.unit, p.status.replace('_', ' '), fittedWithId(a)])));
  root.append(h('p', {}, `Residual RMS ${(id.residual.rms * 1000).toFixed(2)} µm, max ${(id.residual.max_abs * 1000).toFixed(2)} µm; rank ${id.rank}, condition ${fmtNum(id.condition)}.`));
  root.append(h('ul', {}, id.groups.map((g) => h('li', {}, g.explanation))));
  if (diagnosisOf(a)) root.append(h('h2', {}, 'Sim-to-real gap'), h('pre', {}, diagnosisOf(a).summary));
  root.append(h('p', { class: 'signature' }, 'Checked by: ____________________   Date: ____________'));
}

/** The export's `fitted_with` column, as the core writes it (identify::export). */
const fittedWithId = (a) => a.correction.fitted_with;

// ---------------------------------------------------------------- Sim-to-real gap
export function gapView(root, a) {
  root.textContent = '';
  if (!a) { root.append(h('p', {}, 'Load a measured part to diagnose the gap.')); return; }
  if (!diagnosisOf(a)) { root.append(h('pre', { class: 'error' }, `The diagnosis could not be made: ${a.diagnosis.reason}`)); return; }
  const d = diagnosisOf(a);
  const v = d.verdict;
  const um = (x) => (x * 1000).toFixed(2);
  if (a.outliers && a.outliers.summary) root.append(h('p', { id: 'gap-outliers', class: 'warn' }, a.outliers.summary));
  root.append(h('h2', {}, 'Sim-to-real gap'), h('pre', { id: 'gap-summary', class: 'summary' }, d.summary),
    h('p', { id: 'gap-corrected', class: `correction correction-${a.correction.basis}` },
      a.correction.basis === 'effects' ? `The machine's errors are corrected for it: ${a.correction.summary}`
        : a.correction.summary));
  root.append(table('gap-shrink', 'How far the gap shrinks with the verdict\'s effect (µm; withheld = cross-validation on points left out of the fit)',
    ['', 'before', 'after'], [
      ['RMS in-sample', { text: um(v.rms_before), num: true, value: v.rms_before * 1000 }, { text: um(v.rms_after), num: true, value: v.rms_after * 1000 }],
      ['max |r| in-sample', { text: um(v.max_before), num: true, value: v.max_before * 1000 }, { text: um(v.max_after), num: true, value: v.max_after * 1000 }],
      ['RMS withheld', { text: um(v.cv_rms_before), num: true, value: v.cv_rms_before * 1000 }, { text: v.cv_rms_after === undefined ? '—' : um(v.cv_rms_after), num: true, value: (v.cv_rms_after ?? NaN) * 1000 }],
    ]));
  if (d.pair) {
    const p = d.pair;
    root.append(table('gap-pair', `No single candidate explains the gap; ${p.first} and ${p.second} together do (joint refit with the baseline)`,
      ['pair', 'parameters', 'RMS (µm)', 'withheld RMS (µm)', `what ${p.second} adds beyond ${p.first} (µm RMS)`, 'F-test p (Bonferroni)'],
      [[`${p.first} + ${p.second}`,
        Object.entries(p.fit.parameters).map(([k, e]) => `${k} = ${Number(e.value.toPrecision(4))} ± ${Number(e.std.toPrecision(2))}`).join('; '),
        { text: um(p.fit.rms), num: true, value: p.fit.rms * 1000 }, { text: um(p.fit.cv_rms), num: true, value: p.fit.cv_rms * 1000 },
        { text: um(p.added_rms), num: true, value: p.added_rms * 1000 },
        { text: p.p_bonferroni.toExponential(1), num: true, value: p.p_bonferroni }]]));
  }
  root.append(table('gap-candidates', `Candidate effects, each added alone to the baseline (folds: ${d.folds.join(', ')})`,
    ['effect', 'parameters', 'RMS (µm)', 'withheld RMS (µm)', 'shrink', 'F-test p (Bonferroni)', 'unabsorbed RMS (µm)', 'significant'],
    d.candidates.map((c) => [c.effect,
      Object.entries(c.parameters).map(([k, p]) => `${k} = ${Number(p.value.toPrecision(4))} ± ${Number(p.std.toPrecision(2))}`).join('; '),
      { text: um(c.rms), num: true, value: c.rms * 1000 }, { text: um(c.cv_rms), num: true, value: c.cv_rms * 1000 },
      { text: `${(c.shrink * 100).toFixed(0)} %`, num: true, value: c.shrink },
      { text: c.evidence.p_bonferroni.toExponential(1), num: true, value: c.evidence.p_bonferroni },
      { text: um(c.evidence.unabsorbed_rms), num: true, value: c.evidence.unabsorbed_rms * 1000 }, c.evidence.significant ? 'yes' : 'no'])));
  if (d.equivalences.length) {
    root.append(h('h2', {}, 'Effects this part cannot tell apart'),
      h('p', {}, 'Cosine between the parts of two candidates\' signatures that the location errors cannot absorb: near 1, this part cannot tell them apart.'),
      h('ul', { id: 'equivalences' }, d.equivalences.map((e) => h('li', {}, `${e.a} ≈ ${e.b} (cosine ${Number(e.cosine).toFixed(3)})`))));
  }
  root.append(table('gap-where', 'Where the baseline residual lies (µm)', ['group', 'name', 'n', 'RMS', 'max |r|', 'mean', 'share'],
    d.where.map((w) => [w.group, w.name, { text: w.n, num: true }, { text: um(w.rms), num: true, value: w.rms * 1000 },
      { text: um(w.max_abs), num: true, value: w.max_abs * 1000 }, { text: um(w.mean), num: true, value: w.mean * 1000 },
      { text: Number(w.concentration.toPrecision(3)), num: true }])));
  root.append(h('h2', {}, 'Where, on the plots and the plan view'),
    h('p', {}, 'The shaded points are those of the chosen group of the table above (by default the curve or region where the core finds the baseline residual concentrated); the ▼ marks are the axis reversals of the tool path that the core marks. The plots show the baseline identification\'s residual (the location errors alone) at the same points: the gap the diagnosis explains.'),
    whereControl(a, 'gap'), residualChart(a, 'gap-where-residual', a.baseline.identification), planView(a, 'gap-where-plan', a.baseline.identification));
}
