// Headless-Chromium test of the demo page in wasm/www (run by scripts/test.sh, after the
// wasm build and `wasm-bindgen --target web --out-dir wasm/www/pkg`).
//
//   node --test wasm/tests/e2e/page.test.mjs
//
// Serves wasm/www from a node:http server on 127.0.0.1 (a free port), opens it in the
// system Chromium (CHROMIUM, default /usr/bin/chromium) through playwright-core, and checks
// the numbers the page shows against the thesis (Tables 3.4 and 3.5). Saves a screenshot
// to target/e2e/index.png (E2E_SCREENSHOT overrides).

import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { createServer } from 'node:http';
import { mkdtemp, mkdir, readFile, rm } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { dirname, extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const repo = resolve(here, '..', '..', '..');
const www = join(repo, 'wasm', 'www');
const screenshot = process.env.E2E_SCREENSHOT ?? join(repo, 'target', 'e2e', 'index.png');
const executablePath = process.env.CHROMIUM ?? '/usr/bin/chromium';

const types = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.wasm': 'application/wasm',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
};

let server;
let context;
let userDataDir;
let page;
let baseUrl;
const problems = []; // console errors and uncaught page errors: any of them fails the run

// Serves static files from `www` only (no directory escape).
async function serve(req, res) {
  const path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
  const file = normalize(join(www, path.endsWith('/') ? `${path}index.html` : path));
  if (!file.startsWith(www + sep)) {
    res.writeHead(403).end();
    return;
  }
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': types[extname(file)] ?? 'application/octet-stream' });
    res.end(body);
  } catch {
    res.writeHead(404).end('not found');
  }
}

before(async () => {
  server = createServer((req, res) => void serve(req, res));
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  baseUrl = `http://127.0.0.1:${server.address().port}/`;

  userDataDir = await mkdtemp(join(tmpdir(), 'sceneinfo-e2e-'));
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath,
    headless: true,
    viewport: { width: 900, height: 900 },
    args: [
      '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
    ],
  });
  page = context.pages()[0] ?? (await context.newPage());
  page.on('console', (msg) => {
    if (msg.type() === 'error') problems.push(`console.error: ${msg.text()}`);
  });
  page.on('pageerror', (err) => problems.push(`page error: ${err.message}`));
});

after(async () => {
  await context?.close();
  await new Promise((ok) => (server ? server.close(ok) : ok()));
  if (userDataDir) await rm(userDataDir, { recursive: true, force: true });
});

test('the page loads the wasm module and shows the triangle measures', async () => {
  await page.goto(baseUrl);
  await page.waitForFunction(() => document.title.startsWith('sceneinfo ') &&
    !document.title.includes('loading'), null, { timeout: 30_000 });
  const title = await page.title();
  assert.equal(title, 'sceneinfo ready', `page failed: ${title}; ${problems.join('; ')}`);

  // Thesis Table 3.4 / 3.5: equilateral triangle, 10 patches per side.
  assert.equal(await page.textContent('#h_s'), '3.739');
  assert.equal(await page.textContent('#i_s'), '1.168');
  // The textarea starts with the same scene, measured.
  assert.equal(await page.textContent('#m_n_patches'), '30');

  await mkdir(dirname(screenshot), { recursive: true });
  await page.screenshot({ path: screenshot, fullPage: true });
  console.log(`screenshot: ${screenshot}`);
});

test('a malformed scene shows the core error message', async () => {
  await page.fill('#scene', 'seg 0 0 1 0 4\nseg 0 0 one 1\n');
  await page.click('#measure');
  const error = await page.textContent('#error');
  assert.match(error, /^line 2: /, `error shown: ${error}`);
  assert.equal(await page.locator('#measures tr').count(), 0);
});

test('a pasted scene is measured', async () => {
  // A unit square room, counter-clockwise, 4 patches per side.
  await page.fill('#scene', '# square\npoly 4 0 0 1 0 1 1 0 1 per_side 4\n');
  await page.click('#measure');
  assert.equal(await page.textContent('#error'), '');
  assert.equal(await page.textContent('#m_n_patches'), '16');
  const hs = Number(await page.textContent('#m_h_s'));
  assert.ok(Number.isFinite(hs) && hs > 0, `h_s = ${hs}`);
  // A closed room: rows sum to one, nested report fields get their own rows.
  assert.equal(await page.textContent('#m_checks_row_stochastic'), 'true');
});

test('no console errors or uncaught exceptions', () => {
  assert.deepEqual(problems, []);
});
