// End-to-end tests of the browser demo in real headless Chromium (Debian's chromium via
// playwright-core's executablePath; scripts/setup-browser.sh). `make test-www` builds out/www/
// first (make www) and runs these with node --test.

import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';
import { zipSync } from 'fflate';
import { startServer } from '../../scripts/serve-www.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const site = process.env.WWW_DIR ?? `${root}out/www`;
const fixture = (rel) => `${root}tests/fixtures/${rel}`;
const executablePath = process.env.CHROMIUM ?? execFileSync(`${root}scripts/setup-browser.sh`, { encoding: 'utf8' }).trim();

let server;
let browser;
const problems = []; // console errors and uncaught page errors, from every page

before(async () => {
  server = await startServer(site);
  browser = await chromium.launch({ executablePath, args: ['--no-sandbox'] });
});

after(async () => {
  await browser?.close();
  server?.close();
});

/** `prepare`: called with the new context before the page opens (e.g. to route requests). */
async function openPage(url = server.url, viewport = { width: 1366, height: 900 }, init = null, prepare = null) {
  const context = await browser.newContext({ viewport, acceptDownloads: true });
  await context.grantPermissions(['clipboard-read', 'clipboard-write'], { origin: new URL(server.url).origin });
  if (init) await context.addInitScript(init);
  if (prepare) await prepare(context);
  const page = await context.newPage();
  page.on('console', (m) => m.type() === 'error' && problems.push(`console: ${m.text()}`));
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  await page.goto(url);
  await page.waitForSelector('body[data-ready=true]', { timeout: 120_000 });
  return page;
}

const results = (page) => page.evaluate(() => Number(document.body.dataset.results) || 0);

/** Clicks Stylize and waits for the next result. */
async function stylize(page) {
  const n = await results(page);
  await page.click('#stylize');
  await page.waitForFunction((k) => Number(document.body.dataset.results) > k && document.body.dataset.busy === 'false', n, { timeout: 60_000 });
}

async function download(page) {
  const [file] = await Promise.all([page.waitForEvent('download'), page.click('#download')]);
  return { name: file.suggestedFilename(), text: readFileSync(await file.path(), 'utf8') };
}

/** The header's frame count and the number of motion rows of a BVH text. */
function bvhShape(text) {
  assert.match(text, /^HIERARCHY\r?\nROOT /);
  const motion = text.slice(text.search(/^MOTION\r?$/m));
  const frames = Number(/^Frames:\s*(\d+)/m.exec(motion)[1]);
  const rows = motion.split(/\r?\n/).slice(3).filter((l) => l.trim() !== '').length;
  return { frames, rows, joints: (text.match(/^\s*(ROOT|JOINT) /gm) ?? []).length };
}

/**
 * Records every text the status line shows (an init script: runs before the page's own). It watches
 * the document from the start and keeps each text put into #status, one per mutation record: app.js
 * replays what the worker said before the page took over synchronously, at module evaluation (before
 * DOMContentLoaded), and an observer's callback sees such a burst once, so reading the line's text
 * per callback, or observing from DOMContentLoaded, loses the download progress (CI did).
 */
function recordStatus() {
  window.__statuses = [];
  new MutationObserver((records) => {
    for (const r of records) {
      if (r.type === 'childList' && r.target.id === 'status') {
        for (const n of r.addedNodes) window.__statuses.push(n.textContent);
      } else if (r.type === 'characterData' && r.target.parentNode?.id === 'status') {
        window.__statuses.push(r.target.data);
      }
    }
  }).observe(document, { childList: true, characterData: true, subtree: true });
}

/** The download progress the package reports, up to the whole, then the engine starting, then the first result. */
async function assertLoadStatuses(page) {
  const statuses = await page.evaluate(() => window.__statuses);
  const downloads = statuses.map((t) => /^Downloading the model: ([\d.]+) of ([\d.]+) MB…$/.exec(t)).filter(Boolean);
  assert.ok(downloads.length >= 2, statuses.join(' | '));
  const [, last, total] = downloads.at(-1);
  assert.equal(last, total);
  assert.ok(Number(total) > 1, `${total} MB`); // the statistics, shared networks and supervised stylizer (issue 17: the unsupervised one later)
  const started = statuses.indexOf('Starting the engine…');
  assert.ok(started > statuses.indexOf(downloads.at(-1)[0]), statuses.join(' | '));
  assert.ok(statuses.findIndex((t) => /Stylized as “old”/.test(t)) > started, statuses.join(' | '));
}

test('loads with download progress, stylizes the default sample, and shows the first-stylization latency', async () => {
  const page = await openPage(server.url, undefined, recordStatus);
  const timings = await page.evaluate(() => window.__demo.timings);
  const load = timings.load;
  console.log(
    `# first stylization ready ${timings.firstResultMs} ms after navigation (weights fetched in ${Math.round(load.fetchMs)} ms, ` +
      `wasm start + weights load ${Math.round(load.loadMs)} ms, first stylize ${Math.round(timings.lastStylizeMs)} ms)`,
  );
  assert.equal(await page.isVisible('#error'), false);
  assert.match(await page.textContent('#status'), /Stylized as “old”/);
  assert.equal((await page.$$('#label option')).length, 16);
  await assertLoadStatuses(page);
  // The weights' fingerprint of share links: the package's, as Node computes it.
  const { Stylizer } = await import(pathToFileURL(`${site}/pkg/index.js`));
  assert.equal(timings.load.weightsId, (await Stylizer.load({ settings: ['supervised'] })).weightsId);
  await page.context().close();
});

test('page modules that arrive after the engine has loaded show the progress it reported before them, then the result', async () => {
  // The head starts the worker before the page's modules arrive (index.html); when they come late
  // (a slow network, a busy machine: CI), app.js takes over a worker that has said everything already.
  // app.js is held back until the head's worker has answered its load (all it said is in `said`).
  let answeredFirst = false;
  const holdAppJs = (context) =>
    context.route('**/js/app.js', async (route) => {
      const page = route.request().frame().page();
      const deadline = Date.now() + 30_000;
      while (!answeredFirst && Date.now() < deadline) {
        answeredFirst = await page
          .evaluate(() => window.__engineStart?.said.some((d) => d.id === 0 && !d.progress) ?? false)
          .catch(() => false);
        if (!answeredFirst) await new Promise((r) => setTimeout(r, 50));
      }
      await route.continue();
    });
  const page = await openPage(server.url, undefined, recordStatus, holdAppJs);
  assert.ok(answeredFirst, 'the head\'s worker never answered its load while app.js was held');
  assert.equal(await page.isVisible('#error'), false);
  await assertLoadStatuses(page);
  await page.context().close();
});

let uploadedBvh;
let shareUrl;

test('upload a fixture, stylize by label, views move, download a BVH that parses, share link reproduces it', async () => {
  const page = await openPage();
  await page.setInputFiles('#content-file', fixture('foreign/m21_walk.bvh'));
  await page.waitForFunction(() => document.getElementById('content-info').textContent.includes('m21_walk.bvh'));
  assert.match(await page.textContent('#content-info'), /m21 rig, 21 joints · 162 frames at 60 fps/);
  await page.selectOption('#label', 'proud');
  await page.fill('#seed', '5');
  // The strength slider (exaggerated), before the first stylization.
  await page.$eval('#strength', (e) => {
    e.value = '1.5';
    e.dispatchEvent(new Event('input', { bubbles: true }));
    e.dispatchEvent(new Event('change', { bubbles: true }));
  });
  assert.equal(await page.textContent('#strength-label'), '1.50');
  // And the guidance slider (default 1).
  assert.equal(await page.inputValue('#guidance'), '1');
  await page.$eval('#guidance', (e) => {
    e.value = '0.5';
    e.dispatchEvent(new Event('input', { bubbles: true }));
    e.dispatchEvent(new Event('change', { bubbles: true }));
  });
  assert.equal(await page.textContent('#guidance-label'), '0.50');
  await stylize(page);
  assert.match(await page.textContent('#status'), /Stylized as “proud”/);

  // The views change between frames (pixels differ), in all three views.
  await page.click('#play'); // pause
  const shots = async () => Promise.all(['#view-front', '#view-side', '#view-top'].map((s) => page.locator(s).screenshot()));
  await page.locator('#scrub').fill('0');
  const first = await shots();
  await page.locator('#scrub').fill('30');
  const later = await shots();
  first.forEach((shot, i) => assert.notDeepEqual(shot, later[i], `view ${i} did not change between frames 0 and 30`));
  assert.equal(await page.textContent('#frame-label'), '30 / 80');

  // Download on the uploaded rig: a BVH with the m21 skeleton and one row per frame, which the package imports.
  const { name, text } = await download(page);
  assert.equal(name, 'm21_walk.proud.bvh');
  const shape = bvhShape(text);
  assert.equal(shape.joints, 21);
  assert.equal(shape.rows, shape.frames);
  assert.ok(shape.frames >= 80, `${shape.frames} frames`);
  const { Stylizer } = await import(pathToFileURL(`${site}/pkg/index.js`));
  const s = await Stylizer.load({ settings: ['supervised'] });
  assert.equal(s.importBvh(text).rig, 'm21');
  uploadedBvh = text;

  // The canonical rig: 21 canonical joints under joint names the canonical rig uses.
  await page.selectOption('#rig', 'canonical');
  const canonical = await download(page);
  assert.equal(canonical.name, 'm21_walk.proud.canonical.bvh');
  assert.equal(bvhShape(canonical.text).joints, 21);
  assert.match(canonical.text, /ROOT Hips/);
  assert.equal(s.importBvh(canonical.text).frames, s.importBvh(text).frames);
  await page.selectOption('#rig', 'content');

  // Share link: copied to the clipboard, opened in a new page, same BVH bytes.
  await page.click('#share');
  await page.waitForFunction(() => document.getElementById('share-info').textContent.startsWith('Link copied'));
  shareUrl = await page.evaluate(() => navigator.clipboard.readText());
  assert.equal(shareUrl, await page.inputValue('#share-url'));
  assert.match(shareUrl, /#s=[A-Za-z0-9_-]+$/);
  const other = await openPage(shareUrl);
  assert.match(await other.textContent('#content-info'), /m21_walk\.bvh/);
  assert.equal(await other.inputValue('#label'), 'proud');
  assert.equal(await other.inputValue('#seed'), '5');
  assert.equal(await other.inputValue('#strength'), '1.5');
  assert.equal(await other.inputValue('#guidance'), '0.5');
  const again = await download(other);
  assert.equal(again.text, uploadedBvh);
  await other.context().close();
  await page.context().close();
});

test('a malformed file shows an error and the page keeps working', async () => {
  const page = await openPage();
  for (const bad of ['missing_close_brace.bvh', 'nan_value.bvh', 'not_utf8.bvh', 'empty.bvh', 'frames_absurd.bvh']) {
    await page.setInputFiles('#content-file', `${root}tests/malformed/${bad}`);
    await page.waitForSelector('#error:not([hidden])');
    const message = await page.textContent('#error');
    assert.match(message, new RegExp(`Could not load ${bad.replace('.', '\\.')} — [A-Z_]+: `), message);
    await page.evaluate(() => (document.getElementById('error').hidden = true));
  }
  await page.setInputFiles('#content-file', `${root}tests/malformed/missing_close_brace.bvh`);
  await page.waitForSelector('#error:not([hidden])');
  assert.match(await page.textContent('#error'), /BVH_PARSE: .*\(line \d+\)/);
  // A rig the importer cannot match (two joints).
  await page.setInputFiles('#content-file', fixture('small.bvh'));
  await page.waitForFunction(() => /RIG_/.test(document.getElementById('error').textContent));
  // It opens the joint-mapping panel; cancelled, the previous content stays and still stylizes.
  await page.waitForSelector('#map-panel:not([hidden])');
  await page.click('#map-cancel');
  assert.match(await page.textContent('#content-info'), /dataset-2_walk_normal_001_f120\.bvh/);
  await stylize(page);
  assert.equal(await page.isVisible('#error'), false);
  await page.context().close();
});

/** The m21 walk with its joints renamed j0, j1, … and a four-joint tail on the hips: no automatic match. */
function tailedRig(text) {
  let k = 0;
  const renamed = text.replace(/^(\s*(?:ROOT|JOINT)\s+)(\S+)/gm, (_, head) => `${head}j${k++}`);
  const lines = renamed.split(/\r?\n/);
  const at = lines.findIndex((l) => /^\s*CHANNELS 6/.test(l)) + 1;
  const tail = [];
  for (let t = 0; t < 4; t++) tail.push(`JOINT tail${t}`, '{', 'OFFSET 0 -4 -15', 'CHANNELS 3 Zrotation Yrotation Xrotation');
  tail.push('End Site', '{', 'OFFSET 0 -4 -15', '}', ...Array(4).fill('}'));
  lines.splice(at, 0, ...tail);
  const motion = lines.findIndex((l) => /^Frame Time/.test(l)) + 1;
  for (let i = motion; i < lines.length; i++) {
    const v = lines[i].trim().split(/\s+/);
    if (v.length > 6) lines[i] = [...v.slice(0, 6), ...Array(12).fill('0'), ...v.slice(6)].join(' ');
  }
  return lines.join('\n');
}

/** The m21 walk's joints in file order, and the canonical joint each plays (`inspect --json`'s map). */
const M21_JOINTS = ['Hips', 'LeftUpLeg', 'LeftLeg', 'LeftFoot', 'LeftToeBase', 'RightUpLeg', 'RightLeg', 'RightFoot', 'RightToeBase', 'Spine', 'Spine1', 'Neck1', 'Head', 'LeftShoulder', 'LeftArm', 'LeftForeArm', 'LeftHand', 'RightShoulder', 'RightArm', 'RightForeArm', 'RightHand'];
const M21_MAP = { Hips: 'Hips', Spine: 'Spine', Chest: 'Spine1', Neck: 'Neck1', Head: 'Head', Shoulder_L: 'LeftShoulder', UpperArm_L: 'LeftArm', LowerArm_L: 'LeftForeArm', Hand_L: 'LeftHand', Shoulder_R: 'RightShoulder', UpperArm_R: 'RightArm', LowerArm_R: 'RightForeArm', Hand_R: 'RightHand', UpperLeg_L: 'LeftUpLeg', LowerLeg_L: 'LeftLeg', Foot_L: 'LeftFoot', Toes_L: 'LeftToeBase', UpperLeg_R: 'RightUpLeg', LowerLeg_R: 'RightLeg', Foot_R: 'RightFoot', Toes_R: 'RightToeBase' };

test('a rig that does not match opens the joint-mapping panel; the mapping chosen imports it and travels in share links', async () => {
  const page = await openPage();
  const walk = readFileSync(fixture('foreign/m21_walk.bvh'), 'utf8');
  const file = { name: 'tailed.bvh', mimeType: 'text/plain', buffer: Buffer.from(tailedRig(walk)) };
  await page.setInputFiles('#content-file', file);
  await page.waitForSelector('#map-panel:not([hidden])');
  assert.match(await page.textContent('#error'), /Could not load tailed\.bvh — RIG_UNMATCHED/);
  assert.match(await page.textContent('#map-title'), /tailed\.bvh/);
  const selects = page.locator('#map-rows select');
  assert.equal(await selects.count(), 21);
  // Every drop-down offers the file's joints (25: the 21 renamed and the tail).
  assert.equal(await selects.first().locator('option').count(), 1 + 25);
  // Cancel: nothing changes.
  await page.click('#map-cancel');
  assert.equal(await page.isVisible('#map-panel'), false);
  assert.match(await page.textContent('#content-info'), /dataset-2_walk_normal_001_f120\.bvh/);

  // Again, and choose the joints by hand: an essential one left out is refused, and the panel stays.
  await page.setInputFiles('#content-file', { ...file, name: 'tailed2.bvh' });
  await page.waitForSelector('#map-panel:not([hidden])');
  for (const [canonical, joint] of Object.entries(M21_MAP)) {
    await page.selectOption(`#map-rows select[data-joint="${canonical}"]`, `j${M21_JOINTS.indexOf(joint)}`);
  }
  await page.selectOption('#map-rows select[data-joint="Hand_L"]', '');
  await page.click('#map-apply');
  await page.waitForFunction(() => /RIG_UNMATCHED: .*Hand_L/.test(document.getElementById('error').textContent));
  await page.waitForSelector('#map-panel:not([hidden])');
  assert.equal(await page.inputValue('#map-rows select[data-joint="Hips"]'), 'j0', 'the panel keeps the choices');
  await page.selectOption('#map-rows select[data-joint="Hand_L"]', `j${M21_JOINTS.indexOf('LeftHand')}`);
  await page.click('#map-apply');
  await page.waitForFunction(() => document.getElementById('content-info').textContent.includes('tailed2.bvh'));
  assert.equal(await page.isVisible('#map-panel'), false);
  assert.equal(await page.isVisible('#error'), false);
  assert.match(await page.textContent('#content-info'), /manual rig, 25 joints · 162 frames at 60 fps/);
  await page.fill('#seed', '4');
  await stylize(page);
  const { text: mine } = await download(page);

  // The share link carries the mapping: it opens without the panel and gives the same result.
  await page.click('#share');
  await page.waitForFunction(() => document.getElementById('share-info').textContent.startsWith('Link copied'));
  const url = await page.inputValue('#share-url');
  const other = await openPage(url);
  await other.waitForFunction(() => document.getElementById('share-info').textContent.includes('Opened a share link'));
  assert.equal(await other.isVisible('#map-panel'), false);
  assert.match(await other.textContent('#content-info'), /manual rig/);
  const { text: theirs } = await download(other);
  assert.equal(theirs, mine, 'the shared result, byte for byte');
  await other.context().close();
  await page.context().close();
});

/** The package's weights with 'chimpira' renamed 'swagger' and no unsupervised model: {name: bytes}. */
function customWeights() {
  const dir = `${site}/pkg/weights`;
  const manifest = JSON.parse(readFileSync(`${dir}/manifest.json`, 'utf8'));
  manifest.styles = manifest.styles.map((s) => (s === 'chimpira' ? 'swagger' : s));
  manifest.models = manifest.models.filter((m) => m.setting === 'supervised');
  return {
    'manifest.json': Buffer.from(JSON.stringify(manifest)),
    'norm.json': readFileSync(`${dir}/norm.json`),
    'shared.bin': readFileSync(`${dir}/shared.bin`),
    'supervised.bin': readFileSync(`${dir}/supervised.bin`),
  };
}

test('your own weights: a .zip or a folder replaces the labels; bad weights change nothing; back to the shipped ones; links say which weights', async () => {
  const page = await openPage();
  const labels = () => page.$$eval('#label option', (o) => o.map((x) => x.value));
  const files = customWeights();
  // A zip without shared.bin: refused, the shipped weights stay.
  const broken = zipSync(Object.fromEntries(Object.entries(files).filter(([n]) => n !== 'shared.bin').map(([n, b]) => [`w/${n}`, b])));
  await page.setInputFiles('#weights-zip', { name: 'broken.zip', mimeType: 'application/zip', buffer: Buffer.from(broken) });
  await page.waitForFunction(() => /BAD_WEIGHTS: .*shared\.bin/.test(document.getElementById('error').textContent));
  assert.ok((await labels()).includes('chimpira'));

  const zip = zipSync(Object.fromEntries(Object.entries(files).map(([n, b]) => [`my-weights/${n}`, b])));
  await page.setInputFiles('#weights-zip', { name: 'my-weights.zip', mimeType: 'application/zip', buffer: Buffer.from(zip) });
  await page.waitForFunction(() => document.getElementById('weights-info').textContent.includes('my-weights.zip'));
  assert.match(await page.textContent('#weights-info'), /16 labels · supervised model\./);
  const custom = await labels();
  assert.ok(custom.includes('swagger') && !custom.includes('chimpira'), custom.join());
  assert.equal(await page.isVisible('#weights-shipped'), true);
  await page.selectOption('#label', 'swagger');
  await stylize(page);
  assert.match(await page.textContent('#status'), /Stylized as “swagger”/);

  // A link made with these weights, opened on the page's own: it says the weights differ.
  await page.selectOption('#label', 'old');
  await stylize(page);
  await page.click('#share');
  await page.waitForFunction(() => document.getElementById('share-info').textContent.startsWith('Link copied'));
  const other = await openPage(await page.inputValue('#share-url'));
  await other.waitForFunction(() => /other model weights/.test(document.getElementById('share-info').textContent));
  await other.context().close();

  // Back to the shipped weights, then the same weights as a folder.
  await page.click('#weights-shipped');
  await page.waitForFunction(() => document.getElementById('weights-shipped').hidden);
  assert.ok((await labels()).includes('chimpira'));
  const folder = mkdtempSync(join(tmpdir(), 'ms-weights-'));
  mkdirSync(join(folder, 'run-weights'));
  for (const [n, b] of Object.entries(files)) writeFileSync(join(folder, 'run-weights', n), b);
  await page.setInputFiles('#weights-folder', join(folder, 'run-weights'));
  await page.waitForFunction(() => document.getElementById('weights-info').textContent.includes('run-weights'));
  assert.ok((await labels()).includes('swagger'));
  rmSync(folder, { recursive: true, force: true });
  await page.context().close();
});

test('body parts: a style per part, the content kept for one; the share link reproduces it', async () => {
  const page = await openPage();
  await page.selectOption('#label', 'old');
  await page.fill('#seed', '3');
  await stylize(page);
  const { text: whole } = await download(page);
  await page.click('summary:has-text("body parts")');
  await page.selectOption('#part-upper', 'label:angry');
  await page.selectOption('#part-head', 'content');
  await stylize(page);
  assert.match(await page.textContent('#status'), /Stylized as “old\+upper-angry\+head-content”/);
  const { name, text: mine } = await download(page);
  assert.match(name, /old\+upper-angry\+head-content/);
  assert.notEqual(mine, whole, 'the parts change the result');
  await page.click('#share');
  await page.waitForFunction(() => document.getElementById('share-info').textContent.startsWith('Link copied'));
  const other = await openPage(await page.inputValue('#share-url'));
  await other.waitForFunction(() => document.getElementById('share-info').textContent.includes('Opened a share link'));
  assert.equal(await other.inputValue('#part-upper'), 'label:angry');
  assert.equal(await other.inputValue('#part-head'), 'content');
  assert.equal(await other.inputValue('#part-lower'), '');
  const { text: theirs } = await download(other);
  assert.equal(theirs, mine, 'the shared result, byte for byte');
  await other.context().close();
  await page.context().close();
});

test('modes: reference motion, prior with N samples as thumbnails, mix slider; WebGPU toggle shows the fallback', async () => {
  const page = await openPage();
  // Reference motion (supervised, the reference's label) from a sample.
  await page.check('input[name=mode][value=motion]');
  await page.selectOption('#ref-sample', 'walk-tired');
  await page.waitForFunction(() => document.getElementById('ref-info').textContent.includes('walk_tired'));
  assert.equal(await page.inputValue('#ref-label'), 'tired');
  await stylize(page);
  assert.match(await page.textContent('#status'), /“tired”/);
  // Left to the package: the supervised model infers the reference's label and the page says so.
  await page.selectOption('#ref-label', '');
  await stylize(page);
  assert.match(await page.textContent('#status'), /label, inferred: tired/);
  // A reference from a file, on another rig, with the label picked by hand.
  await page.setInputFiles('#ref-file', fixture('foreign/cmu31_xia_neutral_16_000.bvh'));
  await page.waitForFunction(() => document.getElementById('ref-info').textContent.includes('cmu31_xia'));
  assert.match(await page.inputValue('#ref-sample'), /^$/);
  await page.selectOption('#ref-label', 'normal');
  await stylize(page);
  assert.match(await page.textContent('#status'), /“normal”/);
  // A one-frame clip (a rest pose) stylizes and plays.
  await page.setInputFiles('#content-file', fixture('foreign/cmu31_rest.bvh'));
  await page.waitForFunction(() => document.getElementById('content-info').textContent.includes('cmu31_rest'));
  await stylize(page);
  assert.equal(await page.textContent('#frame-label'), '0 / 0');
  await page.selectOption('#content-sample', 'walk-normal');
  await page.waitForFunction(() => document.getElementById('content-info').textContent.includes('walk_normal'));

  // Unsupervised prior, 3 samples: three thumbnails, picking one changes the result.
  await page.check('input[name=model][value=unsupervised]');
  assert.equal(await page.isDisabled('input[name=mode][value=label]'), true);
  await page.check('input[name=mode][value=prior]');
  await page.fill('#samples', '3');
  await stylize(page);
  assert.equal(await page.locator('#thumbs button').count(), 3);
  const before = await page.evaluate(() => window.__demo.results[window.__demo.pick].bvh);
  await page.click('#thumbs button:nth-child(3)');
  assert.equal(await page.getAttribute('#thumbs button:nth-child(3)', 'aria-pressed'), 'true');
  const picked = await page.evaluate(() => window.__demo.results[window.__demo.pick].bvh);
  assert.notEqual(picked, before);
  const { name, text: pickedText } = await download(page);
  assert.match(name, /\.prior\.3\.bvh$/);
  assert.equal(pickedText, picked);
  // Its share link (a sample's id, no motion inside) opens on the same pick with the same bytes.
  await page.click('#share');
  await page.waitForFunction(() => document.getElementById('share-info').textContent.startsWith('Link copied'));
  const link = await page.inputValue('#share-url');
  assert.ok(link.length < 1000, `${link.length} characters`);
  const other = await openPage(link);
  assert.equal(await other.locator('#thumbs button').count(), 3);
  assert.equal(await other.getAttribute('#thumbs button:nth-child(3)', 'aria-pressed'), 'true');
  assert.equal((await download(other)).text, picked);
  await other.context().close();

  // Mix: prior (A) to the reference (B); moving the slider restyles.
  await page.fill('#samples', '1');
  await page.check('input[name=mode][value=mix]');
  await page.selectOption('#mix-a-kind', 'prior');
  await page.selectOption('#mix-b-kind', 'motion');
  await page.locator('#mix-t').fill('0');
  await stylize(page);
  const a = await page.evaluate(() => window.__demo.results[0].bvh);
  const n = await results(page);
  await page.locator('#mix-t').fill('1');
  await page.locator('#mix-t').dispatchEvent('change');
  await page.waitForFunction((k) => Number(document.body.dataset.results) > k, n);
  assert.notEqual(await page.evaluate(() => window.__demo.results[0].bvh), a);

  // WebGPU: this browser (headless, no GPU flags) has no adapter; the page says it runs on the CPU
  // and why (the WebGPU run itself: webgpu.test.mjs).
  await page.check('#webgpu');
  await page.waitForFunction(() => document.getElementById('backend-info').textContent.includes('WebGPU fallback'));
  assert.match(await page.textContent('#backend-info'), /Running on the CPU — WebGPU fallback: .*WebGPU.*\(this browser has (no )?WebGPU\)/);
  await stylize(page);
  await page.context().close();
});

test('drag and drop loads a file; a motion too large for a link says so', async () => {
  const page = await openPage();
  const text = readFileSync(fixture('foreign/cmu31_xia_neutral_16_000.bvh'), 'utf8');
  await page.evaluate((bvh) => {
    const data = new DataTransfer();
    data.items.add(new File([bvh], 'dropped_cmu31.bvh', { type: 'text/plain' }));
    document.body.dispatchEvent(new DragEvent('drop', { dataTransfer: data, bubbles: true, cancelable: true }));
  }, text);
  await page.waitForFunction(() => document.getElementById('content-info').textContent.includes('dropped_cmu31.bvh'));
  assert.match(await page.textContent('#content-info'), /cmu31 rig, 31 joints/);

  await page.setInputFiles('#content-file', fixture('foreign/iclone100_cmu_002_04.bvh'));
  await page.waitForFunction(() => document.getElementById('content-info').textContent.includes('iclone100'));
  // The page keeps animating while the worker stylizes 8 samples of a 100-joint clip.
  await page.fill('#samples', '8');
  await page.evaluate(() => {
    const gaps = (window.__gaps = []);
    let last = performance.now();
    const tick = (now) => {
      gaps.push(now - last);
      last = now;
      if (document.body.dataset.busy !== 'false' || gaps.length < 5) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
  await stylize(page);
  const { worst, frames, ms } = await page.evaluate(() => ({ worst: Math.max(...window.__gaps), frames: window.__gaps.length, ms: window.__demo.timings.lastStylizeMs }));
  console.log(`# 8 samples of iclone100 (100 joints) stylized in ${Math.round(ms)} ms in the worker; meanwhile ${frames} animation frames, longest gap ${Math.round(worst)} ms`);
  assert.ok(worst < 250, `the page froze for ${worst} ms`);
  assert.equal(await page.locator('#thumbs button').count(), 8);
  await page.click('#share');
  await page.waitForFunction(() => document.getElementById('share-info').textContent.includes('too large to share'));
  assert.equal(await page.isVisible('#share-url'), false);
  // Keyboard: Space pauses and plays.
  await page.click('h1');
  await page.keyboard.press('Space');
  assert.equal(await page.textContent('#play'), 'Play');
  await page.keyboard.press('Space');
  assert.equal(await page.textContent('#play'), 'Pause');
  await page.context().close();
});

test('damaged and hostile share links are refused with a message, never run as HTML', async () => {
  for (const hash of ['#s=!!!', '#s=AAAA', `#s=${'A'.repeat(130_000)}`]) {
    const page = await openPage(`${server.url}${hash}`);
    await page.waitForSelector('#error:not([hidden])');
    assert.match(await page.textContent('#error'), /This share link cannot be opened — BAD_LINK: /);
    assert.match(await page.textContent('#status'), /Stylized as/); // it still loads the default sample
    await page.context().close();
  }
  // A well-formed link whose fields are hostile: markup in a label is refused as an unknown label.
  const packed = await deflate(JSON.stringify({ v: 1, content: { sample: 'walk-normal' }, mode: 'label', label: '<img src=x onerror=alert(1)>' }));
  const page = await openPage(`${server.url}#s=${packed}`);
  await page.waitForSelector('#error:not([hidden])');
  assert.match(await page.textContent('#error'), /unknown style label "<img src=x onerror=alert\(1\)>"/);
  assert.equal(await page.locator('img').count(), 0);
  await page.context().close();

  // A link whose motion is not BVH the package accepts.
  const broken = await deflate(JSON.stringify({ v: 1, content: { bvh: 'HIERARCHY\nROOT Hips\n{\n', name: 'x.bvh' }, mode: 'label', label: 'old' }));
  const page3 = await openPage(`${server.url}#s=${broken}`);
  await page3.waitForSelector('#error:not([hidden])');
  assert.match(await page3.textContent('#error'), /This share link cannot be opened — BVH_PARSE: its content motion could not be loaded: /);
  await page3.context().close();

  // A link made with other weights opens, and says the result may differ.
  const other = await deflate(JSON.stringify({ v: 1, content: { sample: 'walk-tired' }, mode: 'label', label: 'sad', weights: '00000000' }));
  const page2 = await openPage(`${server.url}#s=${other}`);
  assert.match(await page2.textContent('#share-info'), /made with other model weights \(00000000; these are [0-9a-f]{8}\)/);
  assert.match(await page2.textContent('#status'), /Stylized as “sad”/);
  await page2.context().close();
});

async function deflate(text) {
  const { deflateRawSync } = await import('node:zlib');
  return deflateRawSync(Buffer.from(text)).toString('base64url');
}

test('phone width: no horizontal scrolling, controls reachable', async () => {
  const page = await openPage(server.url, { width: 390, height: 844 });
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  assert.ok(overflow <= 0, `${overflow} px of horizontal overflow`);
  await page.focus('#stylize');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => Number(document.body.dataset.results) >= 2);
  await page.context().close();
});

test('no console errors on any page', () => {
  assert.deepEqual(problems, []);
});
