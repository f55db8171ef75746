// Browser end-to-end test of the Program view (issue 19, step 2): the program made by the wasm
// core has the positions of the native CLI's `testpiece program` (both passes), its CL download
// holds the same GOTO positions to 1e-9 mm, and the G-code download has one G01 block per
// position and the header that says roughing is not included.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import { openBrowser, ROOT } from './browser.mjs';

let browser, url, context;

before(async () => {
  browser = await openBrowser('program', { acceptDownloads: true });
  ({ url, context } = browser);
});

after(async () => {
  await browser?.close();
});

const cli = (...args) => execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'program', ...args], { cwd: ROOT, encoding: 'utf8', maxBuffer: 64 << 20 });
const gotos = (text) => text.split('\n').filter((l) => l.startsWith('GOTO/')).map((l) => l.slice(5).split(',').map(Number));
// The pass's positions in a CL: the GOTOs at feed (not after RAPID) less one exit per pass (one
// FEDRAT per pass).
const positions = (text) => {
  const lines = text.split('\n');
  const feed = lines.filter((l, i) => l.startsWith('GOTO/') && lines[i - 1] !== 'RAPID').length;
  return feed - lines.filter((l) => l.startsWith('FEDRAT/')).length;
};

test('the Program view equals the CLI and its files download', async () => {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
  await page.click('#tab-program');
  await page.waitForSelector('[data-table="program-passes"]', { timeout: 60000 });
  const nativeText = cli();
  const native = gotos(nativeText);
  const shown = Number(await page.locator('#program-out').getAttribute('data-positions'));
  assert.equal(shown, positions(nativeText), `positions page ${shown} vs CLI ${positions(nativeText)}`);
  const [clDownload] = await Promise.all([page.waitForEvent('download'), page.click('#program-cl')]);
  const cl = fs.readFileSync(await clDownload.path(), 'utf8');
  assert.ok(cl.includes('ROUGHING NOT INCLUDED'));
  const page6 = gotos(cl);
  assert.equal(page6.length, native.length);
  let worst = 0;
  page6.forEach((r, i) => r.forEach((v, k) => { worst = Math.max(worst, Math.abs(v - native[i][k])); }));
  assert.ok(worst <= 1e-9, `CL positions differ from the CLI by ${worst}`);
  const [gDownload] = await Promise.all([page.waitForEvent('download'), page.click('#program-gcode')]);
  const gcode = fs.readFileSync(await gDownload.path(), 'utf8');
  // Every feed GOTO of the CL (not after RAPID) is a G01 block; the rapids are G00 blocks.
  const lines = cl.split('\n');
  const feed = lines.filter((l, i) => l.startsWith('GOTO/') && lines[i - 1] !== 'RAPID').length;
  assert.equal(gcode.split('\n').filter((l) => l.startsWith('G01 ')).length, feed);
  assert.ok(gcode.includes('(ROUGHING NOT INCLUDED'));
  assert.ok(gcode.includes('G53 G00 Z0') && gcode.includes('T1 M06') && gcode.includes('G93'));
  // Another controller: the page's program equals the CLI's.
  await page.selectOption('#program-dialect', 'heidenhain');
  await page.waitForFunction(() => !document.querySelector('#program-tcp').disabled, null, { timeout: 60000 });
  const [hDownload] = await Promise.all([page.waitForEvent('download'), page.click('#program-gcode')]);
  const klartext = fs.readFileSync(await hDownload.path(), 'utf8');
  assert.equal(klartext, cli('--format', 'gcode', '--dialect', 'heidenhain'));
  await page.selectOption('#program-dialect', 'iso');
  // A coarser tolerance: fewer positions, at once.
  await page.fill('#program-tolerance', '5');
  await page.dispatchEvent('#program-tolerance', 'change');
  const coarse = positions(cli('--tolerance', '0.005'));
  await page.waitForFunction((n) => document.querySelector('#program-out')?.dataset.positions === String(n), coarse, { timeout: 60000 });
  console.log(`program view: ${shown} positions at 1 µm, ${coarse} at 5 µm; CL equal to the CLI within ${worst.toExponential(1)} mm`);
  assert.deepEqual(errors, []);
  await page.close();
});
