// Shared set-up of the browser tests: the page served by scripts/serve.mjs and Debian's
// chromium (headless, through playwright-core) with a fresh profile, 1280×800.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
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
