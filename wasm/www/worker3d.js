// The 3D lab's worker: every long computation off the main thread (the 3D module, pkg3d).
//
// In:  { type: 'load', id, source }        source: see scene3d.js
//      { type: 'exact', id }               exact measures (unoccluded scenes)
//      { type: 'lines', id, seed, lines, method }  Monte Carlo, chunk by chunk (2^16 lines each)
//      { type: 'stop', id }                stops the running line job after its chunk
//      { type: 'radiosity', id, lines, seed }
//      { type: 'viewpoints', id, views, resolution, best }
//      { type: 'refine-start', id, oracle, pairs, lines, seed, exposure }  the refinement player
//      { type: 'refine-step', id, exposure }, { type: 'refine-mesh', id, exposure }
// Out: { type: 'progress' | 'measures' | 'matrix' | 'light' | 'views' | 'refined' | 'error', id, … }
// Measures carry H_i, I_i, I_i^c per patch; up to HEAT_MAP_LIMIT patches a 'matrix' message
// with I_ij follows them.
import init, { Lab3 } from './pkg3d/sceneinfo_wasm.js';
import { HEAT_MAP_LIMIT, labOf } from './scene3d.js';

const ready = init();
let lab = null;
let current = null; // the running line job: { id, stop }
let refiner = null; // the refinement player's Refiner3

// Lets queued messages ('stop', a newer job) in between chunks: a message to itself, not
// setTimeout(0), which browsers clamp to 4 ms once timers nest five deep (a 10^7-line job
// would wait 0.6 s in all).
const tick = new MessageChannel();
const ticks = [];
tick.port1.onmessage = () => ticks.shift()?.();
const breathe = () => new Promise((resolve) => {
  ticks.push(resolve);
  tick.port2.postMessage(null);
});
const messageOf = (e) => (e instanceof Error ? e.message : String(e));

// Posts measurement `m` (then freed) with `extra`, then its I_ij matrix in a second
// message { type: 'matrix', id, kind: extra.kind, matrix, seconds } (scenes up to
// HEAT_MAP_LIMIT patches), so that the measures are shown while it is computed. Arrays are
// moved, not copied (the matrix of 1024 patches is 8 MiB). `arraysSeconds`: the time of
// the per-patch values.
function postMeasures(id, m, extra) {
  try {
    const start = performance.now();
    const ic = m.patchContinuous();
    const out = {
      type: 'measures', id, json: m.json(), h: m.patchEntropies(), i: m.patchInformation(),
      ic: ic.length ? ic : null, ...extra,
    };
    out.arraysSeconds = (performance.now() - start) / 1000;
    postMessage(out, [out.h, out.i, out.ic].filter((a) => a).map((a) => a.buffer));
    if (lab.nPatches <= HEAT_MAP_LIMIT) {
      const t = performance.now();
      const matrix = m.informationMatrix(HEAT_MAP_LIMIT);
      const seconds = (performance.now() - t) / 1000;
      postMessage({ type: 'matrix', id, kind: extra.kind, matrix, seconds }, [matrix.buffer]);
    }
  } finally {
    m.free();
  }
}

// The refiner's current report and mesh (leaves Gouraud shaded, with their edges).
function refinedMessage(id, req, report, exposure) {
  const mesh = refiner.mesh(exposure);
  const out = {
    type: 'refined', id, req, report, positions: mesh.positions(), colours: mesh.colours(),
    edges: mesh.edges(),
  };
  mesh.free();
  return out;
}

async function lines({ id, seed, lines: count, method }) {
  const me = { id, stop: false };
  current = me;
  let job;
  try {
    const start = performance.now();
    job = lab.lineJob(seed, count, method);
    while (!job.done && !me.stop && current === me) {
      job.run(1);
      postMessage({
        type: 'progress', id, done: job.linesDone, total: job.linesTotal,
        value: job.value, stderr: job.stderr,
      });
      await breathe();
    }
    if (current !== me) return;
    // seconds: the job from its start to its measures (the per-patch values and I_ij after)
    const m = job.finish();
    const seconds = (performance.now() - start) / 1000;
    postMeasures(id, m, { kind: 'lines', stopped: !job.done, done: job.linesDone, seconds });
  } catch (e) {
    if (current === me) postMessage({ type: 'error', id, message: messageOf(e) });
  } finally {
    job?.free();
  }
}

onmessage = async ({ data }) => {
  await ready;
  const { id, req } = data;
  if (data.type === 'stop') {
    if (current && current.id === id) current.stop = true;
    return;
  }
  if (data.type === 'lines') {
    lines(data);
    return;
  }
  try {
    if (data.type === 'load') {
      current = null; // a new scene ends the running line job
      refiner?.free();
      refiner = null;
      lab?.free();
      lab = null;
      lab = labOf(Lab3, data.source);
      postMessage({ type: 'loaded', id, req, n: lab.nPatches });
    } else if (data.type === 'exact') {
      // seconds: form factors and the channel's measures; then the arrays (postMeasures)
      const start = performance.now();
      const m = lab.exact();
      postMeasures(id, m, { kind: 'exact', req, seconds: (performance.now() - start) / 1000 });
    } else if (data.type === 'radiosity') {
      const start = performance.now();
      const light = lab.radiosity(data.lines, data.seed);
      const radiosity = light.patchRadiosity();
      postMessage({
        type: 'light', id, req, json: light.json(), radiosity,
        seconds: (performance.now() - start) / 1000,
      }, [radiosity.buffer]);
      light.free();
    } else if (data.type === 'viewpoints') {
      const start = performance.now();
      const json = lab.viewpoints(data.views, data.resolution, data.best);
      postMessage({ type: 'views', id, req, json, seconds: (performance.now() - start) / 1000 });
    } else if (data.type === 'refine-start') {
      refiner?.free();
      refiner = null;
      const start = performance.now();
      refiner = lab.refiner(data.oracle, data.pairs, data.lines, data.seed);
      const message = refinedMessage(id, req, refiner.reportJson(), data.exposure);
      postMessage({ ...message, seconds: (performance.now() - start) / 1000 });
    } else if (data.type === 'refine-step') {
      const start = performance.now();
      const report = refiner.step();
      const message = refinedMessage(id, req, report, data.exposure);
      postMessage({ ...message, seconds: (performance.now() - start) / 1000 });
    } else if (data.type === 'refine-mesh') {
      postMessage(refinedMessage(id, req, refiner.reportJson(), data.exposure));
    }
  } catch (e) {
    postMessage({ type: 'error', id, req, message: messageOf(e) });
  }
};
