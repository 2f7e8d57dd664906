// The README's screenshots of the demo (www/screenshots/laptop.png, phone.png), taken in headless
// Chromium from out/www/ (`make www-screenshots`).

import { execFileSync } from 'node:child_process';
import { mkdirSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { startServer } from '../../scripts/serve-www.mjs';

const root = fileURLToPath(new URL('../../', import.meta.url));
const out = `${root}www/screenshots`;
const executablePath = process.env.CHROMIUM ?? execFileSync(`${root}scripts/setup-browser.sh`, { encoding: 'utf8' }).trim();
mkdirSync(out, { recursive: true });

const server = await startServer(`${root}out/www`);
// WebGL (the 3D view) through SwiftShader, Chromium's software renderer.
const browser = await chromium.launch({ executablePath, args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'] });

async function shoot(name, viewport, fullPage) {
  const page = await browser.newPage({ viewport, deviceScaleFactor: 1 });
  await page.goto(server.url);
  await page.waitForSelector('body[data-ready=true]', { timeout: 120_000 });
  // Four samples from the prior of the unsupervised model, the third picked, paused mid-clip.
  await page.check('input[name=model][value=unsupervised]');
  await page.check('input[name=mode][value=prior]');
  await page.fill('#samples', '4');
  await page.fill('#seed', '3');
  const n = await page.evaluate(() => Number(document.body.dataset.results));
  await page.click('#stylize');
  await page.waitForFunction((k) => Number(document.body.dataset.results) > k && document.body.dataset.busy === 'false', n);
  await page.click('#thumbs button:nth-child(3)');
  await page.click('#play');
  await page.locator('#scrub').fill('72');
  // Back to the top (picking a thumbnail scrolls it into view): the 3D view first.
  await page.evaluate(() => {
    document.activeElement?.blur();
    window.scrollTo(0, 0);
  });
  await page.screenshot({ path: `${out}/${name}.png`, fullPage });
  await page.close();
  console.log(`${out}/${name}.png`);
}

await shoot('laptop', { width: 1366, height: 860 }, false);
await shoot('phone', { width: 390, height: 844 }, true);
await browser.close();
server.close();
