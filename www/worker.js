// The Web Worker that owns the WebAssembly core, so heavy work never freezes the page.
// The core is two modules (scripts/build-wasm.sh): the first (pkg/testpiece.js) is started with
// the worker; the second (pkg/testpiece_tools.js: the Plan, Program, Error budget and Correction
// views) is imported the first time a message names it, never before.
// Protocol: {id, op, args, prepare?, module?, progress?} in; {id, ok: true, result} or {id, ok: false, error,
// badRows} out, and before them, with `progress: true`, {id, progress: {stage, step, steps,
// fraction, text}} for each stage the export reports through the function it is given last (`badRows`: the `bad_rows` of an error of `analyse`, src/wasm/analysis.rs).
// `op` names an export of the module `module` ('tools' for the second, else the first, src/wasm/);
// {id, load: 'tools'} loads the second module and answers with no result. Arguments and results
// are structured-cloned, but for an analysis (`PACKED_OPS`, columns.js): its per-point arrays
// travel as typed-array columns, transferred, and the answer says `packed: true`.
// With `prepare` (analysis settings), the export gets the module's prepared settings for their
// machine, L0, branch and mode as its first argument (src/wasm/prepared.rs): the worker keeps the
// last two it built per module (a wasm object lives in its own module's memory) and builds
// another only when those settings change.
import init, * as core from './pkg/testpiece.js';
import { packAnalysis, PACKED_OPS } from './columns.js';

const started = init().then(() => core);
let tools = null; // the second module's exports once imported and started
function module(name) {
  if (name !== 'tools') return started;
  if (!tools) {
    tools = import('./pkg/testpiece_tools.js')
      .then(async (m) => { await m.default(); return m; })
      .catch((e) => { tools = null; throw new Error(`the tools module could not be loaded: ${e && e.message ? e.message : e}`); });
  }
  return tools;
}

const kept = new Map(); // module exports -> its prepared settings, newest first
function preparedFor(m, settings) {
  if (!kept.has(m)) kept.set(m, []);
  const list = kept.get(m);
  const i = list.findIndex((p) => p.isFor(settings));
  if (i >= 0) {
    const [p] = list.splice(i, 1);
    list.unshift(p);
    return p;
  }
  list.unshift(new m.Prepared(settings));
  while (list.length > 2) list.pop().free();
  return list[0];
}

self.onmessage = async (ev) => {
  const { id, op, args, prepare, load } = ev.data;
  try {
    const m = await module(load ?? ev.data.module);
    if (load !== undefined) { self.postMessage({ id, ok: true, result: null }); return; }
    const fn = m[op];
    if (typeof fn !== 'function') throw new Error(`the core has no operation "${op}"`);
    const first = prepare === undefined ? [] : [preparedFor(m, prepare)];
    const last = ev.data.progress ? [(p) => self.postMessage({ id, progress: p })] : [];
    const result = fn(...first, ...(args || []), ...last);
    if (PACKED_OPS.includes(op) && !ev.data.module) {
      const transfer = packAnalysis(result);
      self.postMessage({ id, ok: true, result, packed: true }, transfer);
    } else self.postMessage({ id, ok: true, result });
  } catch (e) {
    self.postMessage({ id, ok: false, error: e && e.message ? e.message : String(e), badRows: e && e.bad_rows });
  }
};
