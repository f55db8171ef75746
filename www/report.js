// The Report view: the inputs and settings, the final answer and the diagnosis's summary on
// one printable page, and the whole analysis as JSON.
import { h, table, fmtNum, diagnosisOf, fittedWith, fittedWithId, machineName, machineUsesL0, word } from './ui.js';

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
    ['machine', machineName(s.machine)], ['L0', machineUsesL0(s.machine) ? `${s.l0} mm` : 'not used by this machine'], ['feed', `${s.feed ?? 1000} mm/min`], ['mode', s.mode], ['branch', s.branch],
    ['tool-radius term', s.tool_radius ? 'fitted (dR)' : 'not fitted'], ['CMM σ', a.noise ? a.noise.summary : (s.noise_sigma ? `${(s.noise_sigma * 1000).toFixed(2)} µm` : 'from the residual')],
    ['outliers', a.outliers && a.outliers.summary ? a.outliers.summary : 'none found'], ['errors reported', fittedWith(a)],
  ]));
  const id = a.identification;
  root.append(h('p', { id: 'report-correction' }, a.correction.summary));
  root.append(table('report-parameters', `Identified parameters, final answer (value ± 1 std), ${fittedWith(a)}`, ['parameter', 'value', 'std', 'unit', 'status', 'fitted with'],
    Object.entries(id.parameters).map(([n, p]) => [n, { text: fmtNum(p.value, p.unit), num: true, value: p.value }, { text: fmtNum(p.std, p.unit), num: true, value: p.std ?? '' }, p.unit, word('parameter_status', p.status), fittedWithId(a)])));
  root.append(h('p', {}, `Residual RMS ${(id.residual.rms * 1000).toFixed(2)} µm, max ${(id.residual.max_abs * 1000).toFixed(2)} µm; rank ${id.rank}, condition ${fmtNum(id.condition)}.`));
  root.append(h('ul', {}, id.groups.map((g) => h('li', {}, g.explanation))));
  if (diagnosisOf(a)) root.append(h('h2', {}, 'Sim-to-real gap'), h('pre', {}, diagnosisOf(a).summary));
  root.append(h('p', { class: 'signature' }, 'Checked by: ____________________   Date: ____________'));
}
