// The page's own marks (ms after navigation: app start, core ready, first plot, example analysed)
// of one or two builds of www/, loads alternating, a fresh Chromium profile per load, the service
// worker blocked; prints the median and every value per mark.
// Usage: node scripts/page-marks.mjs ROOT_A [ROOT_B] [LOADS] (e.g. a copy of main's www/ and www).
import fs from 'node:fs'; import os from 'node:os'; import path from 'node:path';
import { chromium } from 'playwright-core';
import { serve } from './serve.mjs';
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'];
const args = process.argv.slice(2);
const n = /^\d+$/.test(args.at(-1)) ? Number(args.pop()) : 5;
const roots = args;
const res = Object.fromEntries(roots.map((r) => [r, []]));
for (let i = 0; i < n; i++) for (const root of roots) {
  const { server, url } = await serve({ root: path.resolve(root) });
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'marks-'));
  const ctx = await chromium.launchPersistentContext(dir, { executablePath: '/usr/bin/chromium', headless: true, args: FLAGS, serviceWorkers: 'block' });
  const page = await ctx.newPage();
  await page.goto(url);
  await page.waitForFunction(() => performance.getEntriesByName('tp-example-analysed').length > 0, null, { timeout: 60000 });
  const m = await page.evaluate(() => Object.fromEntries(performance.getEntriesByType('mark').filter((x) => x.name.startsWith('tp-')).map((x) => [x.name.slice(3), Math.round(x.startTime)])));
  res[root].push(m);
  await ctx.close(); server.close(); fs.rmSync(dir, { recursive: true, force: true });
}
const med = (a) => { const s = [...a].sort((x, y) => x - y); return s[Math.floor(s.length / 2)]; };
for (const r of roots) {
  const keys = Object.keys(res[r][0]);
  console.log(r, Object.fromEntries(keys.map((k) => [k, `${med(res[r].map((m) => m[k]))} (${res[r].map((m) => m[k]).join(',')})`])));
}
