// Browser test of the runs dashboard (#runs), run through run.sh against its own server. It makes two
// short synthetic videos (standard and fast-motion scenarios), sweeps the tracker over 100 random
// parameter points on both (200 runs; ncc_min up to 0.8 and r_max_mm down to 8 mm make part of the
// parameter space fail), opens the sweep in the Runs view and checks:
//  - the projection separates good runs (frames_all_within ≥ GOOD_WITHIN) from bad ones: mean k-NN
//    label agreement (k = 10) in the projected coordinates well above chance, and the centroids of the
//    two groups apart by more than their pooled spread;
//  - brushing a region of good points and one of bad points selects those runs in the table and opens
//    their comparison (one timeline lane per compared run), Shift-brush adds;
//  - clicking a ranked disagreement moves the shared frame cursor of every lane there;
//  - a lane's "open" shows that stored run in the tracker view at the cursor frame (pictures, overlays,
//    state timeline), and stepping there moves the frame;
//  - table selection (click, shift-click), parallel-coordinate brushing and the importance bars.
// Screenshots go to tests/e2e/artifacts/runs-*.png.

import { ARTIFACTS, BASE_URL, TIMEOUT, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test, trackerRunReady, trackerShowsFrame } from './harness.mjs';
import path from 'node:path';

const SAMPLES = Number(process.env.RUNS_SAMPLES ?? 100);
const FRAMES = Number(process.env.RUNS_FRAMES ?? 64);
const SCENARIOS = (process.env.RUNS_SCENARIOS ?? 'standard,fast-motion').split(',');
/** A run is good when at least this share of its frames has every visible teat within 10 mm. */
const GOOD_WITHIN = Number(process.env.RUNS_GOOD_WITHIN ?? 0.5);
const K = 10;
/** Thresholds of "apart": k-NN agreement, its margin over chance, and centroid distance / pooled spread. */
const MIN_KNN = 0.85;
const MIN_KNN_OVER_CHANCE = 0.2;
const MIN_SEPARATION = 1.0;

async function api(method, p, body) {
  const res = await fetch(`${BASE_URL}${p}`, {
    method,
    headers: body ? { 'Content-Type': 'application/json' } : {},
    body: body ? JSON.stringify(body) : undefined,
  });
  const text = await res.text();
  if (!res.ok) throw new Error(`${method} ${p}: ${res.status} ${text.slice(0, 300)}`);
  return text ? JSON.parse(text) : null;
}

async function waitJob(id, label, timeoutMs) {
  const t0 = Date.now();
  let last = -1;
  for (;;) {
    const j = await api('GET', `/api/v1/jobs/${encodeURIComponent(id)}`);
    if (j.state === 'done') return j;
    if (j.state === 'failed' || j.state === 'cancelled') throw new Error(`${label} job ${id} ${j.state}: ${JSON.stringify(j.error)}`);
    const pct = Math.floor((j.progress ?? 0) * 10) * 10;
    if (pct !== last && pct > 0) {
      last = pct;
      console.log(`        ${label}: ${pct} % (${((Date.now() - t0) / 1000).toFixed(0)} s)`);
    }
    if (Date.now() - t0 > timeoutMs) throw new Error(`${label} job ${id} not done after ${timeoutMs / 1000} s (${j.state}, ${j.progress})`);
    await new Promise((r) => setTimeout(r, 500));
  }
}

const within = (run) => run.summary?.accuracy?.frames_all_within ?? 0;
const isGood = (run) => within(run) >= GOOD_WITHIN;

/** Separation of two labels in 2D: mean k-NN label agreement, chance level, centroid distance / pooled spread. */
function separation(points, good) {
  const n = points.length;
  let agree = 0;
  for (let i = 0; i < n; i++) {
    const d = [];
    for (let j = 0; j < n; j++) if (j !== i) d.push([(points[i].x - points[j].x) ** 2 + (points[i].y - points[j].y) ** 2, j]);
    d.sort((a, b) => a[0] - b[0]);
    const nn = d.slice(0, K);
    agree += nn.filter(([, j]) => good[j] === good[i]).length / nn.length;
  }
  const p = good.filter(Boolean).length / n;
  const group = (flag) => {
    const g = points.filter((_, i) => good[i] === flag);
    const cx = g.reduce((s, q) => s + q.x, 0) / g.length;
    const cy = g.reduce((s, q) => s + q.y, 0) / g.length;
    const v = g.reduce((s, q) => s + (q.x - cx) ** 2 + (q.y - cy) ** 2, 0) / g.length;
    return { cx, cy, v };
  };
  const a = group(true);
  const b = group(false);
  const dist = Math.hypot(a.cx - b.cx, a.cy - b.cy);
  return { knn: agree / n, chance: p * p + (1 - p) * (1 - p), sep: dist / Math.sqrt((a.v + b.v) / 2), good: a, bad: b };
}

/** A rectangle (client px) around the `m` points nearest to (cx, cy), padded by 3 px. */
function regionAround(points, cx, cy, m) {
  const near = [...points].sort((p, q) => Math.hypot(p.cx - cx, p.cy - cy) - Math.hypot(q.cx - cx, q.cy - cy)).slice(0, m);
  const x0 = Math.min(...near.map((p) => p.cx)) - 3;
  const x1 = Math.max(...near.map((p) => p.cx)) + 3;
  const y0 = Math.min(...near.map((p) => p.cy)) - 3;
  const y1 = Math.max(...near.map((p) => p.cy)) + 3;
  return { x0, y0, x1, y1 };
}
const inside = (p, r, pad = 0) => p.cx >= r.x0 - pad && p.cx <= r.x1 + pad && p.cy >= r.y0 - pad && p.cy <= r.y1 + pad;

// ---------- run ----------
const browser = await launchBrowser();
const context = await browser.newContext({ viewport: { width: 1600, height: 1000 }, deviceScaleFactor: 1 });
const requests = [];
const errors = [];
context.on('request', (r) => requests.push(r.url()));
const page = await context.newPage();
page.setDefaultTimeout(TIMEOUT);
recordErrors(page, errors);

const st = { videos: [], sweep: null, runs: new Map(), points: [], good: [] };
const state = () => page.evaluate(() => window.__trailscopeRuns.state());

console.log(`TrailScope runs dashboard test against ${BASE_URL}`);

await test(`synthetic videos (${SCENARIOS.join(', ')}; ${FRAMES} frames each)`, async () => {
  for (const scenario of SCENARIOS) {
    const r = await api('POST', '/api/v1/videos/synth', { scenario, frames: FRAMES, seed: 7, name: `runs-e2e-${scenario}` });
    await waitJob(r.job.id, `synth ${scenario}`, 60_000);
    st.videos.push(r.video);
  }
  assertEqual(st.videos.length, SCENARIOS.length, 'videos made');
}, { critical: true });

await test(`a sweep of ${SAMPLES} random points × ${SCENARIOS.length} videos (≥ 200 runs)`, async () => {
  const t0 = Date.now();
  const r = await api('POST', '/api/v1/sweeps', {
    videos: st.videos,
    sweep: {
      mode: 'random',
      samples: SAMPLES,
      seed: 11,
      axes: [
        { param: 'ncc_min', min: 0.1, max: 0.8 },
        { param: 'r_max_mm', min: 8, max: 30 },
        { param: 'd_gate_mm', min: 8, max: 40 },
        { param: 'n_lost', min: 1, max: 12 },
      ],
    },
  });
  st.sweep = r.sweep.id;
  await waitJob(r.job.id, `sweep ${st.sweep}`, 300_000);
  const sweep = await api('GET', `/api/v1/sweeps/${st.sweep}`);
  const all = (await api('GET', '/api/v1/runs')).runs.filter((x) => x.sweep === st.sweep);
  for (const x of all) st.runs.set(x.id, x);
  assert(sweep.runs.length >= 200, `the sweep holds ≥ 200 runs (${sweep.runs.length})`);
  assertEqual(all.length, sweep.runs.length, 'every run of the sweep is stored');
  const good = all.filter(isGood).length;
  console.log(`        ${all.length} runs in ${((Date.now() - t0) / 1000).toFixed(1)} s: ${good} good (frames_all_within ≥ ${GOOD_WITHIN}), ${all.length - good} bad`);
  assert(good >= 20 && all.length - good >= 20, `both good and bad runs exist (${good} good, ${all.length - good} bad)`);
}, { critical: true });

await test('the Runs tab opens the sweep: table, projection, parallel coordinates, importance', async () => {
  await page.goto(`${BASE_URL}/#runs?sweep=${encodeURIComponent(st.sweep)}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.getElementById('app')?.dataset.view === 'runs');
  assertEqual(await page.getAttribute(sel('tab-runs'), 'aria-current'), 'page', 'the Runs tab is current');
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready', null, { timeout: 60_000 });
  const rows = await page.locator(`${sel('runs-table')} tbody tr[data-run]`).count();
  assertEqual(rows, st.runs.size, 'one table row per run');
  const s = await state();
  assertEqual(s.sweep, st.sweep, 'the view shows the sweep');
  assertEqual(s.points.length, st.runs.size, 'one projected point per run');
  const headers = await page.locator(`${sel('runs-table')} thead th`).allTextContents();
  for (const p of ['ncc_min', 'r_max_mm', 'd_gate_mm', 'n_lost']) assert(headers.some((t) => t.includes(p)), `the table shows the varying parameter ${p} (${headers.join(' | ')})`);
  const axes = await page.locator(`${sel('parcoords')} .pc-axis`).count();
  assert(axes >= 6, `parallel coordinates have the 4 parameters and the varying metrics (${axes} axes)`);
  await page.waitForFunction(() => document.querySelectorAll('[data-testid="importance"] .imp-row').length > 0);
  const imp = await page.locator(`${sel('importance')} .imp-row`).first().getAttribute('data-param');
  const meta = await page.textContent(sel('importance-meta'));
  console.log(`        most important for track share: ${imp}; ${meta}`);
  assert(/R²/.test(meta), `the importance shows the forest R² (${meta})`);
  const q = await page.getAttribute(sel('projection-quality'), 'data-trustworthiness');
  assert(Number(q) > 0.5, `the projection's trustworthiness is shown (${q})`);
}, { critical: true });

async function measure(label) {
  const s = await state();
  st.points = s.points;
  st.good = s.points.map((p) => isGood(st.runs.get(p.id)));
  const m = separation(s.points.map((p) => ({ x: p.x, y: p.y })), st.good);
  console.log(
    `        ${label}: k-NN agreement ${m.knn.toFixed(3)} (chance ${m.chance.toFixed(3)}), centroid distance / pooled spread ${m.sep.toFixed(2)}; trustworthiness ${s.projection?.quality?.trustworthiness?.toFixed(3)}`,
  );
  return m;
}

await test('good and bad runs are apart in the projection (PCA of parameters + results)', async () => {
  const m = await measure('PCA, parameters + results');
  assert(m.knn >= MIN_KNN, `k-NN (k=${K}) agreement ${m.knn.toFixed(3)} ≥ ${MIN_KNN}`);
  assert(m.knn - m.chance >= MIN_KNN_OVER_CHANCE, `agreement ${m.knn.toFixed(3)} is ≥ ${MIN_KNN_OVER_CHANCE} over chance ${m.chance.toFixed(3)}`);
  assert(m.sep >= MIN_SEPARATION, `centroid distance / pooled spread ${m.sep.toFixed(2)} ≥ ${MIN_SEPARATION}`);
  await page.mouse.move(5, 5);
  await page.locator('.projection-panel').screenshot({ path: path.join(ARTIFACTS, 'runs-projection-pca.png') });
}, { critical: true });

await test('t-SNE from the method picker: good and bad runs still apart', async () => {
  await page.selectOption(sel('method-select'), 'tsne');
  await page.waitForFunction(() => window.__trailscopeRuns.state().projection?.method === 'tsne', null, { timeout: 60_000 });
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready');
  await page.waitForFunction(() => location.hash.includes('method=tsne')); // the URL keeps the method
  const m = await measure('t-SNE, parameters + results');
  assert(m.knn >= MIN_KNN, `k-NN agreement ${m.knn.toFixed(3)} ≥ ${MIN_KNN}`);
  await page.mouse.move(5, 5);
  await page.locator('.projection-panel').screenshot({ path: path.join(ARTIFACTS, 'runs-projection-tsne.png') });
});

await test('parameters only (no results in the projection): the good region is still apart', async () => {
  await page.selectOption(sel('include-select'), 'params');
  await page.waitForFunction(() => !window.__trailscopeRuns.state().projection?.columns.some((c) => c.startsWith('metric:')), null, { timeout: 60_000 });
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready');
  const m = await measure('t-SNE, parameters only');
  // Informative: the parameters alone decide the outcome only in part (the video matters too).
  assert(m.knn - m.chance >= 0.1, `k-NN agreement ${m.knn.toFixed(3)} is above chance ${m.chance.toFixed(3)}`);
  await page.mouse.move(5, 5);
  await page.locator('.projection-panel').screenshot({ path: path.join(ARTIFACTS, 'runs-projection-params.png') });
  // Back to parameters + results, PCA, for the brushing steps.
  await page.selectOption(sel('include-select'), 'params,metrics');
  await page.selectOption(sel('method-select'), 'pca');
  await page.waitForFunction(() => {
    const p = window.__trailscopeRuns.state().projection;
    return p?.method === 'pca' && p.columns.some((c) => c.startsWith('metric:'));
  });
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready');
  await measure('PCA again');
});

async function brush(r, { shift = false } = {}) {
  await page.mouse.move(5, 5);
  if (shift) await page.keyboard.down('Shift');
  await page.mouse.move(r.x0, r.y0);
  await page.mouse.down();
  await page.mouse.move((r.x0 + r.x1) / 2, (r.y0 + r.y1) / 2, { steps: 4 });
  await page.mouse.move(r.x1, r.y1, { steps: 4 });
  await page.mouse.up();
  if (shift) await page.keyboard.up('Shift');
}

/** Waits for the comparison of the current selection and checks table, lanes and selection agree. */
async function checkSelectionAndLanes(expectIn, expectOut, label) {
  await page.waitForFunction(() => {
    const s = window.__trailscopeRuns.state();
    const c = document.querySelector('[data-testid="compare"]');
    return s.compare && (s.compare.ids.length < 2 || (c?.dataset.state === 'ready' && s.lanes.join(',') === s.compare.ids.join(',')));
  }, null, { timeout: 30_000 });
  const s = await state();
  const selSet = new Set(s.selection);
  for (const id of expectIn) assert(selSet.has(id), `${label}: run ${id} inside the brush is selected`);
  for (const id of s.selection) assert(!expectOut.has(id), `${label}: run ${id} outside the brush is not selected`);
  assertEqual([...s.tableSelected].sort().join(','), [...s.selection].sort().join(','), `${label}: the table shows the selection`);
  const checked = await page.locator(`${sel('runs-table')} tbody tr[aria-selected="true"] input:checked`).count();
  assertEqual(checked, s.selection.length, `${label}: checked boxes`);
  // The comparison: runs of one video from the selection, up to 8, one lane each.
  const perVideo = new Map();
  for (const id of s.selection) perVideo.set(st.runs.get(id).video, (perVideo.get(st.runs.get(id).video) ?? 0) + 1);
  const most = Math.max(...perVideo.values());
  const lanes = Number(await page.getAttribute(sel('compare-lanes'), 'data-lanes'));
  const laneEls = await page.locator(`${sel('compare-lanes')} .lane`).count();
  if (most >= 2) {
    assertEqual(lanes, Math.min(8, most), `${label}: lanes for the selected runs of the most selected video`);
    assertEqual(laneEls, lanes, `${label}: lane elements`);
    for (const id of s.lanes) {
      assert(selSet.has(id), `${label}: lane ${id} is a selected run`);
      assertEqual(st.runs.get(id).video, s.compare.video, `${label}: lane ${id} is of the compared video`);
    }
    const multiples = await page.locator(`${sel('compare-multiples')} .multiple`).count();
    assertEqual(multiples, lanes, `${label}: one small multiple per run`);
  }
  return s;
}

/**
 * Brushes the region around the centroid of the points whose runs `pick` accepts, then checks the
 * selection and the lanes (checkSelectionAndLanes, under `label`): every point inside the region is
 * selected, none outside. Returns the region and the state.
 */
async function brushAroundCentroid(pick, label) {
  const pts = (await state()).points;
  const group = pts.filter((p) => pick(st.runs.get(p.id)));
  const cx = group.reduce((s, p) => s + p.cx, 0) / group.length;
  const cy = group.reduce((s, p) => s + p.cy, 0) / group.length;
  const r = regionAround(pts, cx, cy, 24);
  await brush(r);
  const expectIn = pts.filter((p) => inside(p, r, -1)).map((p) => p.id);
  const expectOut = new Set(pts.filter((p) => !inside(p, r, 1)).map((p) => p.id));
  const s = await checkSelectionAndLanes(expectIn, expectOut, label);
  return { r, s };
}

await test('brush a region of good points: those runs are selected in the table and compared', async () => {
  const { r, s } = await brushAroundCentroid(isGood, 'good brush');
  const share = s.selection.filter((id) => isGood(st.runs.get(id))).length / s.selection.length;
  console.log(`        good brush: ${s.selection.length} runs selected, ${(share * 100).toFixed(0)} % good; lanes ${s.lanes.join(', ')}`);
  assert(s.selection.length >= 5, `the brush holds runs (${s.selection.length})`);
  assert(share >= 0.8, `the region around the good centroid is mostly good runs (${(share * 100).toFixed(0)} %)`);
  assert(s.lanes.length >= 2, 'a comparison opened');
  st.goodRect = r;
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'runs-good-brush.png') });
}, { critical: true });

await test('the lasso brush (lasso mode) selects the same runs around the good region', async () => {
  const before = [...(await state()).selection].sort().join(',');
  await page.check(sel('lasso-mode'));
  const r = st.goodRect;
  // A lasso along the rectangle's edges, with intermediate points.
  const path = [];
  for (let t = 0; t <= 1; t += 0.25) path.push([r.x0 + t * (r.x1 - r.x0), r.y0]);
  for (let t = 0; t <= 1; t += 0.25) path.push([r.x1, r.y0 + t * (r.y1 - r.y0)]);
  for (let t = 0; t <= 1; t += 0.25) path.push([r.x1 - t * (r.x1 - r.x0), r.y1]);
  for (let t = 0; t <= 1; t += 0.25) path.push([r.x0, r.y1 - t * (r.y1 - r.y0)]);
  await page.mouse.click(5, 5);
  await page.mouse.move(path[0][0], path[0][1]);
  await page.mouse.down();
  for (const [x, y] of path.slice(1)) await page.mouse.move(x, y, { steps: 2 });
  await page.mouse.up();
  await page.uncheck(sel('lasso-mode'));
  const pts = (await state()).points;
  const expectIn = pts.filter((p) => inside(p, r, -2)).map((p) => p.id);
  const expectOut = new Set(pts.filter((p) => !inside(p, r, 2)).map((p) => p.id));
  const s = await checkSelectionAndLanes(expectIn, expectOut, 'lasso');
  console.log(`        lasso: ${s.selection.length} runs (rectangle brush: ${before.split(',').length})`);
});

await test('brush a region of bad points: the selection and the lanes follow', async () => {
  const { r, s } = await brushAroundCentroid((run) => !isGood(run), 'bad brush');
  const share = s.selection.filter((id) => !isGood(st.runs.get(id))).length / s.selection.length;
  console.log(`        bad brush: ${s.selection.length} runs selected, ${(share * 100).toFixed(0)} % bad; lanes ${s.lanes.join(', ')}`);
  assert(share >= 0.8, `the region around the bad centroid is mostly bad runs (${(share * 100).toFixed(0)} %)`);
  st.badRect = r;
});

await test('Shift-brush the good region too: both regions selected, the comparison spans good and bad runs', async () => {
  const before = (await state()).selection;
  await brush(st.goodRect, { shift: true });
  await page.waitForFunction((n) => window.__trailscopeRuns.state().selection.length > n, before.length);
  const pts = (await state()).points;
  const expectIn = [...before, ...pts.filter((p) => inside(p, st.goodRect, -1)).map((p) => p.id)];
  const expectOut = new Set(pts.filter((p) => !inside(p, st.goodRect, 1) && !before.includes(p.id)).map((p) => p.id));
  const s = await checkSelectionAndLanes(expectIn, expectOut, 'union');
  const goodLanes = s.lanes.filter((id) => isGood(st.runs.get(id))).length;
  console.log(`        union: ${s.selection.length} selected; lanes ${s.lanes.join(', ')} (${goodLanes} good, ${s.lanes.length - goodLanes} bad); ${s.disagreements.length} disagreement frames`);
  assert(s.lanes.length >= 2, 'a comparison opened');
  if (goodLanes > 0 && goodLanes < s.lanes.length) assert(s.disagreements.length > 0, 'good and bad runs disagree somewhere');
});

await test('click a ranked disagreement: every lane’s cursor moves to its frame', async () => {
  const s0 = await state();
  assert(s0.disagreements.length > 0, 'disagreements are listed');
  const rows = page.locator(sel('disagreement'));
  const n = await rows.count();
  const row = rows.nth(Math.min(2, n - 1));
  const frame = Number(await row.getAttribute('data-frame'));
  await row.click();
  await page.waitForFunction((f) => Number(document.querySelector('[data-testid="compare"]')?.dataset.cursor) === f, frame);
  const s = await state();
  assertEqual(s.cursor, frame, 'the shared cursor');
  const scores = s.disagreements.map((d) => d.score);
  assert(scores.every((v, i) => i === 0 || v <= scores[i - 1]), 'the list is ranked, largest first');
  const first = Number((await page.textContent(sel('compare-meta'))).match(/frames (\d+)/)[1]);
  for (const id of s.lanes) {
    assertEqual(Number(await page.getAttribute(sel(`lane-${id}`), 'data-cursor')), frame - first, `lane ${id} cursor`);
    assertEqual(Number(await page.getAttribute(sel(`multiple-${id}`), 'data-cursor')), frame - first, `small multiple ${id} cursor`);
  }
  await page.waitForFunction((f) => location.hash.includes(`frame=${f}`), frame); // the URL keeps the frame
  assert(await row.evaluate((el) => el.classList.contains('current')), 'the clicked row is marked');
  // Clicking a lane sets the cursor in all lanes.
  const lane = page.locator(sel(`lane-${s.lanes[1]}`));
  const box = await lane.boundingBox();
  const frames = Number(await lane.getAttribute('data-frames'));
  const target = Math.floor(frames * 0.3);
  await page.mouse.click(box.x + ((target + 0.5) * box.width) / frames, box.y + box.height / 2);
  await page.waitForFunction((f) => Number(document.querySelector('[data-testid="compare"]')?.dataset.cursor) === f, first + target);
  assertEqual(Number(await page.getAttribute(sel(`lane-${s.lanes[0]}`), 'data-cursor')), target, 'the other lanes follow a lane click');
  // Keyboard: → steps the shared cursor by one frame, Shift+→ by ten.
  await page.focus(sel('compare-lanes'));
  await page.keyboard.press('ArrowRight');
  await page.waitForFunction((f) => Number(document.querySelector('[data-testid="compare"]')?.dataset.cursor) === f, first + target + 1);
  await page.keyboard.press('Shift+ArrowRight');
  await page.waitForFunction((f) => Number(document.querySelector('[data-testid="compare"]')?.dataset.cursor) === f, first + target + 11);
  assertEqual(Number(await page.getAttribute(sel(`lane-${s.lanes[0]}`), 'data-cursor')), target + 11, 'the lanes follow the keyboard');
  console.log(`        disagreement row → frame ${frame}; lane click → frame ${first + target}; → and Shift+→ → frame ${first + target + 11}`);
  // Parameter and result differences beside each other, the best result marked.
  const diffRows = await page.locator(`${sel('param-diffs')} tbody tr`).count();
  assert(diffRows >= 1, `parameters that differ are listed (${diffRows})`);
  assert((await page.locator(`${sel('result-diffs')} td.best`).count()) >= 1, 'a best result is marked');
  await page.locator(sel('compare')).scrollIntoViewIfNeeded();
  await page.mouse.move(5, 5);
  await page.locator(sel('compare')).screenshot({ path: path.join(ARTIFACTS, 'runs-compare.png') });
});

await test('table: sort by track share, click + Shift-click selects a range of 4', async () => {
  await page.locator(`${sel('runs-table')} thead button[data-sort="track_share"]`).click();
  const ids = await page.locator(`${sel('runs-table')} tbody tr[data-run]`).evaluateAll((trs) => trs.map((t) => t.dataset.run));
  const shares = ids.map((id) => st.runs.get(id).summary.track_share);
  assert(shares.every((v, i) => i === 0 || v <= shares[i - 1]), 'rows sorted by track share, highest first');
  await page.locator(`${sel('runs-table')} tbody tr[data-run="${ids[0]}"]`).click();
  await page.locator(`${sel('runs-table')} tbody tr[data-run="${ids[3]}"]`).click({ modifiers: ['Shift'] });
  await page.waitForFunction(() => window.__trailscopeRuns.state().selection.length === 4);
  const s = await state();
  assertEqual([...s.selection].sort().join(','), ids.slice(0, 4).sort().join(','), 'the range is selected');
  await page.waitForFunction((want) => new URLSearchParams(location.hash.replace(/^#runs\??/, '')).get('sel') === want, s.selection.join(','));
});

await test('the URL restores the view: a new tab shows the same sweep, selection and comparison', async () => {
  // The comparison of the current selection has loaded (it follows the selection after a short delay).
  await page.waitForFunction(() => {
    const t = window.__trailscopeRuns.state();
    return t.compare && (t.compare.ids.length < 2 || t.lanes.join(',') === t.compare.ids.join(','));
  });
  const s = await state();
  const url = page.url();
  const other = await context.newPage();
  other.on('pageerror', (e) => errors.push(`pageerror (second tab): ${e.message}`));
  await other.goto(url, { waitUntil: 'domcontentloaded' });
  await other.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready');
  await other.waitForFunction(
    (want) => {
      const t = window.__trailscopeRuns.state();
      if (t.selection.join(',') !== want || !t.compare) return false;
      return t.compare.ids.length < 2 || t.lanes.join(',') === t.compare.ids.join(',');
    },
    s.selection.join(','),
  );
  const t = await other.evaluate(() => window.__trailscopeRuns.state());
  assertEqual(t.sweep, s.sweep, 'sweep');
  assertEqual(t.lanes.join(','), s.lanes.join(','), 'compared runs');
  await other.close();
});

await test('parallel coordinates: brushing the ncc_min axis filters the runs to that interval', async () => {
  const axis = page.locator(`${sel('parcoords')} .pc-axis[data-axis="param:ncc_min"] .pc-hit`);
  const box = await axis.boundingBox();
  const x = box.x + box.width / 2;
  // The lower half of the axis (low ncc_min: where tracking works).
  await page.mouse.move(x, box.y + box.height * 0.55);
  await page.mouse.down();
  await page.mouse.move(x, box.y + box.height * 0.75, { steps: 3 });
  await page.mouse.move(x, box.y + box.height - 6, { steps: 3 });
  await page.mouse.up();
  await page.waitForFunction(() => window.__trailscopeRuns.state().filter !== null);
  const s = await state();
  const vals = s.filter.map((id) => st.runs.get(id).params[st.runs.get(id).param_names.indexOf('ncc_min')]);
  const all = [...st.runs.values()].map((r) => r.params[r.param_names.indexOf('ncc_min')]);
  const cut = Math.max(...vals);
  assert(s.filter.length > 0 && s.filter.length < st.runs.size, `the filter keeps part of the runs (${s.filter.length})`);
  assertEqual(all.filter((v) => v <= cut).length >= s.filter.length, true, 'the filter is an interval of ncc_min');
  const dimmed = await page.locator(`${sel('runs-table')} tbody tr.dim`).count();
  assertEqual(dimmed, st.runs.size - s.filter.length, 'the table dims the runs outside the filter');
  console.log(`        ncc_min ≤ ${cut.toFixed(3)}: ${s.filter.length} runs in the filter`);
  // The filter is in the URL: a new tab opens with the same runs filtered.
  await page.waitForFunction(() => /[?&]pc=param:ncc_min:/.test(location.hash));
  const other = await context.newPage();
  await other.goto(page.url(), { waitUntil: 'domcontentloaded' });
  await other.waitForFunction((n) => window.__trailscopeRuns?.state().filter?.length === n, s.filter.length);
  await other.close();
  await page.mouse.move(5, 5);
  await page.setViewportSize({ width: 1600, height: 1900 });
  await page.waitForTimeout(400);
  await page.screenshot({ path: path.join(ARTIFACTS, 'runs.png'), fullPage: true });
  await page.setViewportSize({ width: 1600, height: 1000 });
});

await test('hover a point: the tooltip names its run and metric', async () => {
  await page.locator(sel('projection')).scrollIntoViewIfNeeded();
  const p = (await state()).points[0];
  await page.mouse.move(p.cx, p.cy);
  await page.waitForSelector('.scatter-tip:not([hidden])');
  const tip = await page.textContent('.scatter-tip');
  assert(tip.includes(p.id) && /%/.test(tip), `tooltip "${tip}"`);
});

await test('▶ on a lane replays that run in the tracker view (its video, its parameters)', async () => {
  const s = await state();
  const id = s.lanes[0];
  assert(id, 'a comparison is open');
  const run = st.runs.get(id);
  await page.locator(`${sel('compare-lanes')} .lane[data-run="${id}"] .lane-replay`).click();
  await page.waitForFunction(() => document.getElementById('app')?.dataset.view === 'tracker');
  await page.waitForFunction(() => document.querySelector('[data-testid="tracker"]')?.dataset.state === 'ready');
  const replay = await page.getAttribute(sel('tracker'), 'data-replay');
  const r = await api('GET', `/api/v1/replays/${encodeURIComponent(replay)}`);
  assertEqual(r.video, run.video, 'the replay is of the run’s video');
  for (const name of ['ncc_min', 'r_max_mm', 'd_gate_mm', 'n_lost']) {
    const want = run.params[run.param_names.indexOf(name)];
    assert(Math.abs(r.params[name] - want) < 1e-9, `${name}: replay ${r.params[name]}, run ${want}`);
  }
  await page.goBack();
  await page.waitForFunction(() => document.getElementById('app')?.dataset.view === 'runs');
});

await test('"open" on a lane shows the stored run in the tracker view at the cursor frame; stepping moves it', async () => {
  // The worst disagreement's frame under the cursor, then the stored run of the first lane there.
  await page.locator(sel('disagreement')).first().click();
  const s = await state();
  const frame = s.cursor;
  const id = s.lanes[0];
  assert(id && Number.isInteger(frame), `a comparison with a cursor (${id}, ${frame})`);
  const link = page.locator(sel(`lane-open-${id}`));
  assertEqual(await link.getAttribute('href'), `#tracker?run=${encodeURIComponent(id)}&frame=${frame}`, 'the open link follows the cursor');
  const replaysBefore = (await api('GET', '/api/v1/replays')).replays?.length ?? 0;
  await link.click();
  await page.waitForFunction(() => document.getElementById('app')?.dataset.view === 'tracker');
  await trackerRunReady(page, id);
  const shows = (f) => trackerShowsFrame(page, f, { index: true });
  await shows(frame);
  const counter = await page.textContent(sel('replay-frame'));
  assert(new RegExp(`frame ${frame} /`).test(counter), `the counter reads "${counter}"`);
  assertEqual(await page.textContent(sel('run-id')), id, 'the setup panel names the run');
  const d = await page.$eval(sel('replay-images'), (el) => ({ ...el.dataset }));
  const overlays = Number(d.candidates) + Number(d.estimates) + Number(d.truthTips);
  assert(overlays > 0, `overlays are drawn (candidates ${d.candidates}, estimates ${d.estimates}, truth ${d.truthTips})`);
  assert(Number(d.truthTips) + Number(d.truthBoxes) > 0, `the ground truth is drawn (${d.truthTips} tips, ${d.truthBoxes} boxes)`);
  const run = st.runs.get(id);
  await page.waitForFunction((n) => Number(document.querySelector('[data-testid="state-timeline"]')?.dataset.known) === n, run.summary.frames);
  assertEqual(Number(await page.getAttribute(sel('state-timeline'), 'data-cursor')), frame, 'the state timeline cursor');
  assertEqual(Number(await page.getAttribute(sel('trajectory-z'), 'data-cursor')), frame, 'the trajectory cursor');
  assert(Number(await page.getAttribute(sel('trajectories'), 'data-points')) > 0, 'the trajectories hold estimates');
  const replaysAfter = (await api('GET', '/api/v1/replays')).replays?.length ?? 0;
  assertEqual(replaysAfter, replaysBefore, 'no replay was started (the stored run is shown)');
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'runs-open-stored-run.png') });
  // Step one frame (the last frame steps back instead).
  const frames = Number(await page.getAttribute(sel('replay-seek'), 'max')) + 1;
  const next = frame + 1 < frames ? frame + 1 : frame - 1;
  await page.click(sel(next > frame ? 'replay-step' : 'replay-step-back'));
  await shows(next);
  assertEqual(Number(await page.getAttribute(sel('state-timeline'), 'data-cursor')), next, 'the timeline follows the step');
  await page.waitForFunction((f) => location.hash.includes(`frame=${f}`), next); // the URL keeps the frame
  // Play advances the cursor locally, pause stops it.
  await page.click(sel('replay-play'));
  await page.waitForFunction(() => document.querySelector('[data-testid="replay-controls"]')?.dataset.playing === 'true');
  const atPlay = Number(await page.getAttribute(sel('replay-frame'), 'data-frame'));
  await page.waitForFunction(
    (f) => Number(document.querySelector('[data-testid="replay-frame"]')?.dataset.frame) !== f || document.querySelector('[data-testid="replay-controls"]')?.dataset.playing === 'false',
    atPlay,
  );
  await page.click(sel('replay-play'));
  console.log(`        run ${id} at frame ${frame}: ${d.candidates} candidates, ${d.estimates} estimates, ${d.truthTips} truth tips; stepped to ${next}`);
  await page.goBack();
  await page.waitForFunction(() => document.getElementById('app')?.dataset.view === 'runs');
});

await test('the sweep launcher starts a small sweep and opens it when done', async () => {
  await page.locator(`${sel('sweep-launcher')} summary`).click();
  await page.waitForSelector(`${sel('launch-videos')} input[data-video="${st.videos[0]}"]`);
  await page.check(`${sel('launch-videos')} input[data-video="${st.videos[0]}"]`);
  await page.fill(sel('launch-samples'), '3');
  assertEqual(await page.locator(`${sel('sweep-launcher')} [data-testid="launch-param"]`).first().inputValue(), 'ncc_min', 'the first range is ncc_min');
  await page.click(sel('launch-start'));
  await page.waitForFunction((old) => {
    const s = window.__trailscopeRuns.state();
    return s.sweep && s.sweep !== old && s.rows === 3;
  }, st.sweep, { timeout: 60_000 });
  const s = await state();
  const sweep = await api('GET', `/api/v1/sweeps/${s.sweep}`);
  assertEqual(sweep.runs.length, 3, 'the new sweep has 3 runs');
  assertEqual(sweep.spec.axes[0].param, 'ncc_min', 'it sweeps ncc_min');
  await page.waitForFunction((id) => document.querySelector('[data-testid="sweep-select"]')?.value === id, s.sweep);
  console.log(`        sweep ${s.sweep}: ${(await page.textContent(sel('launch-status'))).trim()}`);
});

await test('t-SNE on a 20-run sweep: the perplexity is capped to (N − 1) / 3 and the projection is drawn', async () => {
  // The 3-run sweep the launcher just opened is too small for t-SNE: the option says why.
  const opt = page.locator(`${sel('method-select')} option[value="tsne"]`);
  await page.waitForFunction(() => document.querySelector('[data-testid="method-select"] option[value="tsne"]')?.disabled === true);
  assert(((await opt.getAttribute('title')) ?? '').includes('at least 4 runs'), 'the disabled t-SNE option gives the rule');
  const r = await api('POST', '/api/v1/sweeps', {
    videos: [st.videos[0]],
    sweep: { mode: 'random', samples: 20, seed: 5, axes: [{ param: 'ncc_min', min: 0.1, max: 0.8 }, { param: 'r_max_mm', min: 8, max: 30 }] },
  });
  await waitJob(r.job.id, `sweep ${r.sweep.id}`, 120_000);
  const sweep = await api('GET', `/api/v1/sweeps/${r.sweep.id}`);
  assertEqual(sweep.runs.length, 20, 'the sweep holds 20 runs');
  await page.goto(`${BASE_URL}/#runs?sweep=${encodeURIComponent(r.sweep.id)}&method=tsne`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => window.__trailscopeRuns?.state().projection?.method === 'tsne', null, { timeout: 60_000 });
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready');
  const s = await state();
  assertEqual(s.points.length, 20, 'all 20 runs are projected');
  // Capped as openTSNE does: floor((20 − 1) / 3, 0.01) = 6.33, and the server accepted it (3·6.33 ≤ 19).
  assertEqual(await page.getAttribute('.perplexity', 'data-value'), '6.33', 'the perplexity sent');
  assert((await page.textContent(sel('perplexity-note'))).includes('capped to 6.33'), 'the cap is said');
  // A smaller perplexity is sent as asked and kept in the URL.
  await page.fill(sel('perplexity-input'), '4');
  await page.press(sel('perplexity-input'), 'Enter');
  await page.locator(sel('perplexity-input')).blur();
  await page.waitForFunction(() => location.hash.includes('perp=4') && document.querySelector('.perplexity')?.dataset.value === '4');
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready');
  // Every point is drawn with a visible rim: count lit pixels at the points' places.
  await page.mouse.move(5, 5);
  await page.locator('.projection-panel').screenshot({ path: path.join(ARTIFACTS, 'runs-tsne-20.png') });
});

await test('a projection whose runs changed on the server is marked stale (a comparison whose runs are all there is not); one click recomputes', async () => {
  // The 20-run sweep, two of its runs selected and compared; a third run is deleted by another client.
  const sweepId = (await state()).sweep;
  const ids = (await api('GET', `/api/v1/sweeps/${sweepId}`)).runs.map((r) => (typeof r === 'string' ? r : r.id));
  assertEqual(ids.length, 20, 'the 20-run sweep');
  await page.goto(`${BASE_URL}/#runs?sweep=${encodeURIComponent(sweepId)}&sel=${ids[1]},${ids[2]}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready', null, { timeout: 60_000 });
  await page.waitForFunction(() => window.__trailscopeRuns.state().lanes.length === 2, null, { timeout: 60_000 });
  assertEqual((await state()).points.length, 20, '20 runs projected');
  assert(await page.locator(sel('projection-stale')).isHidden(), 'a fresh projection has no stale mark');
  const del = await fetch(`${BASE_URL}/api/v1/runs/${encodeURIComponent(ids[0])}`, { method: 'DELETE' });
  assertEqual(del.status, 204, 'DELETE run');
  // The view learns it when it checks (here: the window gains focus).
  await page.evaluate(() => window.dispatchEvent(new Event('focus')));
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.stale === 'true');
  assert((await page.textContent(sel('projection-stale'))).includes('19 runs on the server now, 20 projected'), 'the projection says why');
  assert(await page.locator(sel('compare-stale')).isHidden(), 'the comparison (its two runs still there) is not stale');
  assertEqual((await state()).points.length, 20, 'nothing was recomputed behind the analyst');
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'runs-stale.png') });
  // One click: the lists are reloaded and the projection made again from the 19 runs; the mark goes.
  await page.click(sel('projection-recompute'));
  await page.waitForFunction(() => {
    const p = document.querySelector('[data-testid="projection"]');
    return p?.dataset.state === 'ready' && p.dataset.stale === 'false' && window.__trailscopeRuns.state().points.length === 19;
  }, null, { timeout: 60_000 });
  assert(await page.locator(sel('projection-stale')).isHidden(), 'no stale mark after recomputing');
});

await test('a comparison whose run was deleted on the server is marked stale, left as drawn until its Recompute', async () => {
  const sweepId = (await state()).sweep;
  // The sweep's runs still on the server (the sweep's own list keeps the id the last step deleted).
  const ids = (await api('GET', '/api/v1/runs')).runs.filter((r) => r.sweep === sweepId).map((r) => r.id);
  assertEqual(ids.length, 19, 'the sweep\'s runs after the last step');
  const [a, b] = [ids[0], ids[1]];
  // A fresh load (a hash-only navigation would keep the page, whose last step may still be comparing).
  await page.goto('about:blank');
  await page.goto(`${BASE_URL}/#runs?sweep=${encodeURIComponent(sweepId)}&sel=${a},${b}`, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => document.querySelector('[data-testid="projection"]')?.dataset.state === 'ready', null, { timeout: 60_000 });
  await page.waitForFunction(
    ([x, y]) => {
      const l = window.__trailscopeRuns.state().lanes;
      return l.length === 2 && l.includes(x) && l.includes(y);
    },
    [a, b],
    { timeout: 60_000 },
  );
  await page.waitForFunction(() => document.querySelector('[data-testid="compare"]')?.dataset.state === 'ready');
  const requestsBefore = requests.length;
  const errorsBefore = errors.length;
  const del = await fetch(`${BASE_URL}/api/v1/runs/${encodeURIComponent(b)}`, { method: 'DELETE' });
  assertEqual(del.status, 204, 'DELETE a compared run');
  await page.evaluate(() => window.dispatchEvent(new Event('focus')));
  await page.waitForFunction(() => document.querySelector('[data-testid="compare"]')?.dataset.stale === 'true');
  assertEqual((await page.textContent(sel('compare-stale'))).trim().replace(/\s+/g, ' '), `stale compared run ${b} no longer on the server; Recompute`, 'the comparison says which run is gone');
  assertEqual((await state()).lanes.length, 2, 'the comparison is left as drawn');
  await page.mouse.move(5, 5);
  await page.screenshot({ path: path.join(ARTIFACTS, 'runs-compare-stale.png') });
  assertEqual(requests.slice(requestsBefore).filter((u) => u.includes('/api/v1/compare')).length, 0, 'nothing was recompared behind the analyst');
  assertEqual(errors.slice(errorsBefore).join('\n'), '', 'no console errors (no request for the deleted run)');
  // One click: the lists reloaded, the gone run dropped from the selection, one run left: nothing to compare.
  await page.click(sel('compare-recompute'));
  await page
    .waitForFunction(() => document.querySelector('[data-testid="compare"]')?.dataset.stale === 'false' && window.__trailscopeRuns.state().lanes.length === 0, null, { timeout: 60_000 })
    .catch(async (e) => {
      const s = await state();
      const c = await page.$eval(sel('compare'), (el) => ({ ...el.dataset, note: el.querySelector('[data-testid="compare-note"]')?.textContent }));
      throw new Error(`${e.message}; compare ${JSON.stringify(c)}; selection ${s.selection}; lanes ${s.lanes}; hash ${await page.evaluate(() => window.location.hash)}`);
    });
  assertEqual((await page.textContent(sel('compare-note'))).trim(), 'Select at least 2 runs.', 'the comparison says why it is empty');
  // The URL follows (its write is debounced): the gone run left the selection there too.
  await page.waitForFunction((gone) => {
    const q = new URLSearchParams(window.location.hash.replace(/^#runs\/?/, '').replace(/^[?&]/, ''));
    return !(q.get('sel') ?? '').split(',').includes(gone);
  }, b);
});

await test('no request went to a non-loopback host', async () => {
  const outside = [...new Set(requests.filter(leavesMachine))];
  assert(requests.some((u) => u.includes('/api/v1/compare') || u.includes('/api/v1/projections')), 'API requests were recorded');
  assert(outside.length === 0, `requests left the machine: ${outside.slice(0, 5).join(', ')}`);
});

await test('no console errors', async () => {
  assert(errors.length === 0, errors.slice(0, 5).join(' | '));
});

await finish(browser);
