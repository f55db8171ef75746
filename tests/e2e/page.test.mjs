// Browser end-to-end tests: headless Debian Chromium (playwright-core, no browser download)
// against the page served from a local static server, and the single-file build from file://.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';
import { serve } from '../../scripts/serve.mjs';

const ROOT = path.resolve(import.meta.dirname, '..', '..');
const SHOTS = path.join(ROOT, 'tests', 'e2e', 'screenshots');
const EXAMPLES = path.join(ROOT, 'tests', 'data', 'reference', 'examples');
const BROKEN = path.join(ROOT, 'tests', 'data', 'cmm', 'broken');
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--no-first-run'];
let server, url, context, userDataDir;

before(async () => {
  ({ server, url } = await serve());
  userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'testpiece-chromium-'));
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: '/usr/bin/chromium', headless: true, args: FLAGS, viewport: { width: 1280, height: 800 },
    acceptDownloads: true,
  });
  fs.mkdirSync(SHOTS, { recursive: true });
});

after(async () => {
  await context?.close();
  server?.close();
  if (userDataDir) fs.rmSync(userDataDir, { recursive: true, force: true });
});

/** The native CLI (the same core built for this machine). */
function cli(...args) {
  return execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', ...args], { cwd: ROOT, encoding: 'utf8' });
}

async function openPage() {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  await page.waitForSelector('[data-chart="figure19"] svg polyline', { state: 'attached', timeout: 30000 });
  return { page, errors, firstPlotMs: Date.now() - t0 };
}

async function upload(page, file) {
  await page.setInputFiles('#file', file);
  const name = path.basename(file);
  await page.waitForFunction((n) => document.querySelector('#summary')?.textContent.includes(n), name, { timeout: 30000 });
}

test('the example part is analysed at once and its numbers are the core\'s', async () => {
  const { page, errors, firstPlotMs } = await openPage();
  console.log(`first plot ${firstPlotMs} ms after opening the page (localhost, includes wasm start)`);
  const native = JSON.parse(cli('identify', path.join(EXAMPLES, 'example_backlash_c.csv'), '--json'));
  // The parameters table shows 4 significant digits of the wasm core's EA0B.
  const row = page.locator('[data-table="parameters"] tr', { hasText: 'EA0B' });
  const shown = Number(await row.locator('td').nth(1).getAttribute('data-value'));
  const ea0b = native.parameters.EA0B.value;
  assert.ok(Math.abs(shown - ea0b) <= 1e-9 * Math.abs(ea0b) + 1e-15, `EA0B page ${shown} vs CLI ${ea0b}`);
  assert.equal(await page.textContent('#version'), cli('--version').trim().split(' ')[1]);
  assert.deepEqual(errors, []);
  for (const t of ['data', 'fig19', 'identify', 'gap', 'report']) {
    await page.click(`#tab-${t}`);
    await page.screenshot({ path: path.join(SHOTS, `view-${t}.png`), fullPage: true });
  }
  await page.close();
});

test('Figure 19 parameters toggle, and its CSV export equals the CLI sensitivity', async () => {
  const { page } = await openPage();
  await page.click('#tab-fig19');
  const before = await page.locator('[data-chart="figure19"] polyline[data-series="EA0B"]').count();
  assert.equal(before, 4, 'one polyline per measurement curve');
  await page.uncheck('input[data-param="EA0B"]');
  assert.equal(await page.locator('[data-chart="figure19"] polyline[data-series="EA0B"]').count(), 0);
  const [download] = await Promise.all([
    page.waitForEvent('download'),
    page.click('[data-chart="figure19"] button[data-export="figure19.csv"]'),
  ]);
  const csv = fs.readFileSync(await download.path(), 'utf8').trim().split('\n');
  const head = csv[0].split(',');
  const native = cli('sensitivity').trim().split('\n');
  const nhead = native[0].split(',');
  for (const p of ['EC0Y', 'EX0B', 'EC0B']) {
    const k = head.indexOf(p), nk = nhead.indexOf(p);
    const scale = (p === 'EX0B' ? 0.01 : 1e-4) * 1000; // page: µm per 1e-4 rad (per 0.01 mm)
    for (let i = 1; i <= 100; i++) {
      const pv = Number(csv[i].split(',')[k]);
      const nv = Number(native[i].split(',')[nk]) * scale;
      assert.ok(Math.abs(pv - nv) <= 1e-9 * (1 + Math.abs(nv)), `${p} row ${i}: page ${pv} vs CLI ${nv}`);
    }
  }
  await page.close();
});

test('each example file uploads and is analysed; a broken file shows the reader\'s message', async () => {
  const { page } = await openPage();
  // Verdicts keyed in tests/data/reference/examples/*.key.json (`accept`).
  for (const [f, verdict] of [['example_clean.csv', /^Verdict: .*\(`none`\)/], ['example_tool_radius.csv', /^Verdict: .*\(`tool_(radius|taper)`\)/],
    ['example_backlash_c.csv', /^Verdict: .*\(`backlash_c`\)/]]) {
    await upload(page, path.join(EXAMPLES, f));
    assert.match(await page.textContent('#summary'), /from 100 points/);
    const line = await page.textContent('#verdict-line');
    assert.match(line, verdict, `${f}: ${line}`);
    console.log(`${f}: ${line}`);
    await page.click('#tab-gap');
    await page.screenshot({ path: path.join(SHOTS, `gap-${f.replace('.csv', '')}.png`), fullPage: true });
  }
  const broken = fs.readdirSync(BROKEN).filter((f) => /non.?numeric|nan/i.test(f)).sort()[0]
    || fs.readdirSync(BROKEN).sort()[0];
  await upload(page, path.join(BROKEN, broken));
  await page.click('#tab-data');
  const msg = await page.textContent('#file-error');
  const native = (() => { try { cli('identify', path.join(BROKEN, broken), '--json'); return ''; } catch (e) { return String(e.stderr); } })();
  assert.ok(msg.length > 10, 'a message is shown');
  assert.match(msg, /line \d+/, `the message names the line: ${msg}`);
  console.log(`broken file ${broken}: ${msg.split('\n')[0]}`);
  if (native) console.log(`CLI says: ${native.split('\n')[0]}`);
  await page.screenshot({ path: path.join(SHOTS, 'broken-file.png'), fullPage: true });
  await page.close();
});

test('after one visit the page works with the network off (service worker cache)', async () => {
  const { page } = await openPage();
  await page.evaluate(() => navigator.serviceWorker.ready);
  await page.reload();
  await page.waitForSelector('body[data-ready="true"]');
  await page.evaluate(() => navigator.serviceWorker.ready);
  await context.setOffline(true);
  try {
    await page.reload();
    await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
    await page.waitForSelector('[data-table="parameters"]', { state: 'attached', timeout: 30000 });
    assert.match(await page.textContent('#summary'), /from 100 points/);
  } finally {
    await context.setOffline(false);
  }
  await page.close();
});

test('the single-file build works from file:// with no server', async () => {
  execFileSync('node', [path.join(ROOT, 'scripts', 'build-single.mjs')], { cwd: ROOT });
  const file = path.join(ROOT, 'dist', 'testpiece.html');
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(pathToFileURL(file).href);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  assert.match(await page.textContent('#runner'), /main thread/);
  assert.match(await page.textContent('#summary'), /from 100 points/);
  assert.deepEqual(errors, []);
  await page.screenshot({ path: path.join(SHOTS, 'single-file.png'), fullPage: false });
  await page.close();
});
