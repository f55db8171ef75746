// Builds dist/testpiece.html: the whole page in one file that works when double-clicked from
// file:// (a lab machine with no web server). file:// forbids loading other modules, module
// workers and service workers, so: the page's ES modules are folded into one classic inline
// script; the core runs in a classic Web Worker made from a Blob URL whose source (the
// module-free wasm-bindgen glue of both wasm modules + www/worker-inline.js) is inlined as a
// non-executed script; each wasm is inlined as base64: the first decoded once by the page and
// posted to the worker, which starts it with initSync; the second (the Plan, Program, Error budget
// and Correction views) decoded and posted only when one of those views first needs it. Cancel
// terminates the worker and starts another from the same source and bytes.
// Needs www/pkg/ (scripts/build-wasm.sh). Usage: node scripts/build-single.mjs
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const WWW = path.join(ROOT, 'www');
const OUT = path.join(ROOT, 'dist', 'testpiece.html');

/** Turns one ES module into `const __m_<name> = (() => { …; return {exports}; })();`. */
function fold(name, code) {
  const exported = [];
  code = code.replace(/^import\s+\{([^}]*)\}\s+from\s+'\.\/([\w/.-]+)\.js';?$/gm, (_, names, from) => {
    const fields = names.split(',').map((s) => s.trim()).filter(Boolean)
      .map((s) => s.replace(/\s+as\s+/, ': '));
    return `const { ${fields.join(', ')} } = __m_${from.replace(/\W/g, '_')};`;
  });
  if (/^import\s/m.test(code)) throw new Error(`${name}: an import form the single-file build cannot fold`);
  code = code.replace(/^export\s+(async\s+function|function|const|let|class)\s+(\w+)/gm, (_, kind, id) => {
    exported.push(id);
    return `${kind} ${id}`;
  });
  if (/^export\s/m.test(code)) throw new Error(`${name}: an export form the single-file build cannot fold`);
  return `const __m_${name.replace(/\W/g, '_')} = (() => {\n${code}\nreturn { ${exported.join(', ')} };\n})();\n`;
}

/** The wasm-bindgen glue (--target web) of module `name` as a module-free block `__m_pkg_<name>`
 * exposing initSync and the exports (its functions and its classes, e.g. `Prepared`). */
function foldGlue(name, code) {
  const names = [...code.matchAll(/^export (?:function|class) (\w+)/gm)].map((m) => m[1]);
  code = code.replace(/^export function /gm, 'function ')
    .replace(/^export class /gm, 'class ')
    .replace(/^export\s*\{[^}]*\};?\s*$/gm, '')
    .replace(/^export default \w+;?\s*$/gm, '');
  if (/^export\s/m.test(code) || /^import\s/m.test(code)) throw new Error('unexpected module syntax in the wasm glue');
  return `const __m_pkg_${name} = (() => {\n${code}\nreturn { initSync, exports: { ${names.join(', ')} } };\n})();\n`;
}

const read = (f) => fs.readFileSync(path.join(WWW, f), 'utf8');
const wasm = fs.readFileSync(path.join(WWW, 'pkg', 'testpiece_bg.wasm'));
const toolsWasm = fs.readFileSync(path.join(WWW, 'pkg', 'testpiece_tools_bg.wasm'));
const glue = foldGlue('testpiece', read('pkg/testpiece.js')) + foldGlue('testpiece_tools', read('pkg/testpiece_tools.js'));
// Dependency order, read from the imports: each module after the ones it imports, app.js last.
function dependencyOrder(entry) {
  const order = [];
  const visit = (m) => {
    if (order.includes(m)) return;
    for (const [, from] of read(`${m}.js`).matchAll(/^import\s+\{[^}]*\}\s+from\s+'\.\/([\w/.-]+)\.js';?$/gm)) visit(from);
    order.push(m);
  };
  visit(entry);
  return order;
}
const modules = dependencyOrder('app');
let app = modules.map((m) => fold(m, read(`${m}.js`))).join('\n');
// The worker's source: the glue, the packing of an analysis (columns.js), then the message handler. `</script` cannot occur in it.
// (The glue's default init resolves the wasm next to `import.meta.url`; only initSync is used
// here, and a classic worker cannot parse `import.meta`.)
const workerSource = `${glue.replace(/import\.meta\.url/g, 'self.location.href')}\n${fold('columns', read('columns.js'))}\n${read('worker-inline.js')}`;
if (/import\.meta/.test(workerSource)) throw new Error('import.meta left in the worker source');
if (/<\/script/i.test(workerSource)) throw new Error('the worker source contains </script');
const boot = `
globalThis.__TESTPIECE_INLINE__ = (() => {
  const decode = (id) => {
    const bin = atob(document.getElementById(id).textContent.trim());
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return bytes;
  };
  let tools = null; // the second module's bytes, decoded when first asked for
  return {
    workerSource: document.getElementById('testpiece-worker').textContent,
    wasm: decode('testpiece-wasm'),
    toolsWasm: () => (tools ??= decode('testpiece-tools-wasm')),
  };
})();
`;
// app.js starts itself; the inline core must exist before it runs.
app = app.replace('const __m_app = (() => {', `${boot}\nconst __m_app = (() => {`);
// A classic script: `import.meta` is a syntax error there (core.js uses it only when served).
app = app.replace(/import\.meta\.url/g, 'location.href');
if (/import\.meta/.test(app)) throw new Error('import.meta left in the single-file script');

let html = read('index.html');
const css = read('style.css');
// The module graph is inlined below: no module preloads.
html = html.replace(/^\s*<!-- Fetch the whole module graph[^\n]*\n/m, '').replace(/^\s*<link rel="modulepreload"[^\n]*\n/gm, '');
html = html.replace(/<link rel="stylesheet" href="style.css">/, `<style>\n${css}\n</style>`);
// (A replacer function: the inlined code may contain `$&`-like text.)
html = html.replace(/<script type="module" src="app.js"><\/script>/, () =>
  `<script type="application/wasm-base64" id="testpiece-wasm">${wasm.toString('base64')}</script>\n` +
  `<script type="application/wasm-base64" id="testpiece-tools-wasm">${toolsWasm.toString('base64')}</script>\n` +
  `<script type="text/plain" id="testpiece-worker">\n${workerSource}\n</script>\n` +
  `<script>\n(() => {\n'use strict';\n${app}\n})();\n</script>`);
// file:// has no origin to connect to: forbid every connection; inline scripts are this file's
// own; the only worker is the Blob-URL one made from this file's inline source.
html = html.replace(/<meta http-equiv="Content-Security-Policy" content="[^"]*">/,
  `<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline' 'wasm-unsafe-eval'; worker-src blob:; style-src 'unsafe-inline'; img-src data: blob:; connect-src 'none'; object-src 'none'; base-uri 'none'; form-action 'none'">`);
fs.mkdirSync(path.dirname(OUT), { recursive: true });
fs.writeFileSync(OUT, html);
console.log(`[build-single] ${path.relative(ROOT, OUT)}: ${fs.statSync(OUT).size} bytes`);
