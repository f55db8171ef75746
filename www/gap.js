// The Sim-to-real gap view: the diagnosis's summary, how far the verdict's effect shrinks the
// gap, the pair, every candidate, the effects this part cannot tell apart, where the baseline
// residual lies, and the same drawn on the plots and the plan view.
import { h, table, diagnosisOf, later } from './ui.js';
import { whereControl, residualChart, planView } from './where.js';
import { surfaceMaps } from './surfacemap.js';

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
    root.append(table('gap-pair', p.second_below_limit
      ? `No single candidate explains the gap alone; fitted with ${p.second} (significant, but below the detection limit, so not named), ${p.first} is visible and the residual left is noise (joint refit with the baseline)`
      : `No single candidate explains the gap; ${p.first} and ${p.second} together do (joint refit with the baseline)`,
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
      Object.entries(c.parameters).map(([k, p]) => `${k} = ${Number(p.value.toPrecision(4))} ± ${Number(p.std.toPrecision(2))}`).join('; ')
        + (c.shape ? `; ${shapeText(c.shape)}` : ''),
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
    whereControl(a, 'gap'), later(() => residualChart(a, 'gap-where-residual', a.baseline.identification)),
    later(() => planView(a, 'gap-where-plan', a.baseline.identification)),
    h('h3', {}, 'Baseline residual map of each surface (developed: tool-path position × height)'),
    later(() => surfaceMaps(a, a.baseline.identification, 'the baseline (the location errors alone)')));
}

/** A family's fitted shape with its 95 % interval (the core's `shape`: a backlash's lag `tau` in
 * mm of tool-tip path, a warm-up constant `f`; an open end is not bounded by the part). */
function shapeText(sh) {
  const v = (x) => (x === null || !Number.isFinite(x) ? '∞ (linear)' : String(Number(x.toPrecision(3))));
  const unit = sh.unit === 'mm' ? ' mm of path' : '';
  // the profiled parameter at the member that fits best: the warm-up's pause between the passes,
  // a backlash's overshoot or take-up (the interval holds the lags with and without it)
  const p = sh.profiled;
  const pause = !p ? '' : p.name === 'pause' ? `; pause between the passes ${v(p.value)} of the machining time`
    : p.name === 'overshoot' ? (p.value > 0 ? `; rings: overshoots by ${Math.round(p.value * 100)} % of the lost motion (second order; the lag is its natural length)` : '; settles in first order')
      : p.value > 0 ? `; play taken up over a lost motion of ${v(p.value)} ${p.unit}` : '; switched at the reversal';
  return `${sh.name} = ${v(sh.value)}${unit} (95 %: ${sh.low_open ? '≤ ' : ''}${v(sh.low)} to ${sh.high_open ? '≥ ' : ''}${v(sh.high)}${pause})`;
}
