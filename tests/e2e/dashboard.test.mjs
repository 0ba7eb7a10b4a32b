// Browser test of the TrailScope flight dashboard (run through run.sh, which starts the server).
// Drives the page like an analyst: picks a data set, brushes a time window, sets an altitude band,
// checks the summary against the API, the density tiles, the flight track and that nothing left the machine.

import { ARTIFACTS, BASE_URL, TIMEOUT, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test } from './harness.mjs';
import path from 'node:path';

const DATASET = process.env.DATASET ?? 'europe';
const ALT_MIN = 20000;
const ALT_MAX = 40000;

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

// ---------- run ----------
const browser = await launchBrowser();
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
recordErrors(page, consoleErrors);

const state = { query: '', row: null, bundle: null };

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

// ---------- bundling ----------
// Frankfurt airport: many trails of the window start or end there, and bundling keeps endpoints fixed,
// so the bundled tiles and the client-side overlay must both draw at its pixel if they are georeferenced
// like the basemap.
const FRA = [8.5706, 50.0333];
const bundlePanel = '#bundle-section';

await test('bundle this window: progress over the WebSocket reaches done', async () => {
  // The whole altitude range (trails reach the airports) in a view around Frankfurt, no flight selected.
  await page.keyboard.press('Escape');
  await page.fill(sel('alt-min'), '');
  await page.fill(sel('alt-max'), '');
  await page.press(sel('alt-max'), 'Enter');
  await page.locator(sel('alt-max')).blur();
  await page.evaluate(([lng, lat]) => window.trailscope.map.jumpTo({ center: [lng, lat], zoom: 5 }), FRA);
  await page.waitForFunction(() => {
    const s = document.querySelector('[data-testid="summary"]');
    const q = new URLSearchParams(s?.dataset.query ?? '');
    return s?.dataset.state === 'ready' && !q.has('alt_min') && q.has('t0');
  });
  await page.waitForSelector(`${sel('bundle-param-iterations')}`);
  await page.fill(sel('bundle-param-iterations'), '10');
  // Record every state and progress value the panel shows (they come from WebSocket job events).
  await page.evaluate((panel) => {
    const el = document.querySelector(panel);
    window.__bundleSeen = [];
    new MutationObserver(() => {
      const bar = el.querySelector('[data-testid="bundle-progress"]');
      window.__bundleSeen.push({ state: el.dataset.state, pct: Number(bar?.getAttribute('aria-valuenow') ?? -1) });
    }).observe(el, { subtree: true, attributes: true, childList: true });
  }, bundlePanel);
  await page.click(sel('bundle-start'));
  await page.waitForFunction((panel) => {
    const el = document.querySelector(panel);
    return el?.dataset.state === 'done' && el.dataset.bundle && el.dataset.mode === 'bundled';
  }, bundlePanel, { timeout: 120_000 });
  const seen = await page.evaluate(() => window.__bundleSeen);
  assert(seen.some((s) => s.state === 'queued' || s.state === 'running'), `the job was seen before it ended: ${JSON.stringify(seen.slice(0, 5))}`);
  const last = seen[seen.length - 1];
  assertEqual(last.pct, 100, 'progress at the end');
  const pcts = seen.filter((s) => s.state === 'running').map((s) => s.pct);
  assert(pcts.every((p, i) => i === 0 || p >= pcts[i - 1]), `progress never goes back: ${pcts.join(',')}`);
  const id = await page.getAttribute(bundlePanel, 'data-bundle');
  const meta = await (await fetch(`${BASE_URL}/api/v1/bundles/${id}`)).json();
  assertEqual(meta.source.dataset, DATASET, 'the bundle is of the data set');
  assert(meta.polylines > 100, `the window holds trails (${meta.polylines})`);
  assertEqual(meta.params.iterations, '10', 'the panel sent its parameter');
  const ink = await page.textContent(sel('bundle-ink'));
  assertEqual(ink, `${(100 * meta.quality.ink_reduction).toFixed(1)} %`, 'ink reduction shown');
  state.bundle = meta;
  console.log(`        ${meta.polylines} trails, ${meta.points} points, ink −${ink}, ${meta.times_ms.total.toFixed(0)} ms on ${meta.path}`);
});

/** Alpha values in a (2r+1)² window of the overlay canvas around a lon/lat. */
async function overlayAlphaAt(lngLat, r = 3) {
  return page.evaluate(
    ([ll, rad]) => {
      const c = document.querySelector('[data-testid="bundle-overlay"]');
      const p = window.trailscope.map.project(ll);
      const dpr = window.devicePixelRatio || 1;
      const d = c.getContext('2d').getImageData(Math.round(p.x * dpr) - rad, Math.round(p.y * dpr) - rad, 2 * rad + 1, 2 * rad + 1).data;
      let max = 0;
      for (let i = 3; i < d.length; i += 4) max = Math.max(max, d[i]);
      return max;
    },
    [lngLat, r],
  );
}

await test('bundled tiles and overlay line up with the basemap (Frankfurt airport pixel)', async () => {
  await page.waitForFunction(() => {
    const m = document.querySelector('[data-testid="map"]');
    return m?.dataset.idle === 'true' && m.dataset.bundleLoaded === 'true' && m.dataset.densityShown === 'false';
  });
  const template = await page.getAttribute(sel('map'), 'data-bundle-template');
  assert(template.includes(`/tiles/${DATASET}/bundle/${state.bundle.id}/{z}/{x}/{y}.png`), `bundle tiles shown: ${template}`);
  const current = tileResponses.filter((r) => r.url.includes(`/bundle/${state.bundle.id}/`));
  assert(current.length > 0 && current.every((r) => r.status === 200 || r.status === 304), `bundle tiles load: ${current.map((r) => r.status).join(',')}`);
  // The tile holding the airport, fetched as the map does, has ink at the airport's pixel.
  const z = 5;
  const n = 2 ** z;
  const fx = ((FRA[0] + 180) / 360) * n;
  const fy = ((1 - Math.asinh(Math.tan((FRA[1] * Math.PI) / 180)) / Math.PI) / 2) * n;
  const url = template.replace('{z}', z).replace('{x}', Math.floor(fx)).replace('{y}', Math.floor(fy));
  const tileAlpha = await page.evaluate(
    async ([u, px, py]) => {
      const img = await createImageBitmap(await (await fetch(u)).blob());
      const c = new OffscreenCanvas(img.width, img.height);
      const ctx = c.getContext('2d');
      ctx.drawImage(img, 0, 0);
      const d = ctx.getImageData(Math.round(px) - 2, Math.round(py) - 2, 5, 5).data;
      let max = 0;
      for (let i = 3; i < d.length; i += 4) max = Math.max(max, d[i]);
      return max;
    },
    [url, (fx % 1) * 256, (fy % 1) * 256],
  );
  assert(tileAlpha > 0, `the bundle tile draws at Frankfurt airport (alpha ${tileAlpha})`);
  assertEqual(await page.getAttribute(sel('bundle-overlay'), 'data-drawn'), 'true', 'the overlay is drawn');
  const overlayAlpha = await overlayAlphaAt(FRA);
  assert(overlayAlpha > 0, `the overlay draws at Frankfurt airport (alpha ${overlayAlpha})`);
});

await test('raw/bundled toggle and the relaxation slider (no recomputation)', async () => {
  const jobsBefore = (await (await fetch(`${BASE_URL}/api/v1/jobs`)).json()).jobs.length;
  const polylineRequests = () => requests.filter((u) => u.includes('/polylines')).length;
  const fetchedBefore = polylineRequests();
  await page.click('label[for="bundle-mode-raw"]');
  await page.waitForFunction(() => {
    const m = document.querySelector('[data-testid="map"]');
    const o = document.querySelector('[data-testid="bundle-overlay"]');
    return m.dataset.densityShown === 'true' && m.dataset.bundleTemplate === '' && o.dataset.drawn === 'false';
  });
  await page.click('label[for="bundle-mode-bundled"]');
  await page.waitForFunction(() => document.querySelector('[data-testid="bundle-overlay"]')?.dataset.drawn === 'true');
  const pixels = () =>
    page.evaluate(() => {
      const c = document.querySelector('[data-testid="bundle-overlay"]');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let h = 0;
      for (let i = 3; i < d.length; i += 4 * 7) h = (h * 31 + d[i]) >>> 0;
      return h;
    });
  const bundled = await pixels();
  for (const v of ['0.5', '1']) {
    await page.evaluate((val) => {
      const s = document.querySelector('[data-testid="bundle-relaxation"]');
      s.value = val;
      s.dispatchEvent(new Event('input', { bubbles: true }));
    }, v);
    await page.waitForFunction((val) => document.querySelector('[data-testid="bundle-overlay"]')?.dataset.relaxation === Number(val).toFixed(2), v);
  }
  const raw = await pixels();
  assert(raw !== bundled, 'the overlay moved with the slider');
  // Relaxed fully, the trails are the raw ones: still through the airport.
  assert((await overlayAlphaAt(FRA)) > 0, 'the relaxed overlay still reaches Frankfurt');
  // The tiles follow once the slider rests, with the same bundle (a new render, not a new bundling).
  await page.waitForFunction(() => {
    const m = document.querySelector('[data-testid="map"]');
    return m.dataset.bundleTemplate.includes('relaxation=1.00') && m.dataset.idle === 'true' && m.dataset.bundleLoaded === 'true';
  });
  const jobsAfter = (await (await fetch(`${BASE_URL}/api/v1/jobs`)).json()).jobs.length;
  assertEqual(jobsAfter, jobsBefore, 'no new job for the slider');
  assertEqual(polylineRequests(), fetchedBefore, 'the polylines were fetched once');
  await page.evaluate(() => {
    const s = document.querySelector('[data-testid="bundle-relaxation"]');
    s.value = '0.3';
    s.dispatchEvent(new Event('input', { bubbles: true }));
  });
  await page.waitForFunction(() => {
    const m = document.querySelector('[data-testid="map"]');
    return m.dataset.bundleTemplate.includes('relaxation=0.30') && m.dataset.idle === 'true' && m.dataset.bundleLoaded === 'true';
  });
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'bundling.png') });
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

await test('a fresh browser signs in with the one-time URL; the URL works once; a token signs in too', async () => {
  const url = process.env.LOGIN_URL ?? '';
  assert(/\?login=[0-9a-f]{64}$/.test(url), `run.sh passes the printed sign-in URL (got '${url}')`);
  const fresh = await browser.newContext({ signIn: false, viewport: { width: 1200, height: 800 } });
  const a = await fresh.newPage();
  a.setDefaultTimeout(TIMEOUT);
  await a.goto(url, { waitUntil: 'domcontentloaded' });
  await a.waitForFunction(() => document.querySelector('[data-testid="session-who"]')?.textContent === 'local · admin');
  assert(!a.url().includes('login='), `the code left the address bar (${a.url()})`);
  await a.waitForSelector(`${sel('dataset-select')} option[value="${DATASET}"]`, { state: 'attached' });
  assertEqual(await a.locator(sel('signin-panel')).count(), 0, 'no sign-in panel once signed in');
  // The same URL in another browser: the code is spent, so the sign-in panel says so; a token then works.
  const other = await browser.newContext({ signIn: false, viewport: { width: 1200, height: 800 } });
  const b = await other.newPage();
  b.setDefaultTimeout(TIMEOUT);
  await b.goto(url, { waitUntil: 'domcontentloaded' });
  await b.waitForSelector(sel('signin-panel'));
  const reason = await b.textContent(sel('signin-reason'));
  assert(/sign-in link did not work|needs signing in/.test(reason ?? ''), `the panel says why: ${reason}`);
  assertEqual(await b.textContent(sel('session-who')), 'Not signed in', 'not signed in');
  await b.fill(sel('signin-token'), 'not a token');
  await b.click(sel('signin-submit'));
  await b.waitForSelector(`${sel('signin-error')}:not([hidden])`);
  await b.fill(sel('signin-token'), process.env.TRAILSCOPE_TOKEN ?? '');
  await Promise.all([b.waitForEvent('load'), b.click(sel('signin-submit'))]);
  await b.waitForFunction(() => document.querySelector('[data-testid="session-who"]')?.textContent === 'e2e · admin');
  // Signing out ends it: the panel opens again on the next request that needs a token.
  await Promise.all([b.waitForEvent('load'), b.click(sel('sign-out'))]);
  await b.waitForFunction(() => document.querySelector('[data-testid="session-who"]')?.textContent === 'Not signed in');
  await b.waitForSelector(sel('signin-panel'));
  await fresh.close();
  await other.close();
});

await finish(browser);
