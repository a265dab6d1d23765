// The 3D lab's worker: every long computation off the main thread (the 3D module, pkg3d).
//
// In:  { type: 'load', id, source }        source = { preset, grid } | { name, bytes, mtl: [[name, text]…] }
//      { type: 'exact', id }               exact measures (unoccluded scenes)
//      { type: 'lines', id, seed, lines }  Monte Carlo, chunk by chunk (2^16 lines each)
//      { type: 'stop', id }                stops the running line job after its chunk
//      { type: 'radiosity', id, lines, seed }
//      { type: 'viewpoints', id, views, resolution, best }
// Out: { type: 'progress' | 'measures' | 'light' | 'views' | 'error', id, … }
import init, { Lab3 } from './pkg3d/sceneinfo_wasm.js';

const ready = init();
let lab = null;
let current = null; // the running line job: { id, stop }

// Lets queued messages ('stop', a newer job) in between chunks.
const breathe = () => new Promise((resolve) => setTimeout(resolve, 0));
const messageOf = (e) => (e instanceof Error ? e.message : String(e));

function measuresMessage(id, m, extra) {
  const out = {
    type: 'measures', id, json: m.json(), h: m.patchEntropies(), i: m.patchInformation(),
    ic: m.patchContinuous(), ...extra,
  };
  m.free();
  return out;
}

async function lines({ id, seed, lines: count }) {
  const me = { id, stop: false };
  current = me;
  let job;
  try {
    job = lab.lineJob(seed, count);
    const start = performance.now();
    while (!job.done && !me.stop && current === me) {
      job.run(1);
      postMessage({
        type: 'progress', id, done: job.linesDone, total: job.linesTotal,
        value: job.value, stderr: job.stderr,
      });
      await breathe();
    }
    if (current !== me) return;
    const seconds = (performance.now() - start) / 1000;
    postMessage(measuresMessage(id, job.finish(), { stopped: !job.done, done: job.linesDone, seconds }));
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
      lab?.free();
      lab = null;
      const s = data.source;
      lab = s.preset
        ? Lab3.preset(s.preset, s.grid)
        : Lab3.fromFile(s.name, s.bytes, s.mtl.map((m) => m[0]), s.mtl.map((m) => m[1]), s.emitFromKa);
      postMessage({ type: 'loaded', id, req, n: lab.nPatches });
    } else if (data.type === 'exact') {
      const start = performance.now();
      const m = lab.exact();
      postMessage(measuresMessage(id, m, { req, seconds: (performance.now() - start) / 1000 }));
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
    }
  } catch (e) {
    postMessage({ type: 'error', id, req, message: messageOf(e) });
  }
};
