// The editor's scene model: objects made of surfaces, to and from `.flat` text, and the URL
// hash. No measures here: every number of the thesis comes from the wasm module.
//
// A surface is { a: [x, y], b: [x, y], n, cuts, mat }: a segment facing its left side, cut
// into n equal patches, or at the parameters `cuts` (0 < t1 < … < 1) when those are given
// (refined scenes); `mat` is [ρr, ρg, ρb, Er, Eg, Eb]. An object is { surfaces: [...] }:
// what the editor selects, moves, rotates and scales as one.

const BLACK = [0, 0, 0, 0, 0, 0];

/// A deep copy of a model (for undo snapshots).
export function cloneModel(model) {
  return { objects: model.objects.map((o) => ({ surfaces: o.surfaces.map(cloneSurface) })) };
}

function cloneSurface(s) {
  return { a: [...s.a], b: [...s.b], n: s.n, cuts: s.cuts ? [...s.cuts] : null, mat: [...s.mat] };
}

/// A surface from a to b cut into n equal patches.
export function surface(a, b, n) {
  return { a: [...a], b: [...b], n: Math.max(1, n), cuts: null, mat: [...BLACK] };
}

/// The model as `.flat` text: one `seg` line per surface, objects in order, a `mat` line
/// whenever the material changes. Numbers in JavaScript's shortest round-trip form, which
/// the core parses back to the same bits.
export function toFlat(model) {
  const lines = ['# sceneinfo flatland lab'];
  let current = BLACK.join(' ');
  for (const object of model.objects) {
    for (const s of object.surfaces) {
      const mat = s.mat.join(' ');
      if (mat !== current) {
        const m = s.mat.map(String);
        lines.push(`mat rho ${m[0]} ${m[1]} ${m[2]} emit ${m[3]} ${m[4]} ${m[5]}`);
        current = mat;
      }
      const head = `seg ${s.a[0]} ${s.a[1]} ${s.b[0]} ${s.b[1]}`;
      lines.push(s.cuts ? `${head} cuts ${s.cuts.join(' ')}` : `${head} ${s.n}`);
    }
  }
  return `${lines.join('\n')}\n`;
}

/// The model of a FlatLab's scene: its surfaces, grouped into objects by shared endpoints
/// (a polygon, a two-sided wall), objects and surfaces in the scene's order.
export function fromLab(lab) {
  const seg = lab.surfaceSegments();
  const counts = lab.surfacePatchCounts();
  const uniform = lab.surfaceUniform();
  const cuts = lab.surfaceCuts();
  const mats = lab.surfaceMaterials();
  const surfaces = [];
  let c = 0;
  for (let k = 0; k < counts.length; k++) {
    const s = surface([seg[4 * k], seg[4 * k + 1]], [seg[4 * k + 2], seg[4 * k + 3]], counts[k]);
    const own = Array.from(cuts.subarray(c, c + counts[k] - 1));
    c += counts[k] - 1;
    if (!uniform[k]) s.cuts = own;
    s.mat = Array.from(mats.subarray(6 * k, 6 * k + 6));
    surfaces.push(s);
  }
  return { objects: groupByEndpoints(surfaces) };
}

// Union-find over surfaces sharing an endpoint (exactly: the scene's own coordinates).
function groupByEndpoints(surfaces) {
  const parent = surfaces.map((_, k) => k);
  const find = (k) => (parent[k] === k ? k : (parent[k] = find(parent[k])));
  const seen = new Map();
  surfaces.forEach((s, k) => {
    for (const p of [s.a, s.b]) {
      const key = `${p[0]},${p[1]}`;
      if (seen.has(key)) parent[find(k)] = find(seen.get(key));
      else seen.set(key, k);
    }
  });
  const groups = new Map();
  surfaces.forEach((s, k) => {
    const root = find(k);
    if (!groups.has(root)) groups.set(root, []);
    groups.get(root).push(s);
  });
  // Map keeps first-insertion order: objects come in the order of their first surface.
  return [...groups.values()].map((list) => ({ surfaces: list }));
}

/// Sets the cuts of the model's surfaces from a lab whose scene has the same surfaces in
/// the same order (a refinement step changes only the cuts).
export function adoptCuts(model, lab) {
  const counts = lab.surfacePatchCounts();
  const uniform = lab.surfaceUniform();
  const cuts = lab.surfaceCuts();
  let k = 0;
  let c = 0;
  for (const object of model.objects) {
    for (const s of object.surfaces) {
      s.n = counts[k];
      s.cuts = uniform[k] ? null : Array.from(cuts.subarray(c, c + counts[k] - 1));
      c += counts[k] - 1;
      k += 1;
    }
  }
}

// ---- geometry of objects (editor transforms) ----------------------------------------------

/// Every endpoint of an object.
export function points(object) {
  return object.surfaces.flatMap((s) => [s.a, s.b]);
}

/// Axis-aligned bounds [minX, minY, maxX, maxY] of some points.
export function bounds(pts) {
  let b = [Infinity, Infinity, -Infinity, -Infinity];
  for (const [x, y] of pts) b = [Math.min(b[0], x), Math.min(b[1], y), Math.max(b[2], x), Math.max(b[3], y)];
  return b;
}

/// Applies p ↦ f(p) to every endpoint of an object (cut parameters are kept: the editor's
/// transforms are similarities, which keep ratios along a segment).
export function mapObject(object, f) {
  for (const s of object.surfaces) {
    s.a = f(s.a);
    s.b = f(s.b);
  }
}

/// Reverses the facing of an object: each surface runs b → a, its cuts mirrored.
export function flipObject(object) {
  for (const s of object.surfaces) {
    [s.a, s.b] = [s.b, s.a];
    if (s.cuts) s.cuts = s.cuts.map((t) => 1 - t).reverse();
  }
}

/// Twice the signed area of a closed polygon (> 0 counter-clockwise).
export function signedArea2(pts) {
  let a = 0;
  for (let k = 0; k < pts.length; k++) {
    const [p, q] = [pts[k], pts[(k + 1) % pts.length]];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a;
}

/// Whether point p is inside the closed polygon pts (even-odd rule).
export function inside(p, pts) {
  let odd = false;
  for (let k = 0, j = pts.length - 1; k < pts.length; j = k++) {
    const [a, b] = [pts[k], pts[j]];
    if (a[1] > p[1] !== b[1] > p[1] && p[0] < ((b[0] - a[0]) * (p[1] - a[1])) / (b[1] - a[1]) + a[0]) {
      odd = !odd;
    }
  }
  return odd;
}

// ---- the URL hash ---------------------------------------------------------------------------

/// `.flat` text → a URL-safe string (deflate + base64url; plain base64url without
/// CompressionStream).
export async function encodeHash(text) {
  let bytes = new TextEncoder().encode(text);
  let tag = 'b';
  if (typeof CompressionStream === 'function') {
    const stream = new Blob([bytes]).stream().pipeThrough(new CompressionStream('deflate-raw'));
    bytes = new Uint8Array(await new Response(stream).arrayBuffer());
    tag = 'z';
  }
  let bin = '';
  for (const b of bytes) bin += String.fromCharCode(b);
  return tag + btoa(bin).replaceAll('+', '-').replaceAll('/', '_').replace(/=+$/, '');
}

/// The inverse of encodeHash.
export async function decodeHash(code) {
  const tag = code[0];
  const b64 = code.slice(1).replaceAll('-', '+').replaceAll('_', '/');
  const bin = atob(b64 + '='.repeat((4 - (b64.length % 4)) % 4));
  let bytes = Uint8Array.from(bin, (c) => c.charCodeAt(0));
  if (tag === 'z') {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate-raw'));
    bytes = new Uint8Array(await new Response(stream).arrayBuffer());
  } else if (tag !== 'b') {
    throw new Error('the link does not hold a scene');
  }
  return new TextDecoder().decode(bytes);
}
