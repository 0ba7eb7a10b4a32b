// The browser tests' shared harness: their environment, sequential named steps with ok/FAIL/SKIP lines,
// assertions, the headless Chromium every test launches (WebGL through SwiftShader), the page-error
// recorder, the loopback check, the tracker view's stored-run waits, and the summary line run.sh reads
// ("N passed, M failed").

import { mkdir } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

/** The server under test (run.sh sets it). */
export const BASE_URL = process.env.BASE_URL ?? 'http://127.0.0.1:8080';
export const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';
/** The screenshots' folder, tests/e2e/artifacts. */
export const ARTIFACTS = path.join(path.dirname(fileURLToPath(import.meta.url)), 'artifacts');
/** Every page's default timeout (ms). */
export const TIMEOUT = 30_000;
/**
 * The server's admin token (run.sh makes it with `trailscope token create` before `serve`): access control
 * is on. Node's own requests to the server carry it (fetch, below); every browser context signs in with it
 * (launchBrowser), as a user pasting it into the sign-in panel would, and holds the session cookie.
 */
export const TOKEN = process.env.TRAILSCOPE_TOKEN ?? '';
if (TOKEN) {
  const plainFetch = globalThis.fetch;
  globalThis.fetch = (input, init = {}) => {
    const url = typeof input === 'string' ? input : input instanceof URL ? input.href : input.url;
    if (!url.startsWith(BASE_URL)) return plainFetch(input, init);
    const headers = new Headers(init.headers ?? (input instanceof Request ? input.headers : undefined));
    if (!headers.has('authorization')) headers.set('authorization', `Bearer ${TOKEN}`);
    return plainFetch(input, { ...init, headers });
  };
}

/** Signs `context` in with TOKEN: POST /api/v1/session, and its cookie into the context. */
async function signIn(context) {
  if (!TOKEN) return;
  const res = await fetch(`${BASE_URL}/api/v1/session`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ token: TOKEN }),
  });
  const cookie = /trailscope_session=([0-9a-f]+)/.exec(res.headers.get('set-cookie') ?? '');
  if (res.status !== 200 || !cookie) throw new Error(`sign-in with the test token failed: ${res.status}`);
  await context.addCookies([
    { name: 'trailscope_session', value: cookie[1], url: BASE_URL, httpOnly: true, sameSite: 'Strict' },
  ]);
}

const results = [];
let stop = false;

/**
 * Runs one named step. A failed `critical` step skips every later step (they need what it set up).
 */
export async function test(name, fn, { critical = false } = {}) {
  if (stop) {
    results.push({ name, ok: false });
    console.log(`  SKIP  ${name} (an earlier step it needs failed)`);
    return;
  }
  const t0 = Date.now();
  try {
    await fn();
    results.push({ name, ok: true });
    console.log(`  ok    ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    results.push({ name, ok: false });
    if (critical) stop = true;
    console.log(`  FAIL  ${name} (${Date.now() - t0} ms)\n        ${String(e?.stack ?? e).split('\n').slice(0, 4).join('\n        ')}`);
  }
}

export function assert(cond, msg) {
  if (!cond) throw new Error(msg);
}

export function assertEqual(actual, expected, msg) {
  if (actual !== expected) throw new Error(`${msg}: expected ${JSON.stringify(expected)}, got ${JSON.stringify(actual)}`);
}

const LOOPBACK = new Set(['127.0.0.1', 'localhost', '[::1]', '::1']);
/** Whether a request URL would leave this machine (the app must work offline). */
export function leavesMachine(url) {
  const u = new URL(url);
  if (u.protocol === 'data:' || u.protocol === 'blob:' || u.protocol === 'about:') return false;
  return !LOOPBACK.has(u.hostname);
}

/** The selector of an element's data-testid. */
export const sel = (id) => `[data-testid="${id}"]`;

/**
 * Makes the artifacts folder, then launches headless Chromium at `executablePath` with WebGL through
 * SwiftShader (never --use-gl=swiftshader); its new contexts are signed in with TOKEN unless
 * `browser.newContext({ signIn: false, ... })`.
 */
export async function launchBrowser(executablePath = CHROMIUM) {
  await mkdir(ARTIFACTS, { recursive: true });
  const browser = await chromium.launch({
    executablePath,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  // Every context the tests open is signed in (TOKEN), unless it asks not to be ({ signIn: false }).
  const newContext = browser.newContext.bind(browser);
  browser.newContext = async ({ signIn: wanted = true, ...options } = {}) => {
    const context = await newContext(options);
    if (wanted) await signIn(context);
    return context;
  };
  return browser;
}

/** Records the page's console errors and uncaught exceptions in `errors`, each line starting with `prefix`. */
export function recordErrors(page, errors, prefix = '') {
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(`${prefix}console: ${m.text()}`);
  });
  page.on('pageerror', (e) => errors.push(`${prefix}pageerror: ${e.message}`));
}

/** Waits until the tracker view shows stored run `run` with all its frames loaded. */
export function trackerRunReady(page, run) {
  return page.waitForFunction((r) => {
    const t = document.querySelector('[data-testid="tracker"]');
    return t?.dataset.run === r && t.dataset.state === 'ready' && t.dataset.complete === 'true';
  }, run);
}

/**
 * Waits until the tracker view shows frame `f`: the frame counter, the pictures (with an image) and the
 * frame data; also each plot of `cursors` (data-testids) with its cursor there, and with `index` the frame
 * data's index text.
 */
export function trackerShowsFrame(page, f, { cursors = [], index = false } = {}) {
  return page.waitForFunction(
    ([f, cursors, index]) => {
      const q = (id) => document.querySelector(`[data-testid="${id}"]`);
      return (
        Number(q('replay-frame')?.dataset.frame) === f &&
        Number(q('replay-images')?.dataset.frame) === f &&
        q('replay-images')?.dataset.hasImage === 'true' &&
        Number(q('frame-data')?.dataset.frame) === f &&
        cursors.every((id) => Number(q(id)?.dataset.cursor) === f) &&
        (!index || q('frame-data-index')?.textContent?.trim() === String(f))
      );
    },
    [f, cursors, index],
  );
}

/** Closes the browser, prints "N passed, M failed" and exits non-zero on any failure. */
export async function finish(browser) {
  await browser.close();
  const passed = results.filter((r) => r.ok).length;
  const failed = results.length - passed;
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed === 0 ? 0 : 1);
}
