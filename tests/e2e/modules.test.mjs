// Browser end-to-end test of the page's two wasm modules (issue 33 item 2): the first view (the
// example part's analysis: verdict, plots, identification, diagnosis) loads the first module only;
// opening the Program view loads the second once, after which the Program and Plan views work.
// The requests are those the server received (page, worker), the service worker blocked (its
// install caches both modules for offline use: tests/e2e/page.test.mjs). Also: each module's
// glue exports what its views call and nothing of the other's.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

const PKG = path.join(ROOT, 'www', 'pkg');
let browser, url, context;
const requests = [];

before(async () => {
  browser = await openBrowser('modules', { serviceWorkers: 'block' });
  ({ url, context } = browser);
  browser.server.on('request', (req) => requests.push(req.url));
});

after(async () => {
  await browser?.close();
});

const fetched = (name) => requests.filter((u) => new URL(u, 'http://x').pathname.endsWith(`/pkg/${name}`)).length;
const exportsOf = (glue) => new Set([...fs.readFileSync(path.join(PKG, glue), 'utf8').matchAll(/^export (?:function|class) (\w+)/gm)].map((m) => m[1]));

test('each module exports the calls of its own views', () => {
  const first = exportsOf('testpiece.js');
  const second = exportsOf('testpiece_tools.js');
  // What app.js, fig19.js and parts.js call, and what plan.js, program.js, budget.js and
  // compensation.js call.
  for (const op of ['start', 'analyse', 'analyseRepeats', 'analysePooled', 'compareParameters', 'curvesFor', 'coneCoefficients', 'Prepared']) {
    assert.ok(first.has(op), `the first module exports ${op}`);
  }
  for (const op of ['measurementPlan', 'partProgram', 'budget', 'budgetExample', 'compensate', 'Prepared']) {
    assert.ok(second.has(op), `the second module exports ${op}`);
  }
  const both = [...first].filter((op) => second.has(op) && op !== 'initSync');
  assert.deepEqual(both, ['Prepared'], 'only the prepared settings are in both');
  const size = (f) => fs.statSync(path.join(PKG, f)).size;
  console.log(`first module ${size('testpiece_bg.wasm')} bytes (${first.size} exports), second ${size('testpiece_tools_bg.wasm')} bytes (${second.size} exports)`);
});

test('the first view does not fetch the second module; Program and Plan work after it is loaded', async () => {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
  // The whole first view: the example analysed and the cone curves drawn (the last step of
  // app.js's start), then nothing computing.
  await page.waitForFunction(() => performance.getEntriesByName('tp-example-analysed').length > 0, null, { timeout: 60000 });
  await page.waitForSelector('#verdict-line', { timeout: 60000 });
  await page.waitForFunction(() => !document.body.dataset.busy, null, { timeout: 60000 });
  assert.equal(fetched('testpiece_bg.wasm'), 1, 'the first module is fetched');
  assert.equal(fetched('testpiece_tools.js') + fetched('testpiece_tools_bg.wasm'), 0, `the first view fetched the second module: ${requests.join(' ')}`);
  assert.equal(await page.evaluate(() => document.body.dataset.tools ?? null), null);

  const t0 = Date.now();
  await page.click('#tab-program');
  await page.waitForSelector('[data-table="program-passes"]', { timeout: 60000 });
  console.log(`Program view with the second module loaded: ${Date.now() - t0} ms after the click`);
  assert.equal(await page.evaluate(() => document.body.dataset.tools), 'loaded');
  assert.equal(fetched('testpiece_tools.js'), 1);
  assert.equal(fetched('testpiece_tools_bg.wasm'), 1);
  const passes = await page.locator('[data-table="program-passes"] tbody tr').count();
  assert.equal(passes, 2, 'both walls');
  assert.match(await page.locator('#program-dialect').innerHTML(), /fanuc/, 'the dialects came from the second module');

  await page.click('#tab-plan');
  await page.waitForSelector('[data-table="plan-parameters"]', { timeout: 60000 });
  assert.ok(await page.locator('[data-table="plan-parameters"] tbody tr', { hasText: 'EX0B' }).count() === 1);
  assert.equal(fetched('testpiece_tools_bg.wasm'), 1, 'loaded once');
  // The first module still answers (a setting that re-analyses the part).
  await page.click('#tab-identify');
  await page.fill('#sigma', '1.5');
  await page.dispatchEvent('#sigma', 'change');
  await page.waitForFunction(() => !document.body.dataset.busy && document.querySelector('#summary')?.textContent.includes('from 100 points') && !document.body.dataset.busy, null, { timeout: 60000 });
  assert.deepEqual(errors, []);
  await page.close();
});
