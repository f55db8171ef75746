// Times the stages of benches/stages.rs (defined once in src/bench.rs: same calls, same
// inputs) through the release wasm (www/pkg) under Node, and prints the table
// `stage | native median | wasm median | wasm / native`, the native medians read from
// target/bench-native.json (written by `cargo bench --features bench --bench stages`).
// Usage: node scripts/bench-wasm.mjs [FILTER]   (env BENCH_BUDGET_MS: time per stage, 500)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const core = await import(path.join(ROOT, 'www', 'pkg', 'testpiece.js'));
core.initSync({ module: fs.readFileSync(path.join(ROOT, 'www', 'pkg', 'testpiece_bg.wasm')) });
const filter = process.argv[2];
const budget = Number(process.env.BENCH_BUDGET_MS || 500);

function median(f) {
  // a call longer than the budget (a 200,000-point scan) is timed once: its first call
  const first = performance.now();
  f();
  const once = performance.now() - first;
  if (once > budget) return once * 1000;
  const times = [];
  const start = performance.now();
  while ((performance.now() - start < budget || times.length < 5) && times.length < 100000) {
    const t = performance.now();
    f();
    times.push(performance.now() - t);
  }
  times.sort((a, b) => a - b);
  return times[Math.floor(times.length / 2)] * 1000;
}

const STAGES = [
  'bspline_eval_1000', 'builtin_points', 'projection_100', 'envelope_100', 'surface_max_overcut',
  'inverse_kinematics_path', 'figure19_matrix', 'read_cmm_100', 'read_cmm_100000', 'identify_100',
  'identify_100000', 'analyse_100', 'analyse_100_further', 'analyse_100_again',
  'diagnose_100', 'diagnose_100_further', 'diagnose_100_again',
  'diagnose_scan_1000', 'diagnose_scan_20000', 'diagnose_scan_200000', 'diagnose_scan_20000_backlash_c',
];
let native = {};
try {
  native = JSON.parse(fs.readFileSync(path.join(ROOT, 'target', 'bench-native.json'), 'utf8'));
} catch {
  console.error('no target/bench-native.json: run `cargo bench --features bench --bench stages` first for the native column');
}
const fmt = (us) => (us >= 1000 ? `${(us / 1000).toFixed(2)} ms` : `${us.toFixed(1)} µs`);
console.log('| stage | native median | wasm median | wasm / native |');
console.log('|---|---|---|---|');
for (const name of STAGES) {
  if (filter && !name.includes(filter)) continue;
  const stage = new core.BenchStage(name);
  const w = median(() => stage.run());
  stage.free();
  const n = native[name];
  const ratio = n > 0 ? (w / n).toFixed(2) : '—';
  console.log(`| ${name} | ${n > 0 ? fmt(n) : '—'} | ${fmt(w)} | ${ratio} |`);
}
