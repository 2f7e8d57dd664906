// The demo's byte budget (issue 17), in real headless Chromium against the demo server, which
// gzips and revalidates like a static host (scripts/serve-www.mjs): every byte transferred
// (encoded bodies and headers, the worker's fetches included) until the page is ready — the first
// label-based stylization on screen, then the 3D view and the reference clip, which come after it
// — at most 6 MB (met since the compact weights of 2026-12-04: EVALUATION.md,
// "Compact weights, fourth try"); the unsupervised model, fetched when first used, at
// most 2 MB more (a todo: not met, see EVALUATION.md); a second visit (same browser profile) fetches no weights (the package's Cache
// API copy) and is served by 304s otherwise. Prints the bytes and times (bench/README.md).
// BUDGET_THROTTLE=1 also runs the first visit under Chromium's network emulation at 20 Mbit/s.

import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readdirSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { startServer } from '../../scripts/serve-www.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const site = process.env.WWW_DIR ?? `${root}out/www`;
const executablePath = process.env.CHROMIUM ?? execFileSync(`${root}scripts/setup-browser.sh`, { encoding: 'utf8' }).trim();

const MB = 1e6;
const FIRST_BUDGET = 6 * MB;
const UNSUPERVISED_BUDGET = 2 * MB;

let server;
let browser;

before(async () => {
  server = await startServer(site);
  // A static host serves precompressed files: the server's gzip cache is filled first, so that
  // the times below are not the server compressing 10 MB on the first request.
  for (const file of readdirSync(site, { recursive: true })) {
    if (statSync(join(site, file)).isFile()) await (await fetch(new URL(file, server.url), { headers: { 'accept-encoding': 'gzip' } })).arrayBuffer();
  }
  browser = await chromium.launch({ executablePath, args: ['--no-sandbox'] });
});

after(async () => {
  await browser?.close();
  server?.close();
});

/** Every request of a page (its workers' too) with the bytes it transferred, once finished. */
function recordTraffic(page) {
  const pending = [];
  page.on('requestfinished', (request) => {
    pending.push(
      (async () => {
        const sizes = await request.sizes();
        const response = await request.response();
        return {
          path: new URL(request.url()).pathname,
          status: response?.status() ?? 0,
          bytes: sizes.responseBodySize + sizes.responseHeadersSize,
          fromCache: response?.fromServiceWorker?.() ?? false,
        };
      })(),
    );
  });
  return {
    /** The requests finished so far (and forgets them). */
    async take() {
      const done = await Promise.all(pending.splice(0));
      return done;
    },
  };
}

const sum = (requests) => requests.reduce((n, r) => n + r.bytes, 0);
const weights = (requests) => requests.filter((r) => r.path.includes('/weights/'));
const fmt = (n) => `${(n / MB).toFixed(2)} MB`;
/** The page's boot marks (ms after navigation), in order: "app 120, engine 480, …". */
const steps = (marks) => Object.entries(marks ?? {}).sort((a, b) => a[1] - b[1]).map(([k, v]) => `${k} ${v}`).join(', ');

/** Opens the demo and waits for its first stylization (the default content, label “old”). */
async function firstVisit(page) {
  const t0 = Date.now();
  await page.goto(server.url);
  await page.waitForSelector('body[data-ready=true]', { timeout: 180_000 });
  const wall = Date.now() - t0;
  const timings = await page.evaluate(() => window.__demo.timings);
  assert.match(await page.textContent('#status'), /Stylized as “old”/);
  assert.equal(await page.isVisible('#error'), false);
  return { wall, firstResultMs: timings.firstResultMs, load: timings.load, stylizeMs: timings.lastStylizeMs, marks: timings.marks };
}

async function stylizeUnsupervised(page) {
  const n = await page.evaluate(() => Number(document.body.dataset.results) || 0);
  await page.check('input[name=model][value=unsupervised]');
  await page.check('input[name=mode][value=prior]');
  await page.click('#stylize');
  await page.waitForFunction((k) => Number(document.body.dataset.results) > k && document.body.dataset.busy === 'false', n, { timeout: 120_000 });
  assert.equal(await page.isVisible('#error'), false);
}

test('first visit: what the first label-based result needs (budget 6 MB), the unsupervised model when first used (2 MB more); a second visit fetches no weights', async (t) => {
  const context = await browser.newContext({ viewport: { width: 1366, height: 900 } });
  const page = await context.newPage();
  const traffic = recordTraffic(page);
  const first = await firstVisit(page);
  const before = await traffic.take();
  const total = sum(before);
  const byKind = (re) => sum(before.filter((r) => re.test(r.path)));
  console.log(
    `# first visit: ${fmt(total)} transferred until the page is ready, the first result and what follows it (${before.length} requests: ` +
      `weights ${fmt(sum(weights(before)))}, wasm ${fmt(byKind(/\.wasm$/))}, three.js ${fmt(byKind(/\/vendor\//))}, ` +
      `other ${fmt(total - sum(weights(before)) - byKind(/\.wasm$/) - byKind(/\/vendor\//))}); ` +
      `first result ${first.firstResultMs} ms after navigation (weights fetched ${Math.round(first.load.fetchMs)} ms, ` +
      `wasm start + weights load ${Math.round(first.load.loadMs)} ms, first stylize ${Math.round(first.stylizeMs)} ms; ` +
      `steps after navigation: ${steps(first.marks)})`,
  );
  const names = weights(before).map((r) => r.path.replace(/.*\/weights\//, ''));
  for (const f of ['manifest.json', 'norm.json', 'shared.bin', 'supervised.bin']) assert.ok(names.includes(f), `${f} fetched: ${names}`);
  assert.ok(!names.includes('unsupervised.bin'), 'the unsupervised model waits until it is used');
  assert.ok(total <= FIRST_BUDGET, `${fmt(total)} until the page is ready (budget ${fmt(FIRST_BUDGET)} before the first result)`);
  // The first result waits for neither the 3D view (three.js and its first frames) nor the reference clip.
  assert.ok(first.marks.result < first.marks.view3d && first.marks.result < first.marks.ref, `boot steps: ${steps(first.marks)}`);

  await stylizeUnsupervised(page);
  const later = await traffic.take();
  const unsup = sum(later);
  console.log(`# the unsupervised model when first used: ${fmt(unsup)} more (${later.map((r) => r.path).join(', ')})`);
  assert.deepEqual(weights(later).map((r) => r.path.replace(/.*\/weights\//, '')), ['unsupervised.bin']);
  assert.ok(unsup < 1.1 * sum(weights(later)), 'nothing but the model');
  // Not met by any encoding that passes the eval gate: the shipped 8-bit core is 2.5 MB gzip; ~6 bits
  // a weight would be needed, and 6 bits moves the motion-based metrics beyond 1 % (EVALUATION.md,
  // "Compact weights"); a todo.
  await t.test(`the unsupervised model within ${fmt(UNSUPERVISED_BUDGET)}`, { todo: 'fewer than 8 bits fail the eval gate (EVALUATION.md)' }, () => {
    assert.ok(unsup <= UNSUPERVISED_BUDGET, `${fmt(unsup)} for the unsupervised model (budget ${fmt(UNSUPERVISED_BUDGET)})`);
  });

  // A second visit in the same profile: the weights come from the Cache API, nothing else changed
  // (304s); the same first result.
  const again = await context.newPage();
  const traffic2 = recordTraffic(again);
  const second = await firstVisit(again);
  const requests = await traffic2.take();
  console.log(
    `# second visit: ${fmt(sum(requests))} transferred (${requests.length} requests, ` +
      `${requests.filter((r) => r.status === 304).length} of them 304), first result ${second.firstResultMs} ms after navigation ` +
      `(weights read ${Math.round(second.load.fetchMs)} ms, wasm start + weights load ${Math.round(second.load.loadMs)} ms, first stylize ${Math.round(second.stylizeMs)} ms; steps: ${steps(second.marks)})`,
  );
  assert.deepEqual(weights(requests), [], 'no weight file requested on the second visit');
  assert.ok(sum(requests) < 0.1 * MB, `${fmt(sum(requests))} on the second visit`);
  await context.close();
});

test('20 Mbit/s network emulation: bytes and time to the first result (reported)', { skip: process.env.BUDGET_THROTTLE !== '1' }, async () => {
  const context = await browser.newContext({ viewport: { width: 1366, height: 900 } });
  const page = await context.newPage();
  const cdp = await context.newCDPSession(page);
  await cdp.send('Network.enable');
  // 20 Mbit/s down, 5 up, 20 ms latency. Worker fetches go through the page's network stack.
  await cdp.send('Network.emulateNetworkConditions', { offline: false, latency: 20, downloadThroughput: 20e6 / 8, uploadThroughput: 5e6 / 8 });
  const traffic = recordTraffic(page);
  const first = await firstVisit(page);
  const total = sum(await traffic.take());
  console.log(
    `# 20 Mbit/s, first visit: ${fmt(total)}, first result ${first.firstResultMs} ms after navigation (${first.wall} ms wall; ` +
      `weights fetched ${Math.round(first.load.fetchMs)} ms, wasm start + weights load ${Math.round(first.load.loadMs)} ms, first stylize ${Math.round(first.stylizeMs)} ms; steps: ${steps(first.marks)})`,
  );
  const again = await context.newPage();
  const cdp2 = await context.newCDPSession(again);
  await cdp2.send('Network.enable');
  await cdp2.send('Network.emulateNetworkConditions', { offline: false, latency: 20, downloadThroughput: 20e6 / 8, uploadThroughput: 5e6 / 8 });
  const second = await firstVisit(again);
  console.log(`# 20 Mbit/s, second visit: first result ${second.firstResultMs} ms after navigation (weights read ${Math.round(second.load.fetchMs)} ms; steps: ${steps(second.marks)})`);
  await context.close();
});

test('a damaged weights cache is dropped and fetched again: the first result all the same', async () => {
  const context = await browser.newContext({ viewport: { width: 1366, height: 900 } });
  const page = await context.newPage();
  await firstVisit(page);
  // One byte changed in the cached supervised model (what a broken disk or an old cache might give).
  const damaged = await page.evaluate(async () => {
    // The package stores what it fetched in the background: wait for it.
    const url = new URL('pkg/weights/supervised.bin', location.href).href;
    let name;
    let hit;
    for (let i = 0; i < 200 && !hit; i++) {
      name = (await caches.keys()).find((n) => n.startsWith('motion-stylizer-weights-'));
      hit = name && (await (await caches.open(name)).match(url));
      if (!hit) await new Promise((r) => setTimeout(r, 50));
    }
    const cache = await caches.open(name);
    const bytes = new Uint8Array(await hit.arrayBuffer());
    bytes[bytes.length >> 1] ^= 0x40;
    await cache.put(url, new Response(bytes, { headers: { 'content-length': String(bytes.length) } }));
    return { name, length: bytes.length };
  });
  assert.match(damaged.name, /^motion-stylizer-weights-[0-9a-f]{8}$/);
  const again = await context.newPage();
  const traffic = recordTraffic(again);
  await firstVisit(again);
  const fetched = weights(await traffic.take()).map((r) => r.path.replace(/.*\/weights\//, ''));
  assert.ok(fetched.includes('supervised.bin'), `fetched again: ${fetched}`);
  // The cache holds good bytes again: a third visit fetches no weights.
  const third = await context.newPage();
  const traffic3 = recordTraffic(third);
  await firstVisit(third);
  assert.deepEqual(weights(await traffic3.take()), []);
  await context.close();
});
