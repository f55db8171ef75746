// Browser end-to-end test of a scan's plan view (issue 31 item 3, the plan view drawn per scan
// line): a 600-point scan written by `testpiece simulate --scan 5x60` (each surface on 5 lines of
// constant height, 60 points a line) is uploaded; the plan view draws one line per scan line,
// 10 in all, none joining two lines across the part, and the verdict is the CLI's. The built-in
// 100-point example keeps its 4 curves.
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
