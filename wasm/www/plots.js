// Pictures of numbers the wasm module computed: colour maps, the Venn diagram of H_P, H_S
// and I_S (thesis Figs. 3.2, 3.4), the I_ij heat map (Fig. 6.14) and the refinement plot
// (Fig. 6.19). Drawing only.

// Viridis, 9 stops (matplotlib's), interpolated linearly.
const VIRIDIS = [
  [68, 1, 84], [71, 44, 122], [59, 81, 139], [44, 113, 142], [33, 144, 141],
  [39, 173, 129], [92, 200, 99], [170, 220, 50], [253, 231, 37],
];
// Diverging blue – light grey – red (Moreland's cool-warm, 5 stops).
const COOLWARM = [[59, 76, 192], [141, 176, 254], [221, 221, 221], [244, 154, 123], [180, 4, 38]];

function interpolate(stops, t) {
  const x = Math.min(Math.max(t, 0), 1) * (stops.length - 1);
  const k = Math.min(Math.floor(x), stops.length - 2);
  const f = x - k;
  return stops[k].map((c, i) => Math.round(c + f * (stops[k + 1][i] - c)));
}

/// A colour scale for `values`: viridis from min to max, or cool-warm symmetric about zero
/// when `diverging`. Returns { colour(v) → 'rgb(…)', rgb(v) → [r,g,b], lo, hi, diverging }.
export function scale(values, diverging) {
  let lo = Infinity;
  let hi = -Infinity;
  for (const v of values) {
    lo = Math.min(lo, v);
    hi = Math.max(hi, v);
  }
  if (!Number.isFinite(lo)) [lo, hi] = [0, 1];
  if (diverging) {
    const m = Math.max(Math.abs(lo), Math.abs(hi)) || 1;
    [lo, hi] = [-m, m];
  } else if (hi <= lo) {
    hi = lo + 1;
  }
  const stops = diverging ? COOLWARM : VIRIDIS;
  const rgb = (v) => interpolate(stops, (v - lo) / (hi - lo));
  return { rgb, colour: (v) => `rgb(${rgb(v).join(',')})`, lo, hi, diverging };
}

/// Draws a horizontal colour bar for scale `s` with its end values on canvas `c`.
export function colourBar(c, s, label) {
  const g = c.getContext('2d');
  const { width: w, height: h } = c;
  g.clearRect(0, 0, w, h);
  for (let x = 0; x < w; x++) {
    g.fillStyle = s.colour(s.lo + ((s.hi - s.lo) * x) / (w - 1));
    g.fillRect(x, 0, 1, h - 16);
  }
  g.fillStyle = '#333';
  g.font = '11px system-ui, sans-serif';
  g.textAlign = 'left';
  g.fillText(fmt(s.lo), 0, h - 3);
  g.textAlign = 'right';
  g.fillText(fmt(s.hi), w, h - 3);
  g.textAlign = 'center';
  g.fillText(label, w / 2, h - 3);
}

function fmt(v) {
  return Math.abs(v) >= 0.01 || v === 0 ? v.toFixed(3) : v.toExponential(1);
}

// Area of the lens of two circles of radius r whose centres are d apart.
function lens(r, d) {
  if (d >= 2 * r) return 0;
  return 2 * r * r * Math.acos(d / (2 * r)) - (d / 2) * Math.sqrt(4 * r * r - d * d);
}

/// The Venn diagram of the scene channel (Figs. 3.2, 3.4): two circles of area H_P (the
/// entropies of X and Y), overlapping in area I_S; each crescent is H_S, the union H_J.
export function venn(c, m) {
  const g = c.getContext('2d');
  const { width: w, height: h } = c;
  g.clearRect(0, 0, w, h);
  if (!m || !(m.h_p > 0)) return;
  const r = Math.min(w / 4.2, (h - 44) / 2);
  // The centre distance whose lens holds the fraction I_S / H_P of a circle (bisection on
  // the monotone lens area: drawing, not measuring).
  const target = (Math.max(0, Math.min(m.i_s, m.h_p)) / m.h_p) * Math.PI * r * r;
  let [lo, hi] = [0, 2 * r];
  for (let k = 0; k < 50; k++) {
    const mid = (lo + hi) / 2;
    if (lens(r, mid) > target) lo = mid;
    else hi = mid;
  }
  const d = (lo + hi) / 2;
  const cy = h / 2;
  const [x1, x2] = [w / 2 - d / 2, w / 2 + d / 2];
  g.globalAlpha = 0.35;
  g.fillStyle = '#3b6fd1';
  g.beginPath();
  g.arc(x1, cy, r, 0, 2 * Math.PI);
  g.fill();
  g.fillStyle = '#d1713b';
  g.beginPath();
  g.arc(x2, cy, r, 0, 2 * Math.PI);
  g.fill();
  g.globalAlpha = 1;
  g.strokeStyle = '#555';
  for (const x of [x1, x2]) {
    g.beginPath();
    g.arc(x, cy, r, 0, 2 * Math.PI);
    g.stroke();
  }
  g.fillStyle = '#111';
  g.font = '12px system-ui, sans-serif';
  g.textAlign = 'center';
  // Labels at the middles of the two crescents and of the lens, name over value.
  const label = (x, name, value) => {
    g.fillText(name, x, cy - 3);
    g.fillText(value.toFixed(3), x, cy + 12);
  };
  const mid = w / 2;
  label(mid - r, 'H_S', m.h_s); // the left crescent spans [mid − d/2 − r, mid + d/2 − r]
  label(mid + r, 'H_S', m.h_s);
  label(mid, 'I_S', m.i_s);
  g.fillText(`H_P = H(X) = H(Y) = ${m.h_p.toFixed(3)}`, mid, cy - r - 6);
  g.fillText(`H_J = ${m.h_j.toFixed(3)} (the union)`, mid, cy + r + 16);
}

/// The mutual information matrix I_ij (6.7) as a heat map (Fig. 6.14): cool-warm about 0 on
/// a square-root scale, cells summed into at most `canvas.width` bins a side.
export function heatMap(c, matrix, n) {
  const g = c.getContext('2d');
  const bins = Math.min(n, c.width);
  const sums = new Float64Array(bins * bins);
  // Each patch's bin once (the 3D lab's 600-patch cube has 360,000 cells to add up)
  const bin = new Int32Array(n);
  for (let i = 0; i < n; i++) bin[i] = Math.floor((i * bins) / n);
  for (let i = 0; i < n; i++) {
    const bi = bin[i] * bins;
    const row = i * n;
    for (let j = 0; j < n; j++) sums[bi + bin[j]] += matrix[row + j];
  }
  let m = 0;
  for (const v of sums) m = Math.max(m, Math.abs(v));
  const s = scale([-1, 1], true);
  const image = g.createImageData(bins, bins);
  const px = image.data;
  for (let k = 0; k < sums.length; k++) {
    const v = sums[k];
    const [r, gg, b] = v === 0 ? [255, 255, 255] : s.rgb(Math.sign(v) * Math.sqrt(Math.abs(v) / (m || 1)));
    px[4 * k] = r;
    px[4 * k + 1] = gg;
    px[4 * k + 2] = b;
    px[4 * k + 3] = 255;
  }
  // Draw the bins, then stretch them over the canvas without smoothing.
  const tmp = new OffscreenCanvas(bins, bins);
  tmp.getContext('2d').putImageData(image, 0, 0);
  g.imageSmoothingEnabled = false;
  g.clearRect(0, 0, c.width, c.height);
  g.drawImage(tmp, 0, 0, c.width, c.height);
  return m;
}

/// I_S against the number of patches for the refinement steps, with I_S^c ± its error as
/// the ceiling (Fig. 6.19). `points` are [{ n, i_s }], `ceiling` { value, stderr } or null.
export function refinementPlot(c, points, ceiling) {
  const g = c.getContext('2d');
  const { width: w, height: h } = c;
  const pad = { l: 44, r: 10, t: 12, b: 30 };
  g.clearRect(0, 0, w, h);
  g.font = '11px system-ui, sans-serif';
  g.fillStyle = '#333';
  g.strokeStyle = '#999';
  g.strokeRect(pad.l, pad.t, w - pad.l - pad.r, h - pad.t - pad.b);
  if (points.length === 0) {
    g.textAlign = 'center';
    g.fillText('step the oracle to plot I_S against the patch count', w / 2, h / 2);
    return;
  }
  const xs = points.map((p) => p.n);
  const ys = points.map((p) => p.i_s);
  if (ceiling) ys.push(ceiling.value + ceiling.stderr);
  let [x0, x1] = [Math.min(...xs), Math.max(...xs)];
  if (x1 === x0) x1 = x0 + 1;
  // The I_S range with the ceiling and a margin (I_S moves by small steps: a zero-based
  // axis would flatten them).
  const [lo, hi] = [Math.min(...ys), Math.max(...ys)];
  const margin = Math.max(0.08 * (hi - lo), 0.02 * hi, 1e-3);
  const y0 = Math.max(0, lo - margin);
  const y1 = hi + margin;
  const px = (x) => pad.l + ((x - x0) / (x1 - x0)) * (w - pad.l - pad.r);
  const py = (y) => h - pad.b - ((y - y0) / (y1 - y0)) * (h - pad.t - pad.b);
  if (ceiling) {
    g.fillStyle = 'rgba(209, 113, 59, 0.2)';
    g.fillRect(pad.l, py(ceiling.value + ceiling.stderr), w - pad.l - pad.r,
      Math.max(1, py(ceiling.value - ceiling.stderr) - py(ceiling.value + ceiling.stderr)));
    g.strokeStyle = '#d1713b';
    g.setLineDash([5, 4]);
    g.beginPath();
    g.moveTo(pad.l, py(ceiling.value));
    g.lineTo(w - pad.r, py(ceiling.value));
    g.stroke();
    g.setLineDash([]);
    g.fillStyle = '#a0501f';
    g.textAlign = 'right';
    g.fillText(`I_S^c = ${ceiling.value.toFixed(4)}`, w - pad.r - 4, py(ceiling.value) - 4);
  }
  g.strokeStyle = '#3b6fd1';
  g.fillStyle = '#3b6fd1';
  g.beginPath();
  points.forEach((p, k) => (k ? g.lineTo(px(p.n), py(p.i_s)) : g.moveTo(px(p.n), py(p.i_s))));
  g.stroke();
  for (const p of points) {
    g.beginPath();
    g.arc(px(p.n), py(p.i_s), 3, 0, 2 * Math.PI);
    g.fill();
  }
  g.fillStyle = '#333';
  g.textAlign = 'center';
  g.fillText('patches', (pad.l + w - pad.r) / 2, h - 6);
  g.fillText(String(x0), pad.l, h - pad.b + 12);
  g.fillText(String(x1), w - pad.r - 8, h - pad.b + 12);
  g.textAlign = 'right';
  g.fillText(y1.toFixed(2), pad.l - 4, pad.t + 8);
  g.fillText(y0.toFixed(2), pad.l - 4, h - pad.b);
  g.save();
  g.translate(12, (pad.t + h - pad.b) / 2);
  g.rotate(-Math.PI / 2);
  g.textAlign = 'center';
  g.fillText('I_S (bits)', 0, 0);
  g.restore();
}
