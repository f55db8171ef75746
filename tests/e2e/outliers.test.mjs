// Browser end-to-end test of the outlier test (src/gap/outliers.rs, issue 18 item 1): the clean
// example with a 30 µm spike added at point 38 (a chip on the part) is uploaded; the page names
// point 38 with the core's size, rings it on the plan view, the verdict stays `none` (the
// example's key), and the final parameters equal the native CLI's to 1e-9.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('outliers'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

test('a spike at one point is named, ringed and left out, as the CLI does', async () => {
  const src = fs.readFileSync(path.join(ROOT, 'tests', 'data', 'reference', 'examples', 'example_clean.csv'), 'utf8').trim().split('\n');
  const head = src[0].split(',');
  const [idCol, devCol] = [head.indexOf('id'), head.indexOf('deviation')];
  const rows = src.slice(1).map((l) => {
    const f = l.split(',');
    if (f[idCol] === '38') f[devCol] = (Number(f[devCol]) + 0.030).toFixed(6);
    return f.join(',');
  });
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'testpiece-spike-'));
  const file = path.join(dir, 'clean_spike38.csv');
  fs.writeFileSync(file, [src[0], ...rows].join('\n') + '\n');
  const native = JSON.parse(execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'identify', file, '--json'], { cwd: ROOT, encoding: 'utf8' }));
  assert.deepEqual(native.outliers.points.map((p) => String(p.id)), ['38']);
  assert.equal(native.verdict, 'none');

  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('clean_spike38.csv') && !document.body.dataset.busy, null, { timeout: 60000 });
  assert.match(await page.textContent('#verdict-line'), /\(`none`\)/);
  assert.match(await page.textContent('#outlier-line'), /38/);
  await page.click('#tab-identify');
  const row = page.locator('[data-table="outlier-points"] tbody tr').first();
  assert.equal((await row.locator('td').first().textContent()).trim(), '38');
  const size = Number(await row.locator('td').nth(2).getAttribute('data-value'));
  assert.ok(Math.abs(size - native.outliers.points[0].size * 1000) <= 1e-9 * Math.abs(size), `size page ${size} µm vs CLI ${native.outliers.points[0].size} mm`);
  assert.equal(await page.locator('[data-chart="plan-view"] circle.outlier-ring[data-id="38"]').count(), 1);
  for (const [n, p] of Object.entries(native.parameters)) {
    const r = page.locator('[data-table="parameters"] tbody tr', { has: page.locator(`td:text-is("${n}")`) });
    const v = Number(await r.locator('td').nth(1).getAttribute('data-value'));
    assert.ok(Math.abs(v - p.value) <= 1e-9 * Math.abs(p.value) + 1e-15, `${n}: page ${v} vs CLI ${p.value}`);
  }
  await page.screenshot({ path: path.join(ROOT, 'tests', 'e2e', 'screenshots', 'outlier-spike38.png'), fullPage: true });
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});
