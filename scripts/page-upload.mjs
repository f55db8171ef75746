// The page from the upload of a measured file to its verdict, in headless Chromium (issue 31
// item 3): the time from `setInputFiles` to the verdict painted (`verdict_ms`: the page's mark
// `tp-verdict-painted`, www/app.js) and to the page idle with every view drawn
// (`upload_to_verdict_ms`: the summary names the file and `body[data-busy]` is gone), the main thread's long tasks over that
// whole span (PerformanceObserver 'longtask': count and longest, ms), the progress line's
// texts with their times (`stages`: the core's stages, ms after the upload), and then the time to draw
// the Identification view (the tab clicked, the next two frames). A fresh profile, the service
// worker blocked, the page served by scripts/serve.mjs; needs www/pkg (scripts/build-wasm.sh).
// Usage: node scripts/page-upload.mjs FILE [TIMEOUT_S] [WWW_DIR]  (a scan: testpiece simulate
// --scan 40x250; WWW_DIR: another checkout's www/ to serve, e.g. to measure before a change)
import fs from 'node:fs'; import os from 'node:os'; import path from 'node:path';
import { chromium } from 'playwright-core';
import { serve } from './serve.mjs';
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'];
const [file, timeoutS = '900', www] = process.argv.slice(2);
if (!file) { console.error('usage: node scripts/page-upload.mjs FILE [TIMEOUT_S]'); process.exit(2); }
const name = path.basename(file);
const { server, url } = await serve(www ? { root: path.resolve(www) } : {});
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'upload-'));
const ctx = await chromium.launchPersistentContext(dir, { executablePath: '/usr/bin/chromium', headless: true, args: FLAGS, serviceWorkers: 'block', viewport: { width: 1280, height: 900 } });
try {
  const page = await ctx.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
  await page.evaluate(() => new Promise((r) => setTimeout(r, 500))); // the example's cone curves settle
  await page.evaluate(() => {
    window.__long = [];
    // the progress line's texts as they change (the core's stages: where the time goes)
    window.__stages = [];
    new MutationObserver(() => window.__stages.push([performance.now(), document.querySelector('#progress-text').textContent]))
      .observe(document.querySelector('#progress-text'), { childList: true, characterData: true, subtree: true });
    new PerformanceObserver((l) => { for (const e of l.getEntries()) window.__long.push({ start: e.startTime, ms: e.duration }); }).observe({ type: 'longtask', buffered: false });
  });
  const t0 = await page.evaluate(() => performance.now());
  await page.setInputFiles('#file', file);
  await page.waitForFunction((n) => document.querySelector('#verdict-line') && document.querySelector('#summary').textContent.includes(n) && !document.body.dataset.busy,
    name, { timeout: Number(timeoutS) * 1000, polling: 50 });
  const t1 = await page.evaluate(() => performance.now());
  // the verdict painted: the page's mark after the upload (null without one: the page before it)
  const tv = await page.evaluate((a) => performance.getEntriesByName('tp-verdict-painted').map((m) => m.startTime).filter((t) => t >= a).pop() ?? null, t0);
  await page.evaluate(() => new Promise((r) => setTimeout(r, 300))); // a long task ending the span is reported after it
  const during = await page.evaluate(([a, b]) => window.__long.filter((e) => e.start >= a && e.start <= b), [t0, t1]);
  const t2 = await page.evaluate(() => performance.now());
  await page.click('#tab-identify');
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const t3 = await page.evaluate(() => performance.now());
  await page.evaluate(() => new Promise((r) => setTimeout(r, 300)));
  const tab = await page.evaluate(([a, b]) => window.__long.filter((e) => e.start >= a && e.start <= b), [t2, t3]);
  const longest = (l) => Math.round(Math.max(0, ...l.map((e) => e.ms)));
  console.log(JSON.stringify({
    file: name,
    verdict_ms: tv === null ? null : Math.round(tv - t0),
    upload_to_verdict_ms: Math.round(t1 - t0),
    long_tasks: during.length, longest_task_ms: longest(during),
    // each long task: [its start after the verdict was painted (ms; from the upload without the mark), its length (ms)]
    tasks: during.map((e) => [Math.round(e.start - (tv ?? t0)), Math.round(e.ms)]),
    identification_tab_ms: Math.round(t3 - t2), identification_long_tasks: tab.length, identification_longest_task_ms: longest(tab),
    // the progress line's texts: [ms after the upload, text]
    stages: await page.evaluate((a) => window.__stages.map(([t, x]) => [Math.round(t - a), x]), t0),
    page_errors: errors,
  }));
} finally {
  await ctx.close(); server.close(); fs.rmSync(dir, { recursive: true, force: true });
}
