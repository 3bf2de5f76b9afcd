// With an admin token, every page, JSON answer and event stream of the dashboard is refused
// without it; the sign-in form takes the token and then they all work; a bearer header works for
// scripts.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { launch, screenshot, watch } from './browser.mjs';
import { startServer } from './server_process.mjs';

const token = 'a-test-token-0123456789';
const guarded = ['/', '/index.html', '/overview.js', '/sparkline.js', '/api/overview',
                 '/api/overview/events', '/metrics'];

let server;
let browser;
before(async () => {
  [server, browser] = await Promise.all([startServer({ matches: 1, token }), launch()]);
});
after(async () => {
  await browser?.close();
  await server?.stop();
});

/// The status of GET `path` from the page (its cookies go with it), redirects not followed.
function status(page, path) {
  return page.evaluate((p) => fetch(p, { redirect: 'manual' }).then(async (r) => {
    await r.arrayBuffer();
    return r.status === 0 ? 303 : r.status;  // 0: an opaque redirect
  }), path);
}

test('without the token every page and feed is refused; signed in, they work', async () => {
  const context = await browser.newContext({ viewport: { width: 1280, height: 720 } });
  const page = await context.newPage();
  await page.goto(`${server.url}/`);
  assert.equal(new URL(page.url()).pathname, '/signin');
  assert.equal(await page.locator('#matches').count(), 0);
  await screenshot(page, 'signin');
  for (const path of guarded) {
    const expected = path === '/' || path.endsWith('.html') ? 303 : 401;
    assert.equal(await status(page, path), expected, path);
  }
  // The page as a browser opens it: its stream refused too.
  const refused = await page.evaluate(() => new Promise((resolve) => {
    const events = new EventSource('/api/overview/events');
    events.onerror = () => { events.close(); resolve(true); };
    events.onmessage = () => { events.close(); resolve(false); };
  }));
  assert.ok(refused, 'the overview stream sent data without the token');

  await page.fill('#token', 'not-the-token');
  await page.press('#token', 'Enter');
  await page.waitForLoadState();
  assert.equal(await status(page, '/api/overview'), 401);

  await page.goto(`${server.url}/signin`);
  const problems = watch(page);
  await page.fill('#token', token);
  await page.press('#token', 'Enter');
  await page.waitForURL(`${server.url}/`);
  await page.locator('#matches tr td:first-child').first().waitFor({ timeout: 5000 });
  assert.equal(await page.locator('#matches tr td:first-child').first().textContent(), 'ffa-1');
  for (const path of guarded.filter((p) => p !== '/api/overview/events')) {
    assert.equal(await status(page, path), 200, path);
  }
  assert.deepEqual(problems, []);

  // Scripts use the bearer header.
  const scripted = await fetch(`${server.url}/api/overview`,
                               { headers: { Authorization: `Bearer ${token}` } });
  assert.equal(scripted.status, 200);
  assert.equal((await scripted.json()).matches[0].name, 'ffa-1');
  // Signed out, refused again.
  await page.locator('header button').click();
  await page.waitForURL(`${server.url}/signin`);
  assert.equal(await status(page, '/api/overview'), 401);
  assert.match(server.log(), /unauthorized/);
  await context.close();
});
