// Browser end-to-end test of the charts of a dense file (issue 31 item 3, charts fluid at 200,000
// points): an 8,000-point scan written by `testpiece simulate --scan 10x400` (more than the page's
// DENSE_POINTS, 3,000) is uploaded; its residual chart and plan view are canvases (no element per
// point), the wheel zooms the chart in (fewer points drawn, a narrower x range) and double-click
// goes back; the cursor reads out the nearest point with its position and residual in µm; the
// points table shows 100 rows a page, every row reachable (Next, Last, a row number). The 100-point example keeps its SVG charts.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { openBrowser, readyPage, simulatedScan } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('dense'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

test('a dense scan\'s charts are canvases with zoom and a read-out', async () => {
  const { file, dir } = simulatedScan('dense', '10x400', 7);

  const { page, errors } = await readyPage(context, url);
  assert.equal(await page.locator('[data-chart="measured-simulated-residual"] svg').count(), 1, 'the example: an SVG chart');
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('scan_10x400.csv') && !document.body.dataset.busy, null, { timeout: 180000 });

  // the points table a page of 100 rows at a time, every row reachable: Next, Last, a row number
  await page.click('#tab-data');
  const points = page.locator('[data-table="points"]');
  const lineOf = async (k) => Number(await points.locator(`tbody tr:nth-child(${k}) td:nth-child(2)`).textContent());
  assert.equal(await points.locator('tbody tr').count(), 100);
  assert.match(await points.locator('caption').textContent(), /8000 points, 100 a page \(the CSV has every point\)/);
  assert.equal(await points.getAttribute('data-rows'), '1-100');
  assert.equal(await lineOf(1), 2, 'the first point is the file\'s line 2 (line 1: the header)');
  assert.equal(await page.locator('[data-page="prev"]').isDisabled(), true);
  await page.click('[data-page="next"]');
  assert.equal(await points.getAttribute('data-rows'), '101-200');
  await page.click('[data-page="last"]');
  assert.equal(await points.getAttribute('data-rows'), '7901-8000');
  assert.equal(await lineOf(100), 8001, 'the last point: the file\'s last line');
  assert.equal(await page.locator('[data-page="next"]').isDisabled(), true);
  await page.fill('.page-go', '4321');
  await page.locator('.page-go').dispatchEvent('change');
  assert.equal(await points.getAttribute('data-rows'), '4301-4400');
  assert.equal(await lineOf(21), 4322, 'row 4,321 on its page');
  assert.match(await page.textContent('.page-where'), /rows 4301–4400 of 8000 \(page 44 of 80\)/);

  await page.click('#tab-identify');
  const block = page.locator('[data-chart="measured-simulated-residual"]');
  assert.equal(await block.locator('svg').count(), 0, 'no SVG');
  assert.equal(await block.locator('canvas').count(), 1);
  assert.equal(await page.locator('[data-chart="plan-view"] canvas').count(), 1, 'the plan view on a canvas');
  const chart = block.locator('.dense-chart');
  const before0 = Number(await chart.getAttribute('data-drawn'));
  assert.equal(before0, 8000, 'every point drawn at the whole range');
  const canvas = block.locator('canvas');
  await canvas.scrollIntoViewIfNeeded();
  const box = await canvas.boundingBox();
  await page.mouse.move(box.x + box.width * 0.5, box.y + box.height * 0.5);
  await page.mouse.wheel(0, -400);
  await page.waitForFunction(() => Number(document.querySelector('[data-chart="measured-simulated-residual"] .dense-chart').dataset.drawn) < 8000);
  const zoomed = Number(await chart.getAttribute('data-drawn'));
  assert.ok(zoomed < 8000 && zoomed > 0, `zoomed in: ${zoomed} points drawn`);
  // the read-out: point, position, residual
  await page.mouse.move(box.x + box.width * 0.52, box.y + box.height * 0.5);
  const text = await block.locator('.dense-readout').textContent();
  assert.match(text, /^point \d+ \([AB]_Z[\d.]+\), s [\d.]+ mm, z [\d.]+ mm: .*residual -?[\d.e+-]+ µm$/, text);
  await page.mouse.dblclick(box.x + box.width * 0.5, box.y + box.height * 0.5);
  assert.equal(Number(await chart.getAttribute('data-drawn')), 8000, 'double-click: the whole range');
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});
