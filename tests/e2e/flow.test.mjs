// Browser test of the flight dashboard's flow layer (run through run.sh, on the server that serves the
// ingested Europe SO6 day): "Show flows" fetches the streamlines of the map view, the line layer holds
// exactly the API's lines (GET /api/v1/datasets/{dataset}/flow?format=json), and the level slider moves on
// the client: at 0 the lines are hidden and the density shows, at 1 the streamlines, at 2 the bundles,
// between 1 and 2 every point halfway. Screenshots go to tests/e2e/artifacts (flow-level-*.png).

import { ARTIFACTS, BASE_URL, TIMEOUT, TOKEN, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test } from './harness.mjs';
import path from 'node:path';

const DATASET = process.env.DATASET ?? 'europe';

const browser = await launchBrowser();
const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1 });
const page = await context.newPage();
page.setDefaultTimeout(TIMEOUT);
const requests = [];
const consoleErrors = [];
context.on('request', (r) => requests.push(r.url()));
recordErrors(page, consoleErrors);
const flowUrls = [];
page.on('response', (r) => r.url().includes('/flow?') && flowUrls.push(r.url()));
const mapIdle = () => page.waitForFunction(() => document.querySelector('[data-testid="map"]')?.dataset.idle === 'true' && !window.trailscope.map.isMoving());
const layerState = () =>
  page.evaluate(async () => {
    const m = window.trailscope.map;
    const src = m.getSource('flow-lines');
    const data = src?.getData ? await src.getData() : src?._data;
    return {
      opacity: m.getPaintProperty('flow-lines', 'line-opacity'),
      density: m.getLayer('density') ? m.getPaintProperty('density', 'raster-opacity') : null,
      features: data?.features?.length ?? -1,
      first: data?.features?.[0]?.geometry?.coordinates?.[0] ?? null,
      data,
    };
  });
const auth = TOKEN ? { headers: { Authorization: `Bearer ${TOKEN}` } } : {};

console.log(`TrailScope flow layer test against ${BASE_URL}`);

await test('page loads the data set', async () => {
  await page.goto(`${BASE_URL}/#dataset=${DATASET}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="summary"]')?.dataset.state === 'ready');
  await page.waitForSelector(sel('flow-show'));
  await mapIdle();
}, { critical: true });

let streams = null, bundles = null;
await test('show flows: the layer holds the API\'s streamlines', async () => {
  await page.click(sel('flow-show'));
  await page.waitForFunction(() => ['shown', 'failed'].includes(document.querySelector('[data-testid="flow-panel"]')?.dataset.state), null, { timeout: 120_000 });
  assertEqual(await page.getAttribute(sel('flow-panel'), 'data-state'), 'shown', `panel state (${await page.textContent(sel('flow-status'))})`);
  assertEqual(flowUrls.length, 2, 'two requests: streamlines and bundles');
  const [s, b] = await Promise.all(flowUrls.map((u) => fetch(u, auth).then((r) => r.json())));
  [streams, bundles] = s.level < b.level ? [s, b] : [b, s];
  assert(streams.lines.length > 50, `many streamlines (${streams.lines.length})`);
  assertEqual(bundles.lines.length, streams.lines.length, 'the bundles pair with the streamlines');
  assertEqual(await page.getAttribute(sel('flow-panel'), 'data-lines'), String(streams.lines.length), 'the panel counts them');
  const st = await layerState();
  assertEqual(st.features, streams.lines.length, 'one feature per line');
  assertEqual(st.opacity, 1, 'level 2: lines fully shown');
  await mapIdle();
  await page.screenshot({ path: path.join(ARTIFACTS, 'flow-level-2.png') });
}, { critical: true });

/** The feature of line `i` (features are sorted by traffic, so find it by its sector and traffic). */
const lineOf = (data, i, src) => data.features.find((f, k) => f.geometry.coordinates.length === src.lines[i].points.length && f.properties.sector === src.lines[i].sector && Math.abs(f.geometry.coordinates[0][0] - src.lines[i].points[0][0]) < 1);

await test('level 1.5: every point halfway between its streamline and its bundle', async () => {
  await page.fill(sel('flow-level'), '1.5');
  await page.dispatchEvent(sel('flow-level'), 'input');
  const st = await layerState();
  const i = streams.lines.findIndex((l) => l.points.length > 4);
  const f = lineOf(st.data, i, streams);
  assert(f, 'the line is in the layer');
  const k = 2;
  const want = [0, 1].map((c) => (streams.lines[i].points[k][c] + bundles.lines[i].points[k][c]) / 2);
  const got = f.geometry.coordinates[k];
  assert(Math.abs(got[0] - want[0]) < 1e-9 && Math.abs(got[1] - want[1]) < 1e-9, `point ${k}: ${got} vs ${want}`);
  await mapIdle();
  await page.screenshot({ path: path.join(ARTIFACTS, 'flow-level-1_5.png') });
});

await test('level 0.5 and 0: the density returns as the lines fade', async () => {
  await page.fill(sel('flow-level'), '0.5');
  await page.dispatchEvent(sel('flow-level'), 'input');
  let st = await layerState();
  assertEqual(st.opacity, 0.5, 'lines at half opacity');
  assert(Math.abs(st.density - 0.46) < 1e-9, `density at half its opacity (${st.density})`);
  await mapIdle();
  await page.screenshot({ path: path.join(ARTIFACTS, 'flow-level-0_5.png') });
  await page.fill(sel('flow-level'), '0');
  await page.dispatchEvent(sel('flow-level'), 'input');
  st = await layerState();
  assertEqual(st.opacity, 0, 'lines hidden');
  assert(Math.abs(st.density - 0.92) < 1e-9, `density at full opacity (${st.density})`);
  assertEqual(await page.textContent(sel('flow-level-value')), '0.00', 'the slider value');
});

await test('no request left the machine, no page errors', async () => {
  const outside = requests.filter(leavesMachine);
  assertEqual(outside.length, 0, `requests leaving the machine: ${outside.slice(0, 3).join(', ')}`);
  assertEqual(consoleErrors.length, 0, `page errors: ${consoleErrors.slice(0, 3).join(' | ')}`);
});

await finish(browser);
