// A small SVG plotting module written for testpiece (no dependency): line/point charts with
// units on both axes, x-axis groups (e.g. the four measurement curves) with separators and labels,
// series toggled on and off, a hover readout, and export as SVG or PNG.

const NS = 'http://www.w3.org/2000/svg';
export const PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#8c564b',
  '#e377c2', '#17becf', '#7f7f7f', '#bcbd22', '#393b79', '#637939', '#843c39', '#7b4173'];

function el(name, attrs = {}, parent) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  if (parent) parent.appendChild(e);
  return e;
}

/** "Nice" tick values covering [lo, hi]. */
export function ticks(lo, hi, count = 6) {
  if (!(hi > lo)) { const d = Math.abs(lo) || 1; lo -= d; hi += d; }
  const raw = (hi - lo) / count;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => s >= raw) || 10 * mag;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return out;
}

/** A tick label: 4 significant digits, exponent outside [1e-3, 1e4). */
export function fmt(v) {
  const a = Math.abs(v);
  if (a === 0) return '0';
  if (a >= 1e4 || a < 1e-3) return v.toExponential(1);
  return String(Number(v.toPrecision(4)));
}

/** The name of the `i`-th x of `spec` (its `xNames`: a list, or a function of `i` for a scan's
 * 200,000 points), or undefined. */
export const xNameOf = (spec, i) => (typeof spec.xNames === 'function' ? spec.xNames(i) : spec.xNames?.[i]);

/**
 * Draws a chart into `container` (its content is replaced) and returns {svg, update}.
 * spec = {
 *   title, xLabel, yLabel,                 // labels carry units, e.g. 'defect (µm)'
 *   x: number[],                           // x positions (shared by all series)
 *   order?: number[],                      // the indices in order of x (densechart.js sorts without)
 *   xNames?: string[] | (i) => string,     // per-x name for the hover readout (e.g. point id): xNameOf
 *   groups?: [{label, from, to}],          // x ranges drawn as labelled bands with separators
 *   series: [{name, y: number[], color?, visible?, dashed?, points?}],
 *   highlight?: [{from, to, label, ids?}], // x ranges shaded (e.g. where the residual lies);
 *                                          // focusable, named by `label`, `ids` in data-ids
 *   markers?: [{x, label, short, id?}],    // vertical marks (e.g. axis reversals), focusable
 *   note?: string,                         // one line under the x label (legend in words)
 *   zeroLine?: true, width?, height?, yUnit?
 * }
 */
export function chart(container, spec) {
  // The note may have several lines ('\n'); room is made for the lines of the first note.
  const noteH = spec.note ? 14 * String(spec.note).split('\n').length + 2 : 0;
  const W = spec.width || 900, H = (spec.height || 340) + noteH;
  const m = { l: 64, r: 12, t: spec.title ? 28 : 10, b: (spec.groups ? 58 : 42) + noteH };
  container.textContent = '';
  const svg = el('svg', { xmlns: NS, viewBox: `0 0 ${W} ${H}`, width: '100%', role: 'img',
    'aria-label': spec.title || 'chart', class: 'chart', 'font-family': 'system-ui, sans-serif', 'font-size': 11 });
  container.appendChild(svg);
  el('rect', { x: 0, y: 0, width: W, height: H, fill: '#fff' }, svg);
  if (spec.title) el('text', { x: m.l, y: 18, 'font-size': 13, 'font-weight': 600 }, svg).textContent = spec.title;
  const plotG = el('g', {}, svg);
  const readout = el('text', { x: W - m.r, y: 18, 'text-anchor': 'end', 'font-size': 12, class: 'readout' }, svg);

  function draw() {
    plotG.textContent = '';
    const vis = spec.series.filter((s) => s.visible !== false);
    const xs = spec.x;
    const xlo = Math.min(...xs), xhi = Math.max(...xs);
    let ylo = Infinity, yhi = -Infinity;
    for (const s of vis) for (const v of s.y) if (Number.isFinite(v)) { ylo = Math.min(ylo, v); yhi = Math.max(yhi, v); }
    if (!Number.isFinite(ylo)) { ylo = -1; yhi = 1; }
    if (spec.zeroLine !== false) { ylo = Math.min(ylo, 0); yhi = Math.max(yhi, 0); }
    const pad = (yhi - ylo) * 0.05 || 1;
    ylo -= pad; yhi += pad;
    const X = (v) => m.l + ((v - xlo) / (xhi - xlo || 1)) * (W - m.l - m.r);
    const Y = (v) => H - m.b - ((v - ylo) / (yhi - ylo)) * (H - m.t - m.b);
    // highlighted ranges
    for (const h of spec.highlight || []) {
      const r = el('rect', { x: X(h.from) - 3, y: m.t, width: Math.max(6, X(h.to) - X(h.from) + 6), height: H - m.t - m.b,
        fill: '#ffd54f', 'fill-opacity': 0.45, class: 'highlight', tabindex: 0, role: 'img', 'aria-label': h.label || 'highlighted points' }, plotG);
      if (h.ids) r.setAttribute('data-ids', h.ids.join(' '));
      if (h.label) el('title', {}, r).textContent = h.label;
    }
    // y grid and ticks
    for (const t of ticks(ylo, yhi)) {
      el('line', { x1: m.l, x2: W - m.r, y1: Y(t), y2: Y(t), stroke: t === 0 ? '#888' : '#e5e7eb' }, plotG);
      el('text', { x: m.l - 6, y: Y(t) + 4, 'text-anchor': 'end' }, plotG).textContent = fmt(t);
    }
    // x groups with separators and labels, or plain x ticks
    if (spec.groups) {
      spec.groups.forEach((g, i) => {
        if (i > 0) {
          const xsep = (X(spec.groups[i - 1].to) + X(g.from)) / 2;
          el('line', { x1: xsep, x2: xsep, y1: m.t, y2: H - m.b + 18, stroke: '#555', 'stroke-dasharray': '4 3' }, plotG);
        }
        el('text', { x: (X(g.from) + X(g.to)) / 2, y: H - m.b + 30, 'text-anchor': 'middle', 'font-weight': 600 }, plotG).textContent = g.label;
        for (const t of [g.from, g.to]) el('text', { x: X(t), y: H - m.b + 14, 'text-anchor': 'middle', fill: '#555' }, plotG).textContent = fmt(t);
      });
    } else {
      for (const t of ticks(xlo, xhi)) el('text', { x: X(t), y: H - m.b + 14, 'text-anchor': 'middle' }, plotG).textContent = fmt(t);
    }
    el('rect', { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: 'none', stroke: '#999' }, plotG);
    if (spec.xLabel) el('text', { x: (m.l + W - m.r) / 2, y: H - 6 - noteH, 'text-anchor': 'middle' }, plotG).textContent = spec.xLabel;
    if (spec.note) {
      const t = el('text', { x: m.l, y: H - noteH + 8, fill: '#7a4b00', class: 'note' }, plotG);
      String(spec.note).split('\n').forEach((line, j) => { el('tspan', { x: m.l, dy: j ? 14 : 0 }, t).textContent = line; });
    }
    if (spec.yLabel) el('text', { x: 14, y: (m.t + H - m.b) / 2, 'text-anchor': 'middle', transform: `rotate(-90 14 ${(m.t + H - m.b) / 2})` }, plotG).textContent = spec.yLabel;
    // series: a polyline per group so that curves do not join across separators
    spec.series.forEach((s, k) => {
      if (s.visible === false) return;
      const color = s.color || PALETTE[k % PALETTE.length];
      const ranges = spec.groups ? spec.groups.map((g) => [g.from, g.to]) : [[xlo, xhi]];
      for (const [a, b] of ranges) {
        const pts = [];
        xs.forEach((x, i) => { if (x >= a && x <= b && Number.isFinite(s.y[i])) pts.push(`${X(x).toFixed(1)},${Y(s.y[i]).toFixed(1)}`); });
        if (!s.points) el('polyline', { points: pts.join(' '), fill: 'none', stroke: color, 'stroke-width': 1.6,
          'stroke-dasharray': s.dashed ? '5 3' : 'none', 'data-series': s.name }, plotG);
        else for (const p of pts) { const [cx, cy] = p.split(','); el('circle', { cx, cy, r: 2.4, fill: color, 'data-series': s.name }, plotG); }
      }
    });
    // vertical marks (drawn over the series, under the hover area; focusable for the keyboard)
    for (const mk of spec.markers || []) {
      const g = el('g', { class: 'marker', tabindex: 0, role: 'img', 'aria-label': mk.label }, plotG);
      if (mk.id !== undefined) g.setAttribute('data-id', mk.id);
      const xm = X(mk.x);
      el('line', { x1: xm, x2: xm, y1: m.t, y2: H - m.b, stroke: '#6a3d9a', 'stroke-width': 1.4, 'stroke-dasharray': '2 2' }, g);
      el('path', { d: `M${xm - 5},${m.t} L${xm + 5},${m.t} L${xm},${m.t + 8} Z`, fill: '#6a3d9a' }, g);
      if (mk.short) el('text', { x: xm + 3, y: H - m.b - 4, fill: '#6a3d9a', 'font-size': 10 }, g).textContent = mk.short;
      el('title', {}, g).textContent = mk.label;
    }
    // legend
    let lx = m.l + 4;
    const ly = m.t + 12;
    spec.series.forEach((s, k) => {
      if (s.visible === false) return;
      const color = s.color || PALETTE[k % PALETTE.length];
      el('rect', { x: lx, y: ly - 8, width: 10, height: 10, fill: color }, plotG);
      const t = el('text', { x: lx + 13, y: ly + 1 }, plotG);
      t.textContent = s.name;
      lx += 20 + 6.5 * s.name.length;
    });
    // hover readout: nearest x, values of visible series
    const hit = el('rect', { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, fill: 'transparent' }, plotG);
    const cursor = el('line', { y1: m.t, y2: H - m.b, stroke: '#333', 'stroke-width': 0.6, visibility: 'hidden' }, plotG);
    hit.addEventListener('mousemove', (ev) => {
      const r = svg.getBoundingClientRect();
      const px = ((ev.clientX - r.left) / r.width) * W;
      let best = 0;
      xs.forEach((x, i) => { if (Math.abs(X(x) - px) < Math.abs(X(xs[best]) - px)) best = i; });
      cursor.setAttribute('x1', X(xs[best])); cursor.setAttribute('x2', X(xs[best]));
      cursor.setAttribute('visibility', 'visible');
      const name = spec.xNames ? xNameOf(spec, best) : fmt(xs[best]);
      const vals = vis.slice(0, 4).map((s) => `${s.name} ${fmt(s.y[best])}`).join(' · ');
      readout.textContent = `${name}: ${vals}${vis.length > 4 ? ' …' : ''}${spec.yUnit ? ' ' + spec.yUnit : ''}`;
    });
    hit.addEventListener('mouseleave', () => { cursor.setAttribute('visibility', 'hidden'); readout.textContent = ''; });
  }
  draw();
  return { svg, update: (patch) => { Object.assign(spec, patch); draw(); }, spec };
}

/** The chart as a standalone SVG document (text). */
export function svgText(svg) {
  return '<?xml version="1.0" encoding="UTF-8"?>\n' + new XMLSerializer().serializeToString(svg);
}

/** The chart rendered to a PNG Blob at `scale` × its viewBox size. */
export function pngBlob(svg, scale = 2) {
  const [, , w, h] = svg.getAttribute('viewBox').split(' ').map(Number);
  const url = URL.createObjectURL(new Blob([svgText(svg)], { type: 'image/svg+xml' }));
  return new Promise((resolve, reject) => {
    const img = new Image();
    img.onload = () => {
      const c = document.createElement('canvas');
      c.width = w * scale; c.height = h * scale;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0, c.width, c.height);
      URL.revokeObjectURL(url);
      c.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png');
    };
    img.onerror = () => { URL.revokeObjectURL(url); reject(new Error('could not render the SVG')); };
    img.src = url;
  });
}
