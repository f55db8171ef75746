// The body of the single-file build's worker (a classic worker from a Blob URL; see core.js and
// scripts/build-single.mjs, which puts the module-free wasm-bindgen glue `__m_pkg_testpiece`
// before this text). Same protocol as worker.js, plus a first message {init: wasm bytes}.
/* global __m_pkg_testpiece */
let startError = null;
self.onmessage = (ev) => {
  const msg = ev.data;
  if (msg && msg.init) {
    try { __m_pkg_testpiece.initSync({ module: msg.init }); } catch (e) { startError = e; }
    return;
  }
  const { id, op, args } = msg;
  try {
    if (startError) throw new Error(`the core could not start: ${startError.message || startError}`);
    const fn = __m_pkg_testpiece.exports[op];
    if (typeof fn !== 'function') throw new Error(`the core has no operation "${op}"`);
    self.postMessage({ id, ok: true, result: fn(...(args || [])) });
  } catch (e) {
    self.postMessage({ id, ok: false, error: e && e.message ? e.message : String(e), badRows: e && e.bad_rows });
  }
};
