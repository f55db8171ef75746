// Curves beside Figure 19: the cone frustum's normal defect per error (paper 002 M3_15 / M3_45 on
// its B-C tilting table) and paper 002's coefficients k, k_n, k_t, k_b along the S-shape tool path
// for the chosen machine. The numbers come from the core (src/wasm/curves.rs).
import { h, chartBlock } from './views.js';

const SCALE = (unit) => (unit === 'mm' ? 0.01 : 1e-4); // 1e-4 rad or 0.01 mm, as Figure 19

const unitOf = (param) => (/^E[XYZ]/.test(param) ? 'mm' : 'rad');

function seriesOf(data, comp) {
  return data.coefficients.map((c) => ({ name: c.param, y: c[comp].map((v) => v * SCALE(unitOf(c.param)) * 1000) }));
}

/** Appends the cone and path-coefficient sections to `root`; `st.curves` holds their state. */
export function curvesView(root, st) {
  const c = st.curves;
  // ------------------------------------------------------------ cone frustum
  const kind = h('select', { id: 'cone-kind', 'aria-label': 'cone frustum' },
    h('option', { value: 'M3_15' }, 'M3_15 (θ = 15°, β = 10°)'), h('option', { value: 'M3_45' }, 'M3_45 (θ = 45°, β = 30°)'));
  kind.value = c.cone.kind;
  const off = h('input', { type: 'checkbox', id: 'cone-offsets' });
  off.checked = c.cone.offsets;
  const reload = () => { c.cone.kind = kind.value; c.cone.offsets = off.checked; c.cone.data = null; st.loadCurves(); };
  kind.addEventListener('change', reload);
  off.addEventListener('change', reload);
  root.append(h('h2', {}, 'The same for the cone frustum (paper 002 §4, B-C tilting table)'),
    h('p', {}, 'Normal defect k_n (µm per 1e-4 rad, per 0.01 mm for position errors) of each location error of the tilting table, along one turn of the flank path (up-cutting, counter-clockwise).'),
    h('div', { class: 'bar' }, h('label', { for: 'cone-kind' }, 'Cone '), kind, h('label', {}, off, ' paper 002 offsets (d = 62.5 mm, p = 30 mm)')));
  if (c.cone.error) root.append(h('pre', { class: 'error' }, c.cone.error));
  else if (!c.cone.data) root.append(h('p', { class: 'pending' }, 'Computing the cone curves…'));
  else {
    const d = c.cone.data;
    root.append(chartBlock('cone-frustum', { title: `Normal defect per error: ${d.path}`, x: d.x, series: seriesOf(d, 'k_n'),
      xNames: d.x.map((x) => `φ = ${x.toFixed(1)}°`), xLabel: d.x_label, yLabel: 'k_n (µm per 1e-4 rad; per 0.01 mm)', yUnit: 'µm' }).el);
  }
  // ------------------------------------------------------------ coefficients along the S-shape path
  const surf = h('select', { id: 'path-surface', 'aria-label': 'surface' }, h('option', { value: 'A' }, 'surface A (down-cutting)'), h('option', { value: 'B' }, 'surface B (up-cutting)'));
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
      xNames: d.x.map((x, i) => `u = ${x.toFixed(3)} (s = ${d.s[i].toFixed(1)} mm)`), xLabel: 'u along the path (0 → 1)', yLabel: `${c.path.comp} (µm per 1e-4 rad; per 0.01 mm)`, yUnit: 'µm' }).el);
  }
}
