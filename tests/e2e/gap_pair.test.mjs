// Browser end-to-end test of the pair step of the gap diagnosis (src/gap/pairs.rs): the
// two-effect part of tests/data/gap/ (made by tests/it/gap_pairs.rs: backlash of Y and a tool
// radius error at 4x the detection limit) uploaded; the verdict line names both effects, the
// pair table appears, and the verdict equals the native CLI's `testpiece diagnose --json`.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

let browser, url, context;

before(async () => {
  browser = await openBrowser('gap-pair');
  ({ url, context } = browser);
});

after(async () => {
  await browser?.close();
});

test('a part with two effects names both, as the CLI does', async () => {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  const file = path.join(ROOT, 'tests', 'data', 'gap', 'two_effects.csv');
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('two_effects.csv') && !document.body.dataset.busy, null, { timeout: 60000 });
  const line = await page.locator('#verdict-line').textContent();
  const native = JSON.parse(execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', 'diagnose', file, '--json'],
    { cwd: ROOT, encoding: 'utf8' }));
  const v = native.verdict;
  assert.equal(v.with.length, 1, `CLI verdict ${v.effect} with ${v.with}`);
  assert.ok(line.startsWith(`Verdict: `) && line.includes(`(\`${v.effect}\`)`) && line.includes(`together with`) && line.includes(`(\`${v.with[0]}\`)`),
    `page: ${line}; CLI: ${v.effect} with ${v.with[0]}`);
  await page.click('#tab-gap');
  await page.waitForSelector('[data-table="gap-pair"]', { timeout: 10000 });
  const row = await page.locator('[data-table="gap-pair"] tbody tr').first().textContent();
  assert.ok(row.includes(`${native.pair.first} + ${native.pair.second}`), row);
  console.log(`two-effect part: ${line}`);
  await page.screenshot({ path: path.join(ROOT, 'tests', 'e2e', 'screenshots', 'gap-two-effects.png'), fullPage: true });
  assert.deepEqual(errors, []);
  await page.close();
});
