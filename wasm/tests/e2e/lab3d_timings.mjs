// Issue 24, item 7, timed in headless Chromium: the exact measures of the 600-patch cube in
// the 3D lab, and 10^6 global lines on the Cornell box in its worker (item7.mjs says what
// each timer covers). For a quiet machine, once ./scripts/build-web.sh has built the page:
//
//   node wasm/tests/e2e/lab3d_timings.mjs [RUNS]     # RUNS defaults to 5
//
// Prints every run and the medians; asserts nothing. About 15 s on a quiet 2-core machine
// for 5 runs (the browser's start included). The page runs in one tab, the worker on a
// second thread: the numbers are the page's, not a benchmark of the core.

import { loadavg } from 'node:os';
import { openBrowser } from './harness.mjs';
import { timeItem7 } from './item7.mjs';

const runs = Math.max(1, Number(process.argv[2] ?? 5) || 5);
const loadAtStart = loadavg()[0];
const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const m = s.length >> 1;
  return s.length % 2 ? s[m] : (s[m - 1] + s[m]) / 2;
};

const browser = await openBrowser({
  viewport: { width: 1100, height: 900 },
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const { page, baseUrl, problems } = browser;
  await page.goto(`${baseUrl}lab3d.html`);
  await page.waitForFunction(() => document.getElementById('preset').options.length > 1, null, { timeout: 60_000 });
  const all = [];
  for (let k = 1; k <= runs; k++) all.push(await timeItem7(page, `run ${k}/${runs}: `));
  const line = (what, key, sub) => {
    const xs = all.map((r) => r[key][sub]);
    return `${what}: median ${median(xs).toFixed(3)} s, min ${Math.min(...xs).toFixed(3)} s, max ${Math.max(...xs).toFixed(3)} s`;
  };
  console.log(`\nissue 24, item 7, ${runs} runs (1-minute load average ${loadAtStart.toFixed(2)} at the start, ${loadavg()[0].toFixed(2)} at the end):`);
  console.log(line('cube (600 patches), exact measures in the page (budget 0.3 s)', 'cube', 'total'));
  console.log(line('  of which form factors and measures in the worker', 'cube', 'channel'));
  console.log(line('  of which per-patch values in the worker', 'cube', 'arrays'));
  console.log(line('  of which the scene read in the worker and the message', 'cube', 'moved'));
  console.log(line('  of which shown in the page', 'cube', 'shown'));
  console.log(line('cube, from the request to the I_ij heat map shown', 'cube', 'heat'));
  console.log(line('  of which I_ij in the worker', 'cube', 'matrix'));
  for (const grid of [4, 2]) {
    console.log(line(`Cornell box (grid ${grid}, ${all[0][`cornell${grid}`].patches} patches), 10^6 lines, click to measures shown (budget 2 s)`, `cornell${grid}`, 'total'));
    console.log(line('  of which in the worker (lines and measures)', `cornell${grid}`, 'worker'));
  }
  if (problems.length) {
    console.error(`page errors: ${problems.join('; ')}`);
    process.exitCode = 1;
  }
} finally {
  await browser.close();
}
