// Browser test of the flight dashboard's congestion panel (run through run.sh, on the server that serves
// the ingested Europe SO6 day). Selects a time window, runs a congestion analysis on the grid of the map
// view with thresholds, follows the job to its end, checks that the numbers shown equal the API's answer
// (GET /api/v1/congestion/{job}), clicks the top hotspot and checks that the map fits its volume, the time
// window becomes its interval, the clock its peak and the series follow (volume, dense values, cursor),
// then opens playback and steps the clock: the volume's occupancy and the series cursor follow the instant.
// Losses of separation: the list equals the API's, a click moves the clock to the closest point of
// approach. Screenshots go to tests/e2e/artifacts.

import { ARTIFACTS, BASE_URL, TIMEOUT, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test } from './harness.mjs';
import path from 'node:path';

const DATASET = process.env.DATASET ?? 'europe';
const PEAK = Number(process.env.CONG_PEAK ?? 6);
const SUSTAINED = Number(process.env.CONG_SUSTAINED ?? 4);

// ---------- an independent reading of the API's answer ----------
/** The occupancy of a volume in period k, from the API's sparse series (a linear scan). */
function occAt(vol, k) {
  const i = vol.occupancy.step.indexOf(k);
  return i < 0 ? 0 : vol.occupancy.count[i];
}
/** The dense occupancy of a volume over K periods. */
function dense(vol, K) {
  const out = new Array(K).fill(0);
  vol.occupancy.step.forEach((k, i) => (out[k] = vol.occupancy.count[i]));
  return out;
}
/** The ranking the panel promises: excess, then duration (longer first), then start, volume, kind. */
function ranked(hotspots) {
  return [...hotspots].sort(
    (a, b) =>
      b.excess - a.excess || b.end - b.start - (a.end - a.start) || a.start - b.start || (a.volume < b.volume ? -1 : a.volume > b.volume ? 1 : 0) || (a.kind === 'peak' ? 0 : 1) - (b.kind === 'peak' ? 0 : 1),
  );
}
const hhmm = (t) => new Date(t * 1000).toISOString().slice(11, 16);

// ---------- run ----------
const browser = await launchBrowser();
const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1 });
const page = await context.newPage();
page.setDefaultTimeout(TIMEOUT);
const requests = [];
const consoleErrors = [];
context.on('request', (r) => requests.push(r.url()));
page.on('websocket', (ws) => requests.push(ws.url()));
recordErrors(page, consoleErrors);
const failedResponses = [];
page.on('response', (r) => r.status() >= 400 && failedResponses.push(`${r.status()} ${r.url()}`));
const state = { window: null, job: null, api: null, hotspot: null };
const panel = (attr) => page.getAttribute(sel('congestion-panel'), attr);

/** Waits until the map has stopped moving and has drawn. */
const mapIdle = () => page.waitForFunction(() => document.querySelector('[data-testid="map"]')?.dataset.idle === 'true' && !window.trailscope.map.isMoving());

console.log(`TrailScope congestion test against ${BASE_URL}`);

await test('page loads the data set', async () => {
  await page.goto(`${BASE_URL}/#dataset=${DATASET}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="summary"]')?.dataset.state === 'ready');
  await page.waitForFunction(() => document.querySelector('[data-testid="time-brush"]')?.dataset.state === 'ready');
  await page.waitForSelector(sel('cong-start'));
  await mapIdle();
}, { critical: true });

await test('select a time window on the histogram', async () => {
  const box = await page.locator(sel('time-brush')).boundingBox();
  const y = box.y + box.height * 0.5;
  await page.mouse.move(box.x + box.width * 0.42, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.44, y, { steps: 6 });
  await page.mouse.move(box.x + box.width * 0.46, y, { steps: 6 });
  await page.mouse.up();
  const t0 = Number(await page.getAttribute(sel('time-brush'), 'data-t0'));
  const t1 = Number(await page.getAttribute(sel('time-brush'), 'data-t1'));
  assert(t1 > t0 && t1 - t0 <= 3 * 3600, `a window of at most 3 h is selected (${t0}, ${t1})`);
  state.window = { t0, t1 };
}, { critical: true });

await test('run the analysis: the job runs with progress and the result arrives', async () => {
  await page.fill(sel('cong-peak'), String(PEAK));
  await page.fill(sel('cong-sustained'), String(SUSTAINED));
  await page.click(sel('cong-start'));
  await page.waitForFunction(() => document.querySelector('[data-testid="congestion-panel"]')?.dataset.job);
  state.job = await panel('data-job');
  await page.waitForFunction(() => ['done', 'failed', 'cancelled'].includes(document.querySelector('[data-testid="congestion-panel"]')?.dataset.state), null, { timeout: 240_000 });
  const st = await panel('data-state');
  assertEqual(st, 'done', `the panel's state (error: ${await page.textContent(sel('cong-error'))}; status: ${await page.textContent(sel('cong-status'))})`);
  assertEqual(await page.getAttribute(sel('cong-progress'), 'aria-valuenow'), '100', 'the progress bar is full');
  const res = await fetch(`${BASE_URL}/api/v1/congestion/${state.job}`);
  assertEqual(res.status, 200, 'GET /api/v1/congestion/{job}');
  state.api = await res.json();
  const c = state.api.counts;
  assertEqual(c.t0, state.window.t0, "the analysis' t0 is the window's");
  assertEqual(c.t1, state.window.t1, "the analysis' t1 is the window's");
  assertEqual(c.volumes_kind, 'grid', 'volumes');
  assert(c.hotspots.length > 0, `the window has hotspots at peak ${PEAK} / sustained ${SUSTAINED} (set CONG_PEAK / CONG_SUSTAINED)`);
}, { critical: true });

await test('the numbers shown equal the API: counts, hotspots in rank order', async () => {
  const c = state.api.counts;
  const num = async (id) => Number((await page.textContent(sel(id))).replace(/,/g, ''));
  assertEqual(await num('cong-flight-count'), c.flights, 'flights');
  assertEqual(await num('cong-volume-count'), c.volumes.length, 'volumes');
  assertEqual(await num('cong-hotspot-count'), c.hotspots_total, 'hotspots');
  const rows = await page.$$eval(`${sel('cong-hotspots')} ${sel('cong-hotspot')}`, (els) =>
    els.map((e) => ({ volume: e.dataset.volume, kind: e.dataset.kind, start: Number(e.dataset.start), end: Number(e.dataset.end), peak: Number(e.dataset.peak), excess: Number(e.dataset.excess), flights: Number(e.dataset.flights), time: e.querySelector('[data-testid="cong-hotspot-time"]').textContent, numbers: e.querySelector('[data-testid="cong-hotspot-numbers"]').textContent })),
  );
  const want = ranked(c.hotspots).slice(0, 100);
  assertEqual(rows.length, want.length, 'hotspots listed');
  rows.forEach((r, i) => {
    const w = want[i];
    const what = `hotspot ${i + 1}`;
    assertEqual(`${r.volume}/${r.kind}/${r.start}/${r.end}`, `${w.volume}/${w.kind}/${w.start}/${w.end}`, what);
    assertEqual(r.numbers, `peak ${w.peak} > ${w.threshold} (+${w.excess}) · ${w.flights.length} fl`, `${what} numbers`);
    assertEqual(r.time, `${hhmm(w.start)}–${hhmm(w.end)}`, `${what} time`);
  });
  const legend = await page.locator(`${sel('cong-legend')} .cong-legend-item`).count();
  assertEqual(legend, 5, 'legend entries');
  await page.screenshot({ path: path.join(ARTIFACTS, 'congestion-result.png') });
});

await test('click the top hotspot: map, time window, clock and series follow', async () => {
  const top = ranked(state.api.counts.hotspots)[0];
  state.hotspot = top;
  const vol = state.api.counts.volumes.find((v) => v.id === top.volume);
  await page.click(`${sel('cong-hotspot')}[data-rank="1"]`);
  await page.waitForTimeout(50);
  await mapIdle();
  // the time window is the hotspot's interval, the clock its peak
  assertEqual(Number(await page.getAttribute(sel('time-brush'), 'data-t0')), top.start, 'window start');
  assertEqual(Number(await page.getAttribute(sel('time-brush'), 'data-t1')), top.end, 'window end');
  assertEqual(await page.evaluate(() => window.trailscope.clock.get().t), top.peak_time, 'the clock at the peak');
  // the map fits the volume
  const view = await page.evaluate(() => {
    const m = window.trailscope.map;
    const b = m.getBounds();
    return { c: m.getCenter(), b: [b.getWest(), b.getSouth(), b.getEast(), b.getNorth()] };
  });
  assert(view.c.lng > vol.west && view.c.lng < vol.east && view.c.lat > vol.south && view.c.lat < vol.north, `map centre ${JSON.stringify(view.c)} inside the volume [${vol.west}, ${vol.south}, ${vol.east}, ${vol.north}]`);
  assert(view.b[0] <= vol.west && view.b[1] <= vol.south && view.b[2] >= vol.east && view.b[3] >= vol.north, `the view ${view.b} holds the volume`);
  assert(view.b[2] - view.b[0] < 20 * (vol.east - vol.west), `the view is zoomed to the volume (${view.b[2] - view.b[0]}° wide)`);
  // the series: this volume, its values as the API's, the cursor at the peak
  assertEqual(await page.getAttribute(sel('cong-series'), 'data-volume'), top.volume, 'series volume');
  assertEqual(await page.getAttribute(sel('cong-series'), 'data-occupancy'), dense(vol, state.api.counts.steps).join(','), 'series values');
  assertEqual(Number(await page.getAttribute(sel('cong-series'), 'data-cursor')), top.peak_time, 'series cursor');
  assertEqual(await page.locator(`${sel('cong-series')} .cong-cursor`).getAttribute('visibility'), 'visible', 'the cursor is drawn');
  const peakLine = await page.getAttribute(sel('cong-series-peak'), 'data-value');
  assertEqual(Number(peakLine), vol.peak, 'the peak threshold line');
  // the volume's occupancy over the hotspot's window (playback off) is its peak
  assertEqual(await page.textContent(sel('cong-volume-id')), top.volume, 'volume shown');
  assertEqual(Number(await page.textContent(sel('cong-volume-occupancy'))), top.peak, "occupancy shown = the hotspot's peak");
  const maxOver = Math.max(...dense(vol, state.api.counts.steps).slice(top.first_step, top.last_step + 1));
  assertEqual(maxOver, top.peak, "the API's series agrees with its hotspot");
  assertEqual(await page.getAttribute(sel('cong-volume'), 'data-class'), top.peak > (vol.peak ?? Infinity) ? 'peak' : 'sustained', 'colour class');
  // the involved flights: listed, their tracks drawn
  const chips = await page.locator(sel('cong-flight')).evaluateAll((els) => els.map((e) => Number(e.dataset.flight)));
  assertEqual(chips.join(','), top.flights.map((f) => f.id).join(','), 'involved flights');
  await page.waitForFunction(() => Number(document.querySelector('[data-testid="cong-flights"]')?.dataset.tracks) > 0);
  await mapIdle();
  await page.screenshot({ path: path.join(ARTIFACTS, 'congestion-hotspot.png') });
});

await test('playback: the volume and the series cursor follow the clock', async () => {
  const top = state.hotspot;
  const c = state.api.counts;
  const vol = c.volumes.find((v) => v.id === top.volume);
  await page.click(sel('playback-toggle'));
  await page.waitForFunction(() => document.querySelector('[data-testid="playback"]')?.dataset.state === 'on');
  const check = async (what) => {
    const t = await page.evaluate(() => window.trailscope.clock.get().t);
    const k = Math.floor((t - c.t0) / c.step);
    await page.waitForFunction((tt) => Number(document.querySelector('[data-testid="cong-series"]')?.dataset.cursor) === tt, t);
    assertEqual(Number(await page.getAttribute(sel('cong-series'), 'data-k')), k, `${what}: period`);
    assertEqual(Number(await page.textContent(sel('cong-volume-occupancy'))), occAt(vol, k), `${what}: occupancy at ${t}`);
    return t;
  };
  const t0 = await check('at the peak');
  assertEqual(t0, top.peak_time, 'the clock stayed at the peak');
  await page.locator(sel('playback-play')).focus();
  await page.keyboard.press('Shift+ArrowRight');
  const t1 = await check('one minute later');
  assert(t1 === Math.min(t0 + 60, top.end), `the clock stepped (${t0} → ${t1})`);
  await page.screenshot({ path: path.join(ARTIFACTS, 'congestion-playback.png') });
});

await test('losses of separation: the list equals the API, a click moves the clock to the CPA', async () => {
  const sep = state.api.separation;
  assert(sep !== null, 'separation was computed');
  assertEqual(Number((await page.textContent(sel('cong-separation-count'))).replace(/,/g, '')), sep.events.length, 'events');
  const listed = await page.$$eval(`${sel('cong-separation')} ${sel('cong-event')}`, (els) => els.map((e) => Number(e.dataset.cpaT)));
  assertEqual(listed.join(','), sep.events.slice(0, 100).map((e) => e.cpa.t).join(','), 'events listed in order');
  if (sep.events.length === 0) return;
  const e = sep.events[0];
  await page.click(`${sel('cong-event')}[data-index="0"]`);
  await page.waitForTimeout(50);
  await mapIdle();
  assertEqual(await page.evaluate(() => window.trailscope.clock.get().t), e.cpa.t, 'the clock at the CPA');
  const c = await page.evaluate(() => window.trailscope.map.getCenter());
  const mid = { lng: (e.cpa.a.lon + e.cpa.b.lon) / 2, lat: (e.cpa.a.lat + e.cpa.b.lat) / 2 };
  assert(Math.abs(c.lng - mid.lng) < 0.01 && Math.abs(c.lat - mid.lat) < 0.01, `the map centres on the CPA (${JSON.stringify(c)} vs ${JSON.stringify(mid)})`);
  assert(await page.locator(`${sel('cong-event')}[data-index="0"].active`).count() === 1, 'the event is marked in progress at the clock');
  await page.screenshot({ path: path.join(ARTIFACTS, 'congestion-separation.png') });
});

await test('the congestion map: tiles of aircraft per pixel at the clock, under the volumes', async () => {
  const tileResponses = [];
  const onResponse = (r) => r.url().includes('/congestion/tiles/') && tileResponses.push(r.status());
  page.on('response', onResponse);
  await page.fill(sel('cong-map-threshold'), '1');
  await page.check(sel('cong-map-toggle'));
  await page.waitForFunction(() => document.querySelector('[data-testid="map"]')?.dataset.congestionTiles);
  await mapIdle();
  page.off('response', onResponse);
  const template = await page.getAttribute(sel('map'), 'data-congestion-tiles');
  const t = await page.evaluate(() => window.trailscope.clock.get().t);
  const q = new URL(template.replace('{z}/{x}/{y}', '0/0/0')).searchParams;
  assertEqual(Number(q.get('t')), t, 'tiles at the clock (paused: the exact instant)');
  assertEqual(q.get('threshold'), '1', 'threshold');
  assert(await page.locator(sel('cong-map-error')).isHidden(), `no error: ${await page.textContent(sel('cong-map-error'))}`);
  assert(tileResponses.length > 0 && tileResponses.every((st) => st === 200 || st === 304), `tiles answered: ${tileResponses.join(',')}`);
  await page.screenshot({ path: path.join(ARTIFACTS, 'congestion-map.png') });
});

await test('no request left the machine, no page errors', async () => {
  const outside = requests.filter(leavesMachine);
  assertEqual(outside.length, 0, `requests leaving the machine: ${outside.slice(0, 3).join(', ')}`);
  assertEqual(consoleErrors.length, 0, `page errors: ${consoleErrors.slice(0, 3).join(' | ')} (failed responses: ${failedResponses.slice(0, 3).join(', ')})`);
});

await finish(browser);
