// Debian's Chromium (tools/deps.sh), headless, driven by playwright-core (no browser download),
// and what every test checks of a page: no console error, no failed request, a screenshot kept.
import { chromium } from 'playwright-core';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';

export const artifacts = process.env.RICOCHET_WEB_ARTIFACTS ?? join(process.cwd(), 'artifacts');

export function launch() {
  return chromium.launch({ executablePath: '/usr/bin/chromium', headless: true,
                           args: ['--no-sandbox'] });
}

/// Collects the page's console errors and failed requests (no answer, or a status >= 400).
export function watch(page) {
  const problems = [];
  page.on('console', (message) => {
    if (message.type() === 'error') problems.push(`console error: ${message.text()}`);
  });
  page.on('pageerror', (error) => problems.push(`page error: ${error.message}`));
  page.on('requestfailed', (request) => {
    problems.push(`request failed: ${request.url()} ${request.failure()?.errorText}`);
  });
  page.on('response', (response) => {
    if (response.status() >= 400) problems.push(`HTTP ${response.status()}: ${response.url()}`);
  });
  return problems;
}

/// A screenshot of the page as artifacts/<name>.png; prints where.
export async function screenshot(page, name) {
  mkdirSync(artifacts, { recursive: true });
  const path = join(artifacts, `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`screenshot: ${path}`);
}
