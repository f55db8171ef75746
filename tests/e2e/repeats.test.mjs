// Browser end-to-end test of repeat measurements (src/gap/repeat.rs, issue 18 item 3): the same
// simulated part measured twice (two noise seeds) is uploaded, both files are checked under
// "Several parts" and analysed as repeats; the page adds the mean as a part whose σ is the pure
// error of the two measurements, and its final parameters equal the native CLI's
// `identify A --repeat B --json` to 1e-9.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('repeats'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

const cli = (args) => execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', ...args], { cwd: ROOT, encoding: 'utf8' });

test('two measurements of one part are analysed as repeats, as the CLI does', async () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'testpiece-repeat-'));
  const files = ['11', '12'].map((seed) => {
    const f = path.join(dir, `part_run${seed}.csv`);
    fs.writeFileSync(f, cli(['simulate', '--errors', 'EX0B=0.02,EA0B=2e-4', '--effect', 'backlash_c=4e-4', '--noise', '0.0015', '--seed', seed]));
    return f;
  });
  const native = JSON.parse(cli(['identify', files[0], '--repeat', files[1], '--json']));
  assert.equal(native.noise.source, 'repeat');

  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  await page.setInputFiles('#file', files);
  await page.click('#tab-parts');
  await page.waitForSelector('#repeat-run', { timeout: 60000 });
  await page.click('#repeat-run');
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('mean of 2 repeats') && !document.body.dataset.busy, null, { timeout: 60000 });
  await page.click('#tab-gap');
  const gap = await page.textContent('#gap-summary');
  assert.match(gap, /from 2 repeat measurements/);
  assert.match(gap, /Lack of fit/);
  await page.click('#tab-identify');
  for (const [n, p] of Object.entries(native.parameters)) {
    const r = page.locator('[data-table="parameters"] tbody tr', { has: page.locator(`td:text-is("${n}")`) });
    const v = Number(await r.locator('td').nth(1).getAttribute('data-value'));
    assert.ok(Math.abs(v - p.value) <= 1e-9 * Math.abs(p.value) + 1e-15, `${n}: page ${v} vs CLI ${p.value}`);
  }
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});
