// Browser end-to-end test of the analysis's stages on the progress line (issue 31 item 3,
// progress with stages): a 20,000-point scan written by `testpiece simulate --scan 40x250` is
// uploaded; while it is analysed (seconds), the progress line is shown with the core's stage text
// ("stage k of 6: …", src/analysis/progress.rs) and the <progress> bar at the share of the stages
// done, rising; the stages seen are among the core's, in order; at the end the line is hidden and
// the verdict is there.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { openBrowser, readyPage, simulatedScan } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('progress'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

test('a 20,000-point analysis shows its stages on the progress bar', async () => {
  const { file, dir } = simulatedScan('progress', '40x250', 5);

  const { page, errors } = await readyPage(context, url);
  // record what the progress line shows while it is shown
  await page.evaluate(() => {
    window.__seen = [];
    const note = () => {
      const bar = document.getElementById('progress-bar');
      if (document.getElementById('progress').hidden || bar.hidden) return;
      window.__seen.push({ text: document.getElementById('progress-text').textContent, value: bar.value, stage: bar.dataset.stage });
    };
    new MutationObserver(note).observe(document.getElementById('progress'), { subtree: true, childList: true, attributes: true, characterData: true });
  });
  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('scan_40x250.csv') && !document.body.dataset.busy, null, { timeout: 300000 });
  const seen = await page.evaluate(() => window.__seen);
  assert.ok(seen.length >= 2, `stages shown: ${JSON.stringify(seen)}`);
  const order = ['read', 'model', 'design', 'diagnose', 'identify', 'final_fit'];
  let last = -1, lastValue = -1;
  for (const s of seen) {
    assert.match(s.text, /^Analysing scan_40x250\.csv: stage [1-6] of 6: /, s.text);
    const k = order.indexOf(s.stage);
    assert.ok(k >= last, `stages in order: ${JSON.stringify(seen.map((x) => x.stage))}`);
    assert.ok(s.value >= lastValue && s.value < 1, `the bar rises: ${s.value}`);
    last = k; lastValue = s.value;
  }
  assert.ok(seen.some((s) => s.stage === 'diagnose'), 'the diagnosis, the longest stage, is shown');
  assert.equal(await page.isHidden('#progress'), true, 'the line is hidden at the end');
  assert.match(await page.textContent('#verdict-line'), /Verdict/);
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});
