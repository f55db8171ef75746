// The page: settings and files in, the core's results out. All computation is in the core
// (WebAssembly, in a Web Worker: a module worker when served, a Blob-URL one in the single-file
// build), one call per user action (src/wasm/mod.rs lists them); each view draws in its own file.
// The core is two wasm modules: the first view (the analysis of a part) calls the first; the
// Plan, Program, Error budget and Correction views call the second, loaded when one of them first
// needs it (`toolsCtx`).
import { startCore, call, callPrepared, callPreparedWithProgress, cancel, Cancelled, tools } from './core.js';
import { BUILD } from './pkg/build.js';
import { download, sha256Hex } from './export.js';
import { h, core, machineName, fittedWith, nextLater } from './ui.js';
import { toJsonText } from './columns.js';
import { dataView } from './data.js';
import { sensitivityView } from './fig19.js';
import { identifyView } from './identify.js';
import { gapView } from './gap.js';
import { partsView } from './parts.js';
import { reportView } from './report.js';
import { setupBudget } from './budget.js';
import { setupPlan } from './plan.js';
import { setupProgram } from './program.js';
import { setupCompensation } from './compensation.js';

const $ = (id) => document.getElementById(id);
const mark = (name) => { try { performance.mark(name); } catch { /* no User Timing */ } };
mark('tp-app-start');
// Start the core (worker + streaming wasm compile) before anything else: the modules below only
// build the DOM and wait for it.
const coreStarted = startCore(globalThis.__TESTPIECE_INLINE__);

const st = {
  files: [],          // {name, bytes, analysis?, error?, sha256?}
  current: 0,
  settings: {},
  sensitivity: null,
  fig19Visible: null,
  pool: { names: new Set(), result: null, error: null },
  curves: { cone: { kind: 'M3_15', offsets: false, data: null, error: null }, path: { surface: 'A', comp: 'k_n', data: null, error: null } },
  loadCurves: () => loadCurves().then(() => renderFig19($('view-fig19'))),
  loadCone: () => loadCone(),
  renderCurves: () => renderFig19($('view-fig19')),
  comparison: { a: null, b: null, result: null, error: null },
  select(i) { st.current = i; render(); },
  runPool: () => runPool().then(render),
  runRepeats: () => runRepeats().then(render),
  runCompare: (a, b) => runCompare(a, b).then(render),
  clearFiles() { st.files = []; st.current = 0; st.pool = { names: new Set(), result: null, error: null }; st.comparison = { a: null, b: null, result: null, error: null }; render(); },
  excludeAndRetry() { $('exclude').checked = true; readSettings(); analyseAll(); },
  exportJson() {
    const f = st.files[st.current];
    if (!f || !f.analysis) return;
    download(`${f.name.replace(/\.[^.]*$/, '')}.testpiece.json`, toJsonText({ file: f.name, sha256: f.sha256, analysis: f.analysis }, 1), 'application/json');
  },
};

function readSettings() {
  const sigmaUm = parseFloat($('sigma').value);
  st.settings = {
    machine: $('machine').value,
    mode: $('mode').value,
    branch: $('branch').value,
    l0: parseFloat($('l0').value),
    tool_radius: $('toolRadius').checked,
    exclude_bad_rows: $('exclude').checked,
    noise_sigma: Number.isFinite(sigmaUm) && sigmaUm > 0 ? sigmaUm / 1000 : null,
    effects: $('effects').value,
    keep_outliers: $('keepOutliers').checked,
  };
  const feed = parseFloat($('feed').value);
  if (Number.isFinite(feed) && feed > 0) st.settings.feed = feed;
  const a = parseFloat($('mpeA').value), k = parseFloat($('mpeK').value);
  if (Number.isFinite(a) && a > 0 && Number.isFinite(k) && k > 0) st.settings.noise_mpe = { a_um: a, k_mm: k };
  st.setupPerPart = $('setupPerPart').checked;
}

// ---------------------------------------------------------------- progress
let busy = 0;
let busyTimer = null;
let generation = 0; // bumped by Cancel: loops over files stop at the next file
async function withProgress(text, fn) {
  busy++;
  const before = $('progress-text').textContent;
  $('progress-text').textContent = text;
  $('progress-bar').hidden = true; // shown by the stages of a computation that reports them
  document.body.dataset.busy = 'true';
  // Show the indication for anything that takes longer than 200 ms.
  if (!busyTimer) busyTimer = setTimeout(() => { $('progress').hidden = false; document.body.dataset.progressShown = 'true'; }, 200);
  try { return await fn(); } finally {
    if (--busy === 0) { clearTimeout(busyTimer); busyTimer = null; $('progress').hidden = true; $('progress-bar').hidden = true; delete document.body.dataset.busy; }
    else $('progress-text').textContent = before; // an enclosing computation goes on
  }
}

/** Runs `fn` (a call of the second module) once the worker has the second module, loading it
 * first with its own progress line; `body[data-tools]` says `loaded` after. */
async function withTools(fn) {
  if (!tools.loaded()) {
    await withProgress('Loading the core of the Plan, Program, Error budget and Correction views…', () => tools.load());
    document.body.dataset.tools = 'loaded';
  }
  return fn();
}
/** The core calls of the views that use the second module. */
const toolsCtx = {
  call: (op, ...args) => withTools(() => tools.call(op, ...args)),
  callPrepared: (settings, op, ...args) => withTools(() => tools.callPrepared(settings, op, ...args)),
};

// ---------------------------------------------------------------- computing
const CANCELLED = 'The computation was cancelled: change a setting or choose the file again to compute it.';

/** One file (or the mean of its repeats) through the core: the analysis with the machine's
 * location errors and the verdict line, in one call. */
async function analyseFile(f) {
  f.error = null;
  f.badRows = null;
  // the core's stages (src/analysis/progress.rs) on the progress line and bar
  const stage = (p) => {
    $('progress-text').textContent = `Analysing ${f.name}: ${p.text}…`;
    const bar = $('progress-bar');
    bar.hidden = false;
    bar.value = p.fraction;
    bar.dataset.stage = p.stage;
  };
  try {
    f.analysis = f.repeats
      // the mean of repeat measurements: σ comes from their differences, not from the settings
      ? await withProgress(`Analysing ${f.name}…`, () => callPreparedWithProgress(st.settings, stage, 'analyseRepeats', f.repeats,
        { ...st.settings, noise_sigma: null, noise_mpe: undefined }))
      : await withProgress(`Analysing ${f.name}…`, () => callPreparedWithProgress(st.settings, stage, 'analyse', f.bytes, f.name, st.settings));
  } catch (e) {
    f.analysis = null;
    f.error = e instanceof Cancelled ? CANCELLED : e.message;
    f.badRows = e.badRows ?? null;
  }
  if (!f.sha256) f.sha256 = await sha256Hex(f.bytes);
}

async function analyseList(list) {
  const g = generation;
  for (const f of list) {
    if (g !== generation) { f.analysis = null; f.error = CANCELLED; continue; }
    await analyseFile(f);
  }
  await severalParts();
}

async function analyseAll() {
  await analyseList(st.files);
  await showResults();
}

// ---------------------------------------------------------------- several parts
async function runPool() {
  const files = st.files.filter((f) => f.analysis && !f.repeats && st.pool.names.has(f.name));
  st.pool.result = null; st.pool.error = null;
  if (files.length < 2) { st.pool.error = 'Check at least two analysed parts to pool.'; return; }
  try {
    st.pool.result = await withProgress(`Pooling ${files.length} parts…`, () => callPrepared(st.settings, 'analysePooled',
      files.map((f) => ({ name: f.name, bytes: f.bytes })), { ...st.settings, setup_per_part: st.setupPerPart }));
  } catch (e) { st.pool.error = e.message; }
}

/** The checked parts as repeat measurements of one part: a new entry, the analysis of their mean. */
async function runRepeats() {
  const files = st.files.filter((f) => f.analysis && !f.repeats && st.pool.names.has(f.name));
  st.pool.repeatError = null;
  if (files.length < 2) { st.pool.repeatError = 'Check at least two measurements of the same part.'; return; }
  const entry = {
    name: `mean of ${files.length} repeats (${files.map((f) => f.name).join(' + ')})`,
    bytes: files[0].bytes,
    repeats: files.map((f) => ({ name: f.name, bytes: f.bytes })),
  };
  await analyseFile(entry);
  if (entry.error) { st.pool.repeatError = entry.error; return; }
  st.files = st.files.filter((f) => f.name !== entry.name).concat([entry]);
  st.current = st.files.length - 1;
}

const paramList = (f) => Object.entries(f.analysis.identification.parameters).map(([name, p]) => ({ name, value: p.value, std: p.std ?? null, unit: p.unit }));

async function runCompare(a, b) {
  const fa = st.files.find((f) => f.name === a && f.analysis), fb = st.files.find((f) => f.name === b && f.analysis);
  st.comparison = { a, b, result: null, error: null };
  if (!fa || !fb) { st.comparison.error = 'Choose two analysed parts.'; return; }
  try { st.comparison.result = await call('compareParameters', fa.name, paramList(fa), fb.name, paramList(fb)); } catch (e) { st.comparison.error = e.message; }
}

/** With two or more analysed parts: pool them all and compare the first two (or the chosen pair). */
async function severalParts() {
  const ok = st.files.filter((f) => f.analysis && !f.repeats);
  if (ok.length < 2) { st.pool.result = null; st.comparison.result = null; return; }
  for (const f of ok) if (!st.pool.known?.has(f.name)) st.pool.names.add(f.name);
  st.pool.known = new Set(ok.map((f) => f.name));
  await runPool();
  const names = ok.map((f) => f.name);
  const a = names.includes(st.comparison.a) ? st.comparison.a : names[0];
  const b = names.includes(st.comparison.b) && st.comparison.b !== a ? st.comparison.b : names.find((n) => n !== a);
  await runCompare(a, b);
}

/** The curves of the settings: Figure 19 and the path coefficients of the chosen surface. */
async function loadCurves() {
  const path = st.curves.path;
  try {
    const r = await withProgress('Computing the sensitivity curves…', () => callPrepared(st.settings, 'curvesFor', path.surface, 200));
    st.sensitivity = r.sensitivity;
    path.data = r.path;
    path.error = null;
  } catch (e) {
    st.sensitivity = { error: e.message };
    path.data = null;
    path.error = e.message;
  }
}

/** The cone curves (after the first plot and the example: not urgent). */
async function loadCone() {
  const c = st.curves.cone;
  renderFig19($('view-fig19'));
  try { c.data = await withProgress('Computing the cone curves…', () => call('coneCoefficients', c.kind, c.offsets, 360)); c.error = null; } catch (e) { c.error = e.message; }
  renderFig19($('view-fig19'));
}

async function addFiles(list) {
  const added = [];
  for (const file of list) {
    const bytes = new Uint8Array(await file.arrayBuffer());
    added.push({ name: file.name, bytes });
  }
  if (!added.length) return;
  // A newly chosen set of files replaces the example part.
  st.files = st.files.filter((f) => !f.example).concat(added);
  st.current = st.files.length - added.length;
  render();
  await analyseList(added);
  await showResults(() => mark('tp-verdict-painted'));
}

async function loadExample(name) {
  const e = core.examples.find((x) => x.name === name);
  st.files = [{ name, bytes: new TextEncoder().encode(e.text), example: true }];
  st.current = 0;
  await analyseList(st.files);
  mark('tp-example-computed'); // the analysis back from the worker
  await showResults(() => mark('tp-verdict-painted'));
}

// ---------------------------------------------------------------- rendering
function summaryText() {
  const f = st.files[st.current];
  const box = $('summary');
  box.textContent = '';
  if (!f) { box.textContent = 'Load a measured part.'; return; }
  if (f.error) {
    box.append(h('div', { class: 'verdict' }, `${f.name} could not be analysed.`), h('div', {}, f.error.split('\n')[0]));
    return;
  }
  const a = f.analysis;
  if (!a) { box.textContent = 'Computing…'; return; }
  const id = a.identification;
  const weak = id.groups.map((g) => g.parameters.join('/')).join('; ');
  const strong = Object.entries(id.parameters).filter(([, p]) => p.nonzero)
    .map(([n, p]) => `${n} = ${p.unit === 'rad' ? p.value.toExponential(2) : p.value.toFixed(4)} ${p.unit}`);
  box.append(
    h('div', { class: 'verdict', id: 'verdict-line' }, a.verdict_line),
    h('div', {}, `${f.name}: identification of ${Object.keys(id.parameters).length} parameters from ${id.points_used} points, ${fittedWith(a)}.`),
    h('div', {}, `Clearly non-zero (|value| ≥ ${core.thresholds.nonzero_t} std): ${strong.length ? strong.join(', ') : 'none'}.`),
    h('div', {}, `Residual after the fit: RMS ${(id.residual.rms * 1000).toFixed(2)} µm, max ${(id.residual.max_abs * 1000).toFixed(2)} µm.`),
    h('div', {}, weak ? `Not separable or weakly determined by this part: ${weak}.` : 'Every parameter is separately determined by this part.'),
  );
  if (a.outliers && a.outliers.summary) box.append(h('div', { id: 'outlier-line', class: 'warn' }, a.outliers.summary));
  if (a.noise && a.noise.summary) box.append(h('div', { id: 'noise-line' }, a.noise.summary));
}

/** The views, one per tab (index.html: tab-<id> / view-<id>); add a view by adding a line. */
const VIEWS = [
  { id: 'data', render: (root) => dataView(root, st) },
  { id: 'fig19', render: renderFig19 },
  { id: 'identify', render: (root) => identifyView(root, current()) },
  { id: 'gap', render: (root) => gapView(root, current()) },
  { id: 'parts', render: (root) => partsView(root, st) },
  { id: 'report', render: (root) => reportView(root, st) },
];
const current = () => st.files[st.current] && st.files[st.current].analysis;

function renderFig19(root) { sensitivityView(root, st); }

/** The verdict first: the summary is written and painted before the views are drawn (drawing
 * them all takes 100-150 ms on the example, issue 33 item 2); `painted` is called once the frame
 * with the summary has been painted; `body[data-busy]` from the summary to the last view. */
function showResults(painted) {
  return withProgress('Drawing the results…', async () => {
    summaryText();
    await new Promise((resolve) => requestAnimationFrame(() => setTimeout(resolve, 0)));
    painted?.();
    await render();
  });
}

/** Lets the page's thread take other work (input, painting) before the next piece. */
const nextTask = () => (globalThis.scheduler?.yield ? scheduler.yield() : new Promise((resolve) => setTimeout(resolve, 0)));
let drawing = 0; // bumped by each render: an older one stops before its next piece

/** The summary, then each view in a task of its own, and each part a view left for later
 * (ui.js `later`: a scan's charts, plan view and maps) in one of its own, so that no task of the
 * page's thread draws more than one of them (issue 31 item 3: a 200,000-point scan's views took
 * one task of 4 s); `body[data-busy]` until the last is drawn. */
function render() {
  const g = ++drawing;
  summaryText();
  return withProgress('Drawing the results…', async () => {
    for (const v of VIEWS) {
      const root = $(`view-${v.id}`);
      if (root) v.render(root);
      for (let part = nextLater(); part; part = nextLater()) {
        await nextTask();
        if (g !== drawing) return; // the newer render draws what is left (ui.js later)
        part();
      }
      await nextTask();
      if (g !== drawing) return;
    }
    mark('tp-views-drawn');
    document.body.dataset.ready = 'true';
  });
}

// ---------------------------------------------------------------- tabs (arrow keys move between them)
function setupTabs() {
  const tabs = [...document.querySelectorAll('[role=tab]')];
  const show = (t) => {
    for (const o of tabs) {
      const on = o === t;
      o.setAttribute('aria-selected', String(on));
      o.tabIndex = on ? 0 : -1;
      $(o.getAttribute('aria-controls')).hidden = !on;
    }
  };
  tabs.forEach((t, i) => {
    t.tabIndex = i === 0 ? 0 : -1;
    t.addEventListener('click', () => show(t));
    t.addEventListener('keydown', (e) => {
      const d = e.key === 'ArrowRight' ? 1 : e.key === 'ArrowLeft' ? -1 : 0;
      if (!d) return;
      const n = tabs[(i + d + tabs.length) % tabs.length];
      show(n); n.focus(); e.preventDefault();
    });
  });
}

function setupInputs() {
  $('file').addEventListener('change', (e) => addFiles([...e.target.files]));
  const drop = $('drop');
  drop.addEventListener('dragover', (e) => { e.preventDefault(); drop.classList.add('over'); });
  drop.addEventListener('dragleave', () => drop.classList.remove('over'));
  drop.addEventListener('drop', (e) => { e.preventDefault(); drop.classList.remove('over'); addFiles([...e.dataTransfer.files]); });
  drop.addEventListener('keydown', (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); $('file').click(); } });
  $('example').addEventListener('change', () => loadExample($('example').value));
  for (const id of ['machine', 'mode', 'branch', 'l0', 'feed', 'toolRadius', 'effects', 'exclude', 'sigma', 'mpeA', 'mpeK', 'keepOutliers', 'setupPerPart']) {
    $(id).addEventListener('change', async () => {
      readSettings();
      if (id === 'setupPerPart') { await runPool(); render(); return; }
      // One progress span for the whole computation (the curves, then each file), so that an
      // action over 200 ms shows the indication even when each of its calls is shorter.
      await withProgress('Applying the settings…', async () => {
        if (id === 'mode' || id === 'branch' || id === 'machine' || id === 'l0') await loadCurves();
        await analyseList(st.files);
      });
      render();
    });
  }
  $('cancel').addEventListener('click', () => {
    generation++;
    cancel();
    delete document.body.dataset.tools; // the new worker loads the second module again when asked
    $('summary').dataset.cancelled = 'true';
  });
}

/** Whether this browser's WebAssembly has 128-bit SIMD, which the core's dense-scan kernels are
 * compiled for (scripts/build-wasm.sh): a module of one function `() -> v128` made of
 * `i32.const 0; i8x16.splat`, validated. */
function wasmHasSimd() {
  const bytes = [0, 0x61, 0x73, 0x6d, 1, 0, 0, 0, 1, 5, 1, 0x60, 0, 1, 0x7b, 3, 2, 1, 0,
    0x0a, 8, 1, 6, 0, 0x41, 0, 0xfd, 0x0f, 0x0b];
  try { return WebAssembly.validate(new Uint8Array(bytes)); } catch { return false; }
}

async function main() {
  if (!wasmHasSimd()) {
    throw new Error("this browser's WebAssembly has no SIMD, which testpiece's core is compiled for: "
      + 'use Chrome or Edge 91, Firefox 89, Safari 16.4 or later');
  }
  setupTabs();
  setupInputs();
  setupBudget($('view-budget'), { ...toolsCtx, st, withProgress }); // issue 10
  setupPlan($('view-plan'), { ...toolsCtx, st }); // issue 19
  setupProgram($('view-program'), { ...toolsCtx, st, withProgress }); // issue 19
  setupCompensation($('view-compensation'), { ...toolsCtx, st, withProgress }); // issue 19
  readSettings();
  const runner = await coreStarted;
  $('runner').textContent = runner;
  // Queue the first calls together: the worker answers them in order as soon as the wasm is up.
  const [started] = await Promise.all([call('start'), loadCurves()]);
  mark('tp-core-ready');
  // What the views write beside the results: the machines, curves, words and thresholds
  // (src/wasm/page.rs).
  Object.assign(core, started);
  $('version').textContent = started.version;
  for (const o of $('machine').options) o.textContent = machineName(o.value);
  for (const e of started.examples) $('example').append(h('option', { value: e.name }, `${e.name}: ${e.description}`));
  // The first plot (Figure 19) before the example's identification and diagnosis finish.
  renderFig19($('view-fig19'));
  mark('tp-first-plot');
  await loadExample(started.examples[0].name);
  mark('tp-example-analysed');
  await loadCone();
  if ('serviceWorker' in navigator && location.protocol.startsWith('http')) {
    navigator.serviceWorker.register(`sw.js?build=${BUILD}`).catch(() => {});
  }
}

main().catch((e) => {
  $('summary').className = 'summary error';
  $('summary').textContent = `The page could not start: ${e && e.message ? e.message : e}`;
});
