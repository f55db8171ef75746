// The per-point chart of plot.js drawn on a <canvas>, for files of more than DENSE_POINTS points
// (a scan: 20,000 to 200,000): the same spec (x, groups, series, highlight, markers, labels,
// note), drawn by pixel columns: each series' minimum and maximum over the points in a column,
// joined as a vertical stroke (what thousands of points a pixel look like), and the points
// themselves once a zoom leaves fewer than one a column. Zoom: the wheel (about the cursor) or
// a drag (the box's x range); double-click or "Whole range" goes back. The cursor reads out the
// nearest point: its name (`xNames`, plot.js's xNameOf), and each visible series' value in `yUnit`.
import { ticks, fmt, PALETTE, xNameOf } from './plot.js';

const W = 900;

/** Draws `spec` (plot.js's) into `container`; returns
 * {canvas, update(patch), spec, png()}. */
export function denseChart(container, spec) {
  const noteH = spec.note ? 14 * String(spec.note).split('\n').length + 2 : 0;
  const H = (spec.height || 340) + noteH;
  const m = { l: 64, r: 12, t: spec.title ? 28 : 10, b: (spec.groups ? 58 : 42) + noteH };
  const PW = W - m.l - m.r, PH = H - m.t - m.b;
  container.textContent = '';
  const wrap = document.createElement('div');
  wrap.className = 'dense-chart';
  const canvas = document.createElement('canvas');
  canvas.width = W; canvas.height = H;
  canvas.className = 'chart';
  canvas.setAttribute('role', 'img');
  canvas.setAttribute('aria-label', `${spec.title || 'chart'} (${spec.x.length} points; wheel or drag to zoom, double-click for the whole range)`);
  const readout = document.createElement('div');
  readout.className = 'readout dense-readout';
  readout.setAttribute('aria-live', 'polite');
  const reset = document.createElement('button');
  reset.type = 'button'; reset.textContent = 'Whole range'; reset.className = 'dense-reset';
  wrap.append(reset, readout, canvas);
  container.appendChild(wrap);
  const g = canvas.getContext('2d');

  // the points in order of x, once
  const n = spec.x.length;
  const order = spec.order ? Int32Array.from(spec.order) : Int32Array.from({ length: n }, (_, i) => i).sort((a, b) => spec.x[a] - spec.x[b]);
  const xs = Float64Array.from(order, (i) => spec.x[i]);
  let lo = xs[0], hi = xs[n - 1];
  const full = [lo, hi];
  /** First index of `xs` at or above `v`. */
  const lower = (v) => { let a = 0, b = n; while (a < b) { const c = (a + b) >> 1; if (xs[c] < v) a = c + 1; else b = c; } return a; };

  function draw() {
    const span = hi - lo || 1;
    const X = (v) => m.l + ((v - lo) / span) * PW;
    const vis = spec.series.map((s, k) => ({ s, color: s.color || PALETTE[k % PALETTE.length] })).filter((v) => v.s.visible !== false);
    const a = lower(lo), b = Math.min(n, lower(hi + span * 1e-12) + 1);
    let ylo = Infinity, yhi = -Infinity;
    for (const { s } of vis) for (let j = a; j < b; j++) { const v = s.y[order[j]]; if (Number.isFinite(v)) { if (v < ylo) ylo = v; if (v > yhi) yhi = v; } }
    if (!Number.isFinite(ylo)) { ylo = -1; yhi = 1; }
    if (spec.zeroLine !== false) { ylo = Math.min(ylo, 0); yhi = Math.max(yhi, 0); }
    const pad = (yhi - ylo) * 0.05 || 1;
    ylo -= pad; yhi += pad;
    const Y = (v) => m.t + PH - ((v - ylo) / (yhi - ylo)) * PH;
    g.fillStyle = '#fff'; g.fillRect(0, 0, W, H);
    g.font = '11px system-ui, sans-serif';
    if (spec.title) { g.fillStyle = '#111'; g.font = '600 13px system-ui, sans-serif'; g.fillText(spec.title, m.l, 18); g.font = '11px system-ui, sans-serif'; }
    g.save();
    g.beginPath(); g.rect(m.l, m.t, PW, PH); g.clip();
    for (const hl of spec.highlight || []) {
      if (hl.to < lo || hl.from > hi) continue;
      g.fillStyle = 'rgba(255, 213, 79, 0.45)';
      g.fillRect(X(hl.from) - 3, m.t, Math.max(6, X(hl.to) - X(hl.from) + 6), PH);
    }
    for (const t of ticks(ylo, yhi)) { g.strokeStyle = t === 0 ? '#888' : '#e5e7eb'; g.beginPath(); g.moveTo(m.l, Y(t) + 0.5); g.lineTo(m.l + PW, Y(t) + 0.5); g.stroke(); }
    // the series: per pixel column min/max strokes, or the points when fewer than the columns
    const sparse = b - a <= PW;
    for (const { s, color } of vis) {
      g.strokeStyle = color; g.fillStyle = color; g.lineWidth = 1;
      if (sparse) {
        g.beginPath();
        let prev = null;
        for (let j = a; j < b; j++) {
          const i = order[j], v = s.y[i];
          if (!Number.isFinite(v)) { prev = null; continue; }
          const gx = X(xs[j]), gy = Y(v);
          if (s.points) { g.fillRect(gx - 1.5, gy - 1.5, 3, 3); continue; }
          // no line across a gap between groups (their x positions are 2 apart or more)
          if (prev !== null && xs[j] - prev <= 1) g.lineTo(gx, gy); else g.moveTo(gx, gy);
          prev = xs[j];
        }
        if (!s.points) g.stroke();
      } else {
        const cmin = new Float64Array(PW).fill(Infinity), cmax = new Float64Array(PW).fill(-Infinity);
        for (let j = a; j < b; j++) {
          const v = s.y[order[j]];
          if (!Number.isFinite(v)) continue;
          const c = Math.min(PW - 1, Math.max(0, Math.floor(((xs[j] - lo) / span) * PW)));
          if (v < cmin[c]) cmin[c] = v;
          if (v > cmax[c]) cmax[c] = v;
        }
        g.globalAlpha = s.points ? 0.55 : 0.85;
        for (let c = 0; c < PW; c++) {
          if (cmin[c] === Infinity) continue;
          const y0 = Y(cmax[c]), y1 = Y(cmin[c]);
          g.fillRect(m.l + c, y0 - 0.5, 1, Math.max(1, y1 - y0 + 1));
        }
        g.globalAlpha = 1;
      }
    }
    for (const mk of spec.markers || []) {
      if (mk.x < lo || mk.x > hi) continue;
      const xm = X(mk.x);
      g.strokeStyle = '#6a3d9a'; g.lineWidth = 1.4; g.setLineDash([2, 2]);
      g.beginPath(); g.moveTo(xm, m.t); g.lineTo(xm, m.t + PH); g.stroke(); g.setLineDash([]);
      g.fillStyle = '#6a3d9a'; g.beginPath(); g.moveTo(xm - 5, m.t); g.lineTo(xm + 5, m.t); g.lineTo(xm, m.t + 8); g.fill();
      if (mk.short) g.fillText(mk.short, xm + 3, m.t + PH - 4);
    }
    g.restore();
    g.strokeStyle = '#999'; g.lineWidth = 1; g.strokeRect(m.l + 0.5, m.t + 0.5, PW, PH);
    g.fillStyle = '#111'; g.textAlign = 'right';
    for (const t of ticks(ylo, yhi)) g.fillText(fmt(t), m.l - 6, Y(t) + 4);
    g.textAlign = 'center';
    if (spec.groups) {
      // separators; a group's label where its width leaves room for it
      spec.groups.forEach((gr, i) => {
        if (gr.to < lo || gr.from > hi) return;
        if (i > 0 && gr.from >= lo) {
          const xsep = X((spec.groups[i - 1].to + gr.from) / 2);
          g.strokeStyle = '#555'; g.setLineDash([4, 3]); g.beginPath(); g.moveTo(xsep, m.t); g.lineTo(xsep, m.t + PH + 18); g.stroke(); g.setLineDash([]);
        }
        const x0 = X(Math.max(lo, gr.from)), x1 = X(Math.min(hi, gr.to));
        if (x1 - x0 > g.measureText(gr.label).width + 4) { g.fillStyle = '#111'; g.fillText(gr.label, (x0 + x1) / 2, m.t + PH + 30); }
      });
    }
    for (const t of ticks(lo, hi)) { g.fillStyle = '#555'; g.fillText(fmt(t), X(t), m.t + PH + 14); }
    g.fillStyle = '#111';
    if (spec.xLabel) g.fillText(spec.xLabel + (lo > full[0] || hi < full[1] ? ' (zoomed)' : ''), m.l + PW / 2, H - 6 - noteH);
    g.textAlign = 'left';
    if (spec.note) { g.fillStyle = '#7a4b00'; String(spec.note).split('\n').forEach((line, j) => g.fillText(line, m.l, H - noteH + 8 + 14 * j)); }
    if (spec.yLabel) { g.save(); g.translate(14, m.t + PH / 2); g.rotate(-Math.PI / 2); g.textAlign = 'center'; g.fillStyle = '#111'; g.fillText(spec.yLabel, 0, 0); g.restore(); }
    // legend
    let lx = m.l + 4;
    spec.series.forEach((s, k) => {
      if (s.visible === false) return;
      g.fillStyle = s.color || PALETTE[k % PALETTE.length]; g.fillRect(lx, m.t + 4, 10, 10);
      g.fillStyle = '#111'; g.fillText(s.name, lx + 13, m.t + 13);
      lx += 20 + g.measureText(s.name).width;
    });
    wrap.dataset.from = String(lo); wrap.dataset.to = String(hi); wrap.dataset.drawn = String(b - a);
  }

  const toX = (ev) => { const r = canvas.getBoundingClientRect(); return ((ev.clientX - r.left) / r.width) * W; };
  const valueAt = (px) => lo + ((px - m.l) / PW) * (hi - lo);
  function zoomTo(a, b) {
    const minSpan = 4; // no closer than 4 positions across the plot
    if (b - a < minSpan) { const c = (a + b) / 2; a = c - minSpan / 2; b = c + minSpan / 2; }
    lo = Math.max(full[0], a); hi = Math.min(full[1], b);
    draw();
  }
  canvas.addEventListener('wheel', (ev) => {
    ev.preventDefault();
    const c = valueAt(toX(ev)), k = ev.deltaY > 0 ? 1.25 : 0.8;
    zoomTo(c - (c - lo) * k, c + (hi - c) * k);
  }, { passive: false });
  let dragFrom = null;
  canvas.addEventListener('mousedown', (ev) => { dragFrom = toX(ev); });
  canvas.addEventListener('mouseup', (ev) => {
    const to = toX(ev);
    if (dragFrom !== null && Math.abs(to - dragFrom) > 4) zoomTo(valueAt(Math.min(dragFrom, to)), valueAt(Math.max(dragFrom, to)));
    dragFrom = null;
  });
  const whole = () => { lo = full[0]; hi = full[1]; draw(); };
  canvas.addEventListener('dblclick', whole);
  reset.addEventListener('click', whole);
  canvas.addEventListener('mousemove', (ev) => {
    const px = toX(ev);
    if (px < m.l || px > m.l + PW) { readout.textContent = ''; return; }
    const v = valueAt(px);
    let j = Math.min(n - 1, lower(v));
    if (j > 0 && Math.abs(xs[j - 1] - v) < Math.abs(xs[j] - v)) j--;
    const i = order[j];
    const vals = spec.series.filter((s) => s.visible !== false).map((s) => `${s.name} ${fmt(s.y[i])}`).join(' · ');
    readout.textContent = `${spec.xNames ? xNameOf(spec, i) : fmt(xs[j])}: ${vals}${spec.yUnit ? ' ' + spec.yUnit : ''}`;
    wrap.dataset.hover = String(i);
  });
  canvas.addEventListener('mouseleave', () => { readout.textContent = ''; });
  draw();
  return {
    canvas, spec,
    update(patch) { Object.assign(spec, patch); draw(); },
    png: () => new Promise((resolve, reject) => canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png')),
  };
}
