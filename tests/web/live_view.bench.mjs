// The live view's frame time with a full match, in headless Chromium (issue 32's figure; a
// benchmark, not a test: `tools/bench/live_view.sh` runs it, ctest does not). A real server hosts
// one match of --players bots from ricochet-loadtest (its cheap bots: the same inputs as players,
// fighting); the page follows nobody and draws the whole map. After the match is full the page's
// own timings are cleared and --seconds of them read back (window.ricochetLive): the intervals
// between animation frames, and the time each draw took. One JSON line to stdout and --out;
// percentiles are nearest rank (stats/include/ricochet/stats/percentile.h).
//
//   node live_view.bench.mjs [--players 64] [--seconds 20] [--map foundry] [--width 1280]
//                            [--height 720] [--out FILE]
import { spawn } from 'node:child_process';
import { appendFileSync, mkdtempSync, rmSync } from 'node:fs';
import { loadavg, tmpdir } from 'node:os';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { setTimeout as sleep } from 'node:timers/promises';
import { launch, watch } from './browser.mjs';
import { startServer } from './server_process.mjs';
import { nearestRank } from './percentile.mjs';

const { values: options } = parseArgs({
  options: {
    players: { type: 'string', default: '64' },
    seconds: { type: 'string', default: '20' },
    map: { type: 'string', default: 'foundry' },
    width: { type: 'string', default: '1280' },
    height: { type: 'string', default: '720' },
    out: { type: 'string', default: '' },
  },
});
const players = Number(options.players);
const seconds = Number(options.seconds);

const server = await startServer({
  matches: 1,
  map: options.map,
  toml: {
    matches: `max_players = ${players}\nwarmup_s = 0\nfrag_limit = 0\ntime_limit_s = 3600\n` +
             `seats_per_address = ${players}\n`,
    db: 'password_hashing = "minimum"\n',
  },
});
const out = mkdtempSync(join(tmpdir(), 'ricochet-live-bench-'));
const loadtest = spawn(process.env.RICOCHET_LOADTEST_BINARY, [
  '--server', `127.0.0.1:${server.controlPort}:${new URL(server.url).port}`,
  '--fingerprint', server.fingerprint, '--bots', String(players), '--match-size', String(players),
  '--duration', `${seconds + 60}s`, '--ramp', '32', '--settle', '1s', '--no-plots', '--quiet',
  '--out', out,
], { stdio: ['ignore', 'ignore', 'inherit'] });
const loadtestExited = new Promise((resolve) => loadtest.once('exit', resolve));

const browser = await launch();
try {
  const width = Number(options.width);
  const height = Number(options.height);
  const page = await browser.newPage({ viewport: { width, height } });
  const problems = watch(page);
  await page.goto(`${server.url}/live.html?match=1`);
  const deadline = Date.now() + 60000;
  while ((await page.evaluate(() => window.ricochetLive.players.length)) < players) {
    if (Date.now() > deadline || loadtest.exitCode !== null) {
      throw new Error(`${await page.evaluate(() => window.ricochetLive.players.length)} of ` +
                      `${players} players joined within 60 s`);
    }
    await sleep(250);
  }
  await page.evaluate(() => {
    window.ricochetLive.frameTimesMs.length = 0;
    window.ricochetLive.drawMs.length = 0;
  });
  const load = loadavg()[0];
  await sleep(seconds * 1000);
  const drawn = await page.evaluate(() => ({
    frame: [...window.ricochetLive.frameTimesMs],
    draw: [...window.ricochetLive.drawMs],
    players: window.ricochetLive.players.length,
    projectiles: window.ricochetLive.projectiles.length,
  }));
  if (problems.length > 0) throw new Error(problems.join('\n'));
  const figure = (values, q) => Number(nearestRank(values, q).toFixed(2));
  const line = JSON.stringify({
    bench: 'live_view', map: options.map, players: drawn.players, viewport: `${width}x${height}`,
    seconds, frames: drawn.frame.length,
    raf_interval_ms_p50: figure(drawn.frame, 0.5), raf_interval_ms_p99: figure(drawn.frame, 0.99),
    raf_interval_ms_max: figure(drawn.frame, 1), draw_ms_p50: figure(drawn.draw, 0.5),
    draw_ms_p99: figure(drawn.draw, 0.99), draw_ms_max: figure(drawn.draw, 1),
    raf_intervals_over_25ms: drawn.frame.filter((ms) => ms > 25).length,
    projectiles_at_end: drawn.projectiles, load_avg_1m_at_start: Number(load.toFixed(2)),
    at: new Date().toISOString(),
  });
  console.log(line);
  if (options.out) appendFileSync(options.out, `${line}\n`);
} finally {
  await browser.close();
  if (loadtest.exitCode === null) loadtest.kill('SIGKILL');
  await loadtestExited;
  await server.stop();
  rmSync(out, { recursive: true, force: true });
}
