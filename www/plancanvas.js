// The plan view of where.js drawn on a <canvas>, for files of more than DENSE_POINTS points: the
// same picture (the measured lines, one residual arrow per point along its normal, the outliers
// ringed, the highlighted where-group ringed, the marked reversals), with one path per colour
// instead of an element per point, and a cursor that reads out the nearest point. where.js
// computes what is drawn (`plan`, from the analysis) and what the where choice adds (`overlay()`);
// this file only draws.

/**
 * `plan` = {W, H, pad, title, legend, X, Y, xs, ys (mm), tips: [x, y] per point (mm, the arrow's
 * end), res (mm), ids, lines: [[point index]], outliers: [{i, label}]}; `overlay()` = {rings:
 * [point index], marks: [{i, short, label}], note}. Returns {el, redraw} (redraw: the overlay
 * again).
 */
export function planCanvas(plan, overlay) {
  const { W, H, pad, X, Y, xs, ys, tips, res } = plan;
  const canvas = document.createElement('canvas');
  canvas.width = W; canvas.height = H;
  canvas.className = 'chart';
  canvas.setAttribute('role', 'img');
  canvas.setAttribute('aria-label', `${plan.title} (${xs.length} points)`);
  const readout = document.createElement('div');
  readout.className = 'readout dense-readout';
  const g = canvas.getContext('2d');
  function draw() {
    g.fillStyle = '#fff'; g.fillRect(0, 0, W, H);
    g.fillStyle = '#111'; g.font = '600 13px system-ui, sans-serif'; g.fillText(plan.title, pad, 18);
    g.font = '11px system-ui, sans-serif';
    g.strokeStyle = '#bbb'; g.lineWidth = 1;
    g.beginPath();
    for (const run of plan.lines) run.forEach((i, j) => (j ? g.lineTo(X(xs[i]), Y(ys[i])) : g.moveTo(X(xs[i]), Y(ys[i]))));
    g.stroke();
    for (const [sign, color] of [[1, '#1f77b4'], [-1, '#d62728']]) {
      g.strokeStyle = color; g.lineWidth = 1.2;
      g.beginPath();
      for (let i = 0; i < xs.length; i++) {
        if ((res[i] >= 0 ? 1 : -1) !== sign) continue;
        g.moveTo(X(xs[i]), Y(ys[i])); g.lineTo(X(tips[i][0]), Y(tips[i][1]));
      }
      g.stroke();
    }
    g.strokeStyle = '#d62728'; g.lineWidth = 2.5; g.setLineDash([3, 2]);
    for (const o of plan.outliers) { g.beginPath(); g.arc(X(xs[o.i]), Y(ys[o.i]), 9, 0, 2 * Math.PI); g.stroke(); }
    g.setLineDash([]);
    const ov = overlay();
    g.fillStyle = 'rgba(255, 213, 79, 0.5)'; g.strokeStyle = '#b8860b'; g.lineWidth = 1.5;
    for (const i of ov.rings) { g.beginPath(); g.arc(X(xs[i]), Y(ys[i]), 7, 0, 2 * Math.PI); g.fill(); g.stroke(); }
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
  }
  canvas.addEventListener('mousemove', (ev) => {
    const r = canvas.getBoundingClientRect();
    const px = ((ev.clientX - r.left) / r.width) * W, py = ((ev.clientY - r.top) / r.height) * H;
    let best = -1, bd = 100; // within 10 px
    for (let i = 0; i < xs.length; i++) { const d = (X(xs[i]) - px) ** 2 + (Y(ys[i]) - py) ** 2; if (d < bd) { bd = d; best = i; } }
    readout.textContent = best < 0 ? '' : `point ${plan.ids[best]}: x ${xs[best].toFixed(2)} mm, y ${ys[best].toFixed(2)} mm, residual ${(res[best] * 1000).toFixed(2)} µm`;
  });
  canvas.addEventListener('mouseleave', () => { readout.textContent = ''; });
  draw();
  const el = document.createElement('div');
  el.append(readout, canvas);
  return { el, canvas, redraw: draw };
}
