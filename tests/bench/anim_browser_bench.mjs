// Browser frames/s of TrailScope's animation layer against deck.gl's TripsLayer, in the same headless
// Chromium (WebGL through SwiftShader, the flags of tests/e2e/harness.mjs), the same page and viewport
// (1280×720), on the same seeded synthetic trips (generated in the page: N aircraft flying at once over
// Europe, a sample every 20 s, 25 minutes each), with 120 s tails, at 5k, 25k and 100k aircraft.
// TrailScope's layer gets the trips as TSAN chunks of 300 s (encoded in the page before its clock starts,
// like the server's answers); TripsLayer gets every trip at once (path + timestamps), the usual way.
// Each run is a fresh page: time to first frame, frames/s over a 10× playback (between the first and the
// last frame of a run of at least --seconds and five frames), and the JS heap.
//
//   node tests/bench/anim_browser_bench.mjs [--sizes 5000,25000,100000] [--tail 120] [--seconds 8]
//                                           [--modes empty,trailscope,deckchunks,trips] [--page DIR]
// (mode "empty" is the map without a layer, once: the frame loop's ceiling in this browser; "deckchunks"
// draws TrailScope's chunks and CPU positions with deck.gl layers instead of the custom WebGL2 layer)
// Prints one JSON line per run: {"bench":"anim_browser","mode","n","tail","samples","ttff_ms","frames",
// "seconds","fps","heap_mb","drawn","browser","viewport"} or {..., "error": why}.
// Packages: tests/bench/peers (npm ci there); the page is built with web's Vite (web/node_modules).
// Environment: CHROMIUM (default /usr/bin/chromium).
import { spawnSync } from 'node:child_process';
import { createServer } from 'node:http';
import { existsSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, '../..');
const require = createRequire(path.join(here, 'peers', 'package.json'));
const { chromium } = require('playwright-core');

const args = {};
for (let i = 2; i < process.argv.length; i++) {
  const a = process.argv[i];
  if (a.startsWith('--')) args[a.slice(2)] = process.argv[i + 1] && !process.argv[i + 1].startsWith('--') ? process.argv[++i] : '1';
}
const sizes = (args.sizes ?? '5000,25000,100000').split(',').map(Number);
const modes = (args.modes ?? 'empty,trailscope,deckchunks,trips').split(',');
const tail = Number(args.tail ?? 120);
const seconds = Number(args.seconds ?? 8);
const pageDir = path.resolve(args.page ?? path.join(root, 'tests/bench/out/anim-page'));
const VIEW = { width: 1280, height: 720 };

// Build the page (web's Vite, the config beside the page's sources).
const vite = path.join(root, 'web/node_modules/.bin/vite');
if (!existsSync(vite)) throw new Error('web/node_modules is missing: npm ci in web/');
const b = spawnSync(vite, ['build', '--config', path.join(here, 'peers/anim/vite.config.mjs')], {
  cwd: root, env: { ...process.env, ANIM_PAGE_OUT: pageDir }, encoding: 'utf8',
});
if (b.status !== 0) throw new Error(`page build failed:\n${b.stdout}\n${b.stderr}`);

const types = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.css': 'text/css' };
const server = createServer((req, res) => {
  const p = path.join(pageDir, decodeURIComponent(new URL(req.url, 'http://x').pathname));
  if (!p.startsWith(pageDir) || !existsSync(p) || p === pageDir) {
    res.writeHead(404).end();
    return;
  }
  const file = p.endsWith('/') ? path.join(p, 'index.html') : p;
  res.writeHead(200, { 'content-type': types[path.extname(file)] ?? 'application/octet-stream' }).end(readFileSync(file));
});
await new Promise((r) => server.listen(0, '127.0.0.1', r));
const base = `http://127.0.0.1:${server.address().port}`;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--enable-precise-memory-info', '--js-flags=--max-old-space-size=8192'],
});
const version = browser.version();
for (const n of sizes) {
  for (const mode of modes) {
    if (mode === 'empty' && n !== sizes[0]) continue; // the map alone does not depend on N
    const ctx = await browser.newContext({ viewport: VIEW, deviceScaleFactor: 1 });
    const page = await ctx.newPage();
    page.setDefaultTimeout(180_000);
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
    const line = { bench: 'anim_browser', mode, n, tail, browser: `Chromium ${version} (SwiftShader)`, viewport: `${VIEW.width}x${VIEW.height}` };
    try {
      await page.goto(`${base}/index.html?mode=${mode}&n=${n}&tail=${tail}`);
      await page.waitForFunction(() => window.benchReady === true);
      const r = await page.evaluate((s) => window.benchRun({ seconds: s }), seconds);
      Object.assign(line, r, { fps: Math.round(r.fps * 100) / 100 });
      if (errors.length) line.page_errors = errors.slice(0, 3);
      // A screenshot is a courtesy: a page too slow to draw one keeps its numbers.
      await page.screenshot({ path: path.join(path.dirname(pageDir), `anim_${mode}_${n}.png`), timeout: 60_000 }).catch(() => {});
    } catch (e) {
      line.error = String(e?.message ?? e).split('\n')[0];
      if (errors.length) line.page_errors = errors.slice(0, 3);
    }
    console.log(JSON.stringify(line));
    await ctx.close();
  }
}
await browser.close();
server.close();
