// Issue 24, item 7: the two timed cases of the 3D lab, as a user meets them, on a page
// that lab3d.html is open in (Chromium). Printed, never asserted (speed is not a test).
//
//   - the exact measures of the 600-patch cube (preset `cube`, grid 10) in the page: from
//     the page's request to the measures shown (the worker computes the form factors and
//     the measures, then the per-patch values, and sends them), and to the I_ij heat map
//     shown (the worker computes I_ij after sending the measures);
//   - 10^6 global lines on the Cornell box (preset `cornell`, grid 4 as the page opens it,
//     and grid 2, the 49 patches of earlier sessions' timings) in the worker: from the click
//     on "Run lines" to the measures shown (the worker's part beside it).
//
// Used by lab3d.test.mjs (one run, in scripts/test.sh's browser stage) and by
// lab3d_timings.mjs (several runs and their medians: the command for a quiet machine).

// Waits until `document.body.dataset[key]` changes from what it was before `action`.
async function andWait(page, key, action, timeout) {
  const before = await page.evaluate((k) => document.body.dataset[k] ?? '', key);
  await action();
  await page.waitForFunction(([k, b]) => (document.body.dataset[k] ?? '') !== b, [key, before], { timeout });
}

// Opens preset `name` at `grid` through the page's controls (a change of preset or grid
// reloads the scene).
async function openPreset(page, name, grid, timeout) {
  await page.fill('#grid', String(grid));
  if ((await page.inputValue('#preset')) === name) {
    await andWait(page, 'ready', () => page.dispatchEvent('#grid', 'change'), timeout);
  } else {
    await andWait(page, 'ready', () => page.selectOption('#preset', name), timeout);
  }
}

/// Times the cube's exact measures, then 10^6 lines on the Cornell box at grids 4 and 2:
/// returns `{ cube, cornell4, cornell2 }`, the page's `lab3d.timing` entries, and prints
/// each as it comes with `label`.
export async function timeItem7(page, label = '', timeout = 300_000) {
  // Leave any cube open first, so that the cube is loaded (and measured) afresh
  await openPreset(page, 'tetrahedron', 1, timeout);
  await openPreset(page, 'cube', 10, timeout);
  await page.waitForFunction(() => /^exact measures in.*heat map/.test(document.getElementById('m-note').textContent), null, { timeout });
  const cube = await page.evaluate(() => window.lab3d.timing.exact);
  if (cube.patches !== 600) throw new Error(`the cube has ${cube.patches} patches, not 600`);
  console.log(`${label}cube, 600 patches: ${await page.textContent('#m-note')}`);
  const out = { cube };
  for (const grid of [4, 2]) {
    await openPreset(page, 'cornell', grid, timeout);
    await page.selectOption('#mc-lines', '1000000');
    await andWait(page, 'lines', () => page.click('#mc-run'), timeout);
    const status = await page.textContent('#mc-status');
    if (!/^done: 1,000,000 lines/.test(status)) throw new Error(`the line job did not finish: ${status}`);
    const t = await page.evaluate(() => window.lab3d.timing.lines);
    console.log(`${label}Cornell box (grid ${grid}, ${t.patches} patches): ${status}`);
    out[`cornell${grid}`] = t;
  }
  return out;
}
