// Access to the WebAssembly core: through a module Web Worker when served over http(s), or
// directly on the main thread in the single-file build (file:// allows neither module workers
// nor service workers). Every call returns a promise.

let worker = null;
let direct = null;
let seq = 0;
const pending = new Map();

/** Starts the core once. `inline` = {initSync, module} for the single-file build. */
export async function startCore(inline) {
  if (inline) {
    inline.initSync({ module: inline.module });
    direct = inline.exports;
    return 'main thread';
  }
  worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = (ev) => {
    const { id, ok, result, error } = ev.data;
    const p = pending.get(id);
    if (!p) return;
    pending.delete(id);
    ok ? p.resolve(result) : p.reject(new Error(error));
  };
  worker.onerror = (ev) => {
    for (const p of pending.values()) p.reject(new Error(ev.message || 'the worker stopped'));
    pending.clear();
  };
  return 'web worker';
}

/** Calls the core's export `op` with `args`. */
export function call(op, ...args) {
  if (direct) {
    return new Promise((resolve, reject) => {
      // Let the page paint its progress indication before a synchronous computation.
      setTimeout(() => {
        try { resolve(direct[op](...args)); } catch (e) { reject(e instanceof Error ? e : new Error(String(e))); }
      }, 0);
    });
  }
  const id = ++seq;
  return new Promise((resolve, reject) => {
    pending.set(id, { resolve, reject });
    worker.postMessage({ id, op, args });
  });
}

/** Stops the running computation (the worker is replaced; pending calls are rejected). */
export function cancel() {
  if (!worker) return false;
  worker.terminate();
  for (const p of pending.values()) p.reject(new Error('cancelled'));
  pending.clear();
  startCore();
  return true;
}
