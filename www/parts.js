// The "Several parts" view: one machine identified from the pooled points of several parts, and
// two parts compared side by side. Every number comes from the core (src/pool.rs, src/compare.rs).
import { h, fmtNum, table, word, core } from './ui.js';

/** A false-alarm rate as the paragraph writes it (0.27 %, 4.6 %). */
const percent = (p) => `${Number((p * 100).toPrecision(2))} %`;

/** `st.files` (analysed), `st.pool` = {names: Set, result, error}, `st.comparison` = {a, b, result, error}. */
export function partsView(root, st) {
  root.textContent = '';
  root.append(h('h2', {}, 'Several parts'),
    h('p', {}, 'Choose several files at once (or add more with the file picker): all are read with the same settings. ',
      'Pool them to identify one machine from all their points (repeated measurements or several parts cut on the same machine), ',
      'or compare two of them side by side (before and after compensation, two machines, two dates).'));
  // the mean of repeats (an entry made here) is one part, not a file to pool again
  const ok = st.files.map((f, i) => ({ f, i })).filter((x) => x.f.analysis && !x.f.repeats);
  if (ok.length < 2) {
    root.append(h('p', { id: 'parts-need', class: 'warn' }, `${ok.length} analysed part${ok.length === 1 ? '' : 's'} loaded: load at least two measured parts to pool or compare them.`));
    return;
  }
  // ------------------------------------------------------------ pooled identification
  root.append(h('h3', {}, 'One machine from the pooled points'));
  const picks = h('div', { class: 'toggles', role: 'group', 'aria-label': 'parts in the pool' });
  for (const { f } of ok) {
    const cb = h('input', { type: 'checkbox', 'data-pool': f.name });
    cb.checked = st.pool.names.has(f.name);
    cb.addEventListener('change', () => { cb.checked ? st.pool.names.add(f.name) : st.pool.names.delete(f.name); });
    picks.append(h('label', {}, cb, ` ${f.name}`));
  }
  root.append(picks, h('div', { class: 'bar' },
    h('button', { type: 'button', id: 'pool-run', onclick: () => st.runPool() }, 'Identify one machine from the checked parts'),
    h('button', { type: 'button', id: 'clear-files', onclick: () => st.clearFiles() }, 'Remove all files')));
  root.append(h('p', {}, 'Or, when the checked files are the same part measured again (the same point ids): ',
    h('button', { type: 'button', id: 'repeat-run', onclick: () => st.runRepeats() }, 'Analyse the checked files as repeats of one part'),
    ' — σ is then measured from their differences (pure error) instead of estimated, and the mean of the measurements is analysed as a new part in the list.'));
  if (st.pool.repeatError) root.append(h('pre', { class: 'error', id: 'repeat-error' }, st.pool.repeatError));
  const p = st.pool.result;
  if (st.pool.error) root.append(h('pre', { class: 'error', id: 'pool-error' }, st.pool.error));
  if (p) {
    const id = p.identification;
    root.append(h('p', { id: 'pool-summary' }, `${p.parts.length} parts, ${id.points_used} points: shared machine parameters ${p.shared.join(', ')}`,
      p.per_part.length ? `; per part ${p.per_part.join(', ')}` : '; no per-part terms',
      `. σ ${id.sigma ? (id.sigma * 1000).toFixed(2) + ' µm' : '—'} (${id.sigma_source}), rank ${id.rank}, condition ${fmtNum(id.condition)}. No exact-model refinement on a pool.`));
    // σ of each parameter from the pool next to the smallest σ of the single parts.
    const single = (name) => Math.min(...ok.filter((x) => st.pool.names.has(x.f.name))
      .map((x) => x.f.analysis.identification.parameters[name]?.std ?? Infinity));
    root.append(table('pooled-parameters', 'Pooled identification (value ± 1 std); the last column compares the pooled std with the best single part\'s',
      ['parameter', 'value', 'unit', 'std', 'status', 'std / best single'],
      Object.entries(id.parameters).map(([n, q]) => {
        const s1 = single(n);
        const r = q.std && Number.isFinite(s1) ? q.std / s1 : null;
        return [n, { text: fmtNum(q.value, q.unit), num: true, value: q.value }, q.unit,
          { text: fmtNum(q.std, q.unit), num: true, value: q.std ?? '' }, word('parameter_status', q.status),
          { text: r === null ? '—' : r.toFixed(3), num: true, value: r ?? '' }];
      })));
    root.append(table('pooled-parts', 'Residual of the pooled fit on each part\'s points (a part far above the others does not fit the shared machine)',
      ['k', 'part', 'points', 'excluded rows', 'RMS (µm)', 'mean (µm)'],
      p.parts.map((q) => [{ text: q.index, num: true }, q.name, { text: q.points, num: true }, { text: q.excluded_rows, num: true },
        { text: (q.residual_rms * 1000).toFixed(2), num: true, value: q.residual_rms * 1000 },
        { text: (q.residual_mean * 1000).toFixed(2), num: true, value: q.residual_mean * 1000 }])));
    if (id.groups.length) root.append(h('ul', {}, id.groups.map((g) => h('li', {}, g.explanation))));
  }
  // ------------------------------------------------------------ comparison
  root.append(h('h3', {}, 'Two parts side by side'));
  const sel = (id, value) => {
    const s = h('select', { id }, ok.map(({ f }) => h('option', { value: f.name }, f.name)));
    s.value = value;
    s.addEventListener('change', () => st.runCompare(document.getElementById('compare-a').value, document.getElementById('compare-b').value));
    return s;
  };
  const c = st.comparison;
  root.append(h('div', { class: 'bar' },
    h('label', { for: 'compare-a' }, 'A (e.g. before) '), sel('compare-a', c.a || ok[0].f.name),
    h('label', { for: 'compare-b' }, ' B (e.g. after) '), sel('compare-b', c.b || ok[1].f.name)));
  const t = core.thresholds;
  root.append(h('p', {}, 'd = B − A; σ_d = √(σA² + σB²) (independent parts); z = d / σ_d. ',
    h('strong', {}, 'Different'), ` at |z| ≥ ${t.different_z} (${percent(t.different_false_alarm)} false alarms per parameter); `,
    h('strong', {}, 'suspect'), ` at ${t.suspect_z} ≤ |z| < ${t.different_z} (${percent(t.suspect_false_alarm)} per parameter by chance alone: worth a look, not evidence). `,
    'Pooling the same file twice or comparing a file with itself is not independent.'));
  if (c.error) root.append(h('pre', { class: 'error' }, c.error));
  if (c.result) {
    const r = c.result;
    root.append(h('p', { id: 'compare-summary', class: 'verdict' }, r.summary));
    const cell = (v, unit) => ({ text: fmtNum(v, unit), num: true, value: v ?? '' });
    root.append(table('comparison', `Differences of the identified parameters, ${r.b} − ${r.a}`,
      ['parameter', 'unit', 'A', 'σA', 'B', 'σB', 'd = B − A', 'σ_d', 'z', 'flag'],
      r.differences.map((d) => [d.name, d.unit, cell(d.a, d.unit), cell(d.a_std, d.unit), cell(d.b, d.unit), cell(d.b_std, d.unit),
        cell(d.diff, d.unit), cell(d.std, d.unit), { text: d.z === null ? '—' : d.z.toFixed(2), num: true, value: d.z ?? '' },
        { text: word('flags', d.flag), class: `flag-${d.flag}` }])));
  }
}
