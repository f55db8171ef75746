// The Identification view: the final answer (the location errors fitted with what the
// diagnosis found), the baseline, the outliers, the machine's location errors, what this part
// cannot separate, and the residual per point and on the part with the where highlight.
import { h, table, fmtNum, fittedWith, fittedWithId, word, later } from './ui.js';
import { whereControl, residualChart, planView } from './where.js';
import { surfaceMaps } from './surfacemap.js';

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

/** A parameters table: value, unit, std, t, status, and the shift from the baseline when given
 * (an effect's own parameters, `kind` `effect`, have none). */
function parameterTable(name, caption, id, shift, fitted) {
  const header = ['parameter', 'value', 'unit', 'std', 't', 'status'];
  if (shift) header.push('shift from baseline (std)');
  header.push('fitted with');
  return table(name, caption, header, Object.entries(id.parameters).map(([n, p]) => {
    const row = [n, { text: fmtNum(p.value, p.unit), num: true, value: p.value }, p.unit,
      { text: fmtNum(p.std, p.unit), num: true, value: p.std ?? '' }, { text: p.t === null || p.t === undefined ? '—' : p.t.toFixed(1), num: true, value: p.t ?? '' },
      { text: word('parameter_status', p.status), class: `status-${p.status}` }];
    if (shift) {
      const v = shift[n];
      row.push(v === undefined ? { text: p.kind === 'effect' ? 'effect' : '—', value: '' }
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
  root.append(parameterTable('parameters', `ISO 230-1 location errors (each in the unit of its row), ${fittedWith(a)}${c.effect_parameters.length ? '; the effect\'s own parameters are named <effect>.<parameter>' : ''}. std: one standard deviation${c.std_includes_structure ? ' (includes the unexplained structure)' : ''}; t = |value|/std; shift = (final − baseline)/std.`, id, c.basis === 'baseline' ? null : c.shift, fittedWithId(a)));
  if (c.alternatives && c.alternatives.length) {
    root.append(h('ul', { id: 'alternatives' }, c.alternatives.map((x) => h('li', {}, x.same_answer
      ? `With the equivalent ${x.effect} instead: the same location errors (largest difference ${x.difference_std.toFixed(2)} std, ${x.parameter}).`
      : `With the equivalent ${x.effect} instead: ${x.parameter} differs by ${x.difference_std.toFixed(1)} std; the part cannot choose.`))));
  }
  const base = a.baseline.identification;
  root.append(h('details', { id: 'baseline-details' }, h('summary', {}, 'Baseline identification: the location errors alone, before the diagnosis'),
    h('p', {}, `Residual RMS ${(base.residual.rms * 1000).toFixed(2)} µm, σ ${base.sigma ? (base.sigma * 1000).toFixed(2) + ' µm' : '—'} (${base.sigma_source}).`),
    parameterTable('baseline-parameters', 'Baseline location errors (each in the unit of its row), without any unmodelled effect', base, null, 'none')));
  root.append(outlierBlock(a));
  if (a.error_set) root.append(errorSetBlock(a.error_set));
  root.append(h('h2', {}, 'What this part cannot separate'));
  if (!id.groups.length) root.append(h('p', {}, 'Every parameter is separately determined by this part.'));
  root.append(h('ul', { id: 'groups' }, id.groups.map((g) => h('li', {}, h('strong', {}, `${word('group_kind', g.kind)}: ${g.parameters.join(', ')}. `), g.explanation))));
  if (id.notes && id.notes.length) root.append(h('ul', {}, id.notes.map((n) => h('li', {}, n))));
  // measured vs simulated vs residual, and the plan view, with where the gap diagnosis lies
  root.append(h('h2', {}, 'Residual per point and on the part (final answer)'), whereControl(a, 'identify'));
  root.append(later(() => residualChart(a, 'measured-simulated-residual')));
  root.append(later(() => planView(a, 'plan-view')));
  root.append(h('h3', {}, 'Residual map of each surface (developed: tool-path position × height)'), later(() => surfaceMaps(a)));
  root.append(table('residual-per-curve', 'Residual per curve (paper 001 eq. 15-17)', ['curve', 'n', 'RMS (µm)', 'max |r| (µm)', 'MAD (µm)', 'RMSE (µm)', 'MAPE (%)'],
    id.per_curve.map((cv) => [cv.curve, { text: cv.n, num: true }, ...[cv.rms, cv.max_abs, cv.mad, cv.rmse].map((v) => ({ text: (v * 1000).toFixed(2), num: true, value: v * 1000 })),
      { text: cv.mape === null ? '—' : cv.mape.toFixed(1), num: true, value: cv.mape ?? '' }])));
}

/** The machine's location errors: which ISO 230-1 errors the part sees and is identified with,
 * which it cannot tell from them or cannot see at all, and the machine's coordinate convention. */
function errorSetBlock(s) {
  const um = (v) => ({ text: (v * 1000).toFixed(3), num: true, value: v * 1000 });
  return h('details', { id: 'error-set' },
    h('summary', {}, `This machine's location errors: ${s.kept.join(', ')} (${s.kept.length} of the ${s.rows.length} ISO 230-1 location errors of ${s.code})`),
    h('p', {}, `Derived from what the part sees, not listed: each error's defect at the ${s.points} built-in points is kept when at least ${(s.visible_fraction * 100).toFixed(1)} % of its RMS is left after the errors kept before it (condition index ${Math.round(1 / s.visible_fraction)}, where the identification calls parameters not separable).`),
    table('error-set-rows', 'ISO 230-1 location errors of the chain (RMS in µm of deviation per 1e-4 rad or per 0.01 mm)',
      ['error', 'status', 'RMS (µm)', 'left beyond the ones before (µm)', 'looks like', 'why'],
      s.rows.map((r) => [r.name, word('error_status', r.status), um(r.rms), um(r.unabsorbed), r.looks_like ? r.looks_like.text : '—', r.reason])),
    h('h3', {}, 'Coordinate convention'),
    h('ul', { id: 'error-set-conventions' }, s.conventions.map((c) => h('li', {}, c))),
    h('h3', {}, 'This machine\'s effects (candidates of the gap diagnosis)'),
    h('ul', { id: 'machine-effects' }, (s.effects || []).map((e) => h('li', {}, e.status === 'offered'
      ? `${e.effect}: offered`
      : `${e.effect}: ${word('effect_status', e.status)}: ${e.reason}`))));
}
