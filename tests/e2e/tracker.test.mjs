// Browser test of the tracker dashboard (run through run.sh, which starts the server with --demo so that
// the two synthetic demo videos exist). Two viewers watch one replay of the cups-attached video: one
// plays, the other seeks by clicking the state timeline; both show pictures with overlays, and the
// timeline of the whole video holds tracking (blue) and lost (red) frames. Then the replay's stored run
// opens from #tracker?run=ID&frame=N (no WebSocket): every view at frame N, local step, seek and play.

import { ARTIFACTS, BASE_URL, TIMEOUT, assert, assertEqual, finish, launchBrowser, leavesMachine, recordErrors, sel, test, trackerRunReady, trackerShowsFrame } from './harness.mjs';
import path from 'node:path';

const VIDEO = process.env.TRACKER_VIDEO ?? 'cups-attached';

/** x (from a plot's left edge) of the middle of frame i on a frame axis of `width` px (web/src/tracker/frameAxis.ts). */
const frameX = (i, width) => ((i + 0.5) * width) / st.frames;
const num = async (page, selector, attr) => Number(await page.getAttribute(selector, attr));

/** Pixel statistics of a canvas: pixels differing from the background, distinct colours, a hash. */
function canvasStats(page, testid) {
  return page.evaluate((id) => {
    const c = document.querySelector(`[data-testid="${id}"]`);
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let lit = 0;
    let hash = 0;
    const colours = new Set();
    for (let i = 0; i < d.length; i += 4) {
      const bg = d[i] === 5 && d[i + 1] === 7 && d[i + 2] === 10;
      if (!bg && d[i + 3] > 0) lit++;
      if (i % 16 === 0) colours.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
      hash = (hash * 31 + d[i] + 7 * d[i + 1] + 13 * d[i + 2]) >>> 0;
    }
    return { lit, pixels: d.length / 4, colours: colours.size, hash, w: c.width, h: c.height };
  }, testid);
}

/** Share of the state timeline's columns painted in the TRACK blue and the LOST red. */
function timelineColours(page) {
  return page.evaluate(() => {
    const c = document.querySelector('[data-testid="state-timeline"] canvas');
    const d = c.getContext('2d').getImageData(0, Math.floor(c.height / 2), c.width, 1).data;
    let blue = 0;
    let red = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (d[i] === 0x3b && d[i + 1] === 0x82 && d[i + 2] === 0xf6) blue++;
      if (d[i] === 0xef && d[i + 1] === 0x44 && d[i + 2] === 0x44) red++;
    }
    return { blue, red, width: c.width };
  });
}

// ---------- run ----------
const browser = await launchBrowser();
const context = await browser.newContext({ viewport: { width: 1440, height: 1000 }, deviceScaleFactor: 1 });
const requests = [];
const errors = [];
context.on('request', (r) => requests.push(r.url()));
async function newViewer(name) {
  const page = await context.newPage();
  page.setDefaultTimeout(TIMEOUT);
  page.on('websocket', (ws) => requests.push(ws.url()));
  recordErrors(page, errors, `${name} `);
  return page;
}
const a = await newViewer('A');
const b = await newViewer('B');
const st = { replay: null, video: null, frames: 0 };

console.log(`TrailScope tracker dashboard test against ${BASE_URL}`);

await test(`viewer A opens the Tracker view and starts a replay of the ${VIDEO} video`, async () => {
  const videos = (await (await fetch(`${BASE_URL}/api/v1/videos`)).json()).videos;
  st.video = videos.find((v) => v.source?.scenario === VIDEO || v.name.includes(VIDEO));
  assert(st.video, `a ${VIDEO} video is on the server (${videos.map((v) => v.name).join(', ')}); serve --demo adds it`);
  await a.goto(`${BASE_URL}/`, { waitUntil: 'domcontentloaded' });
  await a.click(sel('tab-tracker'));
  await a.waitForFunction(() => document.getElementById('app')?.dataset.view === 'tracker');
  await a.waitForSelector(`${sel('tracker-video')} option[value="${st.video.id}"]`, { state: 'attached' });
  await a.waitForSelector(`${sel('tracker-params')} input[data-param]`, { state: 'attached' });
  await a.selectOption(sel('tracker-video'), st.video.id);
  await a.click(sel('replay-start'));
  await a.waitForFunction(() => document.querySelector('[data-testid="tracker"]')?.dataset.state === 'ready');
  st.replay = await a.getAttribute(sel('tracker'), 'data-replay');
  assert(st.replay, 'the view names its replay');
  assert(new URL(a.url()).hash === `#tracker?replay=${encodeURIComponent(st.replay)}`, `the URL names the replay: ${a.url()}`);
  await a.waitForFunction(() => document.querySelector('[data-testid="replay-images"]')?.dataset.hasImage === 'true');
  st.frames = Number(await a.getAttribute(sel('state-timeline'), 'data-frames'));
  assertEqual(st.frames, st.video.frame_count, 'the timeline spans the video');
}, { critical: true });

await test('viewer B opens the same replay from its URL: two viewers', async () => {
  await b.bringToFront();
  await b.goto(`${BASE_URL}/#tracker?replay=${encodeURIComponent(st.replay)}`, { waitUntil: 'domcontentloaded' });
  await b.waitForFunction(() => document.querySelector('[data-testid="tracker"]')?.dataset.state === 'ready');
  assertEqual(await b.getAttribute(sel('tracker'), 'data-replay'), st.replay, 'B shows the replay of A');
  await b.waitForFunction(() => document.querySelector('[data-testid="replay-images"]')?.dataset.hasImage === 'true');
  const r = await (await fetch(`${BASE_URL}/api/v1/replays/${encodeURIComponent(st.replay)}`)).json();
  if (r.viewers !== undefined) assertEqual(r.viewers, 2, 'the server counts two viewers');
}, { critical: true });

await test('play in A: its frame counter advances (1×, then 4×), B keeps its own cursor', async () => {
  const bBefore = await num(b, sel('replay-frame'), 'data-frame');
  await a.bringToFront();
  await a.click(sel('replay-play'));
  await a.waitForFunction(() => document.querySelector('[data-testid="replay-controls"]')?.dataset.playing === 'true');
  await a.waitForFunction(() => Number(document.querySelector('[data-testid="replay-frame"]')?.dataset.frame) >= 15, null, { timeout: 20_000 });
  const f1 = await num(a, sel('replay-frame'), 'data-frame');
  await a.waitForTimeout(600);
  const f2 = await num(a, sel('replay-frame'), 'data-frame');
  assert(f2 > f1, `the counter keeps advancing (${f1} → ${f2})`);
  const shown = await num(a, sel('replay-images'), 'data-frame');
  assert(shown > 0, `the pictures follow (frame ${shown} shown)`);
  assertEqual(await num(b, sel('replay-frame'), 'data-frame'), bBefore, "B's cursor did not move with A's");
  await a.selectOption(sel('replay-speed'), '4');
  await a.waitForFunction(() => document.querySelector('[data-testid="replay-controls"]')?.dataset.speed === '4');
  const f3 = await num(a, sel('replay-frame'), 'data-frame');
  await a.waitForFunction((f) => Number(document.querySelector('[data-testid="replay-frame"]')?.dataset.frame) >= f + 20, f3);
  const text = await a.textContent(sel('replay-frame'));
  assert(/frame \d+ \/ \d+/.test(text), `the counter reads "${text}"`);
  assert((await a.textContent(sel('replay-time'))).includes('s'), 'the timestamp is shown');
});

await test("A's depth and amplitude canvases show pictures with overlays", async () => {
  for (const id of ['replay-depth', 'replay-amplitude']) {
    const s = await canvasStats(a, id);
    assertEqual(s.w, st.video.intrinsics.width * 3, `${id} is the video ×3 wide`);
    assert(s.lit > s.pixels * 0.3, `${id} is not blank (${s.lit} of ${s.pixels} pixels lit)`);
    assert(s.colours > 20, `${id} holds an image (${s.colours} colours)`);
  }
  await a.click(sel('replay-play')); // pause, so the picture stays put while overlays are toggled
  await a.waitForFunction(() => document.querySelector('[data-testid="replay-controls"]')?.dataset.playing === 'false');
  await a.waitForTimeout(300);
  const d = await a.$eval(sel('replay-images'), (el) => ({ ...el.dataset }));
  const overlays = Number(d.candidates) + Number(d.estimates) + Number(d.truthTips);
  assert(overlays > 0, `overlays are drawn (candidates ${d.candidates}, estimates ${d.estimates}, truth ${d.truthTips})`);
  if (st.video.has_truth) assert(Number(d.truthTips) > 0, `truth tips are drawn (${d.truthTips})`);
  const withOverlays = await canvasStats(a, 'replay-depth');
  for (const k of ['candidates', 'estimates', 'truth']) await a.uncheck(sel(`overlay-${k}`));
  const bare = await canvasStats(a, 'replay-depth');
  for (const k of ['candidates', 'estimates', 'truth']) await a.check(sel(`overlay-${k}`));
  assert(bare.hash !== withOverlays.hash, 'turning the overlays off changes the picture');
  console.log(`        frame ${d.frame}: ${d.candidates} candidates, ${d.estimates} teat estimates, ${d.truthTips} truth tips, ${d.truthBoxes} boxes`);
  await a.mouse.move(5, 5);
  await a.screenshot({ path: path.join(ARTIFACTS, 'tracker-a.png') });
});

await test('the state timeline covers the whole video once the replay is done', async () => {
  await b.waitForFunction(
    (n) => Number(document.querySelector('[data-testid="state-timeline"]')?.dataset.known) === n,
    st.frames,
    { timeout: 120_000 },
  );
  const d = await b.$eval(sel('state-timeline'), (el) => ({ ...el.dataset }));
  assertEqual(Number(d.track) + Number(d.lost) + Number(d.search), st.frames, 'every frame has a state');
  const r = await (await fetch(`${BASE_URL}/api/v1/replays/${encodeURIComponent(st.replay)}`)).json();
  assert(r.done, 'the replay is done');
  console.log(`        ${d.track} track, ${d.lost} lost, ${d.search} search of ${st.frames}; run ${r.run}`);
});

await test('seek in B by clicking the state timeline: every view moves to the clicked frame', async () => {
  await b.bringToFront();
  const box = await b.locator(sel('state-timeline')).boundingBox();
  const expected = Math.floor(st.frames * 0.62);
  await b.mouse.click(box.x + frameX(expected, box.width), box.y + box.height / 2);
  await b.waitForFunction(
    (f) =>
      Number(document.querySelector('[data-testid="replay-frame"]')?.dataset.frame) === f &&
      Number(document.querySelector('[data-testid="replay-images"]')?.dataset.frame) === f &&
      Number(document.querySelector('[data-testid="frame-data"]')?.dataset.frame) === f,
    expected,
  );
  assertEqual(await num(b, sel('state-timeline'), 'data-cursor'), expected, 'the timeline cursor');
  assertEqual(await num(b, sel('trajectory-z'), 'data-cursor'), expected, 'the trajectory cursor');
  assertEqual(Number(await b.textContent(sel('frame-data-index'))), expected, 'the frame-data view');
  const aFrame = await num(a, sel('replay-frame'), 'data-frame');
  assert(aFrame !== expected || aFrame === 0, `A's cursor stays its own (${aFrame})`);
  console.log(`        clicked frame ${expected}`);
});

await test('seek in B by clicking a trajectory plot, then step +1 (button) and +1 (→ key)', async () => {
  const box = await b.locator(sel('trajectory-x')).boundingBox();
  const expected = Math.floor(st.frames * 0.2);
  await b.mouse.click(box.x + frameX(expected, box.width), box.y + box.height / 2);
  await b.waitForFunction((f) => Number(document.querySelector('[data-testid="replay-images"]')?.dataset.frame) === f, expected);
  await b.click(sel('replay-step'));
  await b.waitForFunction((f) => Number(document.querySelector('[data-testid="replay-images"]')?.dataset.frame) === f, expected + 1);
  assertEqual(await num(b, sel('state-timeline'), 'data-cursor'), expected + 1, 'the timeline follows a step');
  await b.keyboard.press('ArrowRight');
  await b.waitForFunction((f) => Number(document.querySelector('[data-testid="replay-images"]')?.dataset.frame) === f, expected + 2);
  const pts = Number(await b.getAttribute(sel('trajectories'), 'data-points'));
  assert(pts > 0, `the trajectories hold estimates (${pts} points)`);
  if (st.video.has_truth) assert(Number(await b.getAttribute(sel('trajectories'), 'data-truth-points')) > 0, 'and truth');
  const pairs = await b.locator(`${sel('frame-pairs')} thead th`).allTextContents();
  assertEqual(pairs.slice(1).join(' '), 'FL–FR RL–RR FL–RL FR–RR FL–RR FR–RL', 'the six model pairs are listed');
});

await test("the live replay's frame is in the URL: a third viewer opens at it", async () => {
  const f = await num(b, sel('replay-frame'), 'data-frame');
  await b.waitForFunction((fr) => new URLSearchParams(location.hash.split('?')[1]).get('frame') === String(fr), f);
  const url = b.url();
  assert(url.includes(`replay=${encodeURIComponent(st.replay)}`), `the URL names the replay: ${url}`);
  const c = await context.newPage();
  c.setDefaultTimeout(TIMEOUT);
  await c.goto(url, { waitUntil: 'domcontentloaded' });
  await c.waitForFunction((fr) => Number(document.querySelector('[data-testid="replay-images"]')?.dataset.frame) === fr, f);
  assertEqual(await num(c, sel('frame-data'), 'data-frame'), f, 'the third viewer shows the frame of the URL');
  await c.close();
});

await test('a LOST frame shows "-" for what it does not have (never 0.00 0.0 0.0 0.0)', async () => {
  const f = await b.evaluate(() => window.trailscopeTracker.store.records.findIndex((r) => r?.state === 'LOST'));
  assert(f >= 0, 'the replay has a LOST frame');
  await b.evaluate((fr) => window.trailscopeTracker.seek(fr), f);
  await b.waitForFunction((fr) => {
    const d = document.querySelector('[data-testid="frame-data"]');
    return Number(d?.dataset.frame) === fr && d.dataset.state === 'LOST';
  }, f);
  const rows = await b.$$eval(`${sel('frame-teats')} tbody tr`, (trs) => trs.map((tr) => [...tr.querySelectorAll('td')].map((td) => td.textContent.trim())));
  const unseen = rows.filter((r) => r[1] === '-');
  assert(unseen.length > 0, `a LOST frame has teats without an estimate: ${JSON.stringify(rows)}`);
  for (const r of unseen) assertEqual(r.slice(2, 7).join(' '), '- - - - -', `teat ${r[0]}: conf, x, y, z, r`);
  assert(!rows.some((r) => r[1] === '-' && r.slice(3, 6).join(' ') === '0.0 0.0 0.0'), 'no zero position is shown for a teat the frame lacks');
  const rec = await b.evaluate((fr) => window.trailscopeTracker.store.records[fr].model.teatsMatched, f);
  if (rec === 0) assertEqual((await b.textContent(sel('frame-cost'))).trim(), '-', 'no model, no cost');
  await b.locator(sel('frame-data')).screenshot({ path: path.join(ARTIFACTS, 'tracker-lost-frame.png') });
  console.log(`        LOST frame ${f}: ${unseen.length} teats without an estimate, model teats matched ${rec}`);
});

await test(`the ${VIDEO} timeline shows tracking (blue) and lost (red)`, async () => {
  const d = await b.$eval(sel('state-timeline'), (el) => ({ ...el.dataset }));
  const px = await timelineColours(b);
  console.log(`        states: ${d.track} track, ${d.lost} lost, ${d.search} search; pixels: ${px.blue} blue, ${px.red} red of ${px.width}`);
  assert(Number(d.track) > 0 && px.blue > 0, `frames in TRACK are drawn blue (${d.track} frames, ${px.blue} px)`);
  assert(Number(d.lost) > 0 && px.red > 0, `frames in LOST are drawn red (${d.lost} frames, ${px.red} px): the tracker should go LOST while the cups cover the teats`);
});

await test('screenshots', async () => {
  await b.bringToFront();
  await b.mouse.move(5, 5);
  await b.screenshot({ path: path.join(ARTIFACTS, 'tracker-b.png') });
  // The whole view (the tracker scrolls inside the page): a taller window for this one.
  await b.setViewportSize({ width: 1440, height: 1500 });
  await b.waitForTimeout(300);
  await b.screenshot({ path: path.join(ARTIFACTS, 'tracker.png') });
  await b.setViewportSize({ width: 1440, height: 1000 });
});

await test('the Flights tab still shows the map dashboard', async () => {
  await b.click(sel('tab-map'));
  await b.waitForFunction(() => document.getElementById('app')?.dataset.view === 'map');
  await b.waitForSelector(`${sel('dataset-select')} option`, { state: 'attached' });
  assert(await b.isVisible(sel('map')), 'the map is visible');
  assert(!(await b.isVisible(sel('tracker'))), 'the tracker is hidden');
  await b.goBack();
  await b.waitForFunction(() => document.getElementById('app')?.dataset.view === 'tracker');
});

await test("#tracker?run=RUN&frame=N opens the replay's stored run at frame N: every view, local stepping and play, no WebSocket", async () => {
  await b.bringToFront();
  const r = await (await fetch(`${BASE_URL}/api/v1/replays/${encodeURIComponent(st.replay)}`)).json();
  assert(r.run, `the replay's run is stored (${r.run})`);
  const frame = Math.floor(st.frames * 0.4);
  const sockets = [];
  const onSocket = (ws) => sockets.push(ws.url());
  b.on('websocket', onSocket);
  await b.evaluate(([run, f]) => (location.hash = `#tracker?run=${encodeURIComponent(run)}&frame=${f}`), [r.run, frame]);
  await trackerRunReady(b, r.run);
  const shows = (f) => trackerShowsFrame(b, f, { cursors: ['state-timeline', 'trajectory-z'] });
  await shows(frame);
  await b.waitForFunction((n) => Number(document.querySelector('[data-testid="state-timeline"]')?.dataset.known) === n, st.frames);
  assert(new RegExp(`frame ${frame} /`).test(await b.textContent(sel('replay-frame'))), 'the counter shows the frame');
  assertEqual(await b.getAttribute(sel('tracker'), 'data-replay'), null, 'no replay is attached');
  const d = await b.$eval(sel('replay-images'), (el) => ({ ...el.dataset }));
  assert(Number(d.candidates) + Number(d.estimates) + Number(d.truthTips) > 0, `overlays are drawn (${d.candidates} candidates, ${d.estimates} estimates, ${d.truthTips} truth tips)`);
  const s = await canvasStats(b, 'replay-depth');
  assertEqual(s.w, st.video.intrinsics.width * 3, 'the depth canvas is the video ×3 wide');
  assert(s.colours > 20, `the depth canvas holds an image (${s.colours} colours)`);
  // Step with the button and the keyboard, seek with the timeline.
  await b.click(sel('replay-step'));
  await shows(frame + 1);
  await b.keyboard.press('ArrowRight');
  await shows(frame + 2);
  await b.keyboard.press('ArrowLeft');
  await shows(frame + 1);
  await b.waitForFunction((f) => location.hash.endsWith(`frame=${f}`), frame + 1);
  const box = await b.locator(sel('state-timeline')).boundingBox();
  const target = Math.floor(st.frames * 0.75);
  await b.mouse.click(box.x + frameX(target, box.width), box.y + box.height / 2);
  await shows(target);
  // Play advances the local cursor at the video's fps; pause holds it.
  await b.click(sel('replay-play'));
  await b.waitForFunction((f) => Number(document.querySelector('[data-testid="replay-frame"]')?.dataset.frame) >= f + 5, target);
  await b.click(sel('replay-play'));
  await b.waitForFunction(() => document.querySelector('[data-testid="replay-controls"]')?.dataset.playing === 'false');
  const held = await num(b, sel('replay-frame'), 'data-frame');
  await shows(held);
  await b.mouse.move(5, 5);
  await b.screenshot({ path: path.join(ARTIFACTS, 'tracker-stored-run.png') });
  b.off('websocket', onSocket);
  assertEqual(sockets.length, 0, 'the stored run opened no WebSocket');
  console.log(`        run ${r.run}: frame ${frame} → ${frame + 1} → ${frame + 2} → ${frame + 1}, seek ${target}, played to ${held}`);
  // Back to the live replay: it reconnects as before.
  await b.goBack();
  await b.waitForFunction((id) => {
    const t = document.querySelector('[data-testid="tracker"]');
    return t?.dataset.replay === id && t.dataset.state === 'ready' && !t.dataset.run;
  }, st.replay);
});

await test('per-frame depth range: the stored run asks each frame for its own range (no min/max), and the URL keeps it', async () => {
  await b.bringToFront();
  const r = await (await fetch(`${BASE_URL}/api/v1/replays/${encodeURIComponent(st.replay)}`)).json();
  const frame = Math.floor(st.frames * 0.3);
  await b.evaluate(([run, f]) => (location.hash = `#tracker?run=${encodeURIComponent(run)}&frame=${f}`), [r.run, frame]);
  await trackerRunReady(b, r.run);
  await trackerShowsFrame(b, frame);
  const depthReq = (f) => requests.filter((u) => new RegExp(`/frames/${f}/depth\\.png`).test(u));
  const withRange = depthReq(frame).pop();
  assert(withRange && /[?&]min=/.test(withRange) === (st.video.depth_range_mm !== undefined), `one video range by default: ${withRange}`);
  const before = await canvasStats(b, 'replay-depth');
  await b.check(sel('depth-per-frame'));
  await b.waitForFunction(() => location.hash.includes('depth=frame'));
  await b.waitForFunction((f) => [...performance.getEntriesByType('resource')].some((e) => e.name.includes(`/frames/${f}/depth.png`) && !/[?&]min=/.test(e.name)), frame);
  await trackerShowsFrame(b, frame);
  const per = depthReq(frame).filter((u) => !/[?&]min=/.test(u));
  assert(per.length > 0, 'the frame was fetched with its own range');
  const after = await canvasStats(b, 'replay-depth');
  if (st.video.depth_range_mm) assert(after.hash !== before.hash, 'the picture changed with the range');
  await b.mouse.move(5, 5);
  await b.screenshot({ path: path.join(ARTIFACTS, 'tracker-depth-per-frame.png') });
  await b.uncheck(sel('depth-per-frame'));
  await b.waitForFunction(() => !location.hash.includes('depth=frame'));
});

await test('the parameter form: a bad value is refused in place, a good one starts a replay with it', async () => {
  await a.bringToFront();
  await a.click('.tracker-params-details summary');
  await a.fill(sel('tracker-param-n_lost'), '2.5');
  await a.click(sel('replay-start'));
  const err = await a.textContent(sel('tracker-error'));
  assert(/n_lost/.test(err), `the error names the parameter: "${err}"`);
  assertEqual(await a.getAttribute(sel('tracker-param-n_lost'), 'aria-invalid'), '', 'the field is marked invalid');
  assertEqual(await a.getAttribute(sel('tracker'), 'data-replay'), st.replay, 'no replay was started');
  await a.fill(sel('tracker-param-n_lost'), '');
  await a.fill(sel('tracker-param-ncc_min'), '0.6');
  await a.click(sel('replay-start'));
  await a.waitForFunction((old) => {
    const t = document.querySelector('[data-testid="tracker"]');
    return t?.dataset.replay !== old && t?.dataset.state === 'ready';
  }, st.replay);
  const id = await a.getAttribute(sel('tracker'), 'data-replay');
  const r = await (await fetch(`${BASE_URL}/api/v1/replays/${encodeURIComponent(id)}`)).json();
  assertEqual(r.params.ncc_min, 0.6, 'the replay runs with the value typed');
  await a.waitForFunction(() => document.querySelector('[data-testid="replay-images"]')?.dataset.hasImage === 'true');
});

await test('no request went to a non-loopback host', async () => {
  const outside = [...new Set(requests.filter(leavesMachine))];
  assert(requests.some((u) => u.includes('/replays/')), 'replay requests were recorded');
  assert(outside.length === 0, `requests left the machine: ${outside.slice(0, 5).join(', ')}`);
});

await test('no console errors', async () => {
  assert(errors.length === 0, errors.slice(0, 5).join(' | '));
});

await finish(browser);
