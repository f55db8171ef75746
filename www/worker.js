// The Web Worker that owns the WebAssembly core, so heavy work never freezes the page.
// Protocol: {id, op, args, prepare?} in; {id, ok: true, result} or {id, ok: false, error, badRows}
// out (`badRows`: the `bad_rows` of an error of `analyse`, src/wasm/analysis.rs).
// `op` names an export of the core (src/wasm/); arguments and results are structured-cloned.
// With `prepare` (analysis settings), the export gets the core's prepared settings for their
// machine, L0, branch and mode as its first argument (src/wasm/prepared.rs): the worker keeps the
// last two it built and builds another only when those settings change.
import init, * as core from './pkg/testpiece.js';

const ready = init();

const kept = [];
function preparedFor(settings) {
  const i = kept.findIndex((p) => p.isFor(settings));
  if (i >= 0) {
    const [p] = kept.splice(i, 1);
    kept.unshift(p);
    return p;
  }
  kept.unshift(new core.Prepared(settings));
  while (kept.length > 2) kept.pop().free();
  return kept[0];
}

self.onmessage = async (ev) => {
  const { id, op, args, prepare } = ev.data;
  try {
    await ready;
    const fn = core[op];
    if (typeof fn !== 'function') throw new Error(`the core has no operation "${op}"`);
    const first = prepare === undefined ? [] : [preparedFor(prepare)];
    const result = fn(...first, ...(args || []));
    self.postMessage({ id, ok: true, result });
  } catch (e) {
    self.postMessage({ id, ok: false, error: e && e.message ? e.message : String(e), badRows: e && e.bad_rows });
  }
};
