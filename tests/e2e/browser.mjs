// Shared set-up of the browser tests: the page served by scripts/serve.mjs and Debian's
// chromium (headless, through playwright-core) with a fresh profile, 1280×800.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { chromium } from 'playwright-core';
import { serve } from '../../scripts/serve.mjs';

export const ROOT = path.resolve(import.meta.dirname, '..', '..');
export const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--no-first-run'];

/** Serves the page and opens chromium (`options`: more launch options, e.g. acceptDownloads);
 * `close()` undoes both. */
export async function openBrowser(prefix, options = {}) {
  const { server, url } = await serve();
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), `testpiece-${prefix}-`));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: '/usr/bin/chromium', headless: true, args: FLAGS, viewport: { width: 1280, height: 800 },
    ...options,
  });
  return {
    server, url, context,
    async close() {
      await context.close();
      server.close();
      fs.rmSync(userDataDir, { recursive: true, force: true });
    },
  };
}

/** `testpiece ARGS` (the debug build, through cargo): its stdout. */
export function testpiece(args) {
  return execFileSync('cargo', ['run', '--quiet', '--bin', 'testpiece', '--', ...args], { cwd: ROOT, encoding: 'utf8', maxBuffer: 1 << 26 });
}

/** A scan written by `testpiece simulate --scan SCAN` (EX0B = 0.01 mm, noise 1.5 µm, `seed`) as
 * scan_SCAN.csv in a fresh temporary folder: {file, dir}. */
export function simulatedScan(prefix, scan, seed) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), `testpiece-${prefix}-`));
  const file = path.join(dir, `scan_${scan}.csv`);
  fs.writeFileSync(file, testpiece(['simulate', '--errors', 'EX0B=0.01', '--noise', '0.0015', '--seed', String(seed), '--scan', scan]));
  return { file, dir };
}

/** A new page of `context` at `url`, once ready (the example analysed): {page, errors} (`errors`
 * collects the page's uncaught errors). */
export async function readyPage(context, url) {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
  return { page, errors };
}
