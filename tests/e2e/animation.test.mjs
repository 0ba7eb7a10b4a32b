// Browser test of the flight dashboard's playback (run through run.sh, which starts the server on the
// ingested Europe SO6 day). Selects a time window, plays, checks that the aircraft move (the positions
// drawn at two instants differ, and the map's pixels change), pauses, scrubs the time cursor, and checks
// that the positions drawn equal GET /api/v1/datasets/{id}/positions?t= at the same instant (same flights,
// within 1 m), also at a late time of day opened from a link, with the dashboard's altitude band applied
// without refetching; hover, click to follow and Esc. Screenshots go to tests/e2e/artifacts.

import { ARTIFACTS, BASE_URL, TIMEOUT, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test } from './harness.mjs';
import path from 'node:path';

const DATASET = process.env.DATASET ?? 'europe';
/** 23:39:59.5 UTC on the Europe day: late enough that float32 epoch seconds would be off by up to 64 s. */
const LATE = 1514849999.5;
const ALT_MIN_FT = 20000;
const ALT_MAX_FT = 40000;
const EARTH_R = 6371008.8;

// ---------- helpers ----------
function metresBetween(a, b) {
  const rad = Math.PI / 180;
  const dLat = (b.lat - a.lat) * rad;
  let dLon = b.lon - a.lon;
  if (dLon > 180) dLon -= 360;
  if (dLon < -180) dLon += 360;
  const h = Math.sin(dLat / 2) ** 2 + Math.cos(a.lat * rad) * Math.cos(b.lat * rad) * Math.sin((dLon * rad) / 2) ** 2;
  return 2 * EARTH_R * Math.asin(Math.min(1, Math.sqrt(h)));
}

/** The API's positions at t (the instant as the exact decimal string of the double). */
async function apiPositions(t, extra = '') {
  const res = await fetch(`${BASE_URL}/api/v1/datasets/${DATASET}/positions?t=${String(t)}${extra}`);
  assertEqual(res.status, 200, `positions?t=${t} status`);
  return (await res.json()).positions;
}

/** Same flights, each within 1 m horizontally and 1 m in altitude; returns the largest error. */
function comparePositions(drawn, api, what) {
  const want = api.map((p) => p.id);
  const got = drawn.map((p) => p.flightId);
  const missing = want.filter((id) => !got.includes(id));
  const extra = got.filter((id) => !want.includes(id));
  assert(missing.length === 0 && extra.length === 0, `${what}: flights differ (missing ${missing.slice(0, 5)}, extra ${extra.slice(0, 5)}; ${got.length} drawn, ${want.length} from the API)`);
  const byId = new Map(drawn.map((p) => [p.flightId, p]));
  let maxD = 0;
  let maxAlt = 0;
  for (const p of api) {
    const d = byId.get(p.id);
    const m = metresBetween({ lon: d.lon, lat: d.lat }, p);
    maxD = Math.max(maxD, m);
    assert(m <= 1, `${what}: flight ${p.id} (${p.callsign}) drawn ${m.toFixed(3)} m from the API's position`);
    if (p.alt_m !== null) {
      const da = Math.abs(d.altM - p.alt_m);
      maxAlt = Math.max(maxAlt, da);
      assert(da <= 1, `${what}: flight ${p.id} altitude ${d.altM} vs ${p.alt_m}`);
    } else {
      assert(Number.isNaN(d.altM), `${what}: flight ${p.id} has no altitude in the API but ${d.altM} drawn`);
    }
  }
  return { n: api.length, maxD, maxAlt };
}

const playbackT = () => page.getAttribute(sel('playback'), 'data-t');

/** Waits until the layer has the chunks for t, then two frames so they are drawn. */
async function drawnAt(t) {
  await page.evaluate(async (tt) => {
    await window.trailscope.animation.ready(tt);
    await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
  }, t);
}

/** The map area as a PNG (what the analyst sees: basemap, density and the aircraft). */
async function mapShot(name) {
  await page.mouse.move(2, 2);
  // The panels over the map (readouts, cache statistics) are masked: only the map itself is compared.
  const buf = await page.locator(sel('map')).screenshot({ mask: [page.locator(sel('playback')), page.locator('#map-overlay')] });
  if (name) await page.screenshot({ path: path.join(ARTIFACTS, name) });
  return buf.toString('base64');
}

/** How many pixels differ between two PNGs (decoded in the page). */
function pixelsDiffering(a, b) {
  return page.evaluate(async ([x, y]) => {
    const load = async (b64) => {
      // Decoded from bytes, not fetched from a data: URL, which the app's Content-Security-Policy
      // (connect-src 'self') refuses.
      const bytes = Uint8Array.from(atob(b64), (ch) => ch.charCodeAt(0));
      const img = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
      const c = new OffscreenCanvas(img.width, img.height);
      const ctx = c.getContext('2d');
      ctx.drawImage(img, 0, 0);
      return ctx.getImageData(0, 0, img.width, img.height).data;
    };
    const [da, db] = await Promise.all([load(x), load(y)]);
    if (da.length !== db.length) return -1;
    let n = 0;
    for (let i = 0; i < da.length; i += 4) {
      if (Math.abs(da[i] - db[i]) + Math.abs(da[i + 1] - db[i + 1]) + Math.abs(da[i + 2] - db[i + 2]) > 24) n++;
    }
    return n;
  }, [a, b]);
}

// ---------- run ----------
const browser = await launchBrowser();
const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1 });
const page = await context.newPage();
page.setDefaultTimeout(TIMEOUT);
const requests = [];
const consoleErrors = [];
context.on('request', (r) => requests.push(r.url()));
recordErrors(page, consoleErrors);
const animationRequests = () => requests.filter((u) => u.includes(`/api/v1/datasets/${DATASET}/animation`)).length;
const state = { window: null, scrubbed: null };

console.log(`TrailScope playback test against ${BASE_URL}`);

await test('page loads the data set', async () => {
  await page.goto(`${BASE_URL}/#dataset=${DATASET}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="summary"]')?.dataset.state === 'ready');
  await page.waitForFunction(() => document.querySelector('[data-testid="time-brush"]')?.dataset.state === 'ready');
}, { critical: true });

await test('select a time window and open the playback view', async () => {
  const box = await page.locator(sel('time-brush')).boundingBox();
  const y = box.y + box.height * 0.5;
  await page.mouse.move(box.x + box.width * 0.45, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.5, y, { steps: 6 });
  await page.mouse.move(box.x + box.width * 0.55, y, { steps: 6 });
  await page.mouse.up();
  const t0 = Number(await page.getAttribute(sel('time-brush'), 'data-t0'));
  const t1 = Number(await page.getAttribute(sel('time-brush'), 'data-t1'));
  assert(t1 > t0, `a window is selected (${t0}, ${t1})`);
  state.window = { t0, t1 };
  await page.click(sel('playback-toggle'));
  await page.waitForFunction(() => document.querySelector('[data-testid="playback"]')?.dataset.state === 'on');
  assertEqual(Number(await playbackT()), t0, 'the clock starts at the window start');
  assertEqual(await page.getAttribute(sel('map'), 'data-dimmed'), 'true', 'the density is dimmed behind the aircraft');
  assertEqual(Number(await page.getAttribute(sel('time-brush'), 'data-cursor')), t0, 'the histogram shows the cursor');
  await drawnAt(t0);
  const n = await page.evaluate((t) => window.trailscope.animation.positionsAt(t).length, t0);
  assert(n > 100, `aircraft drawn at the window start (${n})`);
  const ticks = await page.locator(`${sel('playback-legend')} ${sel('playback-legend-tick')}`).allTextContents();
  assert(ticks.length >= 2 && ticks.every((t) => t.trim() !== ''), `the legend shows values: ${ticks.join(' | ')}`);
  assert(ticks.some((t) => /^FL\d{3}$/.test(t)), `altitude legend in flight levels: ${ticks.join(' | ')}`);
}, { critical: true });

await test('play: the clock runs and the aircraft move', async () => {
  await page.selectOption(sel('playback-speed'), '100');
  await page.click(sel('playback-play'));
  await page.waitForFunction(() => document.querySelector('[data-testid="playback"]')?.dataset.playing === 'true');
  const sample = () => page.evaluate(() => {
    const t = window.trailscope.clock.get().t;
    return { t, pos: window.trailscope.animation.positionsAt(t) };
  });
  const a = await sample();
  const shotA = await mapShot();
  await page.waitForTimeout(1500);
  const b = await sample();
  const shotB = await mapShot('animation-playing.png');
  const changed = await pixelsDiffering(shotA, shotB);
  assert(changed > 200, `the map's pixels change while playing (${changed} pixels)`);
  assert(b.t > a.t + 10, `the clock advanced at 100× (${a.t} → ${b.t})`);
  const before = new Map(a.pos.map((p) => [p.flightId, p]));
  let common = 0;
  let moved = 0;
  for (const p of b.pos) {
    const q = before.get(p.flightId);
    if (!q) continue;
    common++;
    if (metresBetween(p, q) > 100) moved++;
  }
  assert(common > 50, `the same flights are drawn at both instants (${common})`);
  assert(moved > common * 0.8, `aircraft moved: ${moved} of ${common} by more than 100 m in ${(b.t - a.t).toFixed(1)} s`);
  console.log(`        ${moved} of ${common} aircraft moved over ${(b.t - a.t).toFixed(1)} s of data; ${changed} pixels changed`);
});

await test('pause with Space: the clock stops', async () => {
  await page.keyboard.press('Space');
  await page.waitForFunction(() => document.querySelector('[data-testid="playback"]')?.dataset.playing === 'false');
  const t = await playbackT();
  await page.waitForTimeout(400);
  assertEqual(await playbackT(), t, 'the instant stays while paused');
  await page.waitForFunction((tt) => window.location.hash.includes(`at=${tt}`), t);
  // + and − walk the speed steps.
  await page.keyboard.press('+');
  assertEqual(await page.getAttribute(sel('playback'), 'data-speed'), '200', 'one step faster than 100×');
  await page.keyboard.press('-');
  await page.keyboard.press('-');
  assertEqual(await page.getAttribute(sel('playback'), 'data-speed'), '50', 'two steps slower');
  await page.keyboard.press('+');
  await page.waitForFunction(() => window.location.hash.includes('speed=100'));
});

await test('scrub the cursor on the histogram; the map changes with the instant', async () => {
  const cur = await page.locator(sel('time-cursor')).boundingBox();
  const brush = await page.locator(sel('time-brush')).boundingBox();
  const x0 = cur.x + cur.width / 2;
  const y = brush.y + brush.height * 0.5;
  await page.mouse.move(x0, y);
  await page.mouse.down();
  await page.mouse.move(x0 + 15, y, { steps: 5 });
  await page.mouse.move(x0 + 30, y, { steps: 5 });
  await page.mouse.up();
  const t = Number(await playbackT());
  const { t0, t1 } = state.window;
  assert(t > t0 && t < t1, `the cursor scrubbed inside the window (${t})`);
  // A click elsewhere in the window jumps there (the brush's own pixel-to-time mapping).
  const xMid = (await page.locator(`${sel('time-brush')} .selection`).boundingBox()).x + 5;
  await page.mouse.click(xMid, y);
  const jumped = Number(await playbackT());
  assert(jumped >= t0 && jumped < t0 + (t1 - t0) * 0.2 && jumped !== t, `a click jumps the cursor (${jumped})`);
  await page.mouse.move(xMid, y);
  await page.mouse.down();
  await page.mouse.move(x0 + 15, y, { steps: 5 });
  await page.mouse.move(x0 + 30, y, { steps: 5 });
  await page.mouse.up();
  assertEqual(Number(await playbackT()), t, 'dragging the cursor back scrubs to the same pixel time');
  assertEqual(Number(await page.getAttribute(sel('time-brush'), 'data-t0')), t0, 'scrubbing leaves the window alone');
  state.scrubbed = t;
  await drawnAt(t);
  const a = await mapShot('animation-scrubbed.png');
  // Two minutes later (Shift+→ twice), then back (Shift+← twice) to the very same instant.
  await page.locator(sel('playback-play')).focus();
  await page.keyboard.press('Shift+ArrowRight');
  await page.keyboard.press('Shift+ArrowRight');
  assertEqual(Number(await playbackT()), t + 120, 'Shift+→ steps one minute');
  await drawnAt(t + 120);
  const b = await mapShot();
  await page.keyboard.press('Shift+ArrowLeft');
  await page.keyboard.press('Shift+ArrowLeft');
  await page.keyboard.press('ArrowRight');
  await page.keyboard.press('ArrowLeft');
  assertEqual(await playbackT(), String(t), 'the steps come back to the exact instant');
  await drawnAt(t);
  const c = await mapShot();
  const moved = await pixelsDiffering(a, b);
  const same = await pixelsDiffering(a, c);
  assert(moved > 200, `the map's pixels change with the instant (${moved} pixels)`);
  assert(same * 10 < moved, `the same instant draws the same picture (${same} vs ${moved} pixels)`);
  console.log(`        ${moved} pixels change over 2 min; ${same} between two draws of one instant`);
});

await test('the positions drawn equal GET /positions at the scrubbed instant', async () => {
  const t = state.scrubbed;
  const drawn = await page.evaluate((tt) => window.trailscope.animation.positionsAt(tt), t);
  const r = comparePositions(drawn, await apiPositions(t), `t=${t}`);
  assert(r.n > 100, `the instant has traffic (${r.n})`);
  console.log(`        t=${t}: ${r.n} flights, largest error ${r.maxD.toFixed(4)} m, altitude ${r.maxAlt.toFixed(4)} m`);
});

await test('a link with a late instant, speed and tail reopens that moment; positions match to the metre', async () => {
  const q = new URLSearchParams(new URL(page.url()).hash.slice(1));
  q.delete('t0');
  q.delete('t1');
  q.set('at', String(LATE));
  q.set('speed', '1000');
  q.set('tail', '600');
  q.set('color', 'speed');
  // A fresh load of the link (a hash change alone would keep the running page, which rewrites its hash).
  await page.goto('about:blank');
  await page.goto(`${BASE_URL}/#${q.toString()}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="playback"]')?.dataset.state === 'on' && window.trailscope?.animation);
  await page.waitForFunction((t) => document.querySelector('[data-testid="playback"]')?.dataset.t === t, String(LATE));
  assertEqual(await page.getAttribute(sel('playback'), 'data-speed'), '1000', 'speed from the link');
  assertEqual(await page.getAttribute(sel('playback'), 'data-tail'), '600', 'tail from the link');
  assertEqual(await page.inputValue(sel('playback-speed')), '1000', 'speed control');
  assertEqual(await page.inputValue(sel('playback-color')), 'speed', 'colour-by from the link');
  assert((await page.textContent(sel('playback-time'))).includes('23:39:59.5'), 'the readout shows the instant to the tenth');
  const ticks = await page.locator(`${sel('playback-legend')} ${sel('playback-legend-tick')}`).allTextContents();
  assert(ticks.some((t) => / kt$/.test(t)), `speed legend in knots: ${ticks.join(' | ')}`);
  await drawnAt(LATE);
  const drawn = await page.evaluate((t) => window.trailscope.animation.positionsAt(t), LATE);
  const r = comparePositions(drawn, await apiPositions(LATE), `t=${LATE}`);
  assert(r.n > 50, `late traffic (${r.n})`);
  console.log(`        t=${LATE}: ${r.n} flights, largest error ${r.maxD.toFixed(4)} m`);
  await mapShot('animation-late.png');
});

await test('the altitude band applies during playback without refetching', async () => {
  const before = animationRequests();
  await page.fill(sel('alt-min'), String(ALT_MIN_FT));
  await page.fill(sel('alt-max'), String(ALT_MAX_FT));
  await page.press(sel('alt-max'), 'Enter');
  await page.locator(sel('alt-max')).blur();
  const band = `&alt_min=${ALT_MIN_FT}&alt_max=${ALT_MAX_FT}&alt_unit=ft`;
  const api = await apiPositions(LATE, band);
  const all = await apiPositions(LATE);
  assert(api.length > 0 && api.length < all.length, `the band narrows the traffic (${api.length} of ${all.length})`);
  await page.waitForFunction((n) => window.trailscope.animation.positionsAt(window.trailscope.clock.get().t).length === n, api.length);
  const drawn = await page.evaluate((t) => window.trailscope.animation.positionsAt(t), LATE);
  comparePositions(drawn, api, `t=${LATE} in the band`);
  assertEqual(animationRequests(), before, 'no chunk was fetched again for the filter');
});

await test('hover shows an aircraft; click follows it; Esc releases', async () => {
  // An aircraft with no other within 30 px on screen, so the pointer cannot pick a neighbour.
  const target = await page.evaluate((t) => {
    const map = window.trailscope.map;
    const c = map.getCanvas();
    const pts = window.trailscope.animation.positionsAt(t).map((p) => ({ p, s: map.project([p.lon, p.lat]) }));
    const inside = pts.filter(({ s }) => s.x > 80 && s.y > 80 && s.x < c.clientWidth - 80 && s.y < c.clientHeight - 200);
    const lone = inside.find(({ s }) => pts.every((o) => o.s === s || Math.hypot(o.s.x - s.x, o.s.y - s.y) > 30));
    return lone ? { id: lone.p.flightId, x: lone.s.x, y: lone.s.y } : null;
  }, LATE);
  assert(target, 'an isolated aircraft is on screen');
  const box = await page.locator(sel('map')).boundingBox();
  await page.mouse.move(box.x + target.x, box.y + target.y);
  await page.waitForFunction((id) => {
    const t = document.querySelector('[data-testid="aircraft-tooltip"]');
    return t && !t.hidden && t.dataset.flightId === String(id);
  }, target.id);
  const tip = await page.textContent(sel('aircraft-tooltip'));
  assert(/FL\d{3}/.test(tip) && / kt/.test(tip), `the tooltip shows altitude and speed: ${tip}`);
  await page.mouse.click(box.x + target.x, box.y + target.y);
  await page.waitForFunction((id) => document.querySelector('[data-testid="map"]')?.dataset.following === String(id), target.id);
  await page.waitForFunction(() => document.querySelector('[data-testid="flight-card"]')?.dataset.state === 'ready');
  // Following: a minute later the map is centred on the aircraft.
  await page.locator(sel('playback-play')).focus();
  await page.keyboard.press('Shift+ArrowRight');
  const t = LATE + 60;
  await drawnAt(t);
  const off = await page.evaluate(([id, tt]) => {
    const map = window.trailscope.map;
    const a = window.trailscope.animation.aircraft(id);
    const c = map.getCenter();
    return a ? Math.hypot(a.lon - c.lng, a.lat - c.lat) : -1;
  }, [target.id, t]);
  assert(off >= 0 && off < 1e-5, `the map follows the flight (centre ${off}° away)`);
  await mapShot('animation-follow.png');
  await page.keyboard.press('Escape');
  await page.waitForFunction(() => document.querySelector('[data-testid="map"]')?.dataset.following === undefined);
  assertEqual(await page.evaluate(() => window.trailscope.store.get().selectedFlight), target.id, 'the flight stays selected after Esc');
});

await test('no request went to a non-loopback host; no console errors', async () => {
  const outside = [...new Set(requests.filter(leavesMachine))];
  assert(outside.length === 0, `requests left the machine: ${outside.slice(0, 5).join(', ')}`);
  assert(consoleErrors.length === 0, consoleErrors.slice(0, 5).join(' | '));
});

await finish(browser);
