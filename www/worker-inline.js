// The body of the single-file build's worker (a classic worker from a Blob URL; see core.js and
// scripts/build-single.mjs, which puts the module-free wasm-bindgen glue `__m_pkg_testpiece`
// before this text). Same protocol as worker.js, plus a first message {init: wasm bytes}.
/* global __m_pkg_testpiece */
let startError = null;
const kept = []; // the prepared settings, as in worker.js
function preparedFor(settings) {
  const i = kept.findIndex((p) => p.isFor(settings));
  if (i >= 0) {
    const [p] = kept.splice(i, 1);
    kept.unshift(p);
    return p;
  }
  kept.unshift(new __m_pkg_testpiece.exports.Prepared(settings));
  while (kept.length > 2) kept.pop().free();
  return kept[0];
}
self.onmessage = (ev) => {
  const msg = ev.data;
  if (msg && msg.init) {
    try { __m_pkg_testpiece.initSync({ module: msg.init }); } catch (e) { startError = e; }
    return;
  }
  const { id, op, args, prepare } = msg;
  try {
    if (startError) throw new Error(`the core could not start: ${startError.message || startError}`);
    const fn = __m_pkg_testpiece.exports[op];
    if (typeof fn !== 'function') throw new Error(`the core has no operation "${op}"`);
    const first = prepare === undefined ? [] : [preparedFor(prepare)];
    self.postMessage({ id, ok: true, result: fn(...first, ...(args || [])) });
  } catch (e) {
    self.postMessage({ id, ok: false, error: e && e.message ? e.message : String(e), badRows: e && e.bad_rows });
  }
};
