// Browser end-to-end test: headless Debian Chromium (playwright-core, no browser download)
// against the page served from a local static server.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { serve } from '../../scripts/serve.mjs';

const ROOT = path.resolve(import.meta.dirname, '..', '..');
const SHOTS = path.join(ROOT, 'tests', 'e2e', 'screenshots');
let server, url, browser, userDataDir;

before(async () => {
  ({ server, url } = await serve());
  userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'testpiece-chromium-'));
  browser = await chromium.launchPersistentContext(userDataDir, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--no-first-run'],
    viewport: { width: 1280, height: 800 },
  });
  fs.mkdirSync(SHOTS, { recursive: true });
});

after(async () => {
  await browser?.close();
  server?.close();
  if (userDataDir) fs.rmSync(userDataDir, { recursive: true, force: true });
});

/** The same numbers from the native CLI (the core built for this machine). */
function cliSummary() {
  const out = execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'info', '--json'],
    { cwd: ROOT, encoding: 'utf8' });
  return JSON.parse(out);
}

test('the page computes the example part in the browser and shows the core\'s numbers', async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 15000 });
  const firstResultMs = Date.now() - t0;
  console.log(`first result on the page after ${firstResultMs} ms`);
  const cli = cliSummary();
  for (const c of cli.curves) {
    const cell = await page.textContent(`tr[data-curve="${c.curve}"] td:nth-child(3)`);
    // The page prints 4 decimals of the wasm core's value; the native core must agree to that.
    assert.equal(cell, c.length.toFixed(4), `curve ${c.curve}`);
  }
  assert.equal(await page.textContent('#version'), cli.version);
  assert.deepEqual(errors, []);
  await page.screenshot({ path: path.join(SHOTS, 'example.png'), fullPage: true });
  await page.close();
});
