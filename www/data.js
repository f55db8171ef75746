// The Data view: the files loaded, and the current one as read and matched by the core (format,
// excluded rows, warnings, the matched points), or the reader's message when it was refused.
import { h, table, pagedTable, DENSE_POINTS, TABLE_ROWS } from './ui.js';
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
  // the points as columns (columns.js): the file's id and line, the matched curve, u, foot, normal
  const read = file.points.table('file'), ids = read.col('id'), lines = read.col('line'), curves = a.points.col('curve');
  const u = file.points.num('u'), foot = file.points.vec('foot').v, normal = file.points.vec('normal').v, dev = file.points.num('deviation');
  const row = (i) => [ids.at(i), { text: lines.at(i), num: true }, curves.at(i), { text: u[i].toFixed(5), num: true, value: u[i] },
    ...[0, 1, 2].map((j) => ({ text: foot[3 * i + j].toFixed(4), num: true, value: foot[3 * i + j] })),
    ...[0, 1, 2].map((j) => ({ text: normal[3 * i + j].toFixed(5), num: true, value: normal[3 * i + j] })),
    { text: (dev[i] * 1000).toFixed(2), num: true, value: dev[i] * 1000 }];
  const count = file.points.length;
  const caption = 'Matched points: nominal foot on the surface, outward normal, measured normal deviation (+ = material left, − = overcut)';
  if (count <= DENSE_POINTS) {
    root.append(table('points', caption, header, Array.from({ length: count }, (_, i) => row(i))));
    return;
  }
  // a scan's table a page at a time; the CSV has every point
  const csv = () => toCsv(header, Array.from({ length: count }, (_, i) => row(i).map((c) => (typeof c === 'object' ? c.value ?? c.text : c))));
  root.append(pagedTable('points', `${caption}; ${count} points, ${TABLE_ROWS} a page (the CSV has every point)`, header, count, row, csv));
}
