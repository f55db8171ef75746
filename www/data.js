// The Data view: the files loaded, and the current one as read and matched by the core (format,
// excluded rows, warnings, the matched points), or the reader's message when it was refused.
import { h, table, DENSE_POINTS, TABLE_ROWS } from './ui.js';
import { toCsv } from './export.js';

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
    if (f.badRows && !st.settings.exclude_bad_rows) {
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
  const header = ['id', 'line', 'curve', 'u', 'x (mm)', 'y (mm)', 'z (mm)', 'nx', 'ny', 'nz', 'deviation (µm)'];
  const row = (p, i) => [p.file.id, { text: p.file.line, num: true }, a.points[i].curve, { text: p.u.toFixed(5), num: true, value: p.u },
    ...p.foot.map((v) => ({ text: v.toFixed(4), num: true, value: v })), ...p.normal.map((v) => ({ text: v.toFixed(5), num: true, value: v })),
    { text: (p.deviation * 1000).toFixed(2), num: true, value: p.deviation * 1000 }];
  // a scan's table: its first rows; the CSV has every point
  const dense = file.points.length > DENSE_POINTS;
  const shown = dense ? file.points.slice(0, TABLE_ROWS) : file.points;
  const csv = dense ? () => toCsv(header, file.points.map((p, i) => row(p, i).map((c) => (typeof c === 'object' ? c.value ?? c.text : c)))) : undefined;
  root.append(table('points', `Matched points: nominal foot on the surface, outward normal, measured normal deviation (+ = material left, − = overcut)${dense ? `; the first ${TABLE_ROWS} of ${file.points.length} (the CSV has every point)` : ''}`,
    header, shown.map(row), csv));
}
