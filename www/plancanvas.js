// The plan view of where.js drawn on a <canvas>, for files of more than DENSE_POINTS points: the
// same picture (the measured lines, one residual arrow per point along its normal, the outliers
// ringed, the highlighted where-group ringed, the marked reversals), with one path per colour
// instead of an element per point, and a cursor that reads out the nearest point. A scan puts
// thousands of points on a pixel of the plan: one arrow is drawn per pixel of the points' feet,
// the one of the largest |residual| there (the others would lie under it), and a line is drawn
// through one point per pixel it passes. where.js
// computes what is drawn (`plan`, from the analysis) and what the where choice adds (`overlay()`);
// this file only draws.

/**
 * `plan` = {W, H, pad, title, legend, X, Y, xs, ys (mm), tx, ty (mm, the arrows' ends), res (mm)
 * (all Float64Arrays, one value per point), idOf(i) (point i's id), lines: [[point index]], outliers: [{i, label}]}; `overlay()` = {rings:
 * [point index], marks: [{i, short, label}], note}. Returns {el, redraw} (redraw: the overlay
 * again).
 */
export function planCanvas(plan, overlay) {
  const { W, H, pad, X, Y, xs, ys, tx, ty, res } = plan;
  const canvas = document.createElement('canvas');
  canvas.width = W; canvas.height = H;
  canvas.className = 'chart';
  canvas.setAttribute('role', 'img');
  canvas.setAttribute('aria-label', `${plan.title} (${xs.length} points)`);
  const readout = document.createElement('div');
  readout.className = 'readout dense-readout';
  const g = canvas.getContext('2d');
  // per pixel of the feet, the point of the largest |residual| (-1: none)
  const top = new Int32Array(W * H).fill(-1);
  for (let i = 0; i < xs.length; i++) {
    const px = Math.round(X(xs[i])), py = Math.round(Y(ys[i]));
    if (px < 0 || py < 0 || px >= W || py >= H) continue;
    const k = py * W + px;
    if (top[k] < 0 || Math.abs(res[i]) > Math.abs(res[top[k]])) top[k] = i;
  }
  const arrows = top.filter((i) => i >= 0);
  function draw() {
    g.fillStyle = '#fff'; g.fillRect(0, 0, W, H);
    g.fillStyle = '#111'; g.font = '600 13px system-ui, sans-serif'; g.fillText(plan.title, pad, 18);
    g.font = '11px system-ui, sans-serif';
    g.strokeStyle = '#bbb'; g.lineWidth = 1;
    g.beginPath();
    for (const run of plan.lines) {
      let px = NaN, py = NaN;
      run.forEach((i, j) => {
        const x = X(xs[i]), y = Y(ys[i]);
        if (j && j < run.length - 1 && Math.round(x) === px && Math.round(y) === py) return;
        if (j) g.lineTo(x, y); else g.moveTo(x, y);
        px = Math.round(x); py = Math.round(y);
      });
    }
    g.stroke();
    for (const [sign, color] of [[1, '#1f77b4'], [-1, '#d62728']]) {
      g.strokeStyle = color; g.lineWidth = 1.2;
      g.beginPath();
      for (const i of arrows) {
        if ((res[i] >= 0 ? 1 : -1) !== sign) continue;
        g.moveTo(X(xs[i]), Y(ys[i])); g.lineTo(X(tx[i]), Y(ty[i]));
      }
      g.stroke();
    }
    g.strokeStyle = '#d62728'; g.lineWidth = 2.5; g.setLineDash([3, 2]);
    for (const o of plan.outliers) { g.beginPath(); g.arc(X(xs[o.i]), Y(ys[o.i]), 9, 0, 2 * Math.PI); g.stroke(); }
    g.setLineDash([]);
    const ov = overlay();
    g.fillStyle = 'rgba(255, 213, 79, 0.5)'; g.strokeStyle = '#b8860b'; g.lineWidth = 1.5;
    // one ring per pixel, in one path (a where-group of a scan can hold tens of thousands of points)
    const ringed = new Uint8Array(W * H);
    g.beginPath();
    for (const i of ov.rings) {
      const x = X(xs[i]), y = Y(ys[i]), k = Math.round(y) * W + Math.round(x);
      if (ringed[k]) continue;
      ringed[k] = 1;
      g.moveTo(x + 7, y); g.arc(x, y, 7, 0, 2 * Math.PI);
    }
    g.fill(); g.stroke();
    g.fillStyle = '#6a3d9a';
    for (const k of ov.marks) {
      const cx = X(xs[k.i]), cy = Y(ys[k.i]);
      g.beginPath(); g.moveTo(cx - 6, cy - 15); g.lineTo(cx + 6, cy - 15); g.lineTo(cx, cy - 5); g.fill();
      g.font = '600 10px system-ui, sans-serif'; g.fillText(k.short, cx + 7, cy - 8); g.font = '11px system-ui, sans-serif';
    }
    g.fillStyle = '#7a4b00';
    String(ov.note).split('\n').forEach((line, j) => g.fillText(line, pad, H - 52 + 14 * j));
    g.fillStyle = '#555'; g.textAlign = 'right'; g.fillText(plan.legend, W - pad, H - 8); g.textAlign = 'left';
    canvas.dataset.rings = String(ov.rings.length);
    canvas.dataset.marks = String(ov.marks.length);
    canvas.dataset.arrows = String(arrows.length);
  }
  canvas.addEventListener('mousemove', (ev) => {
    const r = canvas.getBoundingClientRect();
    const px = ((ev.clientX - r.left) / r.width) * W, py = ((ev.clientY - r.top) / r.height) * H;
    let best = -1, bd = 100; // within 10 px
    for (let i = 0; i < xs.length; i++) { const d = (X(xs[i]) - px) ** 2 + (Y(ys[i]) - py) ** 2; if (d < bd) { bd = d; best = i; } }
    readout.textContent = best < 0 ? '' : `point ${plan.idOf(best)}: x ${xs[best].toFixed(2)} mm, y ${ys[best].toFixed(2)} mm, residual ${(res[best] * 1000).toFixed(2)} µm`;
  });
  canvas.addEventListener('mouseleave', () => { readout.textContent = ''; });
  draw();
  const el = document.createElement('div');
  el.append(readout, canvas);
  return { el, canvas, redraw: draw };
}
