// The body of the single-file build's worker (a classic worker from a Blob URL; see core.js and
// scripts/build-single.mjs, which puts the module-free wasm-bindgen glue of both modules,
// `__m_pkg_testpiece` and `__m_pkg_testpiece_tools`, before this text). Same protocol as
// worker.js, plus a first message {init: the first module's wasm bytes}; the load message of the
// second module carries its bytes ({id, load: 'tools', wasm}), which the page decodes only then.
// An analysis is packed into columns as in worker.js (`__m_columns`: columns.js, folded before
// this text).
/* global __m_pkg_testpiece, __m_pkg_testpiece_tools, __m_columns */
let startError = null;
let toolsStarted = false;
const kept = new Map(); // the prepared settings per module, as in worker.js
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
self.onmessage = (ev) => {
  const msg = ev.data;
  if (msg && msg.init) {
    try { __m_pkg_testpiece.initSync({ module: msg.init }); } catch (e) { startError = e; }
    return;
  }
  const { id, op, args, prepare, load } = msg;
  try {
    if (startError) throw new Error(`the core could not start: ${startError.message || startError}`);
    if (load === 'tools') {
      if (!toolsStarted) {
        try { __m_pkg_testpiece_tools.initSync({ module: msg.wasm }); } catch (e) { throw new Error(`the tools module could not be loaded: ${e.message || e}`); }
        toolsStarted = true;
      }
      self.postMessage({ id, ok: true, result: null });
      return;
    }
    if (msg.module === 'tools' && !toolsStarted) throw new Error('the tools module is not loaded');
    const m = msg.module === 'tools' ? __m_pkg_testpiece_tools.exports : __m_pkg_testpiece.exports;
    const fn = m[op];
    if (typeof fn !== 'function') throw new Error(`the core has no operation "${op}"`);
    const first = prepare === undefined ? [] : [preparedFor(m, prepare)];
    const last = msg.progress ? [(p) => self.postMessage({ id, progress: p })] : [];
    const result = fn(...first, ...(args || []), ...last);
    if (__m_columns.PACKED_OPS.includes(op) && !msg.module) {
      const transfer = __m_columns.packAnalysis(result);
      self.postMessage({ id, ok: true, result, packed: true }, transfer);
    } else self.postMessage({ id, ok: true, result });
  } catch (e) {
    self.postMessage({ id, ok: false, error: e && e.message ? e.message : String(e), badRows: e && e.bad_rows });
  }
};
