// The Web Worker that owns the WebAssembly core, so heavy work never freezes the page.
// Protocol: {id, op, args} in; {id, ok: true, result} or {id, ok: false, error, badRows} out
// (`badRows`: the `bad_rows` of an error of `analyse`, src/wasm/analysis.rs).
// `op` names an export of the core (src/wasm/); arguments and results are structured-cloned.
import init, * as core from './pkg/testpiece.js';

const ready = init();

self.onmessage = async (ev) => {
  const { id, op, args } = ev.data;
  try {
    await ready;
    const fn = core[op];
    if (typeof fn !== 'function') throw new Error(`the core has no operation "${op}"`);
    const result = fn(...(args || []));
    self.postMessage({ id, ok: true, result });
  } catch (e) {
    self.postMessage({ id, ok: false, error: e && e.message ? e.message : String(e), badRows: e && e.bad_rows });
  }
};
