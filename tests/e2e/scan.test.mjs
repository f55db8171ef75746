// Browser end-to-end test of a scan's plan view (issue 31 item 3, the plan view drawn per scan
// line): a 600-point scan written by `testpiece simulate --scan 5x60` (each surface on 5 lines of
// constant height, 60 points a line) is uploaded; the plan view draws one line per scan line,
// 10 in all, none joining two lines across the part, and the verdict is the CLI's. The built-in
// 100-point example keeps its 4 curves.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('scan'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

test('a scan\'s plan view has one line per scan line', async () => {
  const cli = (args) => execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', ...args], { cwd: ROOT, encoding: 'utf8' });
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'testpiece-scan-'));
  const file = path.join(dir, 'scan_5x60.csv');
  fs.writeFileSync(file, cli(['simulate', '--errors', 'EX0B=0.01', '--noise', '0.0015', '--seed', '3', '--scan', '5x60']));
  const native = JSON.parse(cli(['diagnose', file, '--json']));

  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  assert.equal(await page.locator('[data-chart="plan-view"] polyline.plan-line').count(), 4, 'the example: one line per curve');
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('scan_5x60.csv'), null, { timeout: 120000 });
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
