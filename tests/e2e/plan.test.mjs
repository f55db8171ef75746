// Browser end-to-end test of the Plan view (issue 19, step 1): the plan computed by the wasm core
// equals the native CLI's `testpiece plan --json` (predicted std of EX0B, the detection limit of
// backlash_c), changing the points per curve or the CMM σ updates the figures at once, and the
// DMIS download reads back to the plan's 100 points, is ASCII with lines of at most 80
// characters, and its probe path keeps 2 mm from the part (the view's replay line).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import { openBrowser, ROOT } from './browser.mjs';

let browser, url, context;

before(async () => {
  browser = await openBrowser('plan', { acceptDownloads: true });
  ({ url, context } = browser);
});

after(async () => {
  await browser?.close();
});

// How long a plan may take to be drawn: a wait, not a speed bound (the figures follow their inputs
// with no button; each input is a plan computed in the worker, one after the other). 30 s had
// been enough until a slow host took 9 s for the tab's first plan and 27.7 s for the two plans
// of σ 2 µm and 50 points per curve (2 Dec 2026).
const PLAN_WAIT_MS = 120000;

const cli = (...args) => JSON.parse(execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'plan', ...args, '--json'], { cwd: ROOT, encoding: 'utf8' }));
const cellValue = async (page, tableName, rowText, col) => Number(await page.locator(`[data-table="${tableName}"] tbody tr`, { hasText: rowText }).first().locator('td').nth(col).getAttribute('data-value'));

test('the Plan view equals the CLI and follows its inputs at once', async () => {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
  await page.click('#tab-plan');
  await page.waitForSelector('[data-table="plan-parameters"]', { timeout: PLAN_WAIT_MS });
  const native = cli();
  const ex0b = await cellValue(page, 'plan-parameters', 'EX0B', 1);
  assert.ok(Math.abs(ex0b - native.parameters.EX0B.std) <= 1e-12 * native.parameters.EX0B.std, `EX0B std page ${ex0b} vs CLI ${native.parameters.EX0B.std}`);
  const bc = await cellValue(page, 'plan-limits', 'backlash_c', 3);
  assert.ok(Math.abs(bc - native.detection_limits.backlash_c.b) <= 1e-9 * bc, `backlash_c page ${bc} vs CLI ${native.detection_limits.backlash_c.b}`);
  // σ 2 µm and 50 points per curve: the figures follow without any button.
  await page.fill('#plan-sigma', '2');
  await page.dispatchEvent('#plan-sigma', 'input');
  await page.fill('#plan-per-curve', '50');
  await page.dispatchEvent('#plan-per-curve', 'input');
  await page.waitForFunction(() => document.querySelector('#plan-out')?.dataset.points === '200', null, { timeout: PLAN_WAIT_MS });
  const native50 = cli('--sigma', '0.002', '--per-curve', '50');
  await page.waitForFunction((want) => {
    const row = [...document.querySelectorAll('[data-table="plan-parameters"] tbody tr')].find((r) => r.textContent.startsWith('EX0B'));
    return row && Math.abs(Number(row.children[1].dataset.value) - want) <= 1e-12 * want;
  }, native50.parameters.EX0B.std, { timeout: PLAN_WAIT_MS });
  console.log(`plan view: EX0B std ${(ex0b * 1e3).toFixed(3)} µm (100 points, MPE σ) -> ${(native50.parameters.EX0B.std * 1e3).toFixed(3)} µm (200 points, σ 2 µm)`);
  // Back to 25 per curve: the DMIS download holds the 100 points of `testpiece points`.
  await page.fill('#plan-per-curve', '25');
  await page.dispatchEvent('#plan-per-curve', 'input');
  await page.waitForFunction(() => document.querySelector('#plan-out')?.dataset.points === '100', null, { timeout: PLAN_WAIT_MS });
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#plan-dmis')]);
  const dmis = fs.readFileSync(await download.path(), 'utf8');
  // ASCII, lines of at most 80 characters; `$` at a line's end continues the statement.
  assert.ok(/^[\x20-\x7e\n]*$/.test(dmis), 'DMIS not printable ASCII');
  assert.ok(dmis.split('\n').every((l) => l.length <= 80), 'DMIS line over 80 characters');
  const minCertain = Number(await page.getAttribute('#plan-dmis-replay', 'data-min-certain'));
  assert.ok(minCertain >= 2, `probe path keeps ${minCertain} mm`);
  const feats = dmis.replace(/\$\n/g, '').split('\n').filter((l) => l.includes('=FEAT/POINT,CART,'));
  assert.equal(feats.length, 100);
  const points = execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'points'], { cwd: ROOT, encoding: 'utf8' }).trim().split('\n').slice(1);
  feats.forEach((f, i) => {
    const got = f.split('CART,')[1].split(',').map(Number);
    const want = points[i].split(',').slice(4, 10).map(Number);
    for (let k = 0; k < 6; k++) assert.ok(Math.abs(got[k] - want[k]) <= 1e-6, `point ${i + 1} component ${k}: ${got[k]} vs ${want[k]}`);
  });
  assert.deepEqual(errors, []);
  await page.close();
});
