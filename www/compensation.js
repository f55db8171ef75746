// The Correction view (issue 19, step 3): the identified location errors in the controller's
// terms (each axis's line and the tool tip at the reference pose, machine frame, before and
// after entering them) and the part the same program would leave once they are compensated,
// with what stays and why; the SINUMERIK toolholder parameters with their std and where each
// entered error goes; the prediction on withheld curves. Every number comes from the core's `compensate` export
// (src/compensation/); this file only draws. It follows the measured part chosen on the left
// and the page's settings, recomputed when the view is shown and they have changed.
import { chart } from './plot.js';
import { exportButtons, toCsv } from './export.js';
import { h, table, layout, word } from './ui.js';

const f6 = (v) => ({ text: v.toFixed(6), num: true, value: v });
const um = (v) => ({ text: (v * 1000).toFixed(2), num: true, value: v * 1000 });

/** Sets up the view in `root`. ctx = {call, st, withProgress}. */
export function setupCompensation(root, ctx) {
  let key = null;
  const out = h('div', { id: 'compensation-out' });
  root.append(h('h2', {}, 'Correction in the controller\'s terms'),
    h('p', {}, 'The final answer\'s location errors that are separable and significant (|value| ≥ 2 std) entered in the controller\'s kinematic description: where each axis\'s line lies and which way it points in the machine frame with every axis at 0, before (nominal) and after, each number with its std; the same as a SINUMERIK orientable toolholder ($TC_CARR), squareness table and work offset, and where each entered error goes; then the deviations the same program would leave once they are compensated, on the measured points and on curves the fit did not see. What is not entered (a location error not significant or not separable, a named effect, the tool-radius term) stays on the part, and the notes say so.'),
    out);

  async function refresh() {
    const f = ctx.st.files[ctx.st.current];
    if (!f) { out.textContent = 'Load a measured part first (left).'; return; }
    const k = `${f.name}|${f.bytes.length}|${JSON.stringify(ctx.st.settings)}`;
    if (k === key) return;
    key = k;
    try {
      const c = await ctx.withProgress('Computing the correction…', () => ctx.callPrepared(ctx.st.settings, 'compensate', f.bytes, f.name, ctx.st.settings));
      render(out, c, f.name);
    } catch (e) {
      key = null;
      out.textContent = '';
      out.append(h('pre', { class: 'error', id: 'compensation-error' }, e.message));
    }
  }
  document.getElementById('tab-compensation')?.addEventListener('click', refresh);
  return { refresh };
}

function render(out, c, name) {
  out.textContent = '';
  out.dataset.file = name;
  out.append(h('p', { id: 'compensation-summary' }, `${c.machine}. Predicted on this part: RMS ${(c.part.before.rms * 1000).toFixed(2)} µm → ${(c.part.after.rms * 1000).toFixed(2)} µm, largest |deviation| ${(c.part.before.max_abs * 1000).toFixed(2)} µm → ${(c.part.after.max_abs * 1000).toFixed(2)} µm.`));
  const rows = c.before.axes.map((b, i) => {
    const a = c.after.axes[i];
    const pt = (l) => (l.point ? l.point.map(f6) : [{ text: '—' }, { text: '—' }, { text: '—' }]);
    return [b.axis, b.rotary ? 'rotary' : 'linear', ...pt(b), ...b.direction.map(f6), ...pt(a), ...a.direction.map(f6), { text: c.changes[i].tilt.toExponential(3), num: true, value: c.changes[i].tilt }];
  });
  rows.push(['tool tip', 'reference pose', ...c.before.tool_tip.map(f6), '', '', '', ...c.after.tool_tip.map(f6), '', '', '', '']);
  out.append(table('compensation-axes', `Kinematic description (${c.before.code}): rotary lines by their point nearest the machine origin (mm) and unit direction; linear axes by their direction`,
    ['axis', 'kind', 'before x', 'before y', 'before z', 'before i', 'before j', 'before k', 'after x', 'after y', 'after z', 'after i', 'after j', 'after k', 'tilt (rad)'], rows));
  out.append(table('compensation-offsets', 'Offset vectors as a five-axis controller chains them: machine zero → rotation centres (common perpendicular of a head\'s or a table\'s two rotary axes, else the foot from the tool tip or the origin) → tool tip (mm)',
    ['from', 'to', 'before x', 'before y', 'before z', 'after x', 'after y', 'after z'],
    c.before.offsets.map((o, i) => [o.from, o.to, ...o.vector.map(f6), ...c.after.offsets[i].vector.map(f6)])));
  const sd = (v) => ({ text: v.toExponential(1), num: true, value: v });
  const s = c.after_std;
  const stdRows = s.axes.map((a) => [a.axis, ...(a.point ? a.point.map(sd) : ['—', '—', '—']), ...a.direction.map(sd)]);
  stdRows.push(['tool tip', ...s.tool_tip.map(sd), '', '', '']);
  s.offsets.forEach((o) => stdRows.push([`${o.from} → ${o.to}`, ...o.vector.map(sd), '', '', '']));
  out.append(table('compensation-std', `Std of the description after (propagated from the entered errors; covariance: ${c.covariance})`,
    ['axis / vector', 'point or vector x (mm)', 'y', 'z', 'direction i', 'j', 'k'], stdRows));
  const val = (e) => ({ text: e.value.toExponential(4), num: true, value: e.value });
  const std = (e) => ({ text: e.std === null ? '—' : e.std.toExponential(2), num: true, value: e.std ?? '' });
  out.append(table('compensation-entered', 'Location errors entered (separable, |value| ≥ 2 std)', ['error', 'value', 'unit', 'std', 'status'],
    c.entered.map((e) => [e.name, val(e), e.unit, std(e), word('parameter_status', e.status)])));
  if (c.not_entered.length) {
    out.append(table('compensation-not-entered', 'Location errors not entered, and why (they stay on the part)', ['error', 'value', 'unit', 'std', 'why'],
      c.not_entered.map((e) => [e.name, val(e), e.unit, std(e), e.why])));
  }
  if (c.controller) {
    const ctl = c.controller;
    out.append(table('compensation-controller', `${ctl.controller}, kinematic type ${ctl.kinematic_type}: the corrected description in the controller's parameters, each with its std`,
      ['parameter', 'meaning', 'value', 'std', 'unit', 'where'],
      ctl.parameters.map((p) => [p.name, p.meaning, { text: p.value.toExponential(6), num: true, value: p.value }, sd(p.std), p.unit, p.place])));
    out.append(table('compensation-homes', 'Where each entered error goes', ['error', 'goes to'], ctl.homes.map((g) => [g.name, g.sentence])));
  } else if (c.controller_unavailable) {
    out.append(h('p', { id: 'compensation-controller-unavailable' }, c.controller_unavailable));
  }
  const w = c.withheld;
  out.append(table('compensation-withheld', 'Predicted after compensation on withheld curves (each curve by the fit of the other curves)', ['curve', 'points', 'entered by that fit', 'measured RMS (µm)', 'after RMS (µm)', 'after max |d| (µm)'],
    [...w.curves.map((k) => [k.curve, String(k.points), k.entered.join(' '), um(k.measured.rms), um(k.after.rms), um(k.after.max_abs)]),
      ['all', String(w.points.length), '', um(w.measured.rms), um(w.after.rms), um(w.after.max_abs)]]));
  const pts = c.part.points;
  const { x, xNames, groups } = layout(pts.map((p) => p.curve), pts.map((p) => p.id));
  const spec = { title: 'Measured, and predicted after compensation', x, xNames, groups,
    series: [{ name: 'measured', y: pts.map((p) => p.measured * 1000), points: true }, { name: 'after compensation', y: pts.map((p) => p.after * 1000) }, { name: 'location errors (removed)', y: pts.map((p) => p.machine * 1000), dashed: true }],
    xLabel: 'measurement point (grouped by curve)', yLabel: 'normal deviation (µm)', yUnit: 'µm' };
  const holder = h('div', {});
  const ch = chart(holder, spec);
  const bar = h('div', { class: 'bar' }, h('span', { class: 'spacer' }));
  exportButtons(bar, { name: 'compensation-part', svg: () => ch.svg, csv: () => toCsv(['id', 'curve', 'measured', 'machine', 'left_model', 'residual', 'after', 'used'], pts.map((p) => [p.id, p.curve, p.measured, p.machine, p.left_model, p.residual, p.after, p.used])) });
  out.append(h('div', { class: 'chart-block', 'data-chart': 'compensation-part' }, bar, holder));
  if (c.part.left_in.length) {
    out.append(table('compensation-left', 'Fitted terms the compensation leaves on the part', ['parameter', 'value', 'unit', 'RMS on the part (µm)'],
      c.part.left_in.map((l) => [l.parameter, { text: l.value.toExponential(4), num: true, value: l.value }, l.unit, um(l.rms)])));
  }
  out.append(h('ul', { id: 'compensation-notes' }, c.notes.map((n) => h('li', {}, n))));
}
