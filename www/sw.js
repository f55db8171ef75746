// Service worker: after one visit the page works with the network off, every view included: both
// wasm modules are cached at install, the second too (the Plan, Program, Error budget and
// Correction views: the page loads it only when one of them needs it). The cache is versioned by
// the build id the page registers it with (sw.js?build=<id>); `activate` deletes older caches.
// Strategy: network first for same-origin GETs (a new build shows at once when online), falling
// back to the cache when the network is unreachable.
const BUILD = new URL(self.location.href).searchParams.get('build') || 'dev';
const CACHE = `testpiece-${BUILD}`;
const ASSETS = [
  './', 'index.html', 'style.css', 'app.js', 'core.js', 'columns.js', 'worker.js', 'plot.js', 'densechart.js', 'plancanvas.js', 'export.js', 'ui.js', 'where.js', 'surfacemap.js',
  'data.js', 'fig19.js', 'identify.js', 'gap.js', 'parts.js', 'plan.js', 'program.js', 'budget.js', 'compensation.js', 'report.js',
  'pkg/testpiece.js', 'pkg/testpiece_bg.wasm', 'pkg/testpiece_tools.js', 'pkg/testpiece_tools_bg.wasm', 'pkg/build.js',
];

self.addEventListener('install', (ev) => {
  ev.waitUntil(caches.open(CACHE).then((c) => c.addAll(ASSETS)).then(() => self.skipWaiting()));
});

self.addEventListener('activate', (ev) => {
  ev.waitUntil(caches.keys()
    .then((keys) => Promise.all(keys.filter((k) => k.startsWith('testpiece-') && k !== CACHE).map((k) => caches.delete(k))))
    .then(() => self.clients.claim()));
});

self.addEventListener('fetch', (ev) => {
  const req = ev.request;
  if (req.method !== 'GET' || new URL(req.url).origin !== self.location.origin) return;
  ev.respondWith(
    fetch(req)
      .then((res) => {
        if (res.ok) {
          const copy = res.clone();
          caches.open(CACHE).then((c) => c.put(req, copy));
        }
        return res;
      })
      .catch(() => caches.open(CACHE).then((c) => c.match(req, { ignoreSearch: true }))
        .then((hit) => hit || new Response('offline and not cached', { status: 503 }))),
  );
});
