// Times the same stages as benches/stages.rs through the release wasm (www/pkg) under Node.
// Prints `stage<TAB>median_us`. Usage: node scripts/bench-wasm.mjs [FILTER]
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const core = await import(path.join(ROOT, 'www', 'pkg', 'testpiece.js'));
core.initSync({ module: fs.readFileSync(path.join(ROOT, 'www', 'pkg', 'testpiece_bg.wasm')) });
const filter = process.argv[2];

function median(f, budgetMs = 500) {
  f();
  const times = [];
  const start = performance.now();
  while ((performance.now() - start < budgetMs || times.length < 5) && times.length < 100000) {
    const t = performance.now();
    f();
    times.push(performance.now() - t);
  }
  times.sort((a, b) => a - b);
  return times[Math.floor(times.length / 2)] * 1000;
}

function cmmText(rows) {
  const pts = core.builtinPoints();
  let s = 'id,curve,x,y,z,nx,ny,nz,deviation\n';
  for (let i = 0; i < rows; i++) {
    const p = pts[i % pts.length];
    s += `${i + 1},${p.curve},${p.x},${p.y},${p.z},${p.nx},${p.ny},${p.nz},${0.001 * ((i % 17) - 8)}\n`;
  }
  return new TextEncoder().encode(s);
}

const stages = {
  builtin_points: () => median(() => core.builtinPoints()),
  envelope_100: () => median(() => core.envelopeDeviation(0)),
  figure19_matrix: () => median(() => core.sensitivity('physical', 'signed')),
  read_cmm_100: () => { const b = cmmText(100); return median(() => core.readCmm(b, 'bench.csv', undefined)); },
  read_cmm_100000: () => { const b = cmmText(100000); return median(() => core.readCmm(b, 'bench.csv', undefined)); },
  analyse_100: () => { const b = cmmText(100); return median(() => core.analyse(b, 'bench.csv', undefined)); },
};
for (const [name, f] of Object.entries(stages)) {
  if (filter && !name.includes(filter)) continue;
  console.log(`${name}\t${f().toFixed(3)}`);
}
