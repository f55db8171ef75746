// Where the page's first verdict spends its time (issue 33 item 2): for each of LOADS loads of
// www/ (a fresh Chromium profile each, the service worker blocked, nothing computed before the
// navigation), the page's own marks (ms after navigation: app start, core ready, first plot,
// example analysed), the navigation's and the first module's network timing, and then, on the
// same page, each step of the first view timed alone on the main thread: the first module's wasm
// compiled from its bytes (no code cache), instantiated, `start()`, the prepared settings of the
// page's defaults built (`new Prepared`: the part and path models), the example analysed
// (`analyse`: read, match, identify, diagnose, final answer) and its JSON parsed.
// Then the same chain as the page's worker runs it, in a fresh module worker of the same origin
// (a copy of ROOT with a measuring worker added): the worker started, the glue imported, init()
// (the wasm fetched from the HTTP cache and compiled while it streams), start(), the prepared
// settings, the Figure-19 curves of surface A and the example analysed, each ms after the
// worker was created.
// Prints the median and every value of each figure.
// Usage: node scripts/first-verdict.mjs [ROOT] [LOADS]   (defaults: www, 7)
import fs from 'node:fs'; import os from 'node:os'; import path from 'node:path';
import { chromium } from 'playwright-core';
import { serve } from './serve.mjs';

const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'];
const args = process.argv.slice(2);
const loads = /^\d+$/.test(args.at(-1) ?? '') ? Number(args.pop()) : 7;
const www = path.resolve(args[0] ?? 'www');
// a copy of the page with the measuring worker beside its own
const root = fs.mkdtempSync(path.join(os.tmpdir(), 'verdict-www-'));
fs.cpSync(www, root, { recursive: true });
fs.writeFileSync(path.join(root, 'measure-worker.js'), `
const at = () => performance.timeOrigin + performance.now();
const t = { 'worker: first line': at() };
self.onmessage = async (ev) => {
  const settings = ev.data;
  const glue = await import('./pkg/testpiece.js');
  t['worker: glue imported'] = at();
  await glue.default();
  t['worker: init() (fetch, compile, instantiate)'] = at();
  const started = glue.start();
  t['worker: start()'] = at();
  const prepared = new glue.Prepared(settings);
  t['worker: new Prepared'] = at();
  glue.curvesFor(prepared, 'A', 200);
  t['worker: curvesFor A'] = at();
  const ex = started.examples[0];
  glue.analyse(prepared, new TextEncoder().encode(ex.text), ex.name, settings);
  t['worker: example analysed'] = at();
  self.postMessage(t);
};
`);
const rows = [];
for (let i = 0; i < loads; i++) {
  const { server, url } = await serve({ root });
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'verdict-'));
  const ctx = await chromium.launchPersistentContext(dir, { executablePath: '/usr/bin/chromium', headless: true, args: FLAGS, serviceWorkers: 'block' });
  const page = await ctx.newPage();
  await page.goto(url);
  await page.waitForFunction(() => performance.getEntriesByName('tp-example-analysed').length > 0, null, { timeout: 60000 });
  const row = await page.evaluate(async () => {
    const r = {};
    for (const m of performance.getEntriesByType('mark')) if (m.name.startsWith('tp-')) r[m.name.slice(3)] = m.startTime;
    const nav = performance.getEntriesByType('navigation')[0];
    r['html received'] = nav.responseEnd;
    r['DOM content loaded'] = nav.domContentLoadedEventEnd;
    const wasm = performance.getEntriesByType('resource').find((e) => e.name.endsWith('/pkg/testpiece_bg.wasm'));
    if (wasm) { r['wasm request start'] = wasm.startTime; r['wasm received'] = wasm.responseEnd; }
    // each step alone, on this page's main thread
    const t = () => performance.now();
    const bytes = await (await fetch('pkg/testpiece_bg.wasm')).arrayBuffer();
    let a = t();
    const module = await WebAssembly.compile(bytes);
    r['step: compile'] = t() - a;
    const glue = await import(new URL('pkg/testpiece.js', location.href).href);
    a = t();
    await glue.default({ module_or_path: module });
    r['step: instantiate'] = t() - a;
    a = t();
    const started = glue.start();
    r['step: start()'] = t() - a;
    const v = (id) => document.getElementById(id);
    const settings = {
      machine: v('machine').value, mode: v('mode').value, branch: v('branch').value,
      l0: parseFloat(v('l0').value), tool_radius: v('toolRadius').checked,
      exclude_bad_rows: v('exclude').checked, noise_sigma: null, effects: v('effects').value,
      keep_outliers: v('keepOutliers').checked,
    };
    a = t();
    const prepared = new glue.Prepared(settings);
    r['step: new Prepared (defaults)'] = t() - a;
    const ex = started.examples[0];
    const text = new TextEncoder().encode(ex.text);
    a = t();
    const result = glue.analyse(prepared, text, ex.name, settings);
    r['step: analyse (example)'] = t() - a;
    a = t();
    JSON.parse(JSON.stringify(result));
    r['step: result cloned'] = t() - a;
    a = t();
    glue.analyse(prepared, text, ex.name, settings);
    r['step: analyse again (same points)'] = t() - a;
    prepared.free();
    // the worker's chain, ms after the worker was created
    const created = performance.timeOrigin + performance.now();
    const w = new Worker('measure-worker.js', { type: 'module' });
    const times = await new Promise((resolve) => { w.onmessage = (ev) => resolve(ev.data); w.postMessage(settings); });
    w.terminate();
    for (const [k, at] of Object.entries(times)) r[k] = at - created;
    return r;
  });
  rows.push(row);
  await ctx.close(); server.close(); fs.rmSync(dir, { recursive: true, force: true });
}
fs.rmSync(root, { recursive: true, force: true });
const med = (a) => { const s = [...a].sort((x, y) => x - y); return s[Math.floor(s.length / 2)]; };
console.log(`${www}, ${loads} loads (ms; marks after navigation, steps alone): median (every value)`);
for (const k of Object.keys(rows[0])) {
  const vals = rows.map((r) => r[k]).filter((x) => x !== undefined);
  console.log(`  ${k.padEnd(36)} ${med(vals).toFixed(1).padStart(7)}  (${vals.map((x) => x.toFixed(0)).join(', ')})`);
}
