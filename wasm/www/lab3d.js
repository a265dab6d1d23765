// The 3D lab: scenes in (presets, the user's files), their information coloured on the
// mesh, their light and their views. Every number comes from the wasm module (pkg3d): the
// main thread holds the scene for its geometry and shading; the worker (worker3d.js) holds
// it too and does the long computations.
import init, { Lab3, presets3 } from './pkg3d/sceneinfo_wasm.js';
import { View3 } from './gl3d.js';
import { colourBar, heatMap, refinementPlot, scale } from './plots.js';
import { HEAT_MAP_LIMIT, labOf } from './scene3d.js';

const $ = (id) => document.getElementById(id);

await init();
const view = new View3($('view'));
const worker = new Worker('./worker3d.js', { type: 'module' });

// The page's state: the scene, its measures and light, what is shown.
const state = {
  lab: null, source: null, id: 0,
  exact: null, mc: null, light: null, views: null,
  refine: null, // the refinement player: { points, report, mesh, busy, playing }
  runs: 0, // finished jobs, told to the browser test through data-lines / -light / -views / -refined
  timing: {}, // seconds of the last exact measures and line run, as the page saw them (issue 24, item 7)
};
// For the browser test and curious users
window.lab3d = state;
state.camera = () => ({ ...view.camera });

// ---- messages from the worker -------------------------------------------------------------

const pending = new Map(); // request number → { resolve, reject }
let requests = 0;
function request(message) {
  return new Promise((resolve, reject) => {
    requests += 1;
    pending.set(requests, { resolve, reject });
    worker.postMessage({ ...message, req: requests });
  });
}

worker.onmessage = ({ data }) => {
  const p = data.req === undefined ? null : pending.get(data.req);
  if (p) {
    pending.delete(data.req);
    if (data.type === 'error') p.reject(new Error(data.message));
    else p.resolve(data);
    return;
  }
  if (data.id !== state.id) return; // about a scene no longer shown
  if (data.type === 'progress') {
    $('mc-progress').value = data.done / data.total;
    $('mc-status').textContent = `${data.done.toLocaleString('en')} of ${data.total.toLocaleString('en')} lines: I_S^c = ${data.value.toFixed(5)} ± ${data.stderr.toFixed(5)}`;
  } else if (data.type === 'measures') {
    linesDone(data);
  } else if (data.type === 'matrix') {
    matrixDone(data);
  } else if (data.type === 'error') {
    linesFailed(data.message);
  }
};

// ---- scenes in ------------------------------------------------------------------------------

function showError(message) {
  $('error').hidden = !message;
  $('error').textContent = message ?? '';
}

function showWarnings(list) {
  const ul = $('warnings');
  ul.replaceChildren(...list.map((w) => Object.assign(document.createElement('li'), { textContent: w })));
  ul.hidden = list.length === 0;
}

async function loadScene(source, name) {
  showError(null);
  let lab;
  try {
    lab = labOf(Lab3, source);
  } catch (e) {
    showError(e.message);
    return;
  }
  state.lab?.free();
  stopPlaying();
  Object.assign(state, { lab, source, exact: null, mc: null, light: null, views: null, running: false, refine: null });
  state.id += 1;
  const id = state.id;
  document.title = `sceneinfo 3D lab: ${name}`;
  $('scene-name').textContent = `${name}: ${lab.nPatches} patches`;
  showWarnings(lab.warnings());
  view.fit(lab.bounds());
  state.triangles = lab.triangles();
  state.trianglePatches = lab.trianglePatches();
  clearMeasures();
  $('colour').value = 'none';
  paint();
  worker.postMessage({ type: 'load', id, source });
  // The exact channel where no patch can hide another (the core refuses the others)
  if (lab.nPatches <= 2000) {
    $('m-note').textContent = 'exact form factors…';
    try {
      const asked = performance.now();
      state.exactAsked = asked;
      const m = await request({ type: 'exact', id });
      if (id !== state.id) return;
      const received = performance.now();
      state.exact = m;
      showMeasures(JSON.parse(m.json), 'exact');
      // Issue 24's item 7: the exact measures from the page's request to their display.
      // `moved`: the round trip less the worker's two parts (the worker reads the scene
      // first: the load message precedes the request; then the message to the page). The
      // I_ij heat map follows (matrixDone: `heat`).
      const now = performance.now();
      const t = {
        total: (now - asked) / 1000, channel: m.seconds, arrays: m.arraysSeconds,
        moved: (received - asked) / 1000 - m.seconds - m.arraysSeconds, shown: (now - received) / 1000,
        patches: lab.nPatches,
      };
      state.timing.exact = t;
      $('m-note').textContent = `exact measures in ${t.total.toFixed(3)} s: in the worker, form factors and ` +
        `measures ${t.channel.toFixed(3)} s, per-patch values ${t.arrays.toFixed(3)} s; reading ` +
        `the scene there and the message ${t.moved.toFixed(3)} s; shown ${t.shown.toFixed(3)} s`;
    } catch (e) {
      if (id !== state.id) return;
      $('m-note').textContent = `No exact measures: ${e.message}. Run lines.`;
    }
  } else {
    $('m-note').textContent = 'Large scene: run lines for its measures.';
  }
  $('status-ready')?.remove();
  document.body.dataset.ready = String(id);
}

// Files that may be a scene; the others the user gives with it are its companions (an OBJ's
// .mtl libraries, a .gltf's .bin buffers). Images (textures) are not read.
const SCENE_FILE = /\.(obj|gltf|glb|ply|vs3)$/i;
const IMAGE_FILE = /\.(png|jpe?g|webp|ktx2|basis)$/i;

async function loadFiles(files) {
  const list = [...files].filter((f) => !IMAGE_FILE.test(f.name));
  const scene = list.find((f) => SCENE_FILE.test(f.name)) ?? list.find((f) => !/\.(mtl|bin)$/i.test(f.name));
  if (!scene) {
    showError('Choose a scene file (OBJ, glTF / GLB, PLY, .vs3), with its .mtl files for an OBJ or its .bin files for a .gltf.');
    return;
  }
  const bytesOf = async (f) => new Uint8Array(await f.arrayBuffer());
  const others = await Promise.all(list.filter((f) => f !== scene).map(async (f) => [f.name, await bytesOf(f)]));
  history.replaceState(null, '', location.pathname);
  $('preset').value = '';
  await loadScene({ name: scene.name, bytes: await bytesOf(scene), files: others, emitFromKa: $('emit-ka').checked }, scene.name);
}

function presetSource() {
  return { preset: $('preset').value, grid: Math.max(1, Math.round(Number($('grid').value) || 1)) };
}

async function loadPreset() {
  const source = presetSource();
  const now = state.source;
  if (!source.preset || (now?.preset === source.preset && now.grid === source.grid)) return;
  history.replaceState(null, '', `#preset=${encodeURIComponent(source.preset)}&grid=${source.grid}`);
  await loadScene(source, source.preset);
}

for (const p of JSON.parse(presets3())) {
  const o = document.createElement('option');
  o.value = p.name;
  o.textContent = `${p.name} — ${p.description}`;
  $('preset').append(o);
}
$('preset').addEventListener('change', loadPreset);
$('grid').addEventListener('change', loadPreset);
$('file').addEventListener('change', (e) => loadFiles(e.target.files));
$('emit-ka').addEventListener('change', () => {
  const s = state.source;
  if (s && !s.preset) loadScene({ ...s, emitFromKa: $('emit-ka').checked }, s.name);
});
$('share').addEventListener('click', async () => {
  if (!state.source?.preset) return;
  await navigator.clipboard?.writeText(location.href).catch(() => {});
});
const canvas = $('view');
canvas.addEventListener('dragover', (e) => { e.preventDefault(); canvas.classList.add('drop'); });
canvas.addEventListener('dragleave', () => canvas.classList.remove('drop'));
canvas.addEventListener('drop', (e) => {
  e.preventDefault();
  canvas.classList.remove('drop');
  loadFiles(e.dataTransfer.files);
});

// ---- measures -------------------------------------------------------------------------------

const show = (id, v) => { $(id).textContent = v === null || v === undefined ? '–' : String(v); };

function clearMeasures() {
  for (const k of ['patches', 'source', 'h_p', 'h_s', 'h_j', 'i_s', 'isc', 'isc-err', 'delta']) show(`m-${k}`, null);
  for (const k of ['h_s', 'i_s', 'isc']) for (const c of [0, 1, 2]) show(`r-${k}-${c}`, null);
  show('m-patches', state.lab?.nPatches);
  $('mc-status').textContent = '–';
  $('rad-status').textContent = '–';
  $('mc-progress').value = 0;
  $('vp-status').textContent = '–';
  $('vp-best').replaceChildren();
  $('vp-sphere').getContext('2d').clearRect(0, 0, 180, 180);
  drawHeat();
  showRefinement();
}

function showMeasures(j, source) {
  show('m-source', source);
  for (const k of ['h_p', 'h_s', 'h_j', 'i_s']) show(`m-${k}`, j[k]);
  if (j.i_s_continuous !== undefined) {
    show('m-isc', j.i_s_continuous);
    show('m-isc-err', j.i_s_continuous_stderr);
    show('m-delta', j.rel_discretisation_error);
  }
}

// ---- Monte Carlo ----------------------------------------------------------------------------

function runLines() {
  if (!state.lab) return;
  state.running = true;
  $('mc-run').disabled = true;
  $('mc-stop').disabled = false;
  $('mc-progress').value = 0;
  state.linesAsked = performance.now();
  worker.postMessage({
    type: 'lines', id: state.id, seed: Number($('mc-seed').value), lines: Number($('mc-lines').value),
    method: $('mc-method').value,
  });
}

function linesDone(m) {
  state.running = false;
  state.mc = m;
  $('mc-run').disabled = false;
  $('mc-stop').disabled = true;
  const j = JSON.parse(m.json);
  showMeasures(j, `${j.lines.toLocaleString('en')} ${j.form_factors}, seed ${j.seed}`);
  drawHeat();
  paint();
  // Issue 24's item 7: the job from the click to its measures shown and painted
  const total = (performance.now() - state.linesAsked) / 1000;
  state.timing.lines = { total, worker: m.seconds, lines: m.done, patches: state.lab.nPatches };
  $('mc-status').textContent = `${m.stopped ? 'stopped after' : 'done:'} ${m.done.toLocaleString('en')} lines in ` +
    `${total.toFixed(2)} s (${m.seconds.toFixed(2)} s in the worker to the measures)`;
  document.body.dataset.lines = `${state.id}:${++state.runs}`;
}

// The I_ij matrix of the measures just shown (exact, or the line run's).
function matrixDone(data) {
  const m = data.kind === 'exact' ? state.exact : state.mc;
  if (!m) return;
  m.matrix = data.matrix;
  drawHeat();
  if (data.kind === 'exact' && state.timing.exact?.patches === state.lab.nPatches) {
    Object.assign(state.timing.exact, { heat: (performance.now() - state.exactAsked) / 1000, matrix: data.seconds });
    $('m-note').textContent += `; the I_ij heat map ${state.timing.exact.heat.toFixed(3)} s after the ` +
      `request (I_ij ${data.seconds.toFixed(3)} s in the worker)`;
  }
}

function linesFailed(message) {
  state.running = false;
  $('mc-run').disabled = false;
  $('mc-stop').disabled = true;
  $('mc-status').textContent = message;
}

$('mc-run').addEventListener('click', runLines);
$('mc-stop').addEventListener('click', () => worker.postMessage({ type: 'stop', id: state.id }));

// ---- light ----------------------------------------------------------------------------------

async function solveRadiosity() {
  if (!state.lab) return;
  const id = state.id;
  $('rad-run').disabled = true;
  $('rad-status').textContent = 'solving…';
  try {
    const light = await request({ type: 'radiosity', id, lines: Number($('rad-lines').value), seed: Number($('mc-seed').value) });
    if (id !== state.id) return;
    state.light = light;
    const j = JSON.parse(light.json);
    for (const c of [0, 1, 2]) {
      show(`r-h_s-${c}`, j.h_s_rgb[c]);
      show(`r-i_s-${c}`, j.i_s_rgb[c]);
      show(`r-isc-${c}`, j.i_s_continuous_rgb?.[c]);
    }
    $('rad-status').textContent = `${j.form_factors === 'exact' ? 'exact form factors' : `${j.lines.toLocaleString('en')} lines, seed ${j.seed}`}; ${j.iterations} iterations; ${light.seconds.toFixed(2)} s`;
    $('colour').value = 'light';
    paint();
    document.body.dataset.light = `${id}:${++state.runs}`;
  } catch (e) {
    $('rad-status').textContent = e.message;
  } finally {
    $('rad-run').disabled = false;
  }
}
$('rad-run').addEventListener('click', solveRadiosity);

// ---- views ----------------------------------------------------------------------------------

const VIEWS = 42;
const VIEW_RADII = 3; // the viewpoint channel's sphere: 3 bounding radii

// Lambert azimuthal equal-area projection about +y onto the sphere canvas.
function sphereXY(d, size) {
  const k = Math.sqrt(2 / (1 + Math.max(-0.999, d[1])));
  return [size / 2 + (d[0] * k * size) / 4.2, size / 2 + (d[2] * k * size) / 4.2];
}

function drawSphere() {
  const v = state.views;
  const c = $('vp-sphere');
  const g = c.getContext('2d');
  g.clearRect(0, 0, c.width, c.height);
  if (!v) return;
  const values = v[$('vp-colour').value];
  const s = scale(values, false);
  for (let k = 0; k < v.n_views; k++) {
    const d = v.directions.slice(3 * k, 3 * k + 3);
    const [x, y] = sphereXY(d, c.width);
    g.fillStyle = s.colour(values[k]);
    g.beginPath();
    g.arc(x, y, v.best.includes(k) ? 8 : 6, 0, 2 * Math.PI);
    g.fill();
    if (v.best.includes(k)) { g.strokeStyle = '#fff'; g.lineWidth = 2; g.stroke(); }
  }
}

async function findViews() {
  if (!state.lab) return;
  const id = state.id;
  $('vp-run').disabled = true;
  $('vp-status').textContent = 'rendering the views…';
  try {
    const r = await request({ type: 'viewpoints', id, views: VIEWS, resolution: 96, best: 4 });
    if (id !== state.id) return;
    state.views = JSON.parse(r.json);
    const v = state.views;
    $('vp-status').textContent = `I(V;O) = ${v.i_vo.toFixed(4)} bits; best views (least VMI) ${v.best.join(', ')}; ${r.seconds.toFixed(2)} s`;
    drawSphere();
    // Thumbnails of the best views, rendered with the current colouring
    const saved = { ...view.camera };
    const thumbs = [];
    for (const k of v.best) {
      view.lookFrom(v.directions.slice(3 * k, 3 * k + 3), VIEW_RADII);
      const img = Object.assign(document.createElement('img'), { src: view.canvas.toDataURL('image/png'), alt: `view ${k}` });
      const b = Object.assign(document.createElement('button'), { type: 'button', title: `view ${k}: VMI ${v.vmi[k].toFixed(4)}` });
      b.append(img, `#${k}`);
      b.addEventListener('click', () => view.lookFrom(v.directions.slice(3 * k, 3 * k + 3), VIEW_RADII));
      thumbs.push(b);
    }
    Object.assign(view.camera, saved);
    view.draw();
    $('vp-best').replaceChildren(...thumbs);
    document.body.dataset.views = `${id}:${++state.runs}`;
  } catch (e) {
    $('vp-status').textContent = e.message;
  } finally {
    $('vp-run').disabled = false;
  }
}
$('vp-run').addEventListener('click', findViews);
$('vp-colour').addEventListener('change', drawSphere);
$('vp-sphere').addEventListener('click', (e) => {
  const v = state.views;
  if (!v) return;
  const c = e.currentTarget;
  const r = c.getBoundingClientRect();
  const x = ((e.clientX - r.left) * c.width) / r.width;
  const y = ((e.clientY - r.top) * c.height) / r.height;
  let best = -1;
  let bestD = Infinity;
  for (let k = 0; k < v.n_views; k++) {
    const [px, py] = sphereXY(v.directions.slice(3 * k, 3 * k + 3), c.width);
    const d = Math.hypot(px - x, py - y);
    if (d < bestD) [best, bestD] = [k, d];
  }
  if (best >= 0) view.lookFrom(v.directions.slice(3 * best, 3 * best + 3), VIEW_RADII);
});

// ---- I_ij heat map --------------------------------------------------------------------------

function drawHeat() {
  const c = $('heat');
  const bar = $('heat-bar');
  c.getContext('2d').clearRect(0, 0, c.width, c.height);
  bar.hidden = true;
  const n = state.lab?.nPatches ?? 0;
  const m = state.exact ?? state.mc;
  if (!state.lab) {
    $('heat-note').textContent = '–';
  } else if (n > HEAT_MAP_LIMIT) {
    $('heat-note').textContent = `not drawn above ${HEAT_MAP_LIMIT} patches (this scene has ${n})`;
  } else if (!m) {
    $('heat-note').textContent = 'needs the exact measures or a finished line run';
  } else if (!m.matrix) {
    $('heat-note').textContent = 'I_ij…';
  } else if (!m.h) {
    $('heat-note').textContent = 'needs every patch to receive a line';
  } else {
    const max = heatMap(c, m.matrix, n);
    bar.hidden = false;
    colourBar(bar, scale([-1, 1], true), 'I_ij / max |I_ij| (√ scale)');
    $('heat-note').textContent = `${n} × ${n} patches (row i, column j; sums of bins when n > ${c.width}), ` +
      `largest |I_ij| ${max.toExponential(2)} bits; red > 0 (more transfer than chance), blue < 0; ` +
      `${m === state.exact ? 'exact form factors' : 'from the line run'}`;
    document.body.dataset.heat = `${state.id}:${n}`;
  }
}

// ---- refinement -----------------------------------------------------------------------------

const PLAY_INTERVAL_MS = 300;
let playTimer = 0;

function stopPlaying() {
  clearTimeout(playTimer);
  if (state.refine) state.refine.playing = false;
  $('ref-play').textContent = 'Play';
}

function resetRefinement() {
  stopPlaying();
  state.refine = null;
  if ($('colour').value === 'refine') $('colour').value = 'none';
  showRefinement();
  paint();
}

function showRefinement() {
  const r = state.refine;
  const j = r?.report;
  const num = (v, d = 4) => (v === null || v === undefined ? '–' : v.toFixed(d));
  $('ref-leaves').textContent = j ? String(j.n_patches) : '–';
  $('ref-eps').textContent = j ? String(j.eps) : '–';
  $('ref-is').textContent = j ? num(j.i_s) : '–';
  $('ref-isc').textContent = j && j.i_s_continuous !== null ? `${num(j.i_s_continuous)} ± ${num(j.i_s_continuous_stderr)}` : '–';
  $('ref-delta').textContent = j && j.rel_discretisation_error !== null ? `${(100 * j.rel_discretisation_error).toFixed(2)} %` : '–';
  $('ref-cost').textContent = j ? `${j.links.toLocaleString('en')}, ${j.rays.toLocaleString('en')}` : '–';
  const points = (r?.points ?? []).filter((p) => p.i_s !== null);
  const ceiling = j && j.i_s_continuous !== null ? { value: j.i_s_continuous, stderr: j.i_s_continuous_stderr } : null;
  refinementPlot($('ref-plot'), points, ceiling);
}

// One step of the player: the first starts the refiner on the scene (its coarsest mesh).
async function refineStep() {
  if (!state.lab || state.refine?.busy) return;
  const id = state.id;
  const exposure = 2 ** Number($('exposure').value);
  const r = state.refine ?? { points: [], report: null, mesh: null, playing: false };
  state.refine = r;
  r.busy = true;
  $('ref-step').disabled = true;
  $('ref-status').textContent = r.report ? 'refining…' : 'building the coarsest mesh…';
  try {
    const message = r.report
      ? { type: 'refine-step', id, exposure }
      : {
        type: 'refine-start', id, exposure, oracle: $('ref-oracle').value, pairs: 10,
        lines: Number($('ref-lines').value), seed: Number($('mc-seed').value),
      };
    const out = await request(message);
    if (id !== state.id || state.refine !== r) return;
    r.report = JSON.parse(out.report);
    r.mesh = { ...out, exposure };
    r.points.push({ n: r.report.n_patches, i_s: r.report.i_s });
    const j = r.report;
    $('ref-status').textContent = `${j.steps === 0 ? 'start' : `step ${j.steps}`}: ${j.oracle}, ε = ${j.eps}, ` +
      `${j.n_patches.toLocaleString('en')} leaves of ${j.elements.toLocaleString('en')} elements; ` +
      `${out.seconds.toFixed(2)} s${j.warning ? `. ${j.warning}` : ''}`;
    $('colour').value = 'refine';
    paint();
    document.body.dataset.refined = `${id}:${++state.runs}`;
  } catch (e) {
    if (id !== state.id) return;
    stopPlaying();
    $('ref-status').textContent = e.message;
    document.body.dataset.refineError = `${id}:${++state.runs}`;
  } finally {
    r.busy = false;
    $('ref-step').disabled = false;
    showRefinement();
  }
}

function playTick() {
  const r = state.refine;
  if (r && !r.playing) return;
  refineStep().then(() => {
    if (state.refine?.playing) playTimer = setTimeout(playTick, PLAY_INTERVAL_MS);
  });
}

$('ref-step').addEventListener('click', refineStep);
$('ref-reset').addEventListener('click', resetRefinement);
$('ref-oracle').addEventListener('change', resetRefinement);
$('ref-lines').addEventListener('change', resetRefinement);
$('ref-play').addEventListener('click', () => {
  if (state.refine?.playing) {
    stopPlaying();
    return;
  }
  if (!state.refine) state.refine = { points: [], report: null, mesh: null, playing: false };
  state.refine.playing = true;
  $('ref-play').textContent = 'Pause';
  playTick();
});

// The refined mesh at the exposure shown (the worker shades it).
async function refineMesh() {
  const r = state.refine;
  if (!r?.report) return;
  const id = state.id;
  const exposure = 2 ** Number($('exposure').value);
  r.busy = true;
  try {
    const out = await request({ type: 'refine-mesh', id, exposure });
    if (id !== state.id || state.refine !== r) return;
    r.mesh = { ...out, exposure };
  } finally {
    r.busy = false;
  }
  paint();
}

// ---- colouring ------------------------------------------------------------------------------

// The values of colouring `key` per patch, or a sentence saying what to run first.
function patchValues(key) {
  const { exact, mc } = state;
  const base = exact ?? mc;
  if (key === 'h') return base?.h ?? 'needs the exact measures or a finished line run';
  if (key === 'i') return base?.i ?? 'needs the exact measures or a finished line run';
  if (key === 'ic' || key === 'delta') {
    if (!mc?.ic) return 'run lines first';
    if (key === 'ic') return mc.ic;
    const i = (exact ?? mc).i;
    if (!i) return 'needs I_i: every patch must receive a line';
    return mc.ic.map((v, k) => v - i[k]);
  }
  if (key === 'saliency') return state.views?.saliency ?? 'find the best views first';
  return null;
}

const LABELS = {
  h: 'H_i (bits)', i: 'I_i (bits)', ic: 'I_i^c (bits)', delta: 'I_i^c − I_i (bits)', saliency: 'S(o)',
};

function paint() {
  const key = $('colour').value;
  const lab = state.lab;
  $('exposure-label').hidden = key !== 'light' && key !== 'refine';
  $('colour-bar').hidden = true;
  $('colour-note').textContent = '';
  if (!lab) return;
  if (key === 'light') {
    if (!state.light) {
      $('colour-note').textContent = 'solve radiosity first';
    } else {
      const exposure = 2 ** Number($('exposure').value);
      $('exposure-value').textContent = `${exposure.toFixed(2)}×`;
      const mesh = lab.litMesh(state.light.radiosity, exposure);
      view.setMesh(mesh.positions(), mesh.colours(), 0);
      mesh.free();
      return;
    }
  }
  if (key === 'refine') {
    const mesh = state.refine?.mesh;
    if (!mesh) {
      $('colour-note').textContent = 'step the refinement first';
    } else {
      const exposure = 2 ** Number($('exposure').value);
      $('exposure-value').textContent = `${exposure.toFixed(2)}×`;
      view.setMesh(mesh.positions, mesh.colours, 0, mesh.edges);
      $('colour-note').textContent = `${state.refine.report.n_patches} leaves, Gouraud shaded, element edges`;
      if (mesh.exposure !== exposure && !state.refine.busy) refineMesh();
      return;
    }
  }
  const values = key === 'light' || key === 'refine' ? null : patchValues(key);
  const tri = state.trianglePatches;
  const colours = new Uint8Array(tri.length * 9).fill(200);
  if (Array.isArray(values) || ArrayBuffer.isView(values)) {
    const s = scale(values, key === 'delta');
    const rgb = Array.from(values, (v) => s.rgb(v));
    for (let t = 0; t < tri.length; t++) {
      const c = rgb[tri[t]];
      for (let k = 0; k < 3; k++) colours.set(c, 9 * t + 3 * k);
    }
    $('colour-bar').hidden = false;
    colourBar($('colour-bar'), s, LABELS[key]);
  } else if (typeof values === 'string') {
    $('colour-note').textContent = values;
  }
  view.setMesh(state.triangles, colours, 0.35);
}
$('colour').addEventListener('change', paint);
$('exposure').addEventListener('input', paint);

// ---- start: the preset in the address, or the Cornell box --------------------------------------

const hash = new URLSearchParams(location.hash.slice(1));
$('preset').value = hash.get('preset') ?? 'cornell';
if (!$('preset').value) $('preset').value = 'cornell';
$('grid').value = hash.get('grid') ?? '4';
await loadPreset();
