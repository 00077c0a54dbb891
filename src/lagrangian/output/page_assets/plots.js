// The page's plots on a canvas (lagrangian page): the axes every plot draws (the phase
// portrait, the time series, the Poincaré section of section.js) and the line plot.

// The axes of a plot on the canvas `target`: the canvas sized to its CSS width (0.7 as
// high) and cleared, the box of the values xs, ys (their finite ones) with a 5 % margin
// outlined, labels = [x label, y label] and the y range written; the x label may be a
// function of the x range (xa, xb), written from the middle less `shift` pixels (or 0).
// Returns {c, width, height, pad, xa, xb, ya, yb, X, Y} (X(x), Y(y): the CSS pixels of a
// value), or null where xs has no finite value (the canvas cleared only).  The canvas is
// resized only when its width changed: a resize lays out the whole page again.
function lagrangianAxes(target, xs, ys, labels, shift) {
  "use strict";
  const c = target.getContext("2d");
  const ratio = window.devicePixelRatio || 1;
  const width = Math.max(100, target.clientWidth);
  const height = Math.round(width * 0.7);
  if (target.width !== width * ratio) {
    target.width = width * ratio;
    target.height = height * ratio;
    target.style.height = `${height}px`;
  }
  c.setTransform(ratio, 0, 0, ratio, 0, 0);
  c.clearRect(0, 0, width, height);
  xs = xs.filter(Number.isFinite);
  ys = ys.filter(Number.isFinite);
  if (!xs.length) return null;
  const pad = 28;
  const range = (v) => {
    let [a, b] = [Math.min(...v), Math.max(...v)];
    if (b - a < 1e-12) [a, b] = [a - 1, b + 1];
    return [a - 0.05 * (b - a), b + 0.05 * (b - a)];
  };
  const [xa, xb] = range(xs);
  const [ya, yb] = range(ys);
  const X = (x) => pad + ((x - xa) / (xb - xa)) * (width - pad - 6);
  const Y = (y) => height - pad + 6 - ((y - ya) / (yb - ya)) * (height - pad);
  c.strokeStyle = "#c7cdd4";
  c.strokeRect(pad, 6, width - pad - 6, height - pad);
  c.fillStyle = "#5b6570";
  c.font = "11px sans-serif";
  const xLabel = typeof labels[0] === "function" ? labels[0](xa, xb) : labels[0];
  c.fillText(xLabel, width / 2 - (shift || 0), height - 6);
  c.save();
  c.translate(11, height / 2);
  c.rotate(-Math.PI / 2);
  c.fillText(labels[1], 0, 0);
  c.restore();
  c.fillText(ya.toPrecision(3), pad + 2, height - pad + 2);
  c.fillText(yb.toPrecision(3), pad + 2, 18);
  return { c, width, height, pad, xa, xb, ya, yb, X, Y };
}

// A line plot: series [{points: [[x, y], ...], color, label}] over the axes of all points
// (lagrangianAxes), labels: [x label, y label]; a legend where there are several series.
function lagrangianPlot(target, series, labels) {
  "use strict";
  const xs = series.flatMap((s) => s.points.map((p) => p[0]));
  const ys = series.flatMap((s) => s.points.map((p) => p[1]));
  const frame = lagrangianAxes(target, xs, ys, labels);
  if (frame === null) return;
  const { c, width, X, Y } = frame;
  if (series.length > 1) {
    let x = width - 8;
    for (const s of [...series].reverse()) {
      x -= c.measureText(s.label).width;
      c.fillStyle = s.color;
      c.fillText(s.label, x, 18);
      x -= 8;
    }
  }
  for (const s of series) {
    c.beginPath();
    s.points.forEach(([x, y], i) => (i ? c.lineTo(X(x), Y(y)) : c.moveTo(X(x), Y(y))));
    c.strokeStyle = s.color;
    c.lineWidth = 1.3;
    c.stroke();
  }
}
