// The Plan view (issue 19, step 1): before a part is machined, the points to measure and what
// an identification on them will tell (predicted std, groups, detection limit of every effect).
// Every number comes from the core's `measurementPlan` export (src/plan/); this file only
// reads the view's inputs and draws. The machine, mode, branch, L0 and tool-radius term are the
// page's settings (left); points per curve and the CMM noise are the view's own inputs, and any
// change recomputes the plan at once.
import { download } from './export.js';
import { h, table, fmtNum, word, core } from './ui.js';

const num = (v, unit) => ({ text: fmtNum(v, unit), num: true, value: v ?? '' });

/** Sets up the view in `root`. ctx = {call, st}: the core call and the page state (settings).
 *  Returns {refresh}; the view also refreshes when its tab is chosen. */
export function setupPlan(root, ctx) {
  let seq = 0;
  let last = null;
  const input = (id, label, attrs, help) => h('label', { for: id }, label, ' ', h('input', { id, type: 'number', ...attrs }), help ? h('small', {}, ` ${help}`) : null);
  const controls = h('div', { class: 'bar', id: 'plan-controls' },
    input('plan-per-curve', 'Points per curve', { min: 1, max: 1000, step: 1, value: 25 }),
    input('plan-sigma', 'CMM σ (µm)', { min: 0, step: 0.1, placeholder: 'from the MPE' }),
    input('plan-mpe-a', 'or MPE A (µm)', { min: 0, step: 0.1, value: 3 }),
    input('plan-mpe-k', 'K (mm/µm)', { min: 1, step: 1, value: 75 }),
    input('plan-mpe-r0', 'R0 (µm)', { min: 0, step: 0.1, value: 3 }));
  const downloads = h('div', { class: 'bar' },
    h('button', { type: 'button', id: 'plan-dmis', onclick: () => last && download('testpiece-plan.dms', last.dmis, 'text/plain') }, 'Download DMIS program (ISO 22093)'),
    h('button', { type: 'button', id: 'plan-csv', onclick: () => last && download('testpiece-plan.csv', last.csv, 'text/csv') }, 'Download nominal table (CSV)'));
  const dmisInfo = h('p', { id: 'plan-dmis-replay' });
  const out = h('div', { id: 'plan-out' });
  root.append(h('h2', {}, 'Measurement plan: where to probe the part, and what it will tell'),
    h('p', {}, 'The points per curve lie at equal arc length from 5 % to 95 % of each measurement curve. The predicted std is what the identification (location errors alone, this σ given) will report on a part measured at these points; the detection limit of an effect is the size at which the part of it that the location errors cannot absorb reaches the diagnosis\'s detection rule (k σ, with the k of the table below).'),
    controls, downloads,
    h('p', {}, 'The DMIS program runs on the CMM: it defines the probe (tip diameter 4 mm, on an indexable head that tilts the stylus away from the wall where the wall overhangs), aligns on the fixture plate (its top face and two edge faces: datums A, B, C; the flanks themselves are what is measured, so they are not used for the alignment), measures the points with clearance moves over the part wherever the straight move between two touches would come near it (found by replaying the probe path against the walls and plate), and outputs the measured points. ASCII, lines of at most 80 characters.'),
    dmisInfo, out);
  const value = (id) => parseFloat(root.querySelector(`#${id}`).value);

  async function refresh() {
    const n = Math.round(value('plan-per-curve'));
    const sigmaUm = value('plan-sigma');
    const a = value('plan-mpe-a'), k = value('plan-mpe-k'), r0 = value('plan-mpe-r0');
    const s = ctx.st.settings;
    const options = { per_curve: core.curves.map(() => n), machine: s.machine, mode: s.mode, branch: s.branch, l0: s.l0, tool_radius: s.tool_radius };
    if (Number.isFinite(sigmaUm) && sigmaUm > 0) options.sigma = sigmaUm / 1000;
    else if (Number.isFinite(a) && Number.isFinite(k)) options.mpe = { a_um: a, k_mm: k, r0_um: Number.isFinite(r0) ? r0 : 0 };
    const mine = ++seq;
    try {
      const r = await ctx.callPrepared(options, 'measurementPlan', options);
      if (mine !== seq) return;
      last = r;
      renderReplay(dmisInfo, r.dmis_replay);
      render(out, r.plan);
    } catch (e) {
      if (mine !== seq) return;
      last = null;
      out.textContent = '';
      out.append(h('pre', { class: 'error', id: 'plan-error' }, e.message));
    }
  }
  controls.addEventListener('input', refresh);
  document.getElementById('tab-plan')?.addEventListener('click', () => { if (!last) refresh(); });
  // The page's machine settings (app.js reads them first: its listeners were added before).
  for (const id of ['machine', 'mode', 'branch', 'l0', 'toolRadius']) {
    document.getElementById(id)?.addEventListener('change', () => { if (root.hidden) last = null; else refresh(); });
  }
  return { refresh };
}

/** The replay of the DMIS program's probe path (crate::plan::probe_path::ProbeReplay). */
function renderReplay(el, r) {
  const moves = r.straight_moves + r.cleared_moves;
  el.dataset.minCertain = String(r.min_distance_certain);
  el.textContent = `DMIS probe path: ${r.cleared_moves} of ${moves} moves between touches go over the part (${r.gotos} GOTOs, ${r.index_changes} head indexings); every move keeps ${fmtNum(r.min_distance_certain, 'mm')} mm from the part and plate (replayed: ${fmtNum(r.min_distance, 'mm')} mm sampled less the sampling bound ${fmtNum(r.sampling_bound, 'mm')} mm; ${r.clearance} mm required).`;
}

function render(out, p) {
  out.textContent = '';
  out.dataset.points = String(p.points.length);
  out.append(h('p', { id: 'plan-summary' }, `${p.points.length} points. ${p.noise.summary} Rank ${p.rank}, condition number ${fmtNum(p.condition)}.`));
  out.append(table('plan-parameters', 'Predicted std of each location error on a part measured with this plan (same names and units as the identification)',
    ['parameter', 'predicted std', 'unit', 'status'],
    Object.entries(p.parameters).map(([name, q]) => [name, num(q.std, q.unit), q.unit, { text: word('parameter_status', q.status), class: `status-${q.status}` }])));
  if (p.groups.length) out.append(h('ul', { id: 'plan-groups' }, p.groups.map((g) => h('li', {}, g.explanation))));
  out.append(table('plan-limits', `Detection limit of each effect (smallest visible size: its unabsorbed part reaches ${p.detect_factor} σ RMS over the points)`,
    ['effect', 'meaning', 'parameter', 'smallest visible size', 'unit', 'absorbed by the location errors'],
    p.detection_detail.flatMap((d) => d.parameters.map((q) => [d.effect, d.plain_name, q.name,
      q.size === null ? { text: 'never visible', class: 'status-not_separable' } : num(q.size, q.unit), q.unit,
      { text: `${(q.absorbed_fraction * 100).toFixed(1)} %`, num: true, value: q.absorbed_fraction }]))));
  out.append(h('ul', { id: 'plan-notes' }, p.notes.map((n) => h('li', {}, n))));
  out.append(table('plan-points', 'The points to measure (mm; outward unit normal)', ['id', 'curve', 'x', 'y', 'z', 'nx', 'ny', 'nz'],
    p.points.map((q) => [q.id, q.curve, ...['x', 'y', 'z', 'nx', 'ny', 'nz'].map((k) => ({ text: q[k].toFixed(4), num: true, value: q[k] }))])));
}
