// Browser test of the TrailScope dashboard (run through run.sh, which starts the server).
// Drives the page like an analyst: picks a data set, brushes a time window, sets an altitude band,
// checks the summary against the API, the density tiles, the flight track and that nothing left the machine.

import { chromium } from 'playwright-core';
import { mkdir } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const BASE_URL = process.env.BASE_URL ?? 'http://127.0.0.1:8080';
const DATASET = process.env.DATASET ?? 'europe';
const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';
const HERE = path.dirname(fileURLToPath(import.meta.url));
const ARTIFACTS = path.join(HERE, 'artifacts');
const TIMEOUT = 30_000;
const ALT_MIN = 20000;
const ALT_MAX = 40000;

// ---------- a tiny sequential harness ----------
const results = [];
async function test(name, fn) {
  const t0 = Date.now();
  try {
    await fn();
    results.push({ name, ok: true });
    console.log(`  ok    ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    results.push({ name, ok: false });
    console.log(`  FAIL  ${name} (${Date.now() - t0} ms)\n        ${String(e?.stack ?? e).split('\n').slice(0, 4).join('\n        ')}`);
  }
}
function assert(cond, msg) {
  if (!cond) throw new Error(msg);
}
function assertEqual(actual, expected, msg) {
  if (actual !== expected) throw new Error(`${msg}: expected ${JSON.stringify(expected)}, got ${JSON.stringify(actual)}`);
}

// ---------- tile maths (XYZ, Web Mercator) ----------
function lon2x(lon, z) {
  return Math.floor(((lon + 180) / 360) * 2 ** z);
}
function lat2y(lat, z) {
  const r = (Math.max(-85.0511, Math.min(85.0511, lat)) * Math.PI) / 180;
  return Math.floor(((1 - Math.asinh(Math.tan(r)) / Math.PI) / 2) * 2 ** z);
}
/** Tiles at zoom z covering [w,s,e,n], shrunk by a hair so an edge exactly on a tile border does not count. */
function coveringTiles([w, s, e, n], z) {
  const eps = 1e-7;
  const max = 2 ** z - 1;
  const clamp = (v) => Math.max(0, Math.min(max, v));
  const x0 = clamp(lon2x(Math.max(-180, w) + eps, z));
  const x1 = clamp(lon2x(Math.min(180, e) - eps, z));
  const y0 = clamp(lat2y(n - eps, z));
  const y1 = clamp(lat2y(s + eps, z));
  const out = [];
  for (let x = x0; x <= x1; x++) for (let y = y0; y <= y1; y++) out.push(`${z}/${x}/${y}`);
  return out;
}

const LOOPBACK = new Set(['127.0.0.1', 'localhost', '[::1]', '::1']);
function leavesMachine(url) {
  const u = new URL(url);
  if (u.protocol === 'data:' || u.protocol === 'blob:' || u.protocol === 'about:') return false;
  return !LOOPBACK.has(u.hostname);
}

// ---------- run ----------
await mkdir(ARTIFACTS, { recursive: true });
const browser = await chromium.launch({
  executablePath: CHROMIUM,
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1 });
const page = await context.newPage();
page.setDefaultTimeout(TIMEOUT);

const requests = [];
const tileResponses = [];
const consoleErrors = [];
context.on('request', (r) => requests.push(r.url()));
page.on('websocket', (ws) => requests.push(ws.url()));
page.on('response', (r) => {
  if (r.url().includes('/tiles/')) tileResponses.push({ url: r.url(), status: r.status(), type: r.headers()['content-type'] ?? '' });
});
page.on('console', (m) => {
  if (m.type() === 'error') consoleErrors.push(`console: ${m.text()}`);
});
page.on('pageerror', (e) => consoleErrors.push(`pageerror: ${e.message}`));

const sel = (id) => `[data-testid="${id}"]`;
const state = { query: '', row: null };

console.log(`TrailScope dashboard test against ${BASE_URL}`);

await test('page loads and lists the data set', async () => {
  await page.goto(`${BASE_URL}/`, { waitUntil: 'domcontentloaded' });
  await page.waitForSelector(`${sel('dataset-select')} option[value="${DATASET}"]`, { state: 'attached' });
  await page.waitForFunction(() => document.querySelector('#health')?.dataset.state === 'ok');
});

await test(`pick data set ${DATASET}`, async () => {
  await page.selectOption(sel('dataset-select'), DATASET);
  await page.waitForFunction(() => document.querySelector('[data-testid="summary"]')?.dataset.state === 'ready');
  await page.waitForFunction(() => document.querySelector('[data-testid="time-brush"]')?.dataset.state === 'ready');
  const flights = Number(await page.getAttribute(sel('summary-flights'), 'data-value'));
  assert(flights > 0, `the unfiltered data set shows ${flights} flights`);
});

await test('brush a time window over the histogram with the mouse', async () => {
  const box = await page.locator(sel('time-brush')).boundingBox();
  assert(box && box.width > 100, 'the brush is laid out');
  const y = box.y + box.height * 0.5;
  await page.mouse.move(box.x + box.width * 0.35, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.5, y, { steps: 8 });
  await page.mouse.move(box.x + box.width * 0.65, y, { steps: 8 });
  await page.mouse.up();
  const t0 = Number(await page.getAttribute(sel('time-brush'), 'data-t0'));
  const t1 = Number(await page.getAttribute(sel('time-brush'), 'data-t1'));
  assert(t0 > 0 && t1 > t0, `the brush holds a window (${t0}, ${t1})`);
  const readout = await page.textContent(sel('time-window'));
  assert(readout.includes('→'), `the readout shows the window: ${readout}`);
});

await test('set an altitude band', async () => {
  await page.fill(sel('alt-min'), String(ALT_MIN));
  await page.fill(sel('alt-max'), String(ALT_MAX));
  await page.press(sel('alt-max'), 'Enter');
  await page.locator(sel('alt-max')).blur();
  await page.waitForFunction(
    ([lo, hi]) => {
      const s = document.querySelector('[data-testid="summary"]');
      const q = new URLSearchParams(s?.dataset.query ?? '');
      return s?.dataset.state === 'ready' && q.get('alt_min') === lo && q.get('alt_max') === hi && q.has('t0') && q.has('t1');
    },
    [String(ALT_MIN), String(ALT_MAX)],
  );
  state.query = await page.getAttribute(sel('summary'), 'data-query');
});

await test('summary numbers equal GET /summary with the same query', async () => {
  const q = new URLSearchParams(state.query);
  assertEqual(q.get('t0'), String(Math.floor(Number(await page.getAttribute(sel('time-brush'), 'data-t0')))), 'query t0 is the brushed start');
  assertEqual(q.get('t1'), String(Math.ceil(Number(await page.getAttribute(sel('time-brush'), 'data-t1')))), 'query t1 is the brushed end');
  assertEqual(q.get('alt_unit'), 'ft', 'altitudes are sent in feet');
  const res = await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/summary?${state.query}&bins=96`);
  assertEqual(res.status, 200, 'summary status');
  const api = await res.json();
  const shownFlights = Number(await page.getAttribute(sel('summary-flights'), 'data-value'));
  const shownPoints = Number(await page.getAttribute(sel('summary-points'), 'data-value'));
  assert(api.points > 0, `the window and band select points (${api.points})`);
  assertEqual(shownFlights, api.flights, 'flights shown');
  assertEqual(shownPoints, api.points, 'points shown');
  const text = await page.textContent(sel('summary-flights'));
  assertEqual(text.replace(/,/g, ''), String(api.flights), 'flights text');
  if (api.top_callsigns.length > 0) {
    const firstTop = await page.textContent(`${sel('summary-top-callsigns')} li:first-child .cs`);
    assertEqual(firstTop, api.top_callsigns[0].callsign, 'top callsign');
  }
  // The unfiltered data set has more points than the filtered view.
  const all = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/summary?bins=96`)).json();
  assert(all.points > api.points, `filters narrow the data (${api.points} of ${all.points})`);
});

await test('density tiles for the current view load (200 image/png)', async () => {
  await page.waitForFunction(
    (q) => {
      const m = document.querySelector('[data-testid="map"]');
      const t = m?.dataset.densityTemplate ?? '';
      return m?.dataset.idle === 'true' && m.dataset.densityLoaded === 'true' && t.includes(`?${q}&`);
    },
    state.query,
  );
  const map = await page.$(sel('map'));
  const template = await map.getAttribute('data-density-template');
  const bounds = (await map.getAttribute('data-bounds')).split(',').map(Number);
  // The map must actually be on screen (a 0-px canvas still "loads" tiles and passes queries).
  const canvas = await page.evaluate(() => {
    const c = window.trailscope.map.getCanvas();
    return { w: c.clientWidth, h: c.clientHeight };
  });
  assert(canvas.w >= 400 && canvas.h >= 300, `the map canvas is laid out (${canvas.w}×${canvas.h})`);
  assert(bounds[2] - bounds[0] > 1 && bounds[3] - bounds[1] > 1, `the view spans an area (${bounds.join(', ')})`);
  const tileQuery = template.split('?')[1];
  const re = new RegExp(`/tiles/${DATASET}/density/(\\d+)/(\\d+)/(\\d+)\\.png$`);
  const current = tileResponses
    .map((r) => ({ ...r, u: new URL(r.url) }))
    .filter((r) => r.u.search.slice(1) === tileQuery && re.test(r.u.pathname));
  assert(current.length > 0, 'tiles were requested for the current query');
  const bad = current.filter((r) => !(r.status === 200 || r.status === 304) || (r.status === 200 && !r.type.startsWith('image/png')));
  assert(bad.length === 0, `tiles failed: ${bad.map((r) => `${r.status} ${r.type} ${r.u.pathname}`).join('; ')}`);
  const ok = new Set(current.filter((r) => r.status === 200).map((r) => r.u.pathname.match(re).slice(1).join('/')));
  const z = Math.max(...[...ok].map((k) => Number(k.split('/')[0])));
  const want = coveringTiles(bounds, z);
  const missing = want.filter((k) => !ok.has(k));
  assert(missing.length === 0, `tiles of the view at z${z} not loaded: ${missing.join(', ')}`);
  console.log(`        ${ok.size} tiles at 200 image/png, view needs ${want.length} at z${z}`);
});

await test('the flight list follows the filters; clicking a flight draws its track', async () => {
  await page.waitForFunction(() => document.querySelector('[data-testid="flights"]')?.dataset.state === 'ready');
  const total = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/flights?${state.query}&page=0&page_size=1`)).json();
  const shown = await page.textContent(sel('flights-total'));
  assertEqual(shown.replace(/[^0-9]/g, ''), String(total.total), 'flight total');
  const first = page.locator(sel('flight-row')).first();
  const id = await first.getAttribute('data-flight-id');
  const callsign = (await first.locator('.cs').textContent()).trim();
  await first.click();
  await page.waitForFunction(() => document.querySelector('[data-testid="flight-card"]')?.dataset.state === 'ready');
  assertEqual((await page.textContent(sel('card-callsign'))).trim(), callsign, 'card callsign');
  await page.waitForFunction((fid) => {
    const m = document.querySelector('[data-testid="map"]');
    return m?.dataset.track === fid && m.dataset.idle === 'true';
  }, id);
  const rendered = await page.evaluate(() => {
    const map = window.trailscope.map;
    return map.getLayer('track-line') ? map.queryRenderedFeatures({ layers: ['track-line'] }).length : -1;
  });
  assert(rendered > 0, `the track layer shows on the map (${rendered} rendered segments)`);
  state.row = { id, callsign };
});

await test('no request went to a non-loopback host', async () => {
  const outside = [...new Set(requests.filter(leavesMachine))];
  assert(requests.length > 0, 'requests were recorded');
  assert(outside.length === 0, `requests left the machine: ${outside.slice(0, 5).join(', ')}`);
});

await test('no console errors', async () => {
  assert(consoleErrors.length === 0, consoleErrors.slice(0, 5).join(' | '));
});

await test('screenshot', async () => {
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'dashboard.png') });
});

await browser.close();
const passed = results.filter((r) => r.ok).length;
const failed = results.length - passed;
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
