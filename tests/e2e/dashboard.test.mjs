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
const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1, acceptDownloads: true });
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
  // Data quality: the panel shows the API's counts of implausible values for the window.
  assert(api.quality, 'the summary reports data quality');
  for (const k of ['speed', 'altitude', 'jumps']) {
    assertEqual(Number(await page.getAttribute(sel(`quality-${k}`), 'data-count')), api.quality[k].count, `implausible ${k}`);
  }
  // The Europe day holds implausible values (FL836, FL1141, 2,904 kt): the whole day's summary flags them.
  assert(all.quality.altitude.count > 0 && all.quality.speed.count > 0, `the day's implausible values are counted (${JSON.stringify({ speed: all.quality.speed.count, altitude: all.quality.altitude.count, jumps: all.quality.jumps.count })})`);
  console.log(`        quality of the day: ${all.quality.speed.count} speeds, ${all.quality.altitude.count} altitudes, ${all.quality.jumps.count} jumps`);
  // The ingest report's counts are shown with the data set.
  const ds = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}`)).json();
  assert(ds.ingest?.quality, 'the ingest report holds data quality');
  assertEqual(Number(await page.getAttribute(sel('dataset-quality'), 'data-altitude')), ds.ingest.quality.altitude.count, 'ingest: implausible altitudes');
  assertEqual(Number(await page.getAttribute(sel('dataset-quality'), 'data-speed')), ds.ingest.quality.speed.count, 'ingest: implausible speeds');
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
  // The bundle's colour legend: trail length in km, a bar of real width with ticks.
  const bl = await page.$eval('[data-testid="bundle-legend"]', (el) => ({
    width: el.querySelector('[data-testid="bundle-legend-bar"]').getBoundingClientRect().width,
    ticks: el.dataset.ticks.split('|'),
    lo: Number(el.dataset.loKm),
    hi: Number(el.dataset.hiKm),
  }));
  assert(bl.width >= 200, `bundle legend ${bl.width} px wide`);
  assert(bl.ticks.length >= 3 && bl.ticks.every((t) => /^≈[\d,]+$/.test(t)), `bundle legend ticks in km: ${bl.ticks}`);
  assert(bl.lo > 0 && bl.hi > bl.lo && bl.hi < 5000, `trail lengths ${bl.lo}–${bl.hi} km`);
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'bundling.png') });
});

await test('bundle colour modes: each with its legend (real width, ticks in its units) and the tiles asked in that colour', async () => {
  const want = {
    direction: /^[NESW] \d+°$/,
    density: /^(0|1|0\.\d\d)$/,
    displacement: /^\d+(\.\d)? %$/,
    length: /^≈[\d,]+$/,
  };
  for (const [mode, re] of Object.entries(want)) {
    await page.selectOption(sel('bundle-color'), mode);
    await page.waitForFunction((m) => {
      const t = document.querySelector('[data-testid="map"]').dataset.bundleTemplate;
      const l = document.querySelector('.bundle-legend');
      return (m === 'length' ? !t.includes('color=') : t.includes(`color=${m}`)) && l?.dataset.color === m;
    }, mode);
    const bl = await page.$eval('[data-testid="bundle-legend"]', (el) => ({
      width: el.querySelector('[data-testid="bundle-legend-bar"]').getBoundingClientRect().width,
      ticks: el.dataset.ticks.split('|'),
      drawn: [...el.querySelectorAll('.value-legend-axis .tick text')].map((t) => t.textContent),
      title: el.querySelector('.value-legend-title').textContent,
    }));
    assert(bl.width >= 200, `${mode}: legend ${bl.width} px wide`);
    assert(bl.ticks.length >= 3 && bl.ticks.every((t) => re.test(t)), `${mode}: ticks ${bl.ticks}`);
    assertEqual(bl.drawn.join('|'), bl.ticks.join('|'), `${mode}: the axis draws the ticks`);
    if (mode === 'direction') assertEqual(bl.ticks.join('|'), 'N 0°|E 90°|S 180°|W 270°|N 360°', 'bearings');
    if (mode === 'density') assertEqual(bl.ticks.at(-1), '1', 'density up to the local maximum');
    if (mode === 'displacement') {
      const md = Number((await (await fetch(`${BASE_URL}/api/v1/bundles/${await page.getAttribute('#bundle-section', 'data-bundle')}`)).json()).params.max_displacement);
      assertEqual(bl.ticks.at(-1), `${Math.round(100 * md * 10) / 10} %`, 'displacement up to max_displacement');
    }
    // The tiles of that colour load (200 image/png from the server's renderer).
    await page.waitForFunction(() => {
      const m = document.querySelector('[data-testid="map"]');
      return m.dataset.idle === 'true' && m.dataset.bundleLoaded === 'true';
    });
    if (mode !== 'length') {
      const tile = tileResponses.filter((r) => r.url.includes('/bundle/') && r.url.includes(`color=${mode}`));
      assert(tile.length > 0 && tile.every((r) => r.status === 200 || r.status === 304), `${mode}: tiles fetched (${tile.map((r) => r.status)})`);
      await page.mouse.move(5, 5);
      await page.screenshot({ path: path.join(ARTIFACTS, `bundle-colour-${mode}.png`) });
    }
  }
  // Flat is one colour: no legend.
  await page.selectOption(sel('bundle-color'), 'flat');
  await page.waitForFunction(() => document.querySelector('.bundle-legend')?.dataset.color === 'flat');
  assertEqual(await page.locator('[data-testid="bundle-legend"]').count(), 0, 'flat has no legend');
  await page.selectOption(sel('bundle-color'), 'length');
  await page.waitForFunction(() => document.querySelector('.bundle-legend')?.dataset.color === 'length');
});

// ---------- legends, time axis, state you can trust ----------

/** The density legend's ticks as drawn: label and x of each tick relative to the bar's left edge. */
async function legendTicks() {
  return page.evaluate(() => {
    const el = document.querySelector('[data-testid="density-legend"]');
    const bar = el.querySelector('[data-testid="density-legend-bar"]').getBoundingClientRect();
    return {
      width: bar.width,
      ticks: [...el.querySelectorAll('.value-legend-axis .tick')].map((t) => ({
        label: t.querySelector('text').textContent,
        x: t.querySelector('line').getBoundingClientRect().left - bar.left,
      })),
    };
  });
}

/** The legend as the API gives it for the map's current query and zoom (21 stops, as the dashboard asks). */
async function apiSpan(how) {
  const m = await page.$(sel('map'));
  const q = new URLSearchParams((await m.getAttribute('data-density-template')).split('?')[1]);
  // The zoom of the tiles the map actually asked for with this template (the legend must be theirs).
  const tq = (await m.getAttribute('data-density-template')).split('?')[1];
  const zs = tileResponses.filter((r) => r.url.split('?')[1] === tq).map((r) => Number(new URL(r.url).pathname.split('/')[4]));
  assert(zs.length > 0, 'tiles of the current template were requested');
  const z = Math.max(...zs);
  assertEqual(Number(await page.getAttribute(sel('density-legend'), 'data-z')), z, "the legend is of the tiles' zoom");
  const p = new URLSearchParams();
  for (const [k, v] of q) if (!['value', 'how', 'cmap', 'size'].includes(k)) p.set(k, v);
  p.set('z', String(z));
  p.set('value', q.get('value'));
  p.set('how', how);
  p.set('cmap', q.get('cmap'));
  p.set('stops', '21');
  const res = await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/density/legend?${p}`);
  assertEqual(res.status, 200, 'density/legend status');
  return res.json();
}

await test('the density legend reads values: real width, ticks of the server span (linear and eq_hist)', async () => {
  await page.click('label[for="bundle-mode-raw"]');
  await page.selectOption(sel('density-how'), 'linear');
  await page.waitForFunction(() => {
    const l = document.querySelector('[data-testid="density-legend"]');
    const m = document.querySelector('[data-testid="map"]');
    return l?.dataset.state === 'ready' && l.dataset.how === 'linear' && m.dataset.idle === 'true' && m.dataset.densityLoaded === 'true';
  });
  const span = await apiSpan('linear');
  assertEqual(Number(await page.getAttribute(sel('density-legend'), 'data-hi')), span.hi, 'the legend shows the API span (hi)');
  const lin = await legendTicks();
  assert(lin.width >= 200, `the legend bar is ${lin.width} px wide`);
  assert(lin.ticks.length >= 3, `linear ticks: ${JSON.stringify(lin.ticks)}`);
  // Each tick sits where the linear shading puts its value: (v − lo) / (hi − lo) of the bar.
  for (const t of lin.ticks) {
    const v = Number(t.label.replace(/,/g, '').replace(/k$/, 'e3').replace(/M$/, 'e6'));
    assert(Number.isFinite(v), `a count label: ${t.label}`);
    const want = ((v - span.lo) / (span.hi - span.lo)) * lin.width;
    assert(Math.abs(t.x - want) < 2.5 || /k|M/.test(t.label), `tick ${t.label} at ${t.x.toFixed(1)} px, linear shading puts it at ${want.toFixed(1)} px`);
  }
  await page.selectOption(sel('density-how'), 'eq_hist');
  await page.waitForFunction(() => document.querySelector('[data-testid="density-legend"]')?.dataset.how === 'eq_hist' && document.querySelector('[data-testid="density-legend"]')?.dataset.state === 'ready');
  const eq = await apiSpan('eq_hist');
  const ticks = (await legendTicks()).ticks;
  assertEqual(ticks.length, 5, 'eq_hist: five quartile ticks');
  // The quartile ticks carry the API's values at t = 0, ¼, ½, ¾, 1, in order.
  const fmt = (v) => (v >= 10_000 ? null : v >= 10 || Number.isInteger(v) ? Math.round(v).toLocaleString('en-US') : v.toFixed(1));
  [0, 5, 10, 15, 20].forEach((k, i) => {
    const want = fmt(eq.stops[k].value);
    if (want !== null) assertEqual(ticks[i].label, want, `eq_hist tick ${k * 5} %`);
    assert(Math.abs(ticks[i].x - (k / 20) * lin.width) < 2.5, `quartile tick ${i} at ${ticks[i].x} px`);
  });
  assert(eq.stops.every((x, k) => k === 0 || x.value >= eq.stops[k - 1].value), 'quantiles never decrease');
  // The bar is painted with the tiles' colours: its first stop is the colormap at the minimum level.
  const grad = await page.$$eval('[data-testid="density-legend"] stop', (st) => st.map((x) => x.getAttribute('stop-color')));
  assertEqual(grad.join(','), eq.stops.map((x) => x.color).join(','), 'the bar has the API colours');
  assert(eq.min_level > 0 && eq.stops[0].color !== '#000000', `faint traffic is not black (first colour ${eq.stops[0].color}, min level ${eq.min_level})`);
  assert((await page.textContent(sel('density-legend'))).includes('quantiles'), 'the eq_hist legend says its ticks are quantiles');
  state.legend = eq;
  await page.locator(sel('density-legend')).screenshot({ path: path.join(ARTIFACTS, 'density-legend.png') });
  console.log(`        linear ${lin.ticks.map((t) => t.label).join(' | ')}; eq_hist ${ticks.map((t) => t.label).join(' | ')}`);
});

await test('export PNG: the map view with its legend, at the canvas size', async () => {
  const [dl] = await Promise.all([page.waitForEvent('download'), page.click(sel('export-png'))]);
  const file = await dl.path();
  const { readFile, copyFile } = await import('node:fs/promises');
  const bytes = await readFile(file);
  await copyFile(file, path.join(ARTIFACTS, 'export-view.png'));
  assert(dl.suggestedFilename().endsWith('.png') && dl.suggestedFilename().startsWith(`trailscope-${DATASET}`), `file name ${dl.suggestedFilename()}`);
  assertEqual(bytes.subarray(1, 4).toString('latin1'), 'PNG', 'a PNG file');
  const px = await page.evaluate(async (b64) => {
    const bin = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const img = await createImageBitmap(new Blob([bin], { type: 'image/png' }));
    const c = new OffscreenCanvas(img.width, img.height);
    const ctx = c.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const at = (x, y) => [...ctx.getImageData(x, y, 1, 1).data];
    const H = img.height;
    // The legend box sits 30 px above the bottom: bar from x = 30 to 250, 22 px below the box's top.
    const barY = H - (8 * 2 + 14 + 10 + 18 + 13 + 30) + 8 + 14 + 5;
    const d = ctx.getImageData(0, 0, img.width, img.height).data;
    let lit = 0;
    for (let i = 0; i < d.length; i += 4 * 97) if (d[i] + d[i + 1] + d[i + 2] > 60) lit++;
    const map = window.trailscope.map.getCanvas();
    return { w: img.width, h: img.height, mapW: map.width, mapH: map.height, left: at(32, barY), right: at(248, barY), lit };
  }, bytes.toString('base64'));
  assertEqual(px.w, px.mapW, 'PNG width is the map canvas width');
  assertEqual(px.h, px.mapH, 'PNG height is the map canvas height');
  // The legend's bar ends have the API legend's first and last colours (fire from its minimum level to white).
  const hex = (c) => [1, 3, 5].map((i) => parseInt(c.slice(i, i + 2), 16));
  const near = (a, b, tol) => a.every((v, i) => Math.abs(v - b[i]) <= tol);
  assert(near(px.left.slice(0, 3), hex(state.legend.stops[0].color), 40), `the bar starts with ${state.legend.stops[0].color} (${px.left})`);
  assert(near(px.right.slice(0, 3), hex(state.legend.stops[20].color), 40), `the bar ends with ${state.legend.stops[20].color} (${px.right})`);
  assert(px.lit > 200, `the view is drawn (${px.lit} lit samples)`);
});

await test('a loading indicator shows while tiles of a new state load, then goes', async () => {
  await page.evaluate(() => {
    const m = document.querySelector('[data-testid="map"]');
    window.__loadingSeen = [];
    new MutationObserver(() => window.__loadingSeen.push(m.dataset.loading)).observe(m, { attributes: true, attributeFilter: ['data-loading'] });
  });
  await page.selectOption(sel('density-cmap'), 'viridis');
  await page.waitForFunction(() => {
    const m = document.querySelector('[data-testid="map"]');
    return m.dataset.densityTemplate.includes('cmap=viridis') && m.dataset.idle === 'true' && m.dataset.densityLoaded === 'true' && m.dataset.loading === 'false';
  });
  const seen = await page.evaluate(() => window.__loadingSeen);
  assertEqual(seen[0], 'true', `the indicator came on first (${seen.join(',')})`);
  assertEqual(seen[seen.length - 1], 'false', 'and went once the tiles were in');
  assert(await page.locator(sel('map-loading')).isHidden(), 'the indicator is hidden at rest');
  await page.selectOption(sel('density-cmap'), 'fire');
});

await test('an invalid callsign pattern shows its error and is never sent', async () => {
  const before = requests.length;
  await page.fill(sel('callsign'), 'AF-R');
  await page.press(sel('callsign'), 'Enter');
  await page.locator(sel('callsign')).blur();
  await page.waitForFunction(() => (document.getElementById('callsign-error')?.textContent ?? '').includes('letters, digits'));
  await page.waitForTimeout(800);
  const sent = requests.slice(before).filter((u) => /callsign=AF-R|callsign=AF%2DR/i.test(u));
  assertEqual(sent.length, 0, `requests with the invalid pattern: ${sent.join(', ')}`);
  await page.fill(sel('callsign'), '');
  await page.press(sel('callsign'), 'Enter');
  await page.waitForFunction(() => !(document.getElementById('callsign-error')?.textContent ?? ''));
});

/** The largest of the axis's nudge steps at most 1/100 of the view (an independent copy of the rule). */
const nudgeFor = (span) => [1, 5, 10, 30, 60, 300, 900, 3600, 10800, 21600, 86400].filter((s) => s <= span / 100).pop() ?? 1;

await test('time axis: wheel zoom to minutes, a 10-minute selection at second resolution, typed ISO times, nudges', async () => {
  const brush = sel('time-brush');
  const box = await page.locator(brush).boundingBox();
  const ds = (await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}`)).json());
  // Zoom in with the wheel around the middle until the view is under an hour.
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  for (let i = 0; i < 6; i++) {
    await page.mouse.wheel(0, -500);
    await page.waitForTimeout(80);
  }
  await page.waitForFunction((b) => {
    const e = document.querySelector(b);
    return e.dataset.viewT1 && Number(e.dataset.viewT1) - Number(e.dataset.viewT0) < 3600;
  }, brush);
  const v0 = Number(await page.getAttribute(brush, 'data-view-t0'));
  const v1 = Number(await page.getAttribute(brush, 'data-view-t1'));
  assert(v0 >= ds.t_min - 1 && v1 <= ds.t_max + 2, `the view stays in the data (${v0}…${v1})`);
  // The histogram is asked for the view: its bins are finer than the whole day's.
  await page.waitForFunction(() => new URLSearchParams(location.hash.slice(1)).has('tview'));
  // Drag over 10 minutes of the view: the window keeps the dragged seconds (no 15/30-minute bins).
  // (The earlier window covers the whole zoomed view, where a press would move it: clear it first.)
  await page.click(sel('time-clear'));
  await page.waitForFunction((b) => document.querySelector(b).dataset.t0 === '', brush);
  const plot = await page.locator(brush).boundingBox();
  assert(Math.abs(plot.y - box.y) < 3, `the wheel did not scroll the page (${box.y} → ${plot.y})`);
  const pxPerS = plot.width / (v1 - v0);
  const xa = plot.x + (plot.width - 600 * pxPerS) / 2;
  await page.mouse.move(xa, plot.y + plot.height * 0.5);
  await page.mouse.down();
  await page.mouse.move(xa + 300 * pxPerS, plot.y + plot.height * 0.5, { steps: 6 });
  await page.mouse.move(xa + 600 * pxPerS, plot.y + plot.height * 0.5, { steps: 6 });
  await page.mouse.up();
  const t0 = Number(await page.getAttribute(brush, 'data-t0'));
  const t1 = Number(await page.getAttribute(brush, 'data-t1'));
  assert(Number.isInteger(t0) && Number.isInteger(t1), `whole seconds (${t0}, ${t1})`);
  assert(Math.abs(t1 - t0 - 600) <= 2 * Math.ceil(1 / pxPerS) + 1, `a 10-minute drag selects 10 minutes (${t1 - t0} s)`);
  // Typed ISO 8601 at second resolution: exactly what the summary asks for.
  const iso = (t) => new Date(t * 1000).toISOString().replace(/\.\d{3}Z$/, 'Z');
  const a = Math.floor((v0 + v1) / 2) - 293; // deliberately not on any bin edge
  await page.fill(sel('time-t0-input'), iso(a));
  await page.fill(sel('time-t1-input'), iso(a + 600));
  await page.press(sel('time-t1-input'), 'Enter');
  await page.waitForFunction(([x, y]) => {
    const s = document.querySelector('[data-testid="summary"]');
    const q = new URLSearchParams(s?.dataset.query ?? '');
    return s?.dataset.state === 'ready' && q.get('t0') === String(x) && q.get('t1') === String(y);
  }, [a, a + 600]);
  // The URL keeps the window to the second (written once the state rests).
  await page.waitForFunction(([x, y]) => {
    const q = new URLSearchParams(location.hash.slice(1));
    return q.get('t0') === String(x) && q.get('t1') === String(y);
  }, [a, a + 600]);
  const api = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/summary?t0=${a}&t1=${a + 600}&bins=96`)).json();
  assertEqual(Number(await page.getAttribute(sel('summary-points'), 'data-value')), api.points, 'the 10-minute window summary equals the API');
  // A typo is shown, not sent.
  const before = requests.length;
  await page.fill(sel('time-t0-input'), '2018-13-01T00:00Z');
  await page.press(sel('time-t0-input'), 'Enter');
  await page.waitForSelector(`${sel('time-typed-error')}:not([hidden])`);
  assertEqual(requests.slice(before).filter((u) => u.includes('/summary')).length, 0, 'no query for a bad typed time');
  // Keyboard nudges: → moves the window by the view's nudge step.
  const vs = Number(await page.getAttribute(brush, 'data-view-t1')) - Number(await page.getAttribute(brush, 'data-view-t0'));
  await page.locator(brush).focus();
  await page.keyboard.press('ArrowRight');
  assertEqual(Number(await page.getAttribute(brush, 'data-t0')), a + nudgeFor(vs), `→ nudges by ${nudgeFor(vs)} s`);
  await page.keyboard.press('ArrowLeft');
  assertEqual(Number(await page.getAttribute(brush, 'data-t0')), a, '← nudges back');
  await page.locator('#timeline').screenshot({ path: path.join(ARTIFACTS, 'time-axis-10min.png') });
  console.log(`        view ${Math.round(v1 - v0)} s, drag ${t1 - t0} s, typed ${iso(a)} + 600 s, nudge ${nudgeFor(vs)} s`);
});

// ---------- sorting, picking, exports (the window is now 10 minutes) ----------

await test('the flight list sorts on the server: a header click gives the API order, again reverses; the URL keeps it', async () => {
  const q = await page.getAttribute(sel('summary'), 'data-query');
  const rowsShown = () =>
    page.$$eval('[data-testid="flight-row"]', (rows) =>
      rows.map((r) => ({ id: Number(r.dataset.flightId), dur: r.querySelector('[data-col="flight_duration_s"]').textContent })),
    );
  for (const order of ['asc', 'desc']) {
    await page.click(sel('flight-sort-flight_duration_s'));
    await page.waitForFunction((o) => {
      const f = document.querySelector('[data-testid="flights"]');
      return f?.dataset.state === 'ready' && f.dataset.sort === 'flight_duration_s' && f.dataset.order === o;
    }, order);
    const api = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/flights?${q}&page=0&page_size=50&sort=flight_duration_s&order=${order}`)).json();
    const shown = await rowsShown();
    assertEqual(shown.map((r) => r.id).join(','), api.flights.map((f) => f.id).join(','), `the ${order} page equals the API's`);
    // Independently of the server: the whole-flight durations of the rows are in order.
    const d = api.flights.map((f) => f.flight_t_end - f.flight_t_start);
    assert(d.every((v, i) => i === 0 || (order === 'asc' ? v >= d[i - 1] - 1e-6 : v <= d[i - 1] + 1e-6)), `whole-flight durations ${order}: ${d.slice(0, 8).join(',')}`);
    assert(api.flights.every((f) => f.flight_t_start <= f.t_start && f.flight_t_end >= f.t_end), 'in-window times lie inside the whole flight');
  }
  await page.waitForFunction(() => {
    const h = new URLSearchParams(location.hash.slice(1));
    return h.get('fsort') === 'flight_duration_s' && h.get('forder') === 'desc';
  });
  await page.locator('#flights-section').screenshot({ path: path.join(ARTIFACTS, 'flight-list-sorted.png') });
});

await test('hover and click on the density map pick the flight the API picks', async () => {
  await page.keyboard.press('Escape');
  const q = await page.getAttribute(sel('summary'), 'data-query');
  // A flight of the list with a drawn trail in the window (two matching points or more).
  const ids = (await page.$$eval('[data-testid="flight-row"]', (rows) => rows.map((r) => Number(r.dataset.flightId)))).slice(0, 20);
  let first = -1;
  let coords = [];
  for (const id of ids) {
    const f = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/flights/${id}?${q}&clip=1`)).json();
    if (f.geometry.coordinates.length >= 2) {
      first = id;
      coords = f.geometry.coordinates;
      break;
    }
  }
  assert(first >= 0, `a listed flight has a trail in the window (of ${ids.length})`);
  const mid = coords[Math.floor(coords.length / 2)];
  await page.evaluate(([lng, lat]) => window.trailscope.map.jumpTo({ center: [lng, lat], zoom: 8 }), mid);
  await page.waitForFunction(() => document.querySelector('[data-testid="map"]')?.dataset.idle === 'true');
  const box = await page.locator(sel('map')).boundingBox();
  const p = await page.evaluate(([lng, lat]) => window.trailscope.map.project([lng, lat]), mid);
  await page.mouse.move(box.x + p.x - 3, box.y + p.y - 3);
  await page.mouse.move(box.x + p.x, box.y + p.y);
  await page.waitForFunction(() => !document.querySelector('[data-testid="pick-tooltip"]')?.hidden);
  const ll = await page.evaluate(([x, y]) => {
    const m = window.trailscope.map;
    const l = m.unproject([x, y]);
    return { lng: l.lng, lat: l.lat, zoom: m.getZoom() };
  }, [p.x, p.y]);
  const pq = new URLSearchParams(q);
  for (const k of ['bbox']) pq.delete(k);
  pq.set('lon', ll.lng.toFixed(6));
  pq.set('lat', ll.lat.toFixed(6));
  pq.set('zoom', ll.zoom.toFixed(4));
  pq.set('tile_size', '512');
  pq.set('tolerance', '5');
  pq.set('limit', '5');
  const api = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/pick?${pq}`)).json();
  assert(api.flights.length > 0, 'the API picks a flight there');
  assert(api.flights.some((x) => x.id === first), `the flight drawn there is among the picked (${api.flights.map((x) => x.id)})`);
  assertEqual(Number(await page.getAttribute(sel('pick-tooltip'), 'data-flight-id')), api.flights[0].id, 'the hovered flight is the API nearest');
  assertEqual(await page.getAttribute(sel('pick-tooltip'), 'data-flights'), api.flights.map((x) => x.id).join(','), 'the hovered list');
  await page.screenshot({ path: path.join(ARTIFACTS, 'pick-hover.png') });
  await page.mouse.click(box.x + p.x, box.y + p.y);
  await page.waitForFunction((id) => document.querySelector('[data-testid="map"]')?.dataset.track === String(id), api.flights[0].id);
  await page.waitForFunction(() => document.querySelector('[data-testid="flight-card"]')?.dataset.state === 'ready');
  assertEqual((await page.textContent(sel('card-callsign'))).trim(), api.flights[0].callsign || '—', 'the clicked flight is shown');
  await page.keyboard.press('Escape');
});

/** Downloads what a click on `testid` gives; its text and file name. */
async function download(testid) {
  const [dl] = await Promise.all([page.waitForEvent('download'), page.click(sel(testid))]);
  const { readFile, copyFile } = await import('node:fs/promises');
  const file = await dl.path();
  await copyFile(file, path.join(ARTIFACTS, `export-${dl.suggestedFilename()}`));
  return { name: dl.suggestedFilename(), text: await readFile(file, 'utf8') };
}

await test("exports: the window's flights as GeoJSON and CSV and the summary as JSON and CSV equal the API", async () => {
  const q = await page.getAttribute(sel('summary'), 'data-query');
  const sum = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/summary?${q}&bins=96`)).json();
  const list = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/flights?${q}&page=0&page_size=1`)).json();
  const gj = await download('export-geojson');
  assert(gj.name.endsWith('.geojson'), gj.name);
  const fc = JSON.parse(gj.text);
  assertEqual(fc.type, 'FeatureCollection', 'GeoJSON type');
  assertEqual(fc.features.length, list.total, 'one feature per flight of the list');
  assertEqual(fc.features.reduce((a, f) => a + f.geometry.coordinates.length, 0), sum.points, 'the points are the summary points');
  const f0 = fc.features[0];
  const one = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/flights/${f0.properties.id}?${q}&clip=1`)).json();
  assertEqual(JSON.stringify(f0.geometry.coordinates), JSON.stringify(one.geometry.coordinates), 'a feature equals GET /flights/{id}?clip=1');
  const csv = await download('export-csv');
  const lines = csv.text.trim().split('\n');
  assertEqual(lines[0], 'flight_id,icao24,callsign,t,lat,lon,alt_m,speed_ms,track_deg,vrate_ms,on_ground', 'CSV header');
  assertEqual(lines.length - 1, sum.points, 'one CSV row per point');
  assertEqual(new Set(lines.slice(1).map((l) => l.split(',')[0])).size, list.total, 'the CSV covers every flight');
  // The first feature's first point, in the CSV (same numbers).
  const [lon, lat] = f0.geometry.coordinates[0];
  const row = lines.find((l) => l.startsWith(`${f0.properties.id},`));
  const c = row.split(',');
  // Positions are stored as float32: the CSV's shortest text reads back to the same float32.
  assert(Math.fround(Number(c[5])) === Math.fround(lon) && Math.fround(Number(c[4])) === Math.fround(lat), `the CSV row ${row} holds the GeoJSON point ${lon},${lat}`);
  const sj = JSON.parse((await download('export-summary-json')).text);
  assertEqual(sj.points, sum.points, 'summary JSON points');
  assertEqual(sj.flights, sum.flights, 'summary JSON flights');
  const sc = Object.fromEntries((await download('export-summary-csv')).text.trim().split('\n').slice(1).map((l) => l.split(',')));
  assertEqual(Number(sc.points), sum.points, 'summary CSV points');
  assertEqual(Number(sc.flights), sum.flights, 'summary CSV flights');
  console.log(`        ${fc.features.length} flights, ${sum.points} points exported`);
});

await test('a bundle is marked stale when its window changed; one click recomputes it', async () => {
  // The bundle's window shifted by half an hour, typed (the time-axis step above may have moved it already).
  const iso = (t) => new Date(t * 1000).toISOString().replace(/\.\d{3}Z$/, 'Z');
  const sq = new URLSearchParams(state.query);
  const b0 = Number(state.bundle.source.query?.t0 ?? sq.get('t0'));
  const b1 = Number(state.bundle.source.query?.t1 ?? sq.get('t1'));
  await page.fill(sel('time-t0-input'), iso(b0 + 1800));
  await page.fill(sel('time-t1-input'), iso(b1 + 1800));
  await page.press(sel('time-t1-input'), 'Enter');
  await page.waitForFunction(() => document.querySelector('#bundle-section')?.dataset.stale === 'true');
  assert(await page.locator(sel('bundle-stale')).isVisible(), 'the stale mark shows');
  await page.screenshot({ path: path.join(ARTIFACTS, 'bundle-stale.png') });
  const old = await page.getAttribute(bundlePanel, 'data-bundle');
  await page.click(sel('bundle-recompute'));
  await page.waitForFunction((o) => {
    const el = document.querySelector('#bundle-section');
    return el?.dataset.state === 'done' && el.dataset.bundle && el.dataset.bundle !== o && el.dataset.stale === 'false';
  }, old, { timeout: 120_000 });
  const id = await page.getAttribute(bundlePanel, 'data-bundle');
  const meta = await (await fetch(`${BASE_URL}/api/v1/bundles/${id}`)).json();
  const t0 = await page.getAttribute(sel('time-brush'), 'data-t0');
  assert(t0 && JSON.stringify(meta.source).includes(t0), `the new bundle is of the current window (t0 ${t0}): ${JSON.stringify(meta.source)}`);
  assert(await page.locator(sel('bundle-stale')).isHidden(), 'no stale mark on the new bundle');
});

await test('a link keeps the bundle: id, view, relaxation and colouring in the URL; opened afresh it shows that bundle, stale only when its window differs', async () => {
  const id = await page.getAttribute(bundlePanel, 'data-bundle');
  await page.selectOption(sel('bundle-color'), 'direction');
  await page.$eval(sel('bundle-relaxation'), (el) => {
    el.value = '0.4';
    el.dispatchEvent(new Event('input', { bubbles: true }));
  });
  await page.waitForFunction((b) => {
    const q = new URLSearchParams(window.location.hash.slice(1));
    return q.get('bundle') === b && q.get('bcolor') === 'direction' && q.get('brelax') === '0.40' && !q.has('bview');
  }, id);
  const hash = await page.evaluate(() => window.location.hash);
  const meta = await (await fetch(`${BASE_URL}/api/v1/bundles/${id}`)).json();
  const other = await context.newPage();
  const otherErrors = [];
  recordErrors(other, otherErrors, 'link: ');
  try {
    await other.goto(`${BASE_URL}/${hash}`, { waitUntil: 'domcontentloaded' });
    await other
      .waitForFunction((b) => {
        const el = document.querySelector('#bundle-section');
        const m = document.querySelector('[data-testid="map"]');
        return el?.dataset.bundle === b && el.dataset.state === 'done' && m?.dataset.bundleLoaded === 'true';
      }, id, { timeout: 60_000 })
      .catch(async (e) => {
        const d = await other.evaluate(() => ({ panel: { ...document.querySelector('#bundle-section')?.dataset }, map: { ...document.querySelector('[data-testid="map"]')?.dataset }, result: document.querySelector('[data-testid="bundle-result"]')?.textContent, hash: window.location.hash }));
        throw new Error(`${e.message}; ${JSON.stringify(d)}; page errors: ${otherErrors.join(' | ')}`);
      });
    const shown = await other.$eval('#bundle-section', (el) => ({ ...el.dataset }));
    assertEqual(`${shown.mode} ${shown.color} ${shown.stale}`, 'bundled direction false', 'the link\'s view, not stale (its window is the bundle\'s)');
    assertEqual(await other.inputValue(sel('bundle-relaxation')), '0.4', 'the relaxation');
    assertEqual(await other.inputValue(sel('bundle-color')), 'direction', 'the colour mode');
    const template = await other.getAttribute(sel('map'), 'data-bundle-template');
    assert(template.includes(`/bundle/${id}/`), `the bundle's tiles (${template})`);
    assert(template.includes('color=direction') && template.includes('relaxation=0.40'), `tiles in the link's colour and relaxation (${template})`);
    // Every parameter field shows the bundle's value (left empty where that is the default).
    const fields = await other.$$eval('#bundle-section [data-param]', (els) => els.map((e) => [e.dataset.param, e.value, e.getAttribute('placeholder')]));
    assert(fields.length > 5, `parameter fields (${fields.length})`);
    for (const [name, value, placeholder] of fields) assertEqual(value === '' ? placeholder : value, meta.params[name], `parameter ${name}`);
    // The link's window moved: the same bundle, now marked stale.
    const q = new URLSearchParams(hash.slice(1));
    q.set('t0', String(Number(q.get('t0')) + 600));
    // A new load of the link (a hash-only navigation would keep the running page, which writes its own hash).
    await other.goto('about:blank');
    await other.goto(`${BASE_URL}/#${q}`, { waitUntil: 'domcontentloaded' });
    await other
      .waitForFunction((b) => {
        const el = document.querySelector('#bundle-section');
        return el?.dataset.bundle === b && el.dataset.stale === 'true';
      }, id, { timeout: 60_000 })
      .catch(async (e) => {
        const d = await other.evaluate(() => ({ panel: { ...document.querySelector('#bundle-section')?.dataset }, result: document.querySelector('[data-testid="bundle-result"]')?.textContent, hash: window.location.hash }));
        throw new Error(`${e.message}; ${JSON.stringify(d)}; asked ${q}; page errors: ${otherErrors.join(' | ')}`);
      });
    assert(await other.locator(sel('bundle-stale')).isVisible(), 'the stale mark shows');
    await other.mouse.move(5, 5);
    await other.screenshot({ path: path.join(ARTIFACTS, 'bundle-from-link.png') });
    // A link to a bundle no longer on the server says so.
    q.set('bundle', 'b999999');
    await other.goto('about:blank');
    await other.goto(`${BASE_URL}/#${q}`, { waitUntil: 'domcontentloaded' });
    await other.waitForSelector(sel('bundle-restore-error'), { timeout: 60_000 });
    assert((await other.textContent(sel('bundle-restore-error'))).startsWith('Bundle b999999 from the link: '), 'the missing bundle is named');
    assertEqual(otherErrors.filter((e) => !e.includes('404')).join(' | '), '', 'no page errors besides the missing bundle\'s 404');
  } finally {
    await other.close();
  }
});

/**
 * The time axis zoomed out to the whole data set ("Whole range"): the brush's selector, the data set's span
 * (s), the view's span now (no view attributes: the whole data set) and the window as "t0-t1".
 */
async function timeAxisAtWholeRange() {
  const brush = sel('time-brush');
  const ds = await (await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}`)).json();
  const whole = ds.t_max - ds.t_min;
  const span = async () => {
    const [a, b] = [await page.getAttribute(brush, 'data-view-t0'), await page.getAttribute(brush, 'data-view-t1')];
    return a && b ? Number(b) - Number(a) : whole;
  };
  const win = async () => [await page.getAttribute(brush, 'data-t0'), await page.getAttribute(brush, 'data-t1')].join('-');
  await page.click(sel('time-zoom-all'));
  await page.waitForFunction(([b, w]) => {
    const e = document.querySelector(b);
    return !e.dataset.viewT1 || Number(e.dataset.viewT1) - Number(e.dataset.viewT0) >= w * 0.99;
  }, [brush, whole]);
  assert((await span()) >= whole * 0.99, `the whole range shows (${await span()} of ${whole} s)`);
  return { brush, whole, span, win };
}

await test('time axis: a trackpad pinch (ctrl+wheel) zooms the axis, not the page or the window', async () => {
  const { brush, whole, span, win } = await timeAxisAtWholeRange();
  const window0 = await win();
  const zoom0 = await page.evaluate(() => window.visualViewport?.scale ?? 1);
  const box = await page.locator(brush).boundingBox();
  // Trackpads send a pinch as wheel events with ctrlKey (small deltas, many of them).
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.keyboard.down('Control');
  for (let i = 0; i < 10; i++) {
    await page.mouse.wheel(0, -20);
    await page.waitForTimeout(30);
  }
  await page.keyboard.up('Control');
  await page.waitForFunction(([b, w]) => {
    const e = document.querySelector(b);
    return e.dataset.viewT1 && Number(e.dataset.viewT1) - Number(e.dataset.viewT0) < w / 2;
  }, [brush, whole]);
  const pinched = await span();
  assertEqual(await page.evaluate(() => window.visualViewport?.scale ?? 1), zoom0, 'the page itself did not zoom');
  assertEqual(await win(), window0, 'the window did not change');
  await page.locator('#timeline').screenshot({ path: path.join(ARTIFACTS, 'time-axis-pinch.png') });
  console.log(`        whole ${Math.round(whole)} s → ctrl+wheel ${Math.round(pinched)} s`);
});

await test('time axis: a two-finger touch pinch zooms the axis; the first finger\'s brush drag gives the window back', async () => {
  const { brush, whole, span, win } = await timeAxisAtWholeRange();
  const window0 = await win();
  const box = await page.locator(brush).boundingBox();
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
  // Real touch input through the DevTools protocol (Chromium turns it into touch and pointer events).
  await page.evaluate(() => {
    window.__touchLog = [];
    const plot = document.querySelector('[data-testid="time-brush"] .brush-plot') ?? document.elementFromPoint(0, 0);
    for (const t of ['touchstart', 'touchmove', 'touchend', 'pointerdown', 'pointercancel']) {
      document.addEventListener(t, (e) => window.__touchLog.push(`${t}:${e.touches ? e.touches.length : e.pointerId}:${e.target.className?.baseVal ?? e.target.className}:${plot?.__zoom?.k ?? '-'}`), { capture: true });
    }
  });
  const cdp = await context.newCDPSession(page);
  await cdp.send('Emulation.setTouchEmulationEnabled', { enabled: true, maxTouchPoints: 5 });
  const touch = (type, pts) => cdp.send('Input.dispatchTouchEvent', { type, touchPoints: pts.map(([x, id]) => ({ x, y: cy, id })) });
  try {
    // The first finger lands and drags far enough to start a brush selection...
    await touch('touchStart', [[cx - 30, 0]]);
    await touch('touchMove', [[cx - 10, 0]]);
    await touch('touchMove', [[cx + 10, 0]]);
    // ...then the second lands: a pinch, spread from 40 px to 280 px apart.
    await touch('touchStart', [[cx + 10, 0], [cx + 50, 1]]);
    for (let i = 1; i <= 12; i++) {
      await touch('touchMove', [[cx + 10 - 10 * i, 0], [cx + 50 + 10 * i, 1]]);
      await page.waitForTimeout(16);
    }
    await touch('touchEnd', []);
  } finally {
    await cdp.send('Emulation.setTouchEmulationEnabled', { enabled: false });
    await cdp.detach();
  }
  await page
    .waitForFunction(([b, w]) => {
      const e = document.querySelector(b);
      return e.dataset.viewT1 && Number(e.dataset.viewT1) - Number(e.dataset.viewT0) < w / 2;
    }, [brush, whole], { timeout: 10_000 })
    .catch(async (e) => {
      throw new Error(`${e.message}; events ${await page.evaluate(() => window.__touchLog.join(' '))}`);
    });
  const pinched = await span();
  // d3-zoom's pinch scales by the ratio of the fingers' distances: 280 / 40 = 7 (within d3's own rounding).
  assert(pinched > whole / 9 && pinched < whole / 5, `the span shrank by the fingers' ratio (${Math.round(whole)} s → ${Math.round(pinched)} s)`);
  assertEqual(await win(), window0, 'the window did not change');
  console.log(`        whole ${Math.round(whole)} s → touch pinch ${Math.round(pinched)} s`);
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
