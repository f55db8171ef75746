// The Budget view (issue 10): load a CAM cutter-location file and optionally an NC trace next to
// the CMM file, and show, per point, how much of the measured deviation comes from the design
// (overcut), the CAM path, the NC controller, the machine, the tool and what is left, with the
// CMM's MPE band (paper 000 §3-§6). Every number comes from the core's `budget` export
// (src/budget/); this file only draws.
import { chart, xNameOf } from './plot.js';
import { exportButtons, toCsv } from './export.js';
import { h, table, layout } from './ui.js';

const SOURCES = ['design', 'cam', 'nc', 'machine', 'tool', 'residual'];
const LABEL = { design: 'design (overcut)', cam: 'CAM path', nc: 'NC trace', machine: 'machine', tool: 'tool', residual: 'residual', cmm: 'CMM band (±)', measured: 'measured' };
const um = (v) => v * 1000;
const cell = (v) => ({ text: Number.isFinite(v) ? um(v).toFixed(2) : '—', num: true, value: Number.isFinite(v) ? um(v) : '' });

/** Sets up the view in `root`. ctx = {call, st, withProgress}: the core call, the page state
 *  (its current CMM file and settings) and the progress indicator of app.js. */
export function setupBudget(root, ctx) {
  const bst = { cl: null, trace: null, cmm: null, result: null, error: null };
  const status = h('p', { id: 'budget-status' }, 'Load a CAM cutter-location file (CSV x,y,z,i,j,k or APT GOTO/x,y,z,i,j,k) and, optionally, an NC trace (CSV X,Y,Z,B,C with time) for the measured part chosen on the left.');
  const out = h('div', { id: 'budget-out' });
  const fileInput = (id, label, key) => {
    const input = h('input', { type: 'file', id, accept: '.csv,.txt,.apt,.cl,.cls,.nc,.dat,text/*' });
    input.addEventListener('change', async () => {
      const f = input.files[0];
      bst[key] = f ? { name: f.name, bytes: new Uint8Array(await f.arrayBuffer()) } : null;
      show();
    });
    return h('label', { for: id }, label, ' ', input);
  };
  const options = () => {
    const s = ctx.st.settings;
    return { analysis: { mode: s.mode, branch: s.branch, l0: s.l0, tool_radius: s.tool_radius, exclude_bad_rows: s.exclude_bad_rows, noise_sigma: s.noise_sigma } };
  };
  /** One core call (`fn`) for the budget, with the progress indication. */
  const compute = async (fn) => {
    try {
      bst.error = null;
      bst.result = await ctx.withProgress('Computing the error budget…', fn);
    } catch (e) {
      bst.result = null;
      bst.error = e.message;
    }
    show();
  };
  const run = async () => {
    const f = bst.cmm || ctx.st.files[ctx.st.current];
    if (!f) { bst.error = 'Load a measured part first (left).'; show(); return; }
    if (!bst.cl) { bst.error = 'Load a CAM cutter-location file first.'; show(); return; }
    await compute(() => ctx.callPrepared(options().analysis, 'budget', f.bytes, f.name,
      bst.cl.bytes, bst.cl.name, bst.trace ? bst.trace.bytes : undefined, bst.trace ? bst.trace.name : undefined, options(), undefined));
  };
  // The example files (measured part, CL, trace) and their budget in one call.
  const example = () => compute(async () => {
    const r = await ctx.callPrepared(options().analysis, 'budgetExample', options());
    const utf8 = new TextEncoder();
    for (const e of r.files) bst[e.role] = { name: e.name, bytes: utf8.encode(e.text) };
    return r.budget;
  });
  root.append(h('h2', {}, 'Error budget of the machining process (paper 000 §3-§6)'),
    h('p', {}, 'Per point: design = overcut of the exact envelope of the ideal flank path (eq. 2-5); CAM = CAM path minus design (discrete tool positions, §4.1 Fig. 13); NC = trace minus CAM path (§5.1); machine = location errors identified after the path\'s deviation is subtracted (eq. 14); tool = −dR when the tool-radius term is fitted (§3.2); residual = what is left. The sources add up to the measured deviation. CMM band = ± the CMM\'s MPE (§6), stated with the result.'),
    h('div', { class: 'bar' }, fileInput('budget-cl', 'CAM path (CL)', 'cl'), fileInput('budget-trace', 'NC trace (optional)', 'trace'),
      h('button', { type: 'button', id: 'budget-run', onclick: run }, 'Compute the budget'),
      h('button', { type: 'button', id: 'budget-example', onclick: example }, 'Example: part + CL + trace')),
    status, out);

  function show() {
    const f = bst.cmm || ctx.st.files[ctx.st.current];
    status.textContent = `Measured part: ${f ? f.name : 'none'} · CL: ${bst.cl ? bst.cl.name : 'none'} · trace: ${bst.trace ? bst.trace.name : 'none'}`;
    out.textContent = '';
    if (bst.error) { out.append(h('pre', { class: 'error', id: 'budget-error' }, bst.error)); return; }
    const b = bst.result;
    if (!b) return;
    render(out, b);
  }
}

function render(out, b) {
  const pts = b.points;
  // x layout: curve by curve, as the other views
  const { x, xNames, groups } = layout(pts.map((p) => p.curve), pts.map((p) => p.id));
  // stacked: cumulative sums design, +cam, +nc, +machine, +tool, +residual (= measured)
  const acc = pts.map(() => 0);
  const stacked = SOURCES.map((s) => ({ name: `+ ${LABEL[s]}`, y: pts.map((p, i) => um((acc[i] += p[s]))) }));
  stacked.push({ name: 'measured', y: pts.map((p) => um(p.measured)), points: true });
  stacked.push({ name: 'CMM band +', y: pts.map((p) => um(p.measured + p.cmm)), dashed: true, color: '#999' });
  stacked.push({ name: 'CMM band −', y: pts.map((p) => um(p.measured - p.cmm)), dashed: true, color: '#999' });
  out.append(block('budget-stacked', { title: 'Stacked budget: each line adds one source; the last one is the measurement', x, xNames, groups, series: stacked,
    xLabel: 'measurement point (grouped by curve)', yLabel: 'normal deviation (µm)', yUnit: 'µm' }));
  out.append(block('budget-sources', { title: 'Each source alone', x, xNames, groups,
    series: SOURCES.map((s) => ({ name: LABEL[s], y: pts.map((p) => um(p[s])), dashed: s === 'residual' })),
    xLabel: 'measurement point (grouped by curve)', yLabel: 'deviation (µm)', yUnit: 'µm' }));
  const names = [...SOURCES, 'cmm', 'measured'];
  const mpe = b.settings;
  out.append(h('p', { id: 'budget-band' }, `CMM band = ±(${mpe.mpe_constant_um} + L/${mpe.mpe_length_mm_per_um}) µm (§6).`));
  out.append(table('budget-summary', `Min / max per source over ${pts.length} points (µm; + = material left, − = overcut). Sum check: ${b.sum_check.toExponential(1)} mm.`,
    ['source', 'min (µm)', 'max (µm)'], names.map((s) => [LABEL[s], cell(b.summary[s].min), cell(b.summary[s].max)])));
  out.append(table('budget-per-curve', 'Min / max per source and curve (µm)', ['curve', ...names.flatMap((s) => [`${s} min`, `${s} max`])],
    b.per_curve.map((c) => [c.curve, ...names.flatMap((s) => [cell(c.summary[s].min), cell(c.summary[s].max)])])));
  const paths = [b.cl, b.trace].filter(Boolean);
  out.append(table('budget-paths', 'Tool paths read (eq. 7 chord bound: the discretisation error of the positions)', ['file', 'format', 'positions', 'passes', 'max step (mm)', 'eq. 7 bound (µm)', 'duration (s)', 'notes'],
    paths.map((p) => [p.name, p.format, { text: p.positions, num: true }, { text: p.passes, num: true }, { text: p.max_step.toFixed(3), num: true, value: p.max_step }, cell(p.chord_bound),
      { text: p.duration === null ? '—' : p.duration.toFixed(2), num: true }, p.notes.join('; ')])));
  out.append(h('ul', { id: 'budget-notes' }, [...b.notes, b.verdict ? `Gap diagnosis with the path's deviation subtracted: ${b.verdict}` : null].filter(Boolean).map((n) => h('li', {}, n))));
  const cols = ['id', 'curve', 'measured', ...SOURCES, 'cmm', 'cam_chord_bound', 'nc_chord_bound'];
  out.append(table('budget-points', 'Budget per point (µm)', cols,
    pts.map((p) => [p.id, p.curve, ...cols.slice(2).map((k) => cell(p[k] ?? NaN))])));
}

function block(name, spec) {
  const holder = h('div', {});
  const c = chart(holder, spec);
  const bar = h('div', { class: 'bar' }, h('span', { class: 'spacer' }));
  exportButtons(bar, { name, svg: () => c.svg, csv: () => toCsv(['x', 'label', ...spec.series.map((s) => s.name)],
    spec.x.map((xv, i) => [xv, xNameOf(spec, i), ...spec.series.map((s) => s.y[i])])) });
  return h('div', { class: 'chart-block', 'data-chart': name }, bar, holder);
}
