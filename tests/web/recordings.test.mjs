// The Recordings page: a short bot match recorded by a server the test starts is listed, opens,
// is replayed by the server and played on the page; at a tick the positions the page drew are
// the ones `ricochet-replay --export` prints for it, the timeline and the speeds work, the hash
// verdict is shown, the page holds a bounded window of frames about the playhead, with no console
// error or failed request, at 1280x720 and at a phone's width.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { setTimeout as sleep } from 'node:timers/promises';
import { launch, screenshot, watch } from './browser.mjs';
import { startBots, startServer } from './server_process.mjs';

/// The recorded match: two bots, no warm-up, over after this many seconds. At skill 1 they killed
/// each other twice in each of 3 runs of 5 s, the first at about 3.2 s: 8 s leaves a margin for
/// a loaded machine, as the kill feed's check needs one.
const kMatchS = 8;

let server;
let browser;
let bots;
before(async () => {
  [server, browser] = await Promise.all([
    startServer({ matches: 1, record: true,
                  toml: { matches: `seed = 42\nwarmup_s = 0\nfrag_limit = 0\nmin_players = 2\ntime_limit_s = ${kMatchS}\n` } }),
    launch()]);
  bots = startBots(server, { count: 2, match: 1, seconds: 30, skill: 1 });
});
after(async () => {
  await bots?.stop();
  await browser?.close();
  await server?.stop();
});

/// The recording's file under the server's data directory.
function recordingFile(dir, id) {
  for (const entry of readdirSync(dir, { recursive: true })) {
    if (entry.endsWith(`${id}.rcr`)) return join(dir, entry);
  }
  throw new Error(`no file of ${id} under ${dir}`);
}

/// `ricochet-replay --export`'s rows of tick `tick` (players only): entity -> [x, y, z] as printed.
function exported(file, tick) {
  const csv = join(server.dir, 'export.csv');
  execFileSync(process.env.RICOCHET_REPLAY_BINARY, [file, '--export', csv]);
  const rows = new Map();
  for (const line of readFileSync(csv, 'utf8').trim().split('\n').slice(1)) {
    const [t, entity, x, y, z] = line.split(',');
    if (Number(t) === tick) rows.set(Number(entity), [x, y, z]);
  }
  return rows;
}

/// The replay's first kill as the server's frames say it: {step, killer, victim, tick}.
async function firstKill(id, lastTick) {
  for (let from = 1; from <= lastTick; from += 600) {
    const to = Math.min(from + 600, lastTick + 1);
    const url = `${server.url}/api/recordings/${id}/frames?from=${from}&to=${to}`;
    const frames = await (await fetch(url)).json();
    for (const frame of frames.frames) {
      if (frame.kills.length > 0) return { step: frame.tick, ...frame.kills[0] };
    }
  }
  return null;
}

/// Shows `tick` as dragging the timeline there does.
async function scrubTo(page, tick) {
  await page.evaluate((t) => {
    const timeline = document.getElementById('timeline');
    timeline.value = String(t);
    timeline.dispatchEvent(new Event('input'));
  }, tick);
  await page.waitForFunction((t) => window.ricochetReplay.tick === t && window.ricochetReplay.ready,
                             tick, { timeout: 5000 });
}

/// Ticks the page shows per second of wall time at its current speed, over `ms`.
async function playbackRate(page, ms) {
  const start = await page.evaluate(() => [window.ricochetReplay.tick, performance.now()]);
  await sleep(ms);
  const end = await page.evaluate(() => [window.ricochetReplay.tick, performance.now()]);
  return (end[0] - start[0]) / ((end[1] - start[1]) / 1000);
}

test('a recorded bot match replays on the page as ricochet-replay exports it', async () => {
  // The match ends after kMatchS s of play and its recording is listed, complete.
  let recording;
  for (const deadline = Date.now() + 15000; !recording;) {
    const list = await (await fetch(`${server.url}/api/recordings`)).json();
    recording = list.recordings.find((r) => r.complete);
    if (!recording && Date.now() > deadline) throw new Error(`no recording:\n${server.log()}`);
    if (!recording) await sleep(100);
  }
  await bots.stop();

  const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const problems = watch(page);
  const fetched = [];  // the first tick of each frames request
  page.on('request', (request) => {
    const from = /\/frames\?from=(\d+)/.exec(request.url());
    if (from) fetched.push(Number(from[1]));
  });
  // Chunks of 60 ticks: the 5 s recording spans more of them than the page holds at once.
  await page.goto(`${server.url}/recordings.html?chunk_ticks=60`);
  const row = page.locator(`#recordings tr[data-recording="${recording.id}"]`);
  await row.waitFor({ timeout: 5000 });
  // Players: the server's count, or '—' from a server (or a recording) without it.
  const players = Number.isInteger(recording.players) ? String(recording.players) : '—';
  assert.deepEqual((await row.locator('td').allTextContents()).slice(1, 4),
                   ['arena', 'ffa', players]);
  assert.equal(await row.locator('td').nth(7).textContent(), 'complete');
  // Keyboard: the row's button opens it.
  await row.getByRole('button').focus();
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => window.ricochetReplay.ready, null, { timeout: 10000 });
  const verdict = await page.evaluate(() => window.ricochetReplay.verdict);
  assert.match(verdict, /^Every recorded hash matched \(\d+ checked\)\.$/);
  assert.equal(await page.locator('#verdict').textContent(), verdict);

  // Scrub to T (the timeline by keyboard: End, then back), then compare with the export.
  const last = Number(await page.locator('#timeline').getAttribute('max'));
  assert.ok(last >= kMatchS * 60, `the replay has ${last} ticks`);
  const T = last - 7;
  await page.locator('#timeline').focus();
  await page.keyboard.press('End');
  for (let i = 0; i < 7; ++i) await page.keyboard.press('ArrowLeft');
  await page.waitForFunction((t) => window.ricochetReplay.tick === t && window.ricochetReplay.ready,
                             T, { timeout: 5000 });
  const drawn = (await page.evaluate(() => window.ricochetReplay.positions))
    .filter((e) => e.kind === 'player');
  const rows = exported(recordingFile(server.dir, recording.id), T);
  assert.equal(drawn.length, 2, JSON.stringify(drawn));
  assert.deepEqual(new Map(drawn.map((e) => [e.id, [e.x, e.y, e.z]])),
                   new Map([...rows].map(([id, xyz]) => [id, xyz.map(Number)])));
  assert.equal(await page.locator('#tick').textContent(), String(T));
  // The scoreboard lists both bots at T.
  assert.equal(await page.locator('#scores tr').count(), 2);

  // Speeds: 8x plays about 32 times as fast as 0.25x (from tick 1).
  await page.locator('#step-back').click();
  assert.equal(await page.evaluate(() => window.ricochetReplay.tick), T - 1);
  await page.locator('#step').click();
  assert.equal(await page.evaluate(() => window.ricochetReplay.tick), T);
  await page.locator('#timeline').focus();
  await page.keyboard.press('Home');
  await page.locator('#speed').selectOption('8');
  await page.locator('#play').click();
  const fast = await playbackRate(page, 250);
  await page.locator('#play').click();
  await page.locator('#speed').selectOption('0.25');
  await page.locator('#play').click();
  const slow = await playbackRate(page, 250);
  await page.locator('#play').click();
  assert.ok(fast > 3 * 60, `8x played ${fast} ticks/s`);
  assert.ok(slow < 60, `0.25x played ${slow} ticks/s`);

  // Played to the end at 8x, the page never holds more than maxChunks chunks of frames though it
  // fetched more; back at the start, the first chunk (dropped) is fetched again.
  await page.locator('#speed').selectOption('8');
  await page.locator('#play').click();
  const held = await page.evaluate(() => new Promise((resolve) => {
    let most = 0;
    const sample = () => {
      most = Math.max(most, window.ricochetReplay.chunks);
      if (window.ricochetReplay.playing) requestAnimationFrame(sample); else resolve(most);
    };
    requestAnimationFrame(sample);
  }));
  const maxChunks = await page.evaluate(() => window.ricochetReplay.maxChunks);
  assert.equal(await page.evaluate(() => window.ricochetReplay.tick), last);
  assert.ok(held <= maxChunks, `${held} chunks held, at most ${maxChunks} wanted`);
  assert.ok(new Set(fetched).size > maxChunks, `fetched ${fetched}`);
  const firstFetches = fetched.filter((from) => from === 1).length;
  await page.locator('#timeline').focus();
  await page.keyboard.press('Home');
  await page.waitForFunction(() => window.ricochetReplay.tick === 1 && window.ricochetReplay.ready,
                             null, { timeout: 5000 });
  assert.ok(fetched.filter((from) => from === 1).length > firstFetches, `fetched ${fetched}`);
  assert.ok(await page.evaluate(() => window.ricochetReplay.chunks) <= maxChunks);

  // The first kill shows in the feed from the step it happened in, not the step before.
  const kill = await firstKill(recording.id, last);
  assert.ok(kill, 'the recorded bots killed no one');
  await scrubTo(page, kill.step - 1);
  assert.deepEqual(await page.evaluate(() => window.ricochetReplay.kills), []);
  await scrubTo(page, kill.step);
  assert.deepEqual((await page.evaluate(() => window.ricochetReplay.kills))[0],
                   { killer: kill.killer, victim: kill.victim, tick: kill.tick, step: kill.step });
  assert.match(await page.locator('#kills li').first().textContent(),
               /^(webbot-\d|the world) → webbot-\d \((world|rifle|rocket|grenade)\)$/);
  await screenshot(page, 'recordings-1280x720');

  await page.setViewportSize({ width: 390, height: 844 });
  assert.ok(await page.evaluate(() => document.documentElement.scrollWidth <= window.innerWidth),
            'the page scrolls sideways at 390 px');
  await screenshot(page, 'recordings-390x844');
  assert.deepEqual(problems, []);
  await page.close();

  // A server that counts the players gives "players": N, or null for an older recording.
  const later = await browser.newPage();
  await later.route('**/api/recordings', async (route) => {
    const list = await (await route.fetch()).json();
    const [entry] = list.recordings;
    list.recordings = [{ ...entry, id: 'match-98-1', players: 3 },
                       { ...entry, id: 'match-99-1', players: null }];
    await route.fulfill({ json: list });
  });
  await later.goto(`${server.url}/recordings.html`);
  for (const [id, players] of [['match-98-1', '3'], ['match-99-1', '—']]) {
    const cells = later.locator(`#recordings tr[data-recording="${id}"] td`);
    await cells.first().waitFor({ timeout: 5000 });
    assert.equal(await cells.nth(3).textContent(), players, id);
  }
  await later.close();
});
