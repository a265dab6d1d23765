// The wasm API gives the CLI's numbers bit for bit (run by scripts/test.sh after the wasm
// build; needs wasm/www/pkg and the CLI binary).
//
//   SCENEINFO_BIN=target/debug/sceneinfo node --test wasm/tests/e2e/cli_parity.test.mjs
//
// Without SCENEINFO_BIN the binary is built and run with `cargo run -q -p sceneinfo-cli`.
// Loads the same pkg the page loads (wasm-bindgen --target web) into Node, runs a chunked
// FlatLab line job and compares its JSON with `sceneinfo measure --lines N --seed S --json`
// on 2 threads: every key but the timing (`seconds`, `lines_per_second`) must be the same
// text, so the same f64 bits (both sides print Rust's shortest round-trip form).

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtemp, readFile, rm, writeFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const repo = resolve(here, '..', '..', '..');
const pkg = join(repo, 'wasm', 'www', 'pkg');

const { default: init, FlatLab } = await import(join(pkg, 'sceneinfo_wasm.js'));
await init({ module_or_path: await readFile(join(pkg, 'sceneinfo_wasm_bg.wasm')) });

// Runs the CLI with `args`; returns its stdout.
function cli(args) {
  const bin = process.env.SCENEINFO_BIN;
  if (bin) return execFileSync(bin, args, { encoding: 'utf8' });
  return execFileSync('cargo', ['run', '-q', '-p', 'sceneinfo-cli', '--', ...args], {
    cwd: repo,
    encoding: 'utf8',
  });
}

// The "key":value pairs of a flat-ish JSON text, timing keys removed, as raw text so that
// numbers compare digit for digit.
function fields(json) {
  const parsed = JSON.parse(json);
  delete parsed.seconds;
  delete parsed.lines_per_second;
  return Object.fromEntries(
    Object.keys(parsed).map((k) => [k, JSON.stringify(parsed[k])]),
  );
}

// A room with a two-sided interior wall (occlusion) and a square obstacle, open nowhere.
const SCENE = `# parity scene
poly 4 0 0 3 0 3 2 0 2 per_side 5
seg 1 0.4 1 1.6 4
seg 1 1.6 1 0.4 4
poly 4 2 0.6 2 1.2 2.5 1.2 2.5 0.6 per_side 2
`;

for (const method of ['global', 'local']) {
  test(`FlatLab ${method} lines equal the CLI's JSON bit for bit`, async () => {
    const dir = await mkdtemp(join(tmpdir(), 'sceneinfo-parity-'));
    try {
      const file = join(dir, 'scene.flat');
      await writeFile(file, SCENE);
      const lines = 200_000; // 3 whole chunks of 2^16 and a partial one
      const seed = 11;
      const fromCli = cli([
        'measure', file, '--lines', String(lines), '--seed', String(seed),
        '--method', method, '--threads', '2', '--json',
      ]);
      const lab = new FlatLab(SCENE);
      const job = method === 'global' ? lab.globalLines(seed, lines) : lab.localLines(seed, lines);
      let calls = 0;
      while (!job.done) {
        job.run(1); // one chunk per call, as the page's worker does
        calls += 1;
      }
      assert.equal(calls, 4);
      const fromWasm = job.finish().json();
      assert.deepEqual(fields(fromWasm), fields(fromCli));
      assert.equal(JSON.parse(fromWasm).form_factors, `${method} lines`);
      job.free();
      lab.free();
    } finally {
      await rm(dir, { recursive: true, force: true });
    }
  });
}

test('FlatLab exact measures equal the CLI JSON bit for bit', async () => {
  const dir = await mkdtemp(join(tmpdir(), 'sceneinfo-parity-'));
  try {
    const file = join(dir, 'scene.flat');
    await writeFile(file, SCENE);
    const lab = new FlatLab(SCENE);
    assert.deepEqual(fields(lab.measures()), fields(cli(['measure', file, '--json'])));
    lab.free();
  } finally {
    await rm(dir, { recursive: true, force: true });
  }
});
