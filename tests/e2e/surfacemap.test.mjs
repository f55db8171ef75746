// Browser end-to-end test of the residual map of each developed surface (issue 31 item 3,
// www/surfacemap.js): a 600-point scan written by `testpiece simulate --scan 5x60` (each surface
// on 5 lines of 60 points) is uploaded; the Identification view draws one map per surface, 5 rows
// of 60 cells each, every cell a point of its own (found by hovering the cells' rows); the hovered
// point's residual is the CLI's for that point (`identify --json`, final answer; to 1e-6 µm: the
// same computation in wasm and native) and the map's pixel there is the colour bar's colour of that
// residual; the axis reversals are the CLI diagnosis's (`diagnose --json`, `where` entries of
// group `reversal`: one line each, at its `s`); a scan line chosen as the where highlight shades
// its 60 cells, on the Sim-to-real gap view's map of the baseline residual too. The built-in
// 100-point example maps as 2 rows of cells per surface.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { openBrowser, readyPage, simulatedScan, testpiece } from './browser.mjs';

let browser, url, context;
before(async () => { browser = await openBrowser('surfacemap'); ({ url, context } = browser); });
after(async () => { await browser?.close(); });

/** In the page: hover each row of the map of `surface` at `n` evenly spaced x positions (synthetic
 * mouse events at the rows' centre lines) and return the ids seen per row, and for the first hit
 * of the middle row its id, residual and the pixel colours of the map and of the colour bar. */
function probe({ surface, n }) {
  const wrap = document.querySelector(`#view-identify .surface-map[data-surface="${surface}"]`);
  const svg = wrap.querySelector('svg');
  const cells = wrap.querySelector('canvas.surface-map-cells');
  const r = svg.getBoundingClientRect(), c = cells.getBoundingClientRect();
  const rows = Number(wrap.dataset.rows);
  const seen = [];
  let known = null;
  for (let k = 0; k < rows; k++) {
    const ids = new Set();
    const y = c.top + ((k + 0.5) / rows) * c.height;
    for (let j = 0; j < n; j++) {
      const x = c.left + ((j + 0.5) / n) * c.width;
      delete wrap.dataset.hover;
      svg.dispatchEvent(new MouseEvent('mousemove', { clientX: x, clientY: y, bubbles: true }));
      if (wrap.dataset.hover === undefined) continue;
      ids.add(wrap.dataset.hover);
      if (!known && k === (rows >> 1) && j === n >> 1) {
        const px = Math.floor(((x - c.left) / c.width) * cells.width), py = Math.floor(((y - c.top) / c.height) * cells.height);
        const colour = [...cells.getContext('2d').getImageData(px, py, 1, 1).data.slice(0, 3)];
        const residual = Number(wrap.dataset.hoverResidual);
        const bar = document.querySelector('#view-identify .colour-bar');
        const R = Number(bar.dataset.rangeUm);
        const ramp = bar.querySelector('canvas');
        const idx = Math.max(0, Math.min(255, Math.round(((residual / R + 1) / 2) * 255)));
        known = { id: wrap.dataset.hover, residual, colour, barColour: [...ramp.getContext('2d').getImageData(idx, 0, 1, 1).data.slice(0, 3)] };
      }
    }
    seen.push([...ids]);
  }
  const reversals = [...wrap.querySelectorAll('g.reversal')].map((g) => Number(g.dataset.s));
  return { points: Number(wrap.dataset.points), rows, seen, known, reversals, marked: wrap.querySelectorAll('g.reversal.marked').length };
}

test('a scan is mapped per surface: cells, colours and reversals', async () => {
  const { file, dir } = simulatedScan('map', '5x60', 3);
  const identified = JSON.parse(testpiece(['identify', file, '--json']));
  const diagnosed = JSON.parse(testpiece(['diagnose', file, '--json']));
  const reversals = diagnosed.where.filter((e) => e.group === 'reversal').map((e) => e.s);
  assert.ok(reversals.length > 0, 'the tool path reverses some axis');

  const { page, errors } = await readyPage(context, url);
  // the built-in example: 100 points, 2 measurement curves a surface, each point a cell
  await page.click('#tab-identify');
  for (const s of ['A', 'B']) {
    const ex = await page.evaluate(probe, { surface: s, n: 400 });
    assert.equal(ex.rows, 2, `example, surface ${s}: the curves Z = 11 and 25 mm`);
    assert.equal(ex.points, 50);
    assert.equal(ex.seen.flat().length, 50, `example, surface ${s}: every point's cell is hovered`);
  }

  await page.setInputFiles('#file', file);
  await page.waitForFunction(() => document.querySelector('#summary')?.textContent.includes('scan_5x60.csv') && !document.body.dataset.busy, null, { timeout: 120000 });
  await page.waitForSelector('#view-identify .surface-map[data-surface="A"][data-points="300"]');
  const drawn = [];
  for (const s of ['A', 'B']) {
    const m = await page.evaluate(probe, { surface: s, n: 1200 });
    assert.equal(m.points, 300, `surface ${s}: 300 points`);
    assert.equal(m.rows, 5, `surface ${s}: 5 scan lines`);
    for (const ids of m.seen) assert.equal(ids.length, 60, `surface ${s}: each row shows its 60 points, each in a cell of its own`);
    assert.equal(new Set(m.seen.flat()).size, 300);
    // the known point: its residual is the CLI's, its colour the colour bar's at that residual
    const want = identified.points.find((p) => p.id === m.known.id);
    assert.ok(want, `point ${m.known.id} in the CLI's identification`);
    assert.ok(Math.abs(m.known.residual - want.residual * 1000) < 1e-6, `point ${m.known.id}: ${m.known.residual} µm vs CLI ${want.residual * 1000} µm`);
    assert.deepEqual(m.known.colour, m.known.barColour, `point ${m.known.id}: the colour bar's colour of ${m.known.residual.toFixed(2)} µm`);
    drawn.push(...m.reversals);
  }
  // every reversal of the diagnosis, once, at its path position
  assert.equal(drawn.length, reversals.length, 'one line per axis reversal');
  const sorted = (v) => [...v].sort((p, q) => p - q);
  sorted(drawn).forEach((s, k) => assert.ok(Math.abs(s - sorted(reversals)[k]) < 1e-6, `reversal at ${s} mm vs ${sorted(reversals)[k]} mm`));
  // the marked ones are drawn bold
  const markedCli = diagnosed.where.filter((e) => e.group === 'reversal' && e.marked).length;
  const markedPage = await page.locator('#view-identify .surface-map g.reversal.marked').count();
  assert.ok(markedPage >= markedCli, `${markedPage} marked lines, the CLI marks ${markedCli}`);
  // the where highlight: choosing a scan line shades its 60 cells
  await page.selectOption('#where-choice-identify', 'curve:A_Z15');
  for (const view of ['identify', 'gap']) {
    assert.equal(await page.getAttribute(`#view-${view} .surface-map[data-surface="A"]`, 'data-shaded'), '60', view);
    assert.equal(await page.getAttribute(`#view-${view} .surface-map[data-surface="B"]`, 'data-shaded'), '0', view);
  }
  // the Sim-to-real gap view maps the baseline's residual at the same points
  assert.equal(await page.locator('#view-gap .surface-map[data-points="300"]').count(), 2);
  assert.deepEqual(errors, []);
  await page.close();
  fs.rmSync(dir, { recursive: true, force: true });
});
