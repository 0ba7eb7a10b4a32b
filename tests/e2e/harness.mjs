// The browser tests' shared harness: sequential named steps with ok/FAIL/SKIP lines, assertions, the
// headless Chromium every test launches (WebGL through SwiftShader), the loopback check, and the summary
// line run.sh reads ("N passed, M failed").

import { chromium } from 'playwright-core';

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

/** Headless Chromium at `executablePath` with WebGL through SwiftShader (never --use-gl=swiftshader). */
export function launchBrowser(executablePath) {
  return chromium.launch({
    executablePath,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
}

/** Closes the browser, prints "N passed, M failed" and exits non-zero on any failure. */
export async function finish(browser) {
  await browser.close();
  const passed = results.filter((r) => r.ok).length;
  const failed = results.length - passed;
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed === 0 ? 0 : 1);
}
