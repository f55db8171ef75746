// The Sensitivity view: Figure 19 of paper 000 for the chosen machine (the normal defect per
// error at the 100 built-in points), then the cone frustum's normal defect per error (paper 002
// M3_15 / M3_45 on its B-C tilting table) and paper 002's coefficients k, k_n, k_t, k_b along the
// S-shape tool path. Every number, every parameter's unit and the typical size each is drawn at
// come from the core (src/wasm/curves.rs: `curvesFor`, `coneCoefficients`).
import { h, table, layout, chartBlock, machineName, core } from './ui.js';

const size = (v) => (v < 1e-3 ? v.toExponential(0) : String(v));

/** "per 1e-4 rad; per 0.01 mm for EX0B": the typical size each parameter is drawn at, the most
 * common first. `params` = [{name, unit, scale}]. */
function perSize(params) {
  const groups = new Map();
  for (const p of params) {
    const k = `${size(p.scale)} ${p.unit}`;
    if (!groups.has(k)) groups.set(k, []);
    groups.get(k).push(p.name);
  }
  const sorted = [...groups.entries()].sort((a, b) => b[1].length - a[1].length);
  return sorted.map(([k, names], i) => (i === 0 ? `per ${k}` : `per ${k} for ${names.join(', ')}`)).join('; ');
}

/** Figure-19 curves: `sens` = {ids, curves, params, parameters ([{kind, name, unit}]), units,
 * scales, rows, cols, values (column-major, mm per unit)}. */
function fig19View(root, sens, st) {
  root.textContent = '';
  const params = sens.parameters.map((p, k) => ({ name: p.name, unit: p.unit, scale: sens.scales[k] }));
  const per = perSize(params);
  root.append(h('h2', {}, 'Machined defect per error at the 100 built-in points (Figure 19 of paper 000, for the chosen machine)'),
    h('p', {}, `Machine: ${machineName(st.settings.machine)}. Mode ${st.settings.mode}, ${st.settings.branch} B. Each curve: the normal defect (µm) that one error alone leaves at each point, ${per}. Points are grouped by measurement curve; hover for the value.`));
  const L = layout(sens.curves, sens.ids);
  const series = params.map((p, k) => ({
    name: p.name,
    y: Array.from({ length: sens.rows }, (_, i) => sens.values[k * sens.rows + i] * p.scale * 1000),
    visible: st.fig19Visible ? st.fig19Visible[p.name] !== false : true,
  }));
  const spec = { title: 'Figure 19: defect per error', x: L.x, xNames: L.xNames, groups: L.groups, series,
    xLabel: 'measurement point (grouped by curve)', yLabel: `defect (µm ${per})`, yUnit: 'µm' };
  const toggles = h('div', { class: 'toggles', role: 'group', 'aria-label': 'parameters shown' });
  const block = chartBlock('figure19', spec, toggles);
  for (const s of series) {
    const cb = h('input', { type: 'checkbox', 'data-param': s.name });
    cb.checked = s.visible !== false;
    cb.addEventListener('change', () => { s.visible = cb.checked; st.fig19Visible = { ...(st.fig19Visible || {}), [s.name]: cb.checked }; block.chart.update({}); });
    toggles.append(h('label', {}, cb, ` ${s.name}`));
  }
  root.append(block.el);
  root.append(table('figure19-ranges', `Range of each curve (µm ${per})`, ['parameter', 'min (µm)', 'max (µm)'],
    series.map((s) => [s.name, { text: Math.min(...s.y).toFixed(1), num: true, value: Math.min(...s.y) }, { text: Math.max(...s.y).toFixed(1), num: true, value: Math.max(...s.y) }])));
}

/** The series of component `comp` (µm at each parameter's typical size). */
function seriesOf(data, comp) {
  return data.coefficients.map((c) => ({ name: c.param, y: c[comp].map((v) => v * c.scale * 1000) }));
}
const perSizeOf = (data) => perSize(data.coefficients.map((c) => ({ name: c.param, unit: c.unit, scale: c.scale })));

/** Appends the cone and path-coefficient sections to `root`; `st.curves` holds their state. */
function curvesView(root, st) {
  const c = st.curves;
  // ------------------------------------------------------------ cone frustum
  const p = core.paths;
  const kind = h('select', { id: 'cone-kind', 'aria-label': 'cone frustum' },
    p.cones.map((k) => h('option', { value: k.kind }, `${k.kind} (θ = ${k.half_apex_deg}°, β = ${k.inclination_deg}°)`)));
  kind.value = c.cone.kind;
  const off = h('input', { type: 'checkbox', id: 'cone-offsets' });
  off.checked = c.cone.offsets;
  const reload = () => { c.cone.kind = kind.value; c.cone.offsets = off.checked; c.cone.data = null; st.loadCone(); };
  kind.addEventListener('change', reload);
  off.addEventListener('change', reload);
  root.append(h('h2', {}, 'The same for the cone frustum (paper 002 §4, B-C tilting table)'),
    h('p', {}, `Normal defect k_n (µm${c.cone.data ? ` ${perSizeOf(c.cone.data)}` : ''}) of each location error of the tilting table, along one turn of the flank path (up-cutting, counter-clockwise).`),
    h('div', { class: 'bar' }, h('label', { for: 'cone-kind' }, 'Cone '), kind, h('label', {}, off, ` paper 002 offsets (d = ${p.cone_offsets[0]} mm, p = ${p.cone_offsets[1]} mm)`)));
  if (c.cone.error) root.append(h('pre', { class: 'error' }, c.cone.error));
  else if (!c.cone.data) root.append(h('p', { class: 'pending' }, 'Computing the cone curves…'));
  else {
    const d = c.cone.data;
    root.append(chartBlock('cone-frustum', { title: `Normal defect per error: ${d.path}`, x: d.x, series: seriesOf(d, 'k_n'),
      xNames: d.x.map((x) => `φ = ${x.toFixed(1)}°`), xLabel: d.x_label, yLabel: `k_n (µm ${perSizeOf(d)})`, yUnit: 'µm' }).el);
  }
  // ------------------------------------------------------------ coefficients along the S-shape path
  const surf = h('select', { id: 'path-surface', 'aria-label': 'surface' },
    p.surfaces.map((x) => h('option', { value: x.surface }, `surface ${x.surface} (${x.cutting})`)));
  surf.value = c.path.surface;
  const comp = h('select', { id: 'path-component', 'aria-label': 'component' },
    ['k_n', 'k_t', 'k_b', 'k'].map((k) => h('option', { value: k }, { k_n: 'k_n (normal)', k_t: 'k_t (feed direction)', k_b: 'k_b (tool axis)', k: 'k (magnitude)' }[k])));
  comp.value = c.path.comp;
  surf.addEventListener('change', () => { c.path.surface = surf.value; c.path.data = null; st.loadCurves(); });
  comp.addEventListener('change', () => { c.path.comp = comp.value; st.renderCurves(); });
  root.append(h('h2', {}, 'Paper 002 coefficients along the S-shape tool path'),
    h('p', {}, 'The tool-position error per unit of each location error of the chosen machine, split into the surface frame of the tool path (paper 002 eq. 11-14): n normal to the surface (+ = material left), t along the feed, b along the tool axis.'),
    h('div', { class: 'bar' }, surf, comp));
  if (c.path.error) root.append(h('pre', { class: 'error' }, c.path.error));
  else if (!c.path.data) root.append(h('p', { class: 'pending' }, 'Computing the path coefficients…'));
  else {
    const d = c.path.data;
    root.append(chartBlock('path-coefficients', { title: `${c.path.comp} along ${d.path}`, x: d.x, series: seriesOf(d, c.path.comp),
      xNames: d.x.map((x, i) => `u = ${x.toFixed(3)} (s = ${d.s[i].toFixed(1)} mm)`), xLabel: 'u along the path (0 → 1)', yLabel: `${c.path.comp} (µm ${perSizeOf(d)})`, yUnit: 'µm' }).el);
  }
}

/** The whole view: `st.sensitivity` (or its error) and `st.curves`. */
export function sensitivityView(root, st) {
  if (st.sensitivity && !st.sensitivity.error) fig19View(root, st.sensitivity, st);
  else root.textContent = st.sensitivity ? st.sensitivity.error : 'Computing the sensitivity curves…';
  curvesView(root, st);
}
