// Access to the WebAssembly core, always in a Web Worker so that heavy work never freezes the
// page and can be cancelled:
// - served over http(s): a module worker (worker.js) that loads pkg/testpiece.js;
// - the single-file build (file://, where module workers and service workers cannot work): a
//   classic worker made from a Blob URL of the inlined glue + worker-inline.js
//   (scripts/build-single.mjs), to which the page posts the inlined wasm bytes; the worker
//   starts the core with initSync.
// The core is two wasm modules (scripts/build-wasm.sh): `call` and `callPrepared` reach the first,
// which the worker starts at once; `tools` reaches the second (the Plan, Program, Error budget
// and Correction views), which the worker loads on the first `tools.load()` (each tools call
// loads it first): a dynamic import when served, the inlined bytes, decoded then, in the single
// file.
// An analysis arrives with its per-point arrays as columns (columns.js), read here into
// `Table`s and Float64Arrays.
// Every call returns a promise. Cancel terminates the worker and starts a fresh one; the calls it
// stops reject with a `Cancelled`, the core's own errors with a `CoreError`.

import { unpackAnalysis } from './columns.js';

/** The outcome of a call stopped by Cancel: not an error of the core. */
export class Cancelled extends Error {
  constructor() { super('The computation was cancelled.'); this.name = 'Cancelled'; }
}

/** An error the core threw (its message), with `badRows` when a file was refused for rows that
 * the setting "Exclude rows the reader rejects" would leave out (their number; else null). */
export class CoreError extends Error {
  constructor(message, badRows) { super(message); this.name = 'CoreError'; this.badRows = badRows ?? null; }
}

let worker = null;
let inlineCore = null; // {workerSource, wasm: Uint8Array, toolsWasm: () => Uint8Array} in the single-file build
let seq = 0;
let toolsLoad = null;   // the load of the second module into the current worker (a promise)
let toolsReady = false; // whether it has finished
const pending = new Map();

function rejectAll(error) {
  for (const p of pending.values()) p.reject(error);
  pending.clear();
}

/** Starts the core once. `inline` = {workerSource, wasm, toolsWasm} for the single-file build. */
export async function startCore(inline) {
  toolsLoad = null;
  toolsReady = false;
  if (inline) {
    inlineCore = inline;
    const url = URL.createObjectURL(new Blob([inline.workerSource], { type: 'text/javascript' }));
    worker = new Worker(url);
    URL.revokeObjectURL(url);
    // Messages are handled in order: the core is started before the first call. The bytes are
    // copied (not transferred) so that a restarted worker can be given them again.
    worker.postMessage({ init: inline.wasm });
  } else {
    worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
  }
  worker.onmessage = (ev) => {
    const { id, ok, result, error, badRows, progress, packed } = ev.data;
    const p = pending.get(id);
    if (!p) return;
    if (progress) { p.onProgress?.(progress); return; }
    pending.delete(id);
    ok ? p.resolve(packed ? unpackAnalysis(result) : result) : p.reject(new CoreError(error, badRows));
  };
  worker.onerror = (ev) => {
    ev.preventDefault?.();
    rejectAll(new CoreError(ev.message || 'the worker stopped'));
  };
  return inline ? 'web worker (single file, Blob URL)' : 'web worker';
}

function post(message, onProgress) {
  const id = ++seq;
  return new Promise((resolve, reject) => {
    pending.set(id, { resolve, reject, onProgress });
    worker.postMessage({ id, ...message, progress: Boolean(onProgress) });
  });
}

/** Calls the core's export `op` with `args`. */
export function call(op, ...args) {
  return post({ op, args });
}

/** Calls the core's export `op` with the prepared settings of `settings` (an analysis settings
 * object: its machine, L0, branch and mode) as first argument, then `args`. The worker holds the
 * core's `Prepared` value and builds another only when those settings change (worker.js). */
export function callPrepared(settings, op, ...args) {
  return post({ op, args, prepare: settings });
}

/** `callPrepared` of an export that reports its stages (the analyses, src/wasm/analysis.rs):
 * `onProgress` is called with each ({stage, step, steps, fraction, text}) as it begins. */
export function callPreparedWithProgress(settings, onProgress, op, ...args) {
  return post({ op, args, prepare: settings }, onProgress);
}

/** The second module: the exports of the Plan, Program, Error budget and Correction views. */
export const tools = {
  /** Whether the current worker has the second module (false again after Cancel). */
  loaded: () => toolsReady,
  /** Loads the second module into the worker, once per worker. */
  load() {
    if (!toolsLoad) {
      const w = worker;
      const message = { load: 'tools' };
      if (inlineCore) message.wasm = inlineCore.toolsWasm();
      const loading = post(message).then(
        () => { if (worker === w) toolsReady = true; },
        (e) => { if (toolsLoad === loading) toolsLoad = null; throw e; });
      toolsLoad = loading;
    }
    return toolsLoad;
  },
  /** Calls the second module's export `op` with `args` (as `call`). */
  async call(op, ...args) {
    await tools.load();
    return post({ op, args, module: 'tools' });
  },
  /** Calls the second module's export `op` with its prepared settings of `settings` (as
   * `callPrepared`). */
  async callPrepared(settings, op, ...args) {
    await tools.load();
    return post({ op, args, prepare: settings, module: 'tools' });
  },
};

/** Stops the running computation (the worker is replaced; pending calls are rejected). */
export function cancel() {
  if (!worker) return false;
  worker.terminate();
  rejectAll(new Cancelled());
  startCore(inlineCore);
  return true;
}
