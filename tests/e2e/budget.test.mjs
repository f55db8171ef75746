// Browser end-to-end test of the Budget view (issue 10): the example measured part of
// tests/data/budget/ uploaded as the CMM file, its CL file (APT) and NC trace chosen in the
// Budget view, the budget computed by the wasm core; the min/max table appears with every source
// and its numbers equal the native CLI's `testpiece budget --json`. The files are made by
// tests/it/budget_examples.rs (README in tests/data/budget/).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

const DATA = path.join(ROOT, 'tests', 'data', 'budget');
let browser, url, context;

before(async () => {
  browser = await openBrowser('budget');
  ({ url, context } = browser);
});

after(async () => {
  await browser?.close();
});

test('a CMM file and a CL file give the budget table, equal to the CLI', async () => {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  const cmm = path.join(DATA, 'example_measured.csv');
  await page.setInputFiles('#file', cmm);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('example_measured.csv') && !document.body.dataset.busy, null, { timeout: 30000 });
  await page.click('#tab-budget');
  await page.setInputFiles('#budget-cl', path.join(DATA, 'example_cl.apt'));
  await page.setInputFiles('#budget-trace', path.join(DATA, 'example_trace.csv'));
  await page.waitForFunction(() => document.querySelector('#budget-status')?.textContent.includes('example_trace.csv'), null, { timeout: 10000 });
  await page.click('#budget-run');
  await page.waitForSelector('[data-table="budget-summary"]', { timeout: 60000 });
  const rows = await page.locator('[data-table="budget-summary"] tbody tr').allTextContents();
  for (const s of ['design', 'CAM path', 'NC trace', 'machine', 'tool', 'residual', 'CMM band', 'measured']) {
    assert.ok(rows.some((r) => r.includes(s)), `row ${s} in ${rows.join(' | ')}`);
  }
  assert.equal(await page.locator('[data-chart="budget-stacked"] svg').count(), 1);
  const native = JSON.parse(execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'budget', cmm,
    '--cl', path.join(DATA, 'example_cl.apt'), '--trace', path.join(DATA, 'example_trace.csv'), '--json'], { cwd: ROOT, encoding: 'utf8' }));
  const ncRow = page.locator('[data-table="budget-summary"] tbody tr', { hasText: 'NC trace' });
  const shown = Number(await ncRow.locator('td').nth(2).getAttribute('data-value'));
  assert.ok(Math.abs(shown - native.summary.nc.max * 1000) < 1e-9, `NC max page ${shown} µm vs CLI ${native.summary.nc.max * 1000} µm`);
  console.log(`budget view: NC max ${shown.toFixed(3)} µm (CLI ${(native.summary.nc.max * 1000).toFixed(3)} µm)`);
  assert.deepEqual(errors, []);
  await page.close();
});
