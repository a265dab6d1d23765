// The refinement player (thesis §6.5.2, Fig. 6.19): steps an oracle (DE, power or regular)
// one patch split at a time in a worker, plots I_S against the patch count with I_S^c as
// its ceiling, and hands every new mesh to the page.
import { refinementPlot } from './plots.js';

const PLAY_INTERVAL_MS = 250;

export class Refinement {
  /// `text()` is the current scene's .flat text, `seed()` the Monte Carlo seed;
  /// `onMesh(flat)` receives each refined mesh as .flat text; `onError(message)`.
  constructor({ plot, controls, out, text, seed, onMesh, onError }) {
    Object.assign(this, { plot, controls, out, text, seed, onMesh, onError });
    this.worker = null;
    this.id = 0;
    this.points = [];
    this.ceiling = null;
    this.busy = false;
    this.playing = false;
    this.started = false;
    controls.step.addEventListener('click', () => this.step());
    controls.play.addEventListener('click', () => this.togglePlay());
    controls.reset.addEventListener('click', () => this.reset());
    controls.oracle.addEventListener('change', () => this.reset());
    controls.lines.addEventListener('change', () => this.reset());
    this.show();
  }

  /// Forgets the refiner (the scene's geometry changed, or the user asked).
  reset() {
    this.id += 1;
    this.points = [];
    this.ceiling = null;
    this.busy = false;
    this.started = false;
    this.setPlaying(false);
    this.out.last.textContent = '';
    document.body.dataset.refine = 'idle';
    this.show();
  }

  ensureWorker() {
    if (!this.worker) {
      this.worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
      this.worker.onmessage = ({ data }) => this.message(data);
      this.worker.onerror = (e) => this.onError(`refinement worker: ${e.message}`);
    }
    return this.worker;
  }

  /// One split: the first call starts the refiner on the current scene.
  step() {
    if (this.busy || !this.text()) return;
    this.busy = true;
    document.body.dataset.refine = 'busy';
    const w = this.ensureWorker();
    if (!this.started) {
      this.started = true;
      const lines = Number(this.controls.lines.value);
      this.out.last.textContent = `tracing the I^c profile with ${lines.toLocaleString('en')} lines…`;
      w.postMessage({
        type: 'refine-start', id: this.id, text: this.text(), oracle: this.controls.oracle.value,
        lines, seed: this.seed(), thenStep: true,
      });
    } else {
      w.postMessage({ type: 'refine-step', id: this.id });
    }
  }

  togglePlay() {
    this.setPlaying(!this.playing);
    if (this.playing) this.tick();
  }

  setPlaying(on) {
    this.playing = on;
    this.controls.play.textContent = on ? 'Pause' : 'Play';
    clearTimeout(this.timer);
  }

  tick() {
    if (!this.playing) return;
    if (!this.busy) this.step();
    this.timer = setTimeout(() => this.tick(), PLAY_INTERVAL_MS);
  }

  message(data) {
    if (data.id !== this.id) return; // a refiner that was reset
    if (data.type === 'refine-error') {
      this.busy = false;
      this.setPlaying(false);
      this.out.last.textContent = '';
      document.body.dataset.refine = 'idle';
      this.onError(data.message);
      return;
    }
    const r = JSON.parse(data.report);
    if (this.points.length === 0 || this.points[this.points.length - 1].n !== r.n_patches) {
      this.points.push({ n: r.n_patches, i_s: r.i_s, delta: r.rel_discretisation_error });
    }
    this.ceiling = { value: r.i_s_continuous, stderr: r.i_s_continuous_stderr };
    this.out.last.textContent = r.split === undefined
      ? `start: ${r.n_patches} patches`
      : `step ${r.steps}: halved patch ${r.split} (I_i^c − I_i = ${r.split_error.toExponential(2)} bits)`;
    if (data.final) {
      this.busy = false;
      document.body.dataset.refine = 'idle';
      if (data.flat) this.onMesh(data.flat);
    }
    this.show();
  }

  show() {
    const last = this.points[this.points.length - 1];
    this.out.patches.textContent = last ? String(last.n) : '–';
    this.out.is.textContent = last ? last.i_s.toFixed(4) : '–';
    this.out.isc.textContent = this.ceiling
      ? `${this.ceiling.value.toFixed(4)} ± ${this.ceiling.stderr.toFixed(4)}` : '–';
    this.out.delta.textContent = last ? `${(100 * last.delta).toFixed(2)} %` : '–';
    refinementPlot(this.plot, this.points, this.ceiling);
  }
}
