// What the two page tests (page.test.mjs: the flatland lab; lab3d.test.mjs: the 3D lab)
// share: a static server of wasm/www on 127.0.0.1 (a free port), the system Chromium
// (CHROMIUM, default /usr/bin/chromium) through playwright-core in a throw-away profile, and
// the list of console errors and uncaught page errors, any of which fails a run.

import { createServer } from 'node:http';
import { mkdtemp, readFile, rm } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { dirname, extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
/// The repository's root.
export const repo = resolve(here, '..', '..', '..');
/// The pages' folder.
export const www = join(repo, 'wasm', 'www');

const types = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.wasm': 'application/wasm',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
};

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

/// Starts the server and Chromium: `{ baseUrl, context, page, work, problems, watch, close }`.
/// `work` is a temporary folder (removed by `close`); `watch(page)` adds a page's errors to
/// `problems`. `args` are Chromium's flags beyond the common ones.
export async function openBrowser({ viewport, args = [] }) {
  const server = createServer((req, res) => void serve(req, res));
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  const baseUrl = `http://127.0.0.1:${server.address().port}/`;
  const work = await mkdtemp(join(tmpdir(), 'sceneinfo-e2e-'));
  const context = await chromium.launchPersistentContext(join(work, 'profile'), {
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    viewport,
    args: [
      '--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', ...args,
    ],
  });
  const problems = [];
  const watch = (p) => {
    p.on('console', (msg) => {
      if (msg.type() === 'error') problems.push(`console.error: ${msg.text()}`);
    });
    p.on('pageerror', (err) => problems.push(`page error: ${err.message}`));
  };
  const page = context.pages()[0] ?? (await context.newPage());
  watch(page);
  const close = async () => {
    await context.close();
    await new Promise((ok) => server.close(ok));
    await rm(work, { recursive: true, force: true });
  };
  return { baseUrl, context, page, work, problems, watch, close };
}
