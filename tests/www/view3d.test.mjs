// The demo's 3D view and its glTF download, end to end in headless Chromium (Debian's chromium,
// scripts/setup-browser.sh; WebGL through SwiftShader, Chromium's software renderer). `make
// test-www` builds out/www/ first.
//
// - The 3D canvas draws: WebGL is up, the result's orange body is on it, the picture changes
//   between two frames of the clip and when the view is orbited with the mouse; no console errors.
// - At phone width the 3D view fits the screen and stays large enough to read.
// - The .glb download (the uploaded rig and the canonical one) passes the Khronos glTF validator
//   with zero errors and holds the result's skeleton and frames.

import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import validator from 'gltf-validator';
import { startServer } from '../../scripts/serve-www.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const site = process.env.WWW_DIR ?? `${root}out/www`;
const executablePath = process.env.CHROMIUM ?? execFileSync(`${root}scripts/setup-browser.sh`, { encoding: 'utf8' }).trim();

let server;
let browser;
const problems = [];

before(async () => {
  server = await startServer(site);
  browser = await chromium.launch({ executablePath, args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'] });
});

after(async () => {
  await browser?.close();
  server?.close();
  assert.deepEqual(problems, [], 'no console errors or page errors');
});

async function openPage(viewport = { width: 1366, height: 900 }) {
  const context = await browser.newContext({ viewport, acceptDownloads: true });
  const page = await context.newPage();
  page.on('console', (m) => m.type() === 'error' && problems.push(`console: ${m.text()}`));
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-ready=true]', { timeout: 120_000 });
  assert.equal(await page.isVisible('#error'), false);
  return page;
}

/**
 * Renders the 3D view at `times` (seconds, the player paused) and reads each picture back (in the
 * same task as the render, so the WebGL drawing buffer is still there): per time, the number of
 * result-orange pixels, and the pixels that differ from the first picture.
 */
function pictures(page, times) {
  return page.evaluate((times) => {
    const v = window.__demo.view3d;
    const { width, height } = v.canvas;
    const grab = (t) => {
      if (t != null) v.draw(t);
      else v.render();
      const c = document.createElement('canvas');
      c.width = width;
      c.height = height;
      const ctx = c.getContext('2d');
      ctx.drawImage(v.canvas, 0, 0);
      return ctx.getImageData(0, 0, width, height).data;
    };
    const shots = times.map(grab);
    return shots.map((d) => {
      let orange = 0;
      let changed = 0;
      for (let i = 0; i < d.length; i += 4) {
        const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
        if (r > 120 && r > g + 35 && g > b) orange++;
        if (Math.abs(r - shots[0][i]) + Math.abs(g - shots[0][i + 1]) + Math.abs(b - shots[0][i + 2]) > 24) changed++;
      }
      return { orange, changed, pixels: width * height };
    });
  }, times);
}

async function pause(page) {
  if ((await page.getAttribute('#play', 'aria-pressed')) === 'true') await page.click('#play');
}

test('the 3D view draws the bodies, moves between frames and orbits with the mouse', async () => {
  const page = await openPage();
  assert.equal(await page.getAttribute('#view-3d', 'data-webgl'), 'true', 'WebGL 2 is available');
  assert.equal(await page.isVisible('#view-3d-note'), false);
  // The orthographic views are still there.
  for (const id of ['#view-front', '#view-side', '#view-top']) assert.ok(await page.isVisible(id), id);
  await pause(page);
  const [a, b] = await pictures(page, [0.2, 1.6]);
  console.log(`# 3D view: ${a.orange} and ${b.orange} result pixels of ${a.pixels}; ${b.changed} changed between the frames`);
  assert.ok(a.orange > 300 && b.orange > 300, 'the result body is drawn');
  assert.ok(b.changed > 500, `the picture changes between frames (${b.changed} pixels)`);

  // The player drives the view: its frame counter rises while playing.
  const before = await page.evaluate(() => window.__demo.view3d.frames);
  await page.click('#play');
  await page.waitForFunction((n) => window.__demo.view3d.frames > n + 5, before);
  await pause(page);

  // Orbiting: a drag turns the camera around the bodies.
  const [still] = await pictures(page, [null]);
  // The drag starts on the canvas: scrolled into view (clicking the player's buttons may have scrolled it away).
  await page.locator('#view-3d').scrollIntoViewIfNeeded();
  const box = await page.locator('#view-3d').boundingBox();
  const camera = () => page.evaluate(() => window.__demo.view3d.camera.position.toArray());
  const from = await camera();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 160, box.y + box.height / 2 + 20, { steps: 8 });
  await page.mouse.up();
  // The page handles the pointer events in its own time (a software renderer may be busy): wait.
  await page
    .waitForFunction((from) => Math.hypot(...window.__demo.view3d.camera.position.toArray().map((c, i) => c - from[i])) > 0.3, from, { timeout: 5000 })
    .catch(() => {});
  const to = await camera();
  assert.ok(Math.hypot(...to.map((c, i) => c - from[i])) > 0.3, `the camera moved: ${from} → ${to}`);
  const [orbited, again] = await pictures(page, [null, null]);
  assert.ok(orbited.orange > 300 && again.changed === 0, 'a still view renders the same picture');
  assert.notEqual(orbited.orange, still.orange, 'the orbited picture differs');

  // Side by side and the visibility toggles reach the 3D view too.
  await page.selectOption('#layout', 'side');
  await page.uncheck('#show-content');
  const [sideOnly] = await pictures(page, [0.2]);
  assert.ok(sideOnly.orange > 300);
  assert.equal(await page.evaluate(() => window.__demo.view3d.bodies.length), 1);
  await page.check('#show-content');
  assert.equal(await page.evaluate(() => window.__demo.view3d.bodies.length), 2);
  await page.context().close();
});

test('at phone width the 3D view fits the screen and stays legible', async () => {
  const page = await openPage({ width: 390, height: 844 });
  const size = await page.evaluate(() => {
    const r = document.getElementById('view-3d').getBoundingClientRect();
    return { left: r.left, right: r.right, width: r.width, height: r.height, scroll: document.documentElement.scrollWidth, inner: innerWidth };
  });
  assert.ok(size.left >= 0 && size.right <= size.inner, JSON.stringify(size));
  assert.ok(size.scroll <= size.inner, `no sideways scrolling: ${size.scroll} > ${size.inner}`);
  assert.ok(size.width > 300 && size.height > 280, JSON.stringify(size));
  await pause(page);
  const [a, b] = await pictures(page, [0.2, 1.6]);
  assert.ok(a.orange > 200 && b.changed > 200, JSON.stringify({ a, b }));
  await page.context().close();
});

async function downloadBytes(page) {
  const [file] = await Promise.all([page.waitForEvent('download'), page.click('#download')]);
  return { name: file.suggestedFilename(), bytes: readFileSync(await file.path()) };
}

test('the .glb download validates, on the uploaded rig and on the canonical one', async () => {
  const page = await openPage();
  const result = await page.evaluate(() => {
    const d = window.__demo.results[window.__demo.pick].display;
    return { frames: d.frames, joints: d.joints };
  });
  await page.selectOption('#format', 'glb');
  for (const rig of ['content', 'canonical']) {
    await page.selectOption('#rig', rig);
    const { name, bytes } = await downloadBytes(page);
    assert.match(name, rig === 'canonical' ? /\.canonical\.glb$/ : /[^l]\.glb$/);
    assert.equal(bytes.subarray(0, 4).toString('latin1'), 'glTF');
    const report = await validator.validateBytes(new Uint8Array(bytes), { uri: name, format: 'glb' });
    const errors = report.issues.messages.filter((m) => m.severity === 0).map((m) => `${m.code}: ${m.message}`);
    assert.equal(report.issues.numErrors, 0, errors.join('; '));
    assert.equal(report.info.animationCount, 1);
    const json = JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString('utf8'));
    assert.equal(json.scenes[0].extras.frames, result.frames);
    assert.equal(json.skins[0].joints.length, rig === 'canonical' ? 21 : result.joints);
    console.log(`# ${name}: ${bytes.length} bytes, ${report.issues.numWarnings} validator warnings`);
  }
  // BVH is still the default and still downloads as text.
  await page.selectOption('#format', 'bvh');
  await page.selectOption('#rig', 'content');
  const { name, bytes } = await downloadBytes(page);
  assert.match(name, /\.bvh$/);
  assert.ok(bytes.toString('utf8').startsWith('HIERARCHY'));
  await page.context().close();
});
