// The package's WebGPU engine (issue 16) in real headless Chromium on its software WebGPU adapter
// (SwiftShader's Vulkan; scripts/setup-browser.sh installs mesa-vulkan-drivers beside chromium):
// `Stylizer.load({ backend: 'webgpu' })` runs on WebGPU, its outputs match the CPU engine's for
// the same inputs and seed (to float rounding), the same seed gives the same bytes, and a browser
// without WebGPU falls back to the CPU saying why. The demo page says which one it runs on.
// `make test-www` builds out/www/ (with pkg/'s engine-webgpu_bg.wasm) first.

import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { startServer } from '../../scripts/serve-www.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const site = process.env.WWW_DIR ?? `${root}out/www`;
const executablePath = process.env.CHROMIUM ?? execFileSync(`${root}scripts/setup-browser.sh`, { encoding: 'utf8' }).trim();

// WebGPU compute on the software adapter (the page must come from http://127.0.0.1: a secure context).
const WEBGPU_ARGS = [
  '--no-sandbox',
  '--enable-unsafe-webgpu',
  '--enable-features=Vulkan',
  '--use-vulkan=swiftshader',
  '--use-webgpu-adapter=swiftshader',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--disable-vulkan-surface',
];

let server;
let gpuBrowser;
const problems = [];

before(async () => {
  server = await startServer(site);
  gpuBrowser = await chromium.launch({ executablePath, args: WEBGPU_ARGS });
});

after(async () => {
  await gpuBrowser?.close();
  server?.close();
});

async function openPage(browser, path = 'samples/README.md') {
  const page = await browser.newPage();
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  await page.goto(`${server.url}${path}`);
  return page;
}

test('the WebGPU engine stylizes like the CPU engine: label, reference, prior, body parts; same seed, same bytes', { timeout: 600_000 }, async () => {
  const page = await openPage(gpuBrowser);
  const r = await page.evaluate(async () => {
    const { Stylizer } = await import('/pkg/index.js');
    const content = await (await fetch('/samples/dataset-2_walk_normal_001_f120.bvh')).text();
    const reference = await (await fetch('/samples/dataset-2_walk_elderly_001_f120.bvh')).text();
    const gpu = await Stylizer.load({ backend: 'webgpu' });
    const cpu = await Stylizer.load({ backend: 'cpu' });
    const cases = {
      label: { label: 'angry', seed: 3, samples: 2 },
      reference: { styleMotion: reference, seed: 1 },
      prior: { prior: true, unsupervised: true, seed: 5 },
      parts: { label: 'proud', parts: { upper: { label: 'old' }, head: 'content' }, seed: 2 },
    };
    const out = { backend: gpu.backend, fallbackReason: gpu.fallbackReason, cpuBackend: cpu.backend, cases: {} };
    for (const [name, options] of Object.entries(cases)) {
      const t0 = performance.now();
      const g = await gpu.stylize(content, options);
      const ms = performance.now() - t0;
      const g2 = await gpu.stylize(content, options);
      const c = await cpu.stylize(content, options);
      let maxDiff = 0;
      let lo = Infinity;
      let hi = -Infinity;
      let sameBytes = g.length === g2.length;
      let sameBvh = true;
      let movedFromContent = 0;
      for (let k = 0; k < g.length; k++) {
        const p = g[k].positions();
        const p2 = g2[k].positions();
        const q = c[k].positions();
        if (p.length !== q.length) throw new Error(`${name}: ${p.length} vs ${q.length} values`);
        for (let i = 0; i < p.length; i++) {
          maxDiff = Math.max(maxDiff, Math.abs(p[i] - q[i]));
          if (p[i] !== p2[i]) sameBytes = false;
          lo = Math.min(lo, q[i]);
          hi = Math.max(hi, q[i]);
        }
        if (g[k].toBvh() !== g2[k].toBvh()) sameBvh = false;
        if (g[k].frames !== c[k].frames) throw new Error(`${name}: ${g[k].frames} vs ${c[k].frames} frames`);
      }
      // Two samples of one label differ on the GPU too (the seed's draws reach the device).
      if (g.length > 1) {
        const a = g[0].positions();
        const b = g[1].positions();
        for (let i = 0; i < a.length; i++) movedFromContent = Math.max(movedFromContent, Math.abs(a[i] - b[i]));
      }
      out.cases[name] = {
        outputs: g.length,
        cpuOutputs: c.length,
        maxDiff,
        extent: hi - lo,
        sameBytes,
        sameBvh,
        samplesDiffer: movedFromContent,
        inferred: [g[0].inferredLabel ?? null, c[0].inferredLabel ?? null],
        firstMs: ms,
      };
    }
    out.inferLabel = [await gpu.inferLabel(reference), await cpu.inferLabel(reference)];
    return out;
  });
  console.log(`# webgpu: ${JSON.stringify(r)}`);
  assert.equal(r.backend, 'webgpu');
  assert.equal(r.fallbackReason, null);
  assert.equal(r.cpuBackend, 'cpu');
  for (const [name, c] of Object.entries(r.cases)) {
    assert.equal(c.outputs, c.cpuOutputs, name);
    assert.ok(c.extent > 100, `${name}: the motion spans ${c.extent}`);
    // Float rounding of a different device (measured 2.4e-4 cm on a 708 cm extent): 1e-4 of the extent.
    assert.ok(c.maxDiff <= 1e-4 * c.extent, `${name}: WebGPU and CPU differ by ${c.maxDiff} on an extent of ${c.extent}`);
    assert.ok(c.sameBytes && c.sameBvh, `${name}: the same seed gave different outputs on WebGPU`);
    assert.deepEqual(c.inferred[0], c.inferred[1], name);
  }
  assert.ok(r.cases.label.samplesDiffer > 0.1, 'two samples of a label came out the same');
  assert.equal(r.inferLabel[0], r.inferLabel[1]);
  assert.deepEqual(problems, []);
  await page.close();
});

test('without WebGPU, backend "webgpu" falls back to the CPU and says why', { timeout: 300_000 }, async () => {
  // Chromium without the flags above: no WebGPU adapter here.
  const plain = await chromium.launch({ executablePath, args: ['--no-sandbox', '--disable-features=WebGPU,Vulkan'] });
  try {
    const page = await openPage(plain);
    const r = await page.evaluate(async () => {
      const { Stylizer } = await import('/pkg/index.js');
      const content = await (await fetch('/samples/dataset-2_walk_normal_001_f120.bvh')).text();
      const s = await Stylizer.load({ backend: 'webgpu' });
      const [m] = await s.stylize(content, { label: 'angry' });
      return { backend: s.backend, fallbackReason: s.fallbackReason, frames: m.frames };
    });
    assert.equal(r.backend, 'cpu');
    assert.match(r.fallbackReason, /WebGPU/);
    assert.equal(r.frames, 120);
  } finally {
    await plain.close();
  }
});

test('the demo runs on WebGPU when asked and says so', { timeout: 600_000 }, async () => {
  const page = await gpuBrowser.newPage({ viewport: { width: 1366, height: 900 } });
  page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
  await page.goto(server.url);
  await page.waitForSelector('body[data-ready=true]', { timeout: 120_000 });
  await page.check('#webgpu');
  await page.waitForFunction(() => document.getElementById('backend-info').textContent.includes('Running on WebGPU'), null, { timeout: 120_000 });
  const n = await page.evaluate(() => Number(document.body.dataset.results) || 0);
  await page.click('#stylize');
  await page.waitForFunction((k) => Number(document.body.dataset.results) > k && document.body.dataset.busy === 'false', n, { timeout: 300_000 });
  assert.match(await page.evaluate(() => window.__demo.results[0].bvh), /^HIERARCHY/);
  assert.deepEqual(problems, []);
  await page.close();
});
