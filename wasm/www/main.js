// The flatland lab: wires the editor, the wasm module (all the numbers), the Monte Carlo
// worker and the pictures together.
import init, { FlatLab, catalogue, relativeDiscretisationError } from './pkg/sceneinfo_wasm.js';
import { Editor } from './editor.js';
import { adoptCuts, decodeHash, encodeHash, fromLab, toFlat } from './model.js';
import { colourBar, heatMap, scale, venn } from './plots.js';
import { Refinement } from './refine.js';

const $ = (id) => document.getElementById(id);
const HEAT_MAP_LIMIT = 2000; // patches: above this the I_ij matrix is not drawn
// Patches: above this the exact form factors (quadratic and more in the patch count, on the
// main thread) are skipped, so a big preset cannot freeze the page; Monte Carlo still runs.
const EXACT_LIMIT = 3000;

const state = {
  lab: null, // FlatLab of the scene on the canvas
  text: '', // its .flat text
  measures: null, // exact measures (parsed JSON)
  mc: null, // the latest Monte Carlo result for `text`: { value, stderr, patchContinuous, … }
  keep: false, // whether the running job only refreshes I_i^c (new cuts, same geometry)
  job: 0, // id of the latest Monte Carlo job
  worker: null,
  hash: '',
};

let editor;
let refinement;

// ---- errors and status --------------------------------------------------------------------

function showError(message) {
  $('error').textContent = message;
  $('error').hidden = !message;
}

function fmt(v, digits = 4) {
  return Number.isFinite(v) ? v.toFixed(digits) : '–';
}

// ---- the scene changed: exact measures now, Monte Carlo in the worker ----------------------

/// Rebuilds the lab from the editor's model. `kind` is 'geometry' (drop the refinement
/// history) or 'cuts' (a refinement step: same geometry, same I_S^c).
function sceneChanged(kind) {
  const text = toFlat(editor.model);
  if (editor.model.objects.length === 0) {
    clearScene();
    return;
  }
  let lab;
  try {
    lab = new FlatLab(text);
  } catch (e) {
    showError(e.message);
    return;
  }
  state.lab?.free();
  state.lab = lab;
  state.text = text;
  showError('');
  measureExact();
  if (kind === 'geometry') refinement.reset();
  // New cuts on the same geometry keep I_S^c (same lines, same samples) but need a new run
  // for the per-patch I_i^c: the running estimate is not shown meanwhile.
  startMonteCarlo({ keep: kind === 'cuts' });
  colourPatches();
  drawHeatMap();
  scheduleHash();
}

function clearScene() {
  state.lab?.free();
  state.lab = null;
  state.text = '';
  state.measures = null;
  state.mc = null;
  stopMonteCarlo();
  showMeasures();
  showMonteCarlo();
  editor.colours = null;
  editor.draw();
  refinement.reset();
  $('heat').getContext('2d').clearRect(0, 0, $('heat').width, $('heat').height);
  scheduleHash();
}

function measureExact() {
  if (state.lab.nPatches > EXACT_LIMIT) {
    state.measures = null;
    $('m-exact-ms').textContent = `skipped above ${EXACT_LIMIT} patches`;
    delete $('m-exact-ms').dataset.ms;
    showMeasures();
    $('m-patches').textContent = String(state.lab.nPatches);
    return;
  }
  const t0 = performance.now();
  try {
    state.measures = JSON.parse(state.lab.measures());
  } catch (e) {
    state.measures = null;
    showError(e.message);
  }
  const ms = performance.now() - t0;
  $('m-exact-ms').textContent = `${ms.toFixed(1)} ms`;
  $('m-exact-ms').dataset.ms = String(ms);
  showMeasures();
}

function showMeasures() {
  const m = state.measures;
  for (const key of ['h_p', 'h_s', 'h_j', 'i_s', 'h_s_norm', 'i_s_norm']) {
    $(`m-${key}`).textContent = m ? fmt(m[key]) : '–';
  }
  $('m-patches').textContent = m ? String(m.n_patches) : '–';
  $('m-open').hidden = !m?.background;
  venn($('venn'), m);
  showDelta();
}

/// δ̄ = (I_S^c − I_S) / I_S^c (§4.4.2): exact I_S, Monte Carlo I_S^c.
function showDelta() {
  const m = state.measures;
  const mc = state.mc;
  const ok = m && mc && mc.samples !== 0;
  $('m-delta').textContent = ok ? `${fmt(100 * relativeDiscretisationError(mc.value, m.i_s), 2)} %` : '–';
}

// ---- Monte Carlo in the worker ---------------------------------------------------------------

function worker() {
  if (!state.worker) {
    state.worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
    state.worker.onmessage = ({ data }) => monteCarloMessage(data);
    state.worker.onerror = (e) => showError(`Monte Carlo worker: ${e.message}`);
  }
  return state.worker;
}

function startMonteCarlo({ keep = false } = {}) {
  state.job += 1;
  state.keep = keep && state.mc !== null && !state.mc.partial;
  if (state.keep) state.mc = { ...state.mc, patchContinuous: null };
  else state.mc = null;
  document.body.dataset.mc = 'running';
  document.body.dataset.mcJob = String(state.job); // the job whose end data-mc-done will name
  const lines = Number($('mc-lines').value);
  const seed = Number($('mc-seed').value);
  const method = $('mc-method').value;
  $('mc-progress').value = 0;
  $('mc-status').textContent = 'starting…';
  $('mc-stop').disabled = false;
  worker().postMessage({ type: 'run', id: state.job, text: state.text, method, seed, lines });
  showMonteCarlo();
}

function stopMonteCarlo() {
  state.worker?.postMessage({ type: 'stop', id: state.job });
}

function monteCarloMessage(data) {
  if (data.id !== state.job) return; // an older scene's job
  if (data.type === 'progress') {
    if (!state.keep) state.mc = { ...data, patchContinuous: null, partial: true };
    $('mc-progress').value = data.done / data.total;
    $('mc-status').textContent = `${data.done.toLocaleString('en')} / ${data.total.toLocaleString('en')} lines, ` +
      `${(data.done / Math.max(data.seconds, 1e-9) / 1e6).toFixed(2)} M lines/s`;
  } else if (data.type === 'done') {
    state.mc = { ...data, partial: false };
    $('mc-progress').value = data.done / data.total;
    $('mc-status').textContent = `${data.stopped ? 'stopped' : 'done'}: ${data.done.toLocaleString('en')} lines, seed ` +
      `${$('mc-seed').value}, ${data.seconds.toFixed(2)} s`;
    $('mc-stop').disabled = true;
    document.body.dataset.mc = 'done';
    document.body.dataset.mcDone = String(data.id);
    colourPatches();
  } else {
    $('mc-status').textContent = `stopped: ${data.message}`;
    $('mc-stop').disabled = true;
    document.body.dataset.mc = 'done';
    document.body.dataset.mcDone = String(data.id);
    if (state.mc) state.mc.partial = false;
    colourPatches();
  }
  showMonteCarlo();
}

function showMonteCarlo() {
  const mc = state.mc;
  $('m-isc').textContent = mc && mc.samples !== 0 ? fmt(mc.value) : '–';
  $('m-isc-err').textContent = mc && mc.samples !== 0 ? fmt(mc.stderr) : '–';
  showDelta();
}

// ---- colouring, heat map ------------------------------------------------------------------------

const COLOUR_LABELS = {
  h: 'H_i (3.2), bits',
  i: 'I_i (6.8), bits',
  ic: 'I_i^c (6.37), bits',
  delta: 'I_i^c − I_i, bits',
};

function colourPatches() {
  const mode = $('colour').value;
  let values = null;
  let note = '';
  const exact = state.measures !== null; // H_i and I_i need the exact form factors
  try {
    if (exact && mode === 'h') values = state.lab.patchEntropies();
    if (exact && mode === 'i') values = state.lab.patchInformation();
    if (!exact && (mode === 'h' || mode === 'i' || mode === 'delta')) note = 'needs the exact form factors';
    if (!note && (mode === 'ic' || mode === 'delta')) {
      const ic = state.mc?.patchContinuous;
      if (!ic) note = 'waiting for the Monte Carlo run (I_i^c)…';
      else if (mode === 'ic') values = ic;
      else {
        const i = state.lab.patchInformation();
        values = ic.map((v, k) => v - i[k]);
      }
    }
  } catch (e) {
    showError(e.message);
  }
  if (values) {
    const s = scale(values, mode === 'delta');
    editor.colours = Array.from(values, s.colour);
    colourBar($('colour-bar'), s, COLOUR_LABELS[mode]);
  } else {
    editor.colours = null;
    const c = $('colour-bar');
    c.getContext('2d').clearRect(0, 0, c.width, c.height);
  }
  $('colour-note').textContent = note;
  $('colour-bar').hidden = !values;
  editor.draw();
}

function drawHeatMap() {
  const lab = state.lab;
  const note = $('heat-note');
  if (!lab) return;
  if (lab.nPatches > HEAT_MAP_LIMIT) {
    const c = $('heat');
    c.getContext('2d').clearRect(0, 0, c.width, c.height);
    note.textContent = `not drawn above ${HEAT_MAP_LIMIT} patches`;
    return;
  }
  try {
    const max = heatMap($('heat'), lab.informationMatrix(), lab.nPatches);
    note.textContent = `${lab.nPatches} × ${lab.nPatches} patches, largest |I_ij| cell ${max.toExponential(2)} bits; ` +
      'red > 0 (more transfer than chance), blue < 0, √ scale';
  } catch (e) {
    note.textContent = e.message;
  }
}

// ---- presets, import, export, link ---------------------------------------------------------------

function fillPresets() {
  const entries = JSON.parse(catalogue());
  const select = $('preset');
  for (const [name, e] of Object.entries(entries)) {
    const option = document.createElement('option');
    option.value = name;
    option.textContent = `${name} — ${e.figure}: ${e.description}`;
    select.append(option);
  }
}

function loadPreset() {
  const name = $('preset').value;
  if (!name) return;
  try {
    const lab = FlatLab.preset(name, Number($('per-side').value));
    const model = fromLab(lab);
    lab.free();
    editor.setModel(model);
  } catch (e) {
    showError(e.message);
  }
}

/// Loads `.flat` text into the editor; errors name `source`.
function loadText(text, source) {
  let lab;
  try {
    lab = new FlatLab(text);
  } catch (e) {
    showError(`${source}: ${e.message}`);
    return false;
  }
  const model = fromLab(lab);
  lab.free();
  $('preset').value = '';
  editor.setModel(model);
  return true;
}

async function importFile(file) {
  if (!file) return;
  loadText(await file.text(), file.name);
  $('import').value = '';
}

function exportFile() {
  if (!state.lab) return;
  const blob = new Blob([state.lab.toFlat()], { type: 'text/plain' });
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = `${$('preset').value || 'scene'}.flat`;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

let hashTimer = 0;
function scheduleHash() {
  clearTimeout(hashTimer);
  hashTimer = setTimeout(async () => {
    state.hash = state.text ? `#scene=${await encodeHash(state.text)}` : '';
    history.replaceState(null, '', state.hash || location.pathname);
  }, 250);
}

async function loadHash() {
  const hash = location.hash;
  if (!hash.startsWith('#scene=') || hash === state.hash) return false;
  try {
    return loadText(await decodeHash(hash.slice('#scene='.length)), 'link');
  } catch (e) {
    showError(`link: ${e.message}`);
    return false;
  }
}

async function copyLink() {
  clearTimeout(hashTimer);
  state.hash = `#scene=${await encodeHash(state.text)}`;
  history.replaceState(null, '', state.hash);
  try {
    await navigator.clipboard.writeText(location.href);
    $('share-note').textContent = 'link copied';
  } catch {
    $('share-note').textContent = 'the address bar holds the link';
  }
  setTimeout(() => ($('share-note').textContent = ''), 2500);
}

// ---- wiring ------------------------------------------------------------------------------------

function wire() {
  for (const tool of ['select', 'segment', 'polygon']) {
    $(`tool-${tool}`).addEventListener('click', () => {
      editor.setTool(tool);
      for (const t of ['select', 'segment', 'polygon']) $(`tool-${t}`).classList.toggle('on', t === tool);
    });
  }
  $('snap').addEventListener('change', (e) => {
    editor.snap = e.target.checked;
    editor.draw();
  });
  $('two-sided').addEventListener('change', (e) => (editor.twoSided = e.target.checked));
  $('density').addEventListener('change', (e) => (editor.density = Math.max(1, Number(e.target.value) || 10)));
  $('undo').addEventListener('click', () => editor.undo());
  $('delete').addEventListener('click', () => editor.deleteSelected());
  $('flip').addEventListener('click', () => editor.flipSelected());
  $('rotate').addEventListener('click', () => editor.transformSelected(Math.PI / 12, 1));
  $('fit').addEventListener('click', () => editor.fit());
  $('preset').addEventListener('change', loadPreset);
  $('per-side').addEventListener('change', loadPreset);
  $('import').addEventListener('change', (e) => importFile(e.target.files[0]));
  $('export').addEventListener('click', exportFile);
  $('share').addEventListener('click', copyLink);
  $('colour').addEventListener('change', colourPatches);
  $('mc-run').addEventListener('click', () => state.text && startMonteCarlo());
  $('mc-stop').addEventListener('click', stopMonteCarlo);
  window.addEventListener('hashchange', loadHash);
}

async function main() {
  await init();
  editor = new Editor($('editor'), {
    onChange: (kind) => sceneChanged(kind),
    onStatus: (text) => ($('hint').textContent = text),
  });
  refinement = new Refinement({
    plot: $('refine-plot'),
    controls: {
      oracle: $('refine-oracle'), lines: $('refine-lines'), step: $('refine-step'),
      play: $('refine-play'), reset: $('refine-reset'),
    },
    out: {
      patches: $('refine-patches'), is: $('refine-is'), isc: $('refine-isc'),
      delta: $('refine-delta'), last: $('refine-last'),
    },
    text: () => state.text,
    seed: () => Number($('mc-seed').value),
    onMesh: (flat) => {
      let lab;
      try {
        lab = new FlatLab(flat);
      } catch (e) {
        showError(e.message);
        return;
      }
      editor.pushUndo();
      adoptCuts(editor.model, lab);
      lab.free();
      sceneChanged('cuts');
    },
    onError: showError,
  });
  fillPresets();
  wire();
  editor.status();
  if (!(await loadHash())) {
    $('preset').value = 'koch-0';
    loadPreset();
  }
  document.title = 'sceneinfo flatland lab';
  document.body.dataset.ready = 'yes';
}

main().catch((e) => {
  const message = e instanceof Error ? e.message : String(e);
  document.title = `sceneinfo error: ${message}`;
  showError(message);
});
