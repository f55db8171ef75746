// What an analysis costs the worker before it can be posted to the page (issue 31 item 3): the
// page's export `analyse` of this checkout's module (www/pkg: the per-point arrays written as
// columns by the core, src/wasm/columns.rs) plus the worker's `packAnalysis` (www/columns.js:
// here only collecting the buffers to transfer), against the same of another module given as
// OTHER_PKG (e.g. /work/main/www/pkg before the core wrote columns: its JSON of every point
// parsed by the browser's JSON.parse, then packed in JavaScript). Three rounds, alternated, under
// Node (V8, as the worker); then whether the two give the same JSON text once read back as the
// page reads them (www/columns.js unpackAnalysis, toJsonText).
// Usage: node scripts/columns-cost.mjs FILE OTHER_PKG  (needs both www/pkg built)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const [file, other] = process.argv.slice(2);
if (!file || !other) { console.error('usage: node scripts/columns-cost.mjs FILE OTHER_PKG'); process.exit(2); }
async function load(dir) {
  const m = await import(path.resolve(dir, 'testpiece.js'));
  m.initSync({ module: fs.readFileSync(path.resolve(dir, 'testpiece_bg.wasm')) });
  return { m, prepared: new m.Prepared({}) };
}
const C = await import(path.join(here, '..', 'www', 'columns.js'));
const mine = await load(path.join(here, '..', 'www', 'pkg')), theirs = await load(other);
const bytes = fs.readFileSync(file), name = path.basename(file);
/** ms of `analyse`, ms of `packAnalysis`, and the analysis as the page reads it. */
function run({ m, prepared }) {
  const t0 = performance.now();
  const a = m.analyse(prepared, bytes, name, {}, undefined);
  const t1 = performance.now();
  const transfer = C.packAnalysis(a);
  const t2 = performance.now();
  return { analyse: Math.round(t1 - t0), pack: Math.round(t2 - t1), page: C.unpackAnalysis(structuredClone(a, { transfer })) };
}
let texts = null;
for (let round = 1; round <= 3; round++) {
  const o = run(theirs), n = run(mine);
  console.log(`round ${round}: other ${o.analyse} + ${o.pack} = ${o.analyse + o.pack} ms; this ${n.analyse} + ${n.pack} = ${n.analyse + n.pack} ms`);
  texts ??= [C.toJsonText(o.page, 1), C.toJsonText(n.page, 1)];
}
console.log(`the same JSON text: ${texts[0] === texts[1]} (${texts[1].length} characters)`);
