// The residual as a colour map over each developed surface (issue 31 item 3): for surface A and
// surface B, one image whose horizontal axis is the point's position along the tool path and whose
// vertical axis is its height, each measured point a cell coloured by its residual.
// - Horizontal: the core's `path_position` (src/analysis/report.rs): the tool-tip path length in
//   mm from the start of A's pass to the pose that cut the point, the `s` at which the diagnosis
//   places the axis reversals; when the core sends none, the surface parameter u (unitless).
// - Vertical: the height z (mm) of the matched point on the nominal surface (`points`' `z`).
// - Rows: the core's group of each point (`identification.points`' `curve`: its scan line for a
//   scan, its measurement curve for a few discrete points), at the mean height of its points; a
//   point's cell reaches half-way to the next row and to its neighbours along its row, so a scan
//   tiles the surface and the 100 built-in points are drawn as 4 rows of cells.
// - Colour: the residual of the final answer (µm), a diverging scale symmetric about 0 (blue:
//   material left, +; red: overcut, −, as the plan view), to the 99.5th percentile of |r| (points
//   beyond take the end colour; the colour bar says so).
// The cells are binned into the canvas's pixels (a pixel shared by several points shows their
// mean), so 200,000 points cost a few passes over typed arrays. The axis reversals are drawn as
// vertical lines (all faint; the ones the core marks bold), the highlighted where-group
// (where.js) as a yellow tint with an outline; hovering reads out the point under the cursor.
import { h, later } from './ui.js';
import { ticks, fmt } from './plot.js';
import { whereOf, onWhereChange, pointsOf } from './where.js';

const NS = 'http://www.w3.org/2000/svg';
const W = 900, H = 250;
const M = { l: 58, r: 16, t: 30, b: 44 };
const PW = W - M.l - M.r, PH = H - M.t - M.b;
const EMPTY = [224, 224, 224]; // a pixel holding no point
const QUANTILE = 0.995;        // the colour scale's end, as a quantile of |r|

// Diverging scale, red (−) through near-white (0) to blue (+) (ColorBrewer RdBu, 5 classes).
const ANCHORS = [[178, 24, 43], [239, 138, 98], [247, 247, 247], [103, 169, 207], [33, 102, 172]];
const LUT = (() => {
  const n = 256, out = new Uint8ClampedArray(n * 3);
  for (let k = 0; k < n; k++) {
    const t = (k / (n - 1)) * (ANCHORS.length - 1), i = Math.min(ANCHORS.length - 2, Math.floor(t)), f = t - i;
    for (let c = 0; c < 3; c++) out[k * 3 + c] = Math.round(ANCHORS[i][c] * (1 - f) + ANCHORS[i + 1][c] * f);
  }
  return out;
})();
/** The LUT index of a residual `r` on the scale ±`R` (same unit). */
const lutIndex = (r, R) => Math.max(0, Math.min(255, Math.round(((r / R + 1) / 2) * 255)));

/** The points of one surface, with their cells, as columns (a surface of a dense scan holds
 * 100,000 points: no object per cell): {rows: [{label, idx, z}], cells: {n, i (the point's
 * index), s, z, r (µm), s0, s1, z0, z1}}, row after row (by height), along each row by s. */
function cellsOf(a, id, surface, xOf) {
  const rows = new Map();
  const surfaces = a.points.col('surface'), zs = a.points.num('z'), labels = id.points.col('curve'), res = id.points.num('residual');
  for (let i = 0; i < zs.length; i++) {
    if (surfaces.at(i) !== surface) continue;
    const label = labels.at(i);
    if (!rows.has(label)) rows.set(label, []);
    rows.get(label).push(i);
  }
  const list = [...rows.entries()].map(([label, idx]) => ({ label, idx, z: idx.reduce((t, i) => t + zs[i], 0) / idx.length }))
    .sort((p, q) => p.z - q.z);
  const n = list.reduce((t, row) => t + row.idx.length, 0);
  const f64 = () => new Float64Array(n);
  const c = { n, i: new Int32Array(n), s: f64(), z: f64(), r: f64(), s0: f64(), s1: f64(), z0: f64(), z1: f64() };
  let k = 0;
  list.forEach((row, j) => {
    const below = j > 0 ? (row.z - list[j - 1].z) / 2 : null, above = j < list.length - 1 ? (list[j + 1].z - row.z) / 2 : null;
    const half = (below ?? above ?? 1);
    const z0 = row.z - (below ?? half), z1 = row.z + (above ?? half);
    const sv = row.idx.map(xOf);
    const order = sv.map((_, m) => m).sort((p, q) => sv[p] - sv[q]);
    const ps = order.map((m) => sv[m]);
    // (points at one path position, a ruling's heights within a height band, leave no gap)
    const gaps = ps.slice(1).map((v, m) => v - ps[m]).filter((g) => g > 1e-9).sort((p, q) => p - q);
    const typical = gaps.length ? gaps[gaps.length >> 1] / 2 : 1;
    order.forEach((m, q) => {
      const i = row.idx[m], sq = ps[q];
      const left = q > 0 ? (sq - ps[q - 1]) / 2 : null, right = q < ps.length - 1 ? (ps[q + 1] - sq) / 2 : null;
      // a hole in a line stays a hole: no cell reaches further than 1.5 typical half-gaps
      c.i[k] = i; c.s[k] = sq; c.z[k] = zs[i]; c.r[k] = res[i] * 1000;
      c.s0[k] = sq - Math.min(left ?? right ?? typical, 1.5 * typical);
      c.s1[k] = sq + Math.min(right ?? left ?? typical, 1.5 * typical);
      c.z0[k] = z0; c.z1[k] = z1;
      k++;
    });
  });
  return { rows: list, cells: c };
}

/** The end of the colour scale (µm): the QUANTILE of |r| over every point. */
function scaleOf(id) {
  const v = id.points.num('residual').map((r) => Math.abs(r * 1000)).sort();
  return Math.max(1e-6, v[Math.min(v.length - 1, Math.floor(QUANTILE * (v.length - 1)))] || 0);
}

function el(name, attrs, parent) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  if (parent) parent.appendChild(e);
  return e;
}

/** The map of one surface: a canvas of binned cells under an SVG of axes, reversals and read-out. */
function surfaceMap(a, id, surface, R, xAxis) {
  const { rows, cells } = cellsOf(a, id, surface, xAxis.of);
  if (!cells.n) return null;
  let s0 = Infinity, s1 = -Infinity, z0 = Infinity, z1 = -Infinity; // (no spread: 100,000 arguments overflow)
  for (let k = 0; k < cells.n; k++) { s0 = Math.min(s0, cells.s0[k]); s1 = Math.max(s1, cells.s1[k]); z0 = Math.min(z0, cells.z0[k]); z1 = Math.max(z1, cells.z1[k]); }
  const X = (s) => M.l + ((s - s0) / (s1 - s0 || 1)) * PW, Y = (z) => M.t + PH - ((z - z0) / (z1 - z0 || 1)) * PH;
  // bin: per pixel of the plot area, the sum and count of the residuals of the cells over it
  const sum = new Float64Array(PW * PH), count = new Uint32Array(PW * PH), owner = new Int32Array(PW * PH).fill(-1);
  // each cell's pixels: px0, px1, py0, py1 (4 a cell; 100,000 cells a surface for a dense scan)
  const px = new Int32Array(4 * cells.n);
  const cellPx = (k) => px.subarray(4 * k, 4 * k + 4);
  for (let k = 0; k < cells.n; k++) {
    const px0 = Math.max(0, Math.min(PW - 1, Math.floor(X(cells.s0[k]) - M.l))), px1 = Math.max(px0 + 1, Math.min(PW, Math.round(X(cells.s1[k]) - M.l)));
    const py0 = Math.max(0, Math.min(PH - 1, Math.floor(Y(cells.z1[k]) - M.t))), py1 = Math.max(py0 + 1, Math.min(PH, Math.round(Y(cells.z0[k]) - M.t)));
    px[4 * k] = px0; px[4 * k + 1] = px1; px[4 * k + 2] = py0; px[4 * k + 3] = py1;
    const r = cells.r[k];
    for (let y = py0; y < py1; y++) for (let x = px0; x < px1; x++) { const p = y * PW + x; sum[p] += r; count[p]++; owner[p] = k; }
  }
  const canvas = h('canvas', { width: PW, height: PH, class: 'surface-map-cells', 'aria-hidden': 'true' });
  const g = canvas.getContext('2d');
  const img = g.createImageData(PW, PH), data = img.data;
  let filled = 0;
  for (let p = 0; p < PW * PH; p++) {
    const o = p * 4;
    if (count[p]) {
      const k = lutIndex(sum[p] / count[p], R) * 3;
      data[o] = LUT[k]; data[o + 1] = LUT[k + 1]; data[o + 2] = LUT[k + 2];
      filled++;
    } else { data[o] = EMPTY[0]; data[o + 1] = EMPTY[1]; data[o + 2] = EMPTY[2]; }
    data[o + 3] = 255;
  }
  g.putImageData(img, 0, 0);
  canvas.style.left = `${(M.l / W) * 100}%`; canvas.style.top = `${(M.t / H) * 100}%`;
  canvas.style.width = `${(PW / W) * 100}%`; canvas.style.height = `${(PH / H) * 100}%`;

  // the where highlight: the cells of the chosen group tinted, on a canvas of its own
  const shade = h('canvas', { width: PW, height: PH, class: 'surface-map-shade', 'aria-hidden': 'true' });
  Object.assign(shade.style, { left: canvas.style.left, top: canvas.style.top, width: canvas.style.width, height: canvas.style.height });
  const cellOf = new Int32Array(id.points.length).fill(-1);
  for (let k = 0; k < cells.n; k++) cellOf[cells.i[k]] = k;

  const svg = el('svg', { viewBox: `0 0 ${W} ${H}`, class: 'surface-map-axes', role: 'img', xmlns: NS, 'font-family': 'system-ui, sans-serif', 'font-size': 11,
    'aria-label': `surface ${surface}: residual of ${cells.n} points on ${rows.length} rows, colour from −${R.toFixed(1)} to +${R.toFixed(1)} µm` });
  el('text', { x: M.l, y: 18, 'font-weight': 600, 'font-size': 13 }, svg).textContent =
    `Surface ${surface}: ${cells.n} points on ${rows.length} ${rows.length === 1 ? 'row' : 'rows'}`;
  for (const t of ticks(s0, s1, 8)) {
    el('line', { x1: X(t), x2: X(t), y1: M.t + PH, y2: M.t + PH + 4, stroke: '#555' }, svg);
    el('text', { x: X(t), y: M.t + PH + 16, 'text-anchor': 'middle' }, svg).textContent = fmt(t);
  }
  for (const t of ticks(z0, z1, 4)) {
    el('line', { x1: M.l - 4, x2: M.l, y1: Y(t), y2: Y(t), stroke: '#555' }, svg);
    el('text', { x: M.l - 7, y: Y(t) + 4, 'text-anchor': 'end' }, svg).textContent = fmt(t);
  }
  el('rect', { x: M.l, y: M.t, width: PW, height: PH, fill: 'none', stroke: '#999' }, svg);
  el('text', { x: M.l + PW / 2, y: H - 8, 'text-anchor': 'middle' }, svg).textContent = xAxis.label;
  el('text', { x: 14, y: M.t + PH / 2, 'text-anchor': 'middle', transform: `rotate(-90 14 ${M.t + PH / 2})` }, svg).textContent = 'height z (mm)';
  const revLayer = el('g', { class: 'reversals' }, svg);
  const cursor = el('rect', { class: 'map-cursor', fill: 'none', stroke: '#111', 'stroke-width': 1.2, visibility: 'hidden' }, svg);
  const readout = el('text', { x: W - M.r, y: 18, 'text-anchor': 'end', 'font-size': 12, class: 'readout' }, svg);

  function drawWhere() {
    const w = whereOf(a);
    // the chosen group: tint and outline of the pixels of its cells
    const sg = shade.getContext('2d');
    sg.clearRect(0, 0, PW, PH);
    const mask = new Uint8Array(PW * PH);
    let shaded = 0;
    if (w && w.chosen) {
      for (const i of pointsOf(a, w.chosen.ids)) {
        const k = cellOf[i];
        if (k < 0) continue;
        shaded++;
        for (let y = px[4 * k + 2]; y < px[4 * k + 3]; y++) mask.fill(1, y * PW + px[4 * k], y * PW + px[4 * k + 1]);
      }
      const im = sg.createImageData(PW, PH), data = im.data;
      for (let y = 0; y < PH; y++) {
        for (let x = 0; x < PW; x++) {
          const p = y * PW + x;
          if (!mask[p]) continue;
          const edge = x === 0 || y === 0 || x === PW - 1 || y === PH - 1 || !mask[p - 1] || !mask[p + 1] || !mask[p - PW] || !mask[p + PW];
          const o = p * 4;
          if (edge) { data[o] = 184; data[o + 1] = 134; data[o + 2] = 11; data[o + 3] = 255; } else { data[o] = 255; data[o + 1] = 213; data[o + 2] = 79; data[o + 3] = 90; }
        }
      }
      sg.putImageData(im, 0, 0);
    }
    wrap.dataset.shaded = String(shaded);
    // the axis reversals inside this surface's range: all faint, the marked ones bold
    revLayer.textContent = '';
    if (!w || !xAxis.isPath) return;
    const marked = new Set(w.marked);
    let drawn = 0;
    for (const e of w.reversals) {
      if (e.s < s0 || e.s > s1) continue;
      drawn++;
      const x = X(e.s), on = marked.has(e);
      const g2 = el('g', { class: on ? 'reversal marked' : 'reversal', 'data-axis': e.axis, 'data-s': e.s }, revLayer);
      el('line', { x1: x, x2: x, y1: M.t, y2: M.t + PH, stroke: '#6a3d9a', 'stroke-width': on ? 1.6 : 0.8, 'stroke-opacity': on ? 1 : 0.45, 'stroke-dasharray': on ? '3 2' : 'none' }, g2);
      if (on) {
        el('path', { d: `M${x - 5},${M.t} L${x + 5},${M.t} L${x},${M.t + 8} Z`, fill: '#6a3d9a' }, g2);
        el('text', { x: x + 3, y: M.t + PH - 4, fill: '#6a3d9a', 'font-size': 10 }, g2).textContent = e.axis;
      }
      el('title', {}, g2).textContent = `${e.axis}-axis reversal at ${e.s.toFixed(1)} mm of tool path${on ? ' (marked)' : ''}`;
    }
    wrap.dataset.reversals = String(drawn);
  }

  const ids = id.points.col('id'), labels = id.points.col('curve');
  const wrap = h('div', { class: 'surface-map', 'data-surface': surface, 'data-points': cells.n, 'data-rows': rows.length, 'data-filled': filled },
    canvas, shade, svg);
  wrap.addEventListener('mousemove', (ev) => {
    const r = svg.getBoundingClientRect();
    const px = Math.floor(((ev.clientX - r.left) / r.width) * W - M.l), py = Math.floor(((ev.clientY - r.top) / r.height) * H - M.t);
    const k = px >= 0 && py >= 0 && px < PW && py < PH ? owner[py * PW + px] : -1;
    if (k < 0) { readout.textContent = ''; cursor.setAttribute('visibility', 'hidden'); return; }
    const c = { s: cells.s[k], z: cells.z[k], r: cells.r[k] }, p = { id: ids.at(cells.i[k]), curve: labels.at(cells.i[k]) }, n = count[py * PW + px];
    const [cx0, cx1, cy0, cy1] = cellPx(k);
    cursor.setAttribute('x', M.l + cx0); cursor.setAttribute('y', M.t + cy0);
    cursor.setAttribute('width', cx1 - cx0); cursor.setAttribute('height', cy1 - cy0); cursor.setAttribute('visibility', 'visible');
    readout.textContent = `point ${p.id} (${p.curve}): ${xAxis.short} ${c.s.toFixed(xAxis.isPath ? 1 : 4)}${xAxis.isPath ? ' mm' : ''}, z ${c.z.toFixed(2)} mm, residual ${c.r.toFixed(2)} µm` +
      (n > 1 ? ` (this pixel: ${n} points, mean ${(sum[py * PW + px] / n).toFixed(2)} µm)` : '');
    wrap.dataset.hover = String(p.id);
    wrap.dataset.hoverResidual = String(c.r);
  });
  wrap.addEventListener('mouseleave', () => { readout.textContent = ''; cursor.setAttribute('visibility', 'hidden'); });
  drawWhere();
  onWhereChange(() => wrap.isConnected, drawWhere);
  return wrap;
}

/** The colour bar of the maps (µm), symmetric about 0. */
function colourBar(R) {
  const BW = 900, BH = 58, x0 = 58, x1 = 600;
  const canvas = h('canvas', { width: 256, height: 1, class: 'colour-bar-ramp', 'aria-hidden': 'true' });
  const g = canvas.getContext('2d');
  const img = g.createImageData(256, 1);
  for (let k = 0; k < 256; k++) { img.data.set([LUT[k * 3], LUT[k * 3 + 1], LUT[k * 3 + 2], 255], k * 4); }
  g.putImageData(img, 0, 0);
  Object.assign(canvas.style, { left: `${(x0 / BW) * 100}%`, top: `${(6 / BH) * 100}%`, width: `${((x1 - x0) / BW) * 100}%`, height: `${(14 / BH) * 100}%` });
  const svg = el('svg', { viewBox: `0 0 ${BW} ${BH}`, xmlns: NS, 'font-family': 'system-ui, sans-serif', 'font-size': 11, role: 'img',
    'aria-label': `colour bar: residual from −${R.toFixed(2)} µm (red) to +${R.toFixed(2)} µm (blue)` });
  el('rect', { x: x0, y: 6, width: x1 - x0, height: 14, fill: 'none', stroke: '#999' }, svg);
  for (const t of ticks(-R, R, 6)) {
    if (Math.abs(t) > R * (1 + 1e-9)) continue;
    const x = x0 + ((t + R) / (2 * R)) * (x1 - x0);
    el('line', { x1: x, x2: x, y1: 20, y2: 24, stroke: '#555' }, svg);
    el('text', { x, y: 35, 'text-anchor': 'middle' }, svg).textContent = fmt(t);
  }
  el('text', { x: x1 + 10, y: 17 }, svg).textContent = 'residual (µm)';
  el('text', { x: x0, y: 52, fill: '#555' }, svg).textContent =
    `Blue: material left (+), red: overcut (−); ends ±${R.toFixed(2)} µm (99.5 % of the points' |r| within; beyond: the end colour); grey: no point.`;
  return h('div', { class: 'surface-map colour-bar', 'data-range-um': R }, canvas, svg);
}

/** The maps of both surfaces with their colour bar, of the residual of `id` (the final answer's
 * identification, or the baseline's), or a sentence when there are no points. */
export function surfaceMaps(a, id = a.identification, what = 'the final answer') {
  if (!a || !a.points.length) return h('p', {}, 'No points to map.');
  const path = a.path_position, u = a.points.num('u');
  const xAxis = path && path.length === a.points.length
    ? { of: (i) => path[i], isPath: true, short: 's', label: 'tool-tip path position s (mm from the start of surface A\'s pass; the reversals\' position)' }
    : { of: (i) => u[i], isPath: false, short: 'u', label: 'surface parameter u (unitless; no tool-path position from the core)' };
  const R = scaleOf(id);
  // each surface in a task of its own (ui.js later): 100,000 points a surface for a dense scan
  const maps = ['A', 'B'].map((s) => later(() => surfaceMap(a, id, s, R, xAxis) ?? h('span')));
  return h('div', { class: 'surface-maps', 'data-chart': 'surface-map' },
    h('p', { class: 'where-legend' }, `Each cell is a measured point on its row (a scan line, or a measurement curve), coloured by the residual of ${what}; `,
      'purple lines: the axis reversals of the tool path (bold, ▼: the marked ones); yellow with an outline: the highlighted where-group. Hover for a point\'s values.'),
    ...maps, colourBar(R));
}
