// The page's worker: long computations off the main thread, so the page never freezes.
//
// Monte Carlo: casts a line job chunk by chunk (2^16 lines each), posting the running I_S^c
// after every chunk. In: { type: 'run', id, text, method, seed, lines }, { type: 'stop', id }.
// Out: 'progress', then 'done' (with the per-patch I_i^c) or 'error'.
//
// Refinement: in { type: 'refine-start', id, text, oracle, lines, seed, thenStep } and
// { type: 'refine-step', id }; out 'refine-report' (the report JSON, and with `final` the
// mesh as .flat text) or 'refine-error'.
import init, { FlatLab } from './pkg/sceneinfo_wasm.js';

const ready = init();
let current = null; // { id, stop }

// Lets queued messages ('stop', a newer 'run') in between chunks.
const breathe = () => new Promise((resolve) => setTimeout(resolve, 0));

async function run({ id, text, method, seed, lines }) {
  await ready;
  const me = { id, stop: false };
  current = me;
  let lab;
  let job;
  try {
    lab = new FlatLab(text);
    const start_job = { local: 'localLines', bundle: 'bundleLines' }[method] ?? 'globalLines';
    job = lab[start_job](seed, lines);
    const start = performance.now();
    while (!job.done && !me.stop && current === me) {
      job.run(1);
      postMessage({
        type: 'progress', id, done: job.linesDone, total: job.linesTotal,
        value: job.value, stderr: job.stderr, samples: job.samples,
        seconds: (performance.now() - start) / 1000,
      });
      await breathe();
    }
    if (current !== me) return; // superseded by a newer job: its result is not wanted
    const seconds = (performance.now() - start) / 1000;
    const result = job.finish();
    const patchContinuous = result.patchContinuous();
    postMessage({
      type: 'done', id, json: result.json(), patchContinuous, stopped: !job.done,
      value: job.value, stderr: job.stderr, done: job.linesDone, total: job.linesTotal, seconds,
    }, [patchContinuous.buffer]);
    result.free();
  } catch (e) {
    if (current === me) {
      postMessage({ type: 'error', id, message: e instanceof Error ? e.message : String(e) });
    }
  } finally {
    job?.free();
    lab?.free();
  }
}

// ---- the refinement player's refiner ----------------------------------------------------

let refiner = null; // { id, inner: Refiner }

async function refine(data) {
  await ready;
  const { id } = data;
  try {
    if (data.type === 'refine-start') {
      refiner?.inner.free();
      refiner = null;
      const lab = new FlatLab(data.text);
      try {
        refiner = { id, inner: lab.refiner(data.oracle, data.lines, data.seed) };
      } finally {
        lab.free();
      }
      postMessage({ type: 'refine-report', id, report: refiner.inner.report(), final: !data.thenStep });
      if (!data.thenStep) return;
    }
    if (!refiner || refiner.id !== id) return;
    const report = refiner.inner.step();
    postMessage({ type: 'refine-report', id, report, flat: refiner.inner.toFlat(), final: true });
  } catch (e) {
    postMessage({ type: 'refine-error', id, message: e instanceof Error ? e.message : String(e) });
  }
}

onmessage = ({ data }) => {
  if (data.type === 'run') run(data);
  else if (data.type === 'stop' && current && current.id === data.id) current.stop = true;
  else if (data.type === 'refine-start' || data.type === 'refine-step') refine(data);
};
