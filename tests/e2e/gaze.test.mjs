// Browser test of the gaze dashboard (#gaze), run through run.sh on a server with an empty data dir: it
// uploads a real Lund 2013 recording (Andersson et al., Behav Res Methods 2017; SMI 500 Hz TSV) with its
// stimulus image through the page, then checks the page against the API and against counts made here:
// the listed sample count is the file's data lines and the API's, the drawn fixations are the API's
// scanpaths under each filter, the density tiles painted pixels inside the stimulus, an AOI drawn with
// the mouse gets the table the API answers and the numbers a brute-force pass over the scanpaths gives,
// the AOIs survive a reload from the URL, bundled saccades are the bundle's polylines, and a delete
// removes the data set. Screenshots go to tests/e2e/artifacts (gaze-*.png).

import { ARTIFACTS, BASE_URL, TIMEOUT, TOKEN, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test } from './harness.mjs';
import { readFile } from 'node:fs/promises';
import path from 'node:path';

const SHARED = process.env.TRAILSCOPE_SHARED ?? '../shared';
const LUND = path.join(SHARED, 'data/gaze/andersson2017_lund');
const FILE = process.env.GAZE_FILE ?? path.join(LUND, 'tsv/TH34_img_Europe.tsv');
const IMAGE = process.env.GAZE_IMAGE ?? path.join(LUND, 'stimuli/Europe1024x768.png');
const NAME = 'lund_th34';
const STIMULUS = 'Europe';
const PARTICIPANT = 'TH34';
// The Lund screen (SOURCES.md): 1024 × 768 px, 38 × 30 cm at 67 cm.
const GEOMETRY = { 'width-px': 1024, 'height-px': 768, 'width-cm': 38, 'height-cm': 30, 'distance-cm': 67 };

const browser = await launchBrowser();
const context = await browser.newContext({ viewport: { width: 1440, height: 900 }, deviceScaleFactor: 1 });
const page = await context.newPage();
page.setDefaultTimeout(TIMEOUT);
page.on('dialog', (d) => void d.accept());
const requests = [];
const consoleErrors = [];
context.on('request', (r) => requests.push(r.url()));
recordErrors(page, consoleErrors);
const auth = TOKEN ? { headers: { Authorization: `Bearer ${TOKEN}` } } : {};
const getJson = async (p, init = {}) => {
  const res = await fetch(`${BASE_URL}${p}`, { ...auth, ...init, headers: { ...auth.headers, ...init.headers } });
  assert(res.ok, `${p}: ${res.status} ${await res.clone().text()}`);
  return res.json();
};
const q = (o) => new URLSearchParams(Object.entries(o).filter(([, v]) => v !== null && v !== undefined && v !== '')).toString();
const gazeReady = () => page.waitForFunction(() => document.querySelector('[data-testid="gaze"]')?.dataset.state === 'ready');
const drawnFixations = () => page.locator('[data-testid="gaze-scanpaths"] circle.fixation').count();
/** The API's fixations with a position (a null centroid has no place on the stimulus). */
const apiFixations = (sp) => sp.scanpaths.reduce((s, p) => s + p.fixations.filter((f) => f.x !== null && f.y !== null).length, 0);
/** The hash's view filters as the API's query (t0/t1 → t0_ms/t1_ms). */
const hashFilters = async () => {
  const h = new URLSearchParams((await page.evaluate(() => window.location.hash)).replace(/^#gaze\??/, ''));
  return { stimulus: h.get('stimulus'), participant: h.get('participant'), t0_ms: h.get('t0'), t1_ms: h.get('t1'), method: h.get('method') };
};
/** Drags on the stage from stimulus point a to b (stimulus pixels → page pixels through the view's transform). */
async function dragStimulus(a, b) {
  const [pa, pb] = await page.evaluate(
    ([a, b]) => {
      const v = window.trailscopeGaze.stage;
      const r = document.querySelector('[data-testid="gaze-overlay"]').getBoundingClientRect();
      return [a, b].map((p) => {
        const [x, y] = v.toScreen(p);
        return [r.left + x, r.top + y];
      });
    },
    [a, b],
  );
  await page.mouse.move(pa[0], pa[1]);
  await page.mouse.down();
  await page.mouse.move((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, { steps: 4 });
  await page.mouse.move(pb[0], pb[1], { steps: 4 });
  await page.mouse.up();
}

console.log(`TrailScope gaze dashboard test against ${BASE_URL} (${path.basename(FILE)})`);

await test('the gaze tab opens with an empty list', async () => {
  await page.goto(`${BASE_URL}/#gaze`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="gaze-list"]')?.dataset.state === 'ready');
  assertEqual(await page.getAttribute(sel('gaze-list'), 'data-count'), '0', 'no gaze data sets yet');
  assertEqual(await page.getAttribute(sel('tab-gaze'), 'aria-current'), 'page', 'the gaze tab is current');
}, { critical: true });

let dataset = null;
await test('upload: progress shown, the data set listed with the file\'s and the API\'s sample count', async () => {
  await page.fill(sel('gaze-upload-name'), NAME);
  await page.fill(sel('gaze-upload-participant'), PARTICIPANT);
  await page.fill(sel('gaze-upload-stimulus'), STIMULUS);
  for (const [k, v] of Object.entries(GEOMETRY)) await page.fill(sel(`gaze-upload-${k}`), String(v));
  await page.setInputFiles(sel('gaze-upload-image'), IMAGE);
  const progress = [];
  await page.exposeFunction('noteProgress', (s) => progress.push(s));
  await page.evaluate(() => {
    new MutationObserver(() => {
      for (const j of document.querySelectorAll('[data-testid="gaze-job"]')) window.noteProgress(`${j.dataset.state}:${j.querySelector('[role=progressbar]')?.getAttribute('aria-valuenow')}`);
    }).observe(document.querySelector('[data-testid="gaze-jobs"]'), { subtree: true, childList: true, attributes: true });
  });
  await page.setInputFiles(sel('gaze-upload-input'), FILE);
  // The data set listed, or the upload's error shown.
  await page.waitForFunction(
    (n) => document.querySelector(`[data-testid="gaze-item"][data-id="${n}"]`) || document.querySelector('[data-testid="gaze-upload-error"]')?.textContent?.trim(),
    NAME,
    { timeout: 120_000 },
  );
  const err = (await page.textContent(sel('gaze-upload-error'))).trim();
  assertEqual(err, '', 'no upload error');
  assert(progress.some((p) => p.startsWith('uploading:')), `the upload's progress was shown (${progress.slice(0, 5).join(', ')})`);
  assert(progress.some((p) => /^(queued|running|done):/.test(p)), `the ingest job's progress was shown (${progress.slice(-5).join(', ')})`);
  assert(progress.some((p) => p === 'done:100'), `the job ended done at 100 % (${progress.slice(-3).join(', ')})`);
  const list = await getJson('/api/v1/gaze');
  dataset = list.datasets.find((d) => d.id === NAME);
  assert(dataset, `GET /gaze lists ${NAME}`);
  // Independent count: the file's data lines (one sample each, after the header).
  const lines = (await readFile(FILE, 'utf8')).split('\n').filter((l) => l.trim() !== '').length - 1;
  assertEqual(dataset.samples, lines, 'the API\'s samples are the file\'s data lines');
  const shown = await page.getAttribute(`${sel('gaze-item')}[data-id="${NAME}"] ${sel('gaze-samples')}`, 'data-value');
  assertEqual(Number(shown), dataset.samples, 'the listed sample count');
  assert(dataset.stimuli.includes(STIMULUS) && dataset.participants.includes(PARTICIPANT), `stimulus and participant kept (${JSON.stringify(dataset)})`);
}, { critical: true });

await test('stimulus view: the image, and one drawn fixation per scanpath fixation of the API', async () => {
  await gazeReady();
  const hash = await page.evaluate(() => window.location.hash);
  assert(hash.includes(`g=${NAME}`) && hash.includes(`stimulus=${STIMULUS}`), `the hash names the view (${hash})`);
  const st = await page.$eval(sel('gaze-stage'), (e) => ({ ...e.dataset }));
  assertEqual(st.hasImage, 'true', 'the stimulus image is shown');
  assertEqual(`${st.stimulusWidth}x${st.stimulusHeight}`, '1024x768', 'the stimulus size');
  const img = await fetch(`${BASE_URL}/api/v1/gaze/${NAME}/stimulus?stimulus=${STIMULUS}`, auth);
  assertEqual(img.status, 200, 'GET …/stimulus');
  assert(Buffer.from(await img.arrayBuffer()).equals(await readFile(IMAGE)), 'the stored image is the uploaded file');
  const sp = await getJson(`/api/v1/gaze/${NAME}/scanpaths?${q({ stimulus: STIMULUS })}`);
  const want = apiFixations(sp);
  assert(want > 5, `the recording has fixations (${want})`);
  assertEqual(await drawnFixations(), want, 'drawn fixations');
  assertEqual(await page.locator('[data-testid="gaze-scanpaths"] text.fixation-number').count(), want, 'every fixation numbered');
  // Circles are sized by duration: the longest fixation has the largest circle.
  const radii = await page.$$eval('[data-testid="gaze-scanpaths"] circle.fixation', (cs) => cs.map((c) => [Number(c.dataset.duration), Number(c.getAttribute('r'))]));
  const longest = radii.reduce((a, b) => (b[0] > a[0] ? b : a));
  assert(radii.every((r) => r[1] <= longest[1] + 1e-9), 'the longest fixation has the largest circle');
  await page.screenshot({ path: path.join(ARTIFACTS, 'gaze-scanpaths.png') });
}, { critical: true });

await test('density tiles painted pixels inside the stimulus, with their legend', async () => {
  await page.waitForFunction(() => document.querySelector('[data-testid="gaze-density"]')?.dataset.state === 'ready', null, { timeout: 60_000 });
  const d = await page.$eval(sel('gaze-density'), (c) => {
    const ctx = c.getContext('2d');
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    const v = window.trailscopeGaze.stage;
    const [x0, y0] = v.toScreen([0, 0]);
    const [x1, y1] = v.toScreen([1024, 768]);
    let inside = 0;
    let outside = 0;
    for (let y = 0; y < c.height; y++)
      for (let x = 0; x < c.width; x++) {
        if (px[4 * (y * c.width + x) + 3] === 0) continue;
        if (x >= Math.floor(x0) - 1 && x <= Math.ceil(x1) + 1 && y >= Math.floor(y0) - 1 && y <= Math.ceil(y1) + 1) inside++;
        else outside++;
      }
    return { painted: Number(c.dataset.painted), inside, outside, tiles: Number(c.dataset.tiles), errors: Number(c.dataset.errors ?? 0) };
  });
  assertEqual(d.errors, 0, 'no tile failed');
  assert(d.tiles > 0, `tiles drawn (${d.tiles})`);
  // Fixation centroids weighted by duration, unsmoothed: sparse dots, but some.
  assert(d.painted > 0, `painted pixels (${d.painted})`);
  assertEqual(d.inside, d.painted, 'the painted count is the canvas\'s');
  assertEqual(d.outside, 0, 'nothing painted outside the stimulus');
  await page.waitForFunction(() => ['ready', 'error'].includes(document.querySelector('[data-testid="gaze-density-legend"]')?.dataset.state));
  const legend = await page.$eval(sel('gaze-density-legend'), (e) => ({ state: e.dataset.state, error: e.dataset.error, ticks: e.dataset.ticks }));
  assertEqual(legend.state, 'ready', `the density legend (${legend.error ?? ''})`);
  assert(legend.ticks && legend.ticks.split('|').length >= 2, `legend ticks (${legend.ticks})`);
});

await test('filters: window and detector redraw the API\'s scanpaths', async () => {
  await page.fill(sel('gaze-t1'), '3000');
  await page.waitForFunction(() => window.location.hash.includes('t1=3000'));
  await gazeReady();
  let sp = await getJson(`/api/v1/gaze/${NAME}/scanpaths?${q({ stimulus: STIMULUS, t1_ms: 3000 })}`);
  assertEqual(await drawnFixations(), apiFixations(sp), 'fixations in the first 3 s');
  // Independent of the filter's parser: every fixation starts within 3 s of its recording's first sample.
  const detail = await getJson(`/api/v1/gaze/${NAME}`);
  const recs = Array.isArray(detail.recordings) ? detail.recordings : detail.recording_list;
  const t0 = new Map(recs.map((r) => [r.index, r.t0_ms]));
  assert(sp.scanpaths.every((p) => p.fixations.every((x) => x.t_start_ms - t0.get(p.recording) <= 3000)), 'fixations start inside the window');
  assert(apiFixations(sp) < apiFixations(await getJson(`/api/v1/gaze/${NAME}/scanpaths?${q({ stimulus: STIMULUS })}`)), 'the window keeps fewer fixations than the whole recording');
  await page.selectOption(sel('gaze-method'), 'idt');
  await page.waitForFunction(() => window.location.hash.includes('method=idt'));
  await gazeReady();
  sp = await getJson(`/api/v1/gaze/${NAME}/scanpaths?${q({ stimulus: STIMULUS, t1_ms: 3000, method: 'idt' })}`);
  assertEqual(await drawnFixations(), apiFixations(sp), 'I-DT fixations in the first 3 s');
  const ev = await getJson(`/api/v1/gaze/${NAME}/events?${q({ stimulus: STIMULUS, t1_ms: 3000, method: 'idt', type: 'fixation,saccade' })}`);
  assertEqual(Number(await page.getAttribute(sel('gaze-event-counts'), 'data-total')), ev.events.length, 'events listed');
  // Back to the whole recording with I-VT.
  await page.fill(sel('gaze-t1'), '');
  await page.selectOption(sel('gaze-method'), 'ivt');
  await page.waitForFunction(() => !window.location.hash.includes('t1=') && !window.location.hash.includes('method='));
  await gazeReady();
});

let aoiHash = '';
await test('an AOI drawn with the mouse: the table holds the API\'s numbers and a brute-force count\'s', async () => {
  await page.fill(sel('aoi-name'), 'centre');
  await page.click(sel('aoi-draw-rect'));
  await dragStimulus([256, 192], [768, 576]);
  await page.waitForFunction(() => document.querySelector('[data-testid="aoi-panel"]')?.dataset.state === 'ready');
  const f = await hashFilters();
  const hash = new URLSearchParams((await page.evaluate(() => window.location.hash)).replace(/^#gaze\??/, ''));
  const m = /^centre:r:([-0-9.]+),([-0-9.]+),([-0-9.]+),([-0-9.]+)$/.exec(hash.get('aoi') ?? '');
  assert(m, `the AOI is in the hash (${hash.get('aoi')})`);
  const rect = m.slice(1, 5).map(Number);
  assert(Math.abs(rect[0] - 256) < 2 && Math.abs(rect[1] - 192) < 2 && Math.abs(rect[2] - 768) < 2 && Math.abs(rect[3] - 576) < 2, `the rectangle drawn (${rect})`);
  const body = { aois: [{ name: 'centre', rect }], stimulus: f.stimulus };
  const api = await getJson(`/api/v1/gaze/${NAME}/aoi`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  const row = api.aois[0];
  const cell = (col) => page.getAttribute(`${sel('aoi-table')} tr[data-name="centre"] td[data-col="${col}"]`, 'data-value');
  assertEqual(Number(await cell('fixations')), row.fixations, 'table: fixations');
  assertEqual(Number(await cell('dwell_ms')), row.dwell_ms, 'table: dwell');
  assertEqual(Number(await cell('visitors')), row.visitors, 'table: visitors');
  assertEqual(await cell('first_median'), row.first_fixation_ms.median === null ? '' : String(row.first_fixation_ms.median), 'table: first fixation (median)');
  // Independent: the scanpaths' fixations whose centroid lies in the rectangle.
  const sp = await getJson(`/api/v1/gaze/${NAME}/scanpaths?${q({ stimulus: STIMULUS })}`);
  const inside = sp.scanpaths.map((p) => p.fixations.filter((x) => x.x !== null && x.y !== null && x.x >= rect[0] && x.x <= rect[2] && x.y >= rect[1] && x.y <= rect[3]));
  const n = inside.reduce((s, l) => s + l.length, 0);
  const dwell = inside.reduce((s, l) => s + l.reduce((a, x) => a + x.duration_ms, 0), 0);
  assert(n > 0, 'fixations fall in the centre of the image');
  assertEqual(row.fixations, n, 'fixations inside, counted here');
  assert(Math.abs(row.dwell_ms - dwell) < 1e-6 * Math.max(1, dwell), `dwell inside, summed here (${row.dwell_ms} vs ${dwell})`);
  assertEqual(row.visitors, inside.filter((l) => l.length > 0).length, 'visitors, counted here');
  // The first fixation in it, after its recording's first sample (one recording: median = min).
  const detail = await getJson(`/api/v1/gaze/${NAME}`);
  const recs = Array.isArray(detail.recordings) ? detail.recordings : detail.recording_list;
  const k = inside.findIndex((l) => l.length > 0);
  const first = inside[k][0].t_start_ms - recs.find((r) => r.index === sp.scanpaths[k].recording).t0_ms;
  assert(Math.abs(row.first_fixation_ms.min - first) < 1e-6, `first fixation, found here (${row.first_fixation_ms.min} vs ${first})`);
  assert(Math.abs(Number(await cell('first_min')) - first) < 1e-6, 'table: first fixation (min)');
  aoiHash = await page.evaluate(() => window.location.hash);
  await page.screenshot({ path: path.join(ARTIFACTS, 'gaze-aoi.png') });
});

await test('a second AOI: the transition matrix is the API\'s', async () => {
  await page.fill(sel('aoi-name'), 'left');
  await page.click(sel('aoi-draw-rect'));
  await dragStimulus([0, 0], [250, 768]);
  await page.waitForFunction(() => document.querySelector('[data-testid="aoi-panel"]')?.dataset.rows === '2' && document.querySelector('[data-testid="aoi-panel"]')?.dataset.state === 'ready');
  const aois = new URLSearchParams((await page.evaluate(() => window.location.hash)).replace(/^#gaze\??/, '')).get('aoi');
  const parsed = aois.split(';').map((s) => {
    const [name, , v] = s.split(':');
    return { name, rect: v.split(',').map(Number) };
  });
  assertEqual(parsed.length, 2, 'two AOIs in the hash');
  const api = await getJson(`/api/v1/gaze/${NAME}/aoi`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ aois: parsed, stimulus: STIMULUS }) });
  const shown = await page.$$eval(`${sel('aoi-matrix')} td`, (tds) => tds.map((t) => `${t.dataset.from}>${t.dataset.to}=${t.dataset.value}`));
  const want = [];
  api.transitions.names.forEach((a, i) => api.transitions.names.forEach((b, j) => want.push(`${a}>${b}=${api.transitions.counts[i][j]}`)));
  assertEqual(shown.join(' '), want.join(' '), 'the matrix cells');
  // Independent: each recording's fixations labelled by the AOI holding them (none skipped, breaking
  // nothing), consecutive labels counted, the diagonal included.
  const sp = await getJson(`/api/v1/gaze/${NAME}/scanpaths?${q({ stimulus: STIMULUS })}`);
  const brute = parsed.map(() => parsed.map(() => 0));
  for (const p of sp.scanpaths) {
    const labels = p.fixations
      .filter((f) => f.x !== null && f.y !== null)
      .map((f) => parsed.findIndex((a) => f.x >= a.rect[0] && f.x <= a.rect[2] && f.y >= a.rect[1] && f.y <= a.rect[3]))
      .filter((i) => i >= 0);
    for (let i = 1; i < labels.length; i++) brute[labels[i - 1]][labels[i]]++;
  }
  const order = api.transitions.names.map((n) => parsed.findIndex((a) => a.name === n));
  assertEqual(JSON.stringify(api.transitions.counts), JSON.stringify(order.map((i) => order.map((j) => brute[i][j]))), 'transitions counted here');
  assert(brute.flat().some((v) => v > 0), 'some transitions');
  aoiHash = await page.evaluate(() => window.location.hash);
  await page.screenshot({ path: path.join(ARTIFACTS, 'gaze-aoi-matrix.png') });
});

await test('the AOIs come back from the URL after a reload', async () => {
  assert(aoiHash.includes('aoi='), 'an AOI hash');
  const before = await page.$$eval(`${sel('aoi-table')} td[data-col]`, (tds) => tds.map((t) => t.dataset.value));
  await page.goto(`${BASE_URL}/${aoiHash}`, { waitUntil: 'domcontentloaded' });
  await page.reload({ waitUntil: 'domcontentloaded' });
  await gazeReady();
  await page.waitForFunction(() => document.querySelector('[data-testid="aoi-panel"]')?.dataset.state === 'ready');
  assertEqual(await page.locator('[data-testid="gaze-aois"] path.aoi').count(), 2, 'two AOIs drawn');
  const after = await page.$$eval(`${sel('aoi-table')} td[data-col]`, (tds) => tds.map((t) => t.dataset.value));
  assertEqual(after.join('|'), before.join('|'), 'the same table');
});

await test('bundled saccades: one drawn line per polyline of the bundle', async () => {
  await page.click(sel('gaze-bundle'));
  await page.waitForFunction(() => ['done', 'failed'].includes(document.querySelector('[data-testid="gaze-bundle-status"]')?.dataset.state), null, { timeout: 120_000 });
  const st = await page.$eval(sel('gaze-bundle-status'), (e) => ({ state: e.dataset.state, bundle: e.dataset.bundle, text: e.textContent }));
  assertEqual(st.state, 'done', `bundling (${st.text})`);
  const b = await getJson(`/api/v1/bundles/${st.bundle}`);
  assert(b.polylines > 0, `the bundle has polylines (${b.polylines})`);
  assertEqual(Number(await page.getAttribute(sel('gaze-bundles'), 'data-lines')), b.polylines, 'drawn bundle lines');
  await page.screenshot({ path: path.join(ARTIFACTS, 'gaze-bundles.png') });
});

await test('delete: gone from the list and from the API', async () => {
  await page.click(`${sel('gaze-item')}[data-id="${NAME}"] ${sel('gaze-delete')}`);
  await page.waitForFunction((n) => !document.querySelector(`[data-testid="gaze-item"][data-id="${n}"]`), NAME);
  const res = await fetch(`${BASE_URL}/api/v1/gaze/${NAME}`, auth);
  assertEqual(res.status, 404, 'GET /gaze/{id} after the delete');
});

await test('no request left the machine, no page errors', async () => {
  const outside = requests.filter(leavesMachine);
  assertEqual(outside.length, 0, `requests leaving the machine: ${outside.slice(0, 3).join(', ')}`);
  assertEqual(consoleErrors.length, 0, `page errors: ${consoleErrors.slice(0, 3).join(' | ')}`);
});

await finish(browser);
