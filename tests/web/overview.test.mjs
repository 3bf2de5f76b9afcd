// The overview page of a server the test starts: it lists the server's matches and their tick
// sparklines grow, at 1280x720 and at a phone's width, with no console error or failed request;
// the expected drops stand apart from the problems; two servers on one database list each other.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { launch, screenshot, watch } from './browser.mjs';
import { startBots, startServer } from './server_process.mjs';

let server;
let browser;
let bots;
before(async () => {
  [server, browser] = await Promise.all([startServer({ matches: 3 }), launch()]);
  bots = startBots(server, { count: 2, match: 2, seconds: 30 });
});
after(async () => {
  await bots?.stop();
  await browser?.close();
  await server?.stop();
});

/// The number of points in match `name`'s sparkline.
function points(page, name) {
  return page.locator('#matches tr', { hasText: name }).locator('svg').getAttribute('data-points')
    .then(Number);
}

test('the overview lists the matches and their sparklines grow', async () => {
  const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const problems = watch(page);
  await page.goto(`${server.url}/`);
  const rows = page.locator('#matches tr');
  await rows.nth(2).waitFor({ timeout: 5000 });
  assert.deepEqual(await page.locator('#matches tr td:first-child').allTextContents(),
                   ['ffa-1', 'ffa-2', 'ffa-3']);
  assert.equal(await rows.first().locator('td').nth(1).textContent(), 'arena');
  assert.equal(await rows.first().locator('td').nth(3).textContent(), 'waiting');
  assert.equal(await page.locator('#server dd').first().textContent(), '3');
  // The bots' match shows them, and the server its players and their traffic.
  await page.waitForFunction(() => {
    const cells = document.querySelectorAll('#matches tr:nth-child(2) td');
    return cells[4]?.textContent === '2 / 16' && cells[3]?.textContent !== 'waiting';
  }, null, { timeout: 15000 });
  assert.equal(await page.locator('#server dd').nth(1).textContent(), '2');
  assert.notEqual(await page.locator('#server dd').nth(2).textContent(), '0 B/s');
  const first = await points(page, 'ffa-2');
  await page.waitForFunction(
    (before) => Number(document.querySelector('#matches tr:nth-child(2) svg').dataset.points) > before,
    first, { timeout: 5000 });
  assert.ok(await points(page, 'ffa-2') > first);
  // The bots' repeated inputs are expected, told apart, and not in the problems' table; a server
  // outside a fleet directory shows no fleet.
  await page.waitForFunction(() => /\d+ input stale/.test(document.getElementById('expected').textContent),
                             null, { timeout: 5000 });
  assert.deepEqual((await page.locator('#refusals td:nth-child(2)').allTextContents())
                     .filter((reason) => reason === 'stale'), []);
  assert.equal(await page.locator('#fleet-section').isHidden(), true);
  // Keyboard: the first Tab reaches the navigation, and the tables' scroll areas take focus.
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Overview');
  assert.ok(await page.locator('.scroll[tabindex="0"]').count() >= 2);
  await screenshot(page, 'overview-1280x720');

  await page.setViewportSize({ width: 390, height: 844 });
  // Nothing wider than a phone but the tables' own scroll areas.
  assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= window.innerWidth),
            'the page scrolls sideways at 390 px');
  await screenshot(page, 'overview-390x844');
  assert.deepEqual(problems, []);
  await page.close();
});

test('two servers in one fleet directory list each other, each row linking to its dashboard', async () => {
  // Two servers on one SQLite database: the directory of section 2 of the scale-out issue, as a
  // fleet on PostgreSQL has it (the page reads GET /fleet, whatever the store).
  const data = mkdtempSync(join(tmpdir(), 'ricochet-web-fleet-'));
  const placement = 'enabled = "on"\nadvertise_host = "127.0.0.1"\nheartbeat_s = 1\n';
  const servers = [];
  try {
    servers.push(await startServer({ matches: 1, dataDir: data, toml: { placement } }));
    servers.push(await startServer({ matches: 2, dataDir: data, toml: { placement } }));
    const [a, b] = servers;
    const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
    const problems = watch(page);
    await page.goto(`${a.url}/`);
    await page.locator('#fleet-section').waitFor({ state: 'visible', timeout: 5000 });
    await page.waitForFunction(() => document.querySelectorAll('#fleet tr').length === 2, null,
                               { timeout: 8000 });
    const rows = await page.locator('#fleet tr').evaluateAll((trs) => trs.map((tr) => ({
      self: tr.classList.contains('self'),
      address: tr.cells[1].textContent,
      matches: tr.cells[4].textContent,
      link: tr.cells[6].querySelector('a')?.getAttribute('href') ?? null,
    })));
    const self = rows.find((row) => row.self);
    const other = rows.find((row) => !row.self);
    assert.equal(self.address, `127.0.0.1:${a.controlPort}`);
    assert.equal(self.matches, '1 (1 open)');
    assert.equal(self.link, null);
    assert.equal(other.address, `127.0.0.1:${b.controlPort}`);
    assert.equal(other.matches, '2 (2 open)');
    assert.equal(other.link, `${b.url}/`);
    await screenshot(page, 'overview-fleet-1280x720');
    assert.deepEqual(problems, []);
    await page.close();
  } finally {
    for (const server of servers) await server.stop();
    rmSync(data, { recursive: true, force: true });
  }
});
