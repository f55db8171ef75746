// Browser end-to-end test of the gap diagnosis's "where" drawn on the plots and the plan view
// (issue 7): the backlash example (the page's first built-in example, example_backlash_c) is
// analysed by the wasm core; the shaded bands of the per-point plots and the ringed points of the
// plan view must be exactly the points of the group the core reports (`where[].ids`, taken from
// the page's own JSON export of the wasm analysis), the reversal marks exactly its `nearest`
// points; the choice is made with the keyboard, and the figures export as SVG and PNG.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { openBrowser, ROOT } from './browser.mjs';

const SHOTS = path.join(ROOT, 'tests', 'e2e', 'screenshots');
let browser, url, context;

before(async () => {
  browser = await openBrowser('where');
  ({ url, context } = browser);
  fs.mkdirSync(SHOTS, { recursive: true });
});

after(async () => {
  await browser?.close();
});

const sorted = (a) => [...a].map(Number).sort((p, q) => p - q);

async function download(page, selector) {
  const [d] = await Promise.all([page.waitForEvent('download'), page.click(selector)]);
  return fs.readFileSync(await d.path());
}

/** Ids drawn as highlights in a per-point chart and in a plan view, and the reversal marks. */
async function drawn(page, chart, plan) {
  return page.evaluate(([c, p]) => {
    const q = (s) => [...document.querySelectorAll(s)];
    return {
      bands: q(`[data-chart="${c}"] rect.highlight`).flatMap((r) => r.dataset.ids.split(' ')),
      rings: q(`[data-chart="${p}"] circle.highlight`).map((r) => r.dataset.id),
      chartMarks: q(`[data-chart="${c}"] g.marker`).map((g) => g.dataset.id),
      planMarks: q(`[data-chart="${p}"] g.marker`).map((g) => g.dataset.id),
    };
  }, [chart, plan]);
}

test('the where report is drawn at the points the core reports, chosen by keyboard, exported', async () => {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60000 });
  await page.waitForSelector('[data-chart="gap-where-plan"] svg', { state: 'attached', timeout: 60000 });
  assert.equal(await page.inputValue('#example'), 'example_backlash_c.csv');
  // The wasm core's analysis, as the page exports it.
  await page.click('#tab-report');
  const exported = JSON.parse(String(await download(page, '#export-json')));
  assert.equal(exported.analysis.diagnosis.status, 'made');
  const d = exported.analysis.diagnosis.report;
  const entries = d.where;
  const concentrated = d.structure.concentrated_in;
  console.log(`core: concentrated_in ${concentrated}; structured ${d.structure.structured} (structure RMS ${(d.structure.structure_rms * 1000).toFixed(2)} µm, σ ${(d.structure.noise.used * 1000).toFixed(2)} µm); ` +
    `reversals ${entries.filter((e) => e.group === 'reversal').map((e) => `${e.axis} at ${e.s.toFixed(1)} mm -> point ${e.nearest}`).join(', ')}`);
  const reversals = entries.filter((e) => e.group === 'reversal');
  assert.ok(reversals.length > 0, 'the backlash example\'s tool path has axis reversals');
  // The core's flags follow its rule (src/gap/location.rs): a reversal is of the verdict when a
  // named backlash is of its axis, marked when of the verdict or concentrated (> 1.5× share).
  for (const e of reversals) {
    assert.equal(e.of_verdict, d.verdict.effect === `backlash_${e.axis.toLowerCase()}`, `${e.name}: of_verdict`);
    assert.equal(e.concentrated, e.concentration > 1.5, `${e.name}: concentrated`);
    assert.equal(e.marked, e.of_verdict || e.concentrated, `${e.name}: marked`);
  }
  // The page marks the core's marked reversals and the chosen one (where.js whereOf).
  const marked = (chosen) => [...new Set(sorted(reversals.filter((e) => e === chosen || e.marked).map((e) => e.nearest)))];
  console.log(`verdict ${d.verdict.effect}: marked reversals at points ${marked(null).join(' ')}`);
  assert.ok(marked(null).length > 0);
  const auto = d.structure.concentrated_entry === null ? null : entries[d.structure.concentrated_entry];
  assert.equal(auto ? auto.name : null, concentrated ?? null);

  await page.click('#tab-gap');
  // Default: where the residual is concentrated, on both figures of both views.
  for (const [c, p] of [['gap-where-residual', 'gap-where-plan'], ['measured-simulated-residual', 'plan-view']]) {
    const got = await drawn(page, c, p);
    const want = auto ? sorted(auto.ids) : [];
    assert.deepEqual(sorted(got.bands), want, `${c}: shaded points = the core's ${concentrated} ids`);
    assert.deepEqual(sorted(got.rings), want, `${p}: ringed points = the core's ${concentrated} ids`);
    assert.deepEqual(sorted(got.chartMarks), marked(null), `${c}: reversal marks`);
    assert.deepEqual(sorted(got.planMarks), marked(null), `${p}: reversal marks`);
  }
  await page.screenshot({ path: path.join(SHOTS, 'where-gap-default.png'), fullPage: true });
  await page.locator('[data-chart="gap-where-residual"]').screenshot({ path: path.join(SHOTS, 'where-residual.png') });
  await page.locator('[data-chart="gap-where-plan"]').screenshot({ path: path.join(SHOTS, 'where-plan.png') });

  // Keyboard: choose the first reversal's window with the arrow keys; both views follow.
  const key = `reversal:${reversals[0].name}`;
  const options = await page.locator('#where-choice-gap option').evaluateAll((os) => os.map((o) => o.value));
  await page.focus('#where-choice-gap');
  const steps = options.indexOf(key) - options.indexOf(await page.inputValue('#where-choice-gap'));
  for (let i = 0; i < Math.abs(steps); i++) await page.keyboard.press(steps > 0 ? 'ArrowDown' : 'ArrowUp');
  assert.equal(await page.inputValue('#where-choice-gap'), key);
  for (const [c, p] of [['gap-where-residual', 'gap-where-plan'], ['measured-simulated-residual', 'plan-view']]) {
    const got = await drawn(page, c, p);
    assert.deepEqual(sorted(got.bands), sorted(reversals[0].ids), `${c}: shaded = the ${reversals[0].name} window`);
    assert.deepEqual(sorted(got.rings), sorted(reversals[0].ids), `${p}: ringed = the ${reversals[0].name} window`);
    assert.deepEqual(sorted(got.planMarks), marked(reversals[0]), `${p}: the chosen reversal is marked too`);
  }
  assert.equal(await page.inputValue('#where-choice-identify'), key, 'the identification view\'s control follows');
  assert.match(await page.textContent('#where-legend-gap'), /axis reversal .* µm/);
  await page.locator('[data-chart="gap-where-plan"]').screenshot({ path: path.join(SHOTS, 'where-plan-reversal.png') });
  // Every highlight and mark is reachable with Tab and named.
  const focusables = await page.evaluate(() => [...document.querySelectorAll('[data-chart="gap-where-plan"] [tabindex="0"]')]
    .map((e) => { e.focus(); return { focused: document.activeElement === e, name: e.getAttribute('aria-label') }; }));
  assert.ok(focusables.length >= reversals[0].ids.length + marked(reversals[0]).length);
  assert.ok(focusables.every((f) => f.focused && /point|reversal/.test(f.name)), 'focusable and named');
  await page.keyboard.press('Shift+Tab');
  await page.keyboard.press('Tab');
  assert.match(await page.evaluate(() => document.activeElement.getAttribute('aria-label') || ''), /reversal|point/);

  // Export: the highlight and the legend in words travel with the SVG; the PNG is an image.
  const svg = String(await download(page, '[data-chart="gap-where-plan"] button[data-export="gap-where-plan.svg"]'));
  assert.match(svg, /class="highlight"/);
  assert.match(svg, /Baseline residual of the diagnosis: .*µm/);
  const res = String(await download(page, '[data-chart="gap-where-residual"] button[data-export="gap-where-residual.svg"]'));
  assert.equal((res.match(/class="highlight"/g) || []).length > 0, true);
  const png = await download(page, '[data-chart="gap-where-plan"] button[data-export="gap-where-plan.png"]');
  assert.deepEqual([...png.subarray(1, 4)].map((b) => String.fromCharCode(b)).join(''), 'PNG');
  console.log(`exports: plan SVG ${svg.length} chars, residual SVG ${res.length} chars, plan PNG ${png.length} bytes`);
  assert.deepEqual(errors, []);
  await page.close();
});
