// Browser end-to-end test of a scan's plan view (issue 31 item 3, the plan view drawn per scan
// line): a 600-point scan written by `testpiece simulate --scan 5x60` (each surface on 5 lines of
// constant height, 60 points a line) is uploaded; the plan view draws one line per scan line,
// 10 in all, none joining two lines across the part, and the verdict is the CLI's. The built-in
// 100-point example keeps its 4 curves. A 1,200-point scan whose heights form no lines
// (`--scan 100x6`: 100 heights 0.24 mm apart, 6 points each) is read in height bands: the plan
// view draws one line per band, the map one row per band, as many as the CLI's.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { openBrowser, readyPage, simulatedScan, testpiece } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('scan'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

test('a scan\'s plan view has one line per scan line', async () => {
  const { file, dir } = simulatedScan('scan', '5x60', 3);
  const native = JSON.parse(testpiece(['diagnose', file, '--json']));

  const { page, errors } = await readyPage(context, url);
  assert.equal(await page.locator('[data-chart="plan-view"] polyline.plan-line').count(), 4, 'the example: one line per curve');
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('scan_5x60.csv') && !document.body.dataset.busy, null, { timeout: 120000 });
  assert.match(await page.textContent('#verdict-line'), new RegExp(`\\(\`${native.verdict.effect}\`\\)`));
  await page.click('#tab-identify');
  const lines = page.locator('[data-chart="plan-view"] polyline.plan-line');
  assert.equal(await lines.count(), 10, 'two surfaces of 5 scan lines');
  for (const pts of await lines.evaluateAll((ls) => ls.map((l) => l.getAttribute('points').split(' ').length))) {
    assert.equal(pts, 60, 'each line holds its 60 points');
  }
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});

test('a scan whose heights form no lines is drawn in its height bands', async () => {
  const { file, dir } = simulatedScan('bands', '100x6', 3);
  const native = JSON.parse(testpiece(['diagnose', file, '--json']));
  assert.deepEqual(native.scan.banded, ['A', 'B']);
  const bands = native.scan.lines; // every band, surface A's first, bottom to top
  assert.equal(bands.length, native.scan.lines_per_surface[0] + native.scan.lines_per_surface[1]);

  const { page, errors } = await readyPage(context, url);
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('scan_100x6.csv') && !document.body.dataset.busy, null, { timeout: 120000 });
  assert.match(await page.textContent('#gap-summary'), new RegExp(`${native.scan.lines_per_surface[0]} height bands on A`));
  assert.match(await page.textContent('#verdict-line'), new RegExp(`\\(\`${native.verdict.effect}\`\\)`));
  await page.click('#tab-identify');
  const lines = page.locator('#view-identify [data-chart="plan-view"] polyline.plan-line');
  assert.equal(await lines.count(), bands.length, 'one line per height band');
  const sizes = await lines.evaluateAll((ls) => ls.map((l) => l.getAttribute('points').split(' ').length));
  assert.deepEqual(sizes.sort(), bands.map((b) => b.points).sort(), 'each line holds its band\'s points');
  const rows = await page.locator('#view-identify .surface-map[data-surface]').first().textContent();
  assert.match(rows, new RegExp(`${bands[0].points * native.scan.lines_per_surface[0]} points on ${native.scan.lines_per_surface[0]} rows`));
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});
