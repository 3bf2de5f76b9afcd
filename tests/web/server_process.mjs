// The real ricochet-server as a child process for the browser tests (as
// tests/integration/server_process.h): a temporary directory, 127.0.0.1 with every port 0, the
// bound admin port read from the ports file the server writes once it listens.
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync, openSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { setTimeout as sleep } from 'node:timers/promises';

const binary = process.env.RICOCHET_SERVER_BINARY;
const source = process.env.RICOCHET_SOURCE_DIR;

/// Starts a server with `matches` matches of `map` (server/maps/<map>.toml); `token`: the admin
/// token (none when empty); `record`: matches recorded under <dir>/data; `dataDir`: another data
/// directory (two servers on one SQLite database make a fleet directory of two); `toml`: more
/// keys by section ({matches: 'warmup_s = 0\n', dashboard: ..., placement: ...}). Resolves once
/// it listens, within 20 s.
export async function startServer({ matches = 2, map = 'arena', token = '', record = false,
                                    dataDir = '', toml = {} } = {}) {
  if (!binary || !source) throw new Error('RICOCHET_SERVER_BINARY and RICOCHET_SOURCE_DIR must be set');
  const dir = mkdtempSync(join(tmpdir(), 'ricochet-web-'));
  const ports = join(dir, 'ports.json');
  let admin = `[admin]\nbind = "127.0.0.1"\nport = 0\n${toml.admin ?? ''}`;
  if (token) {
    writeFileSync(join(dir, 'token'), token);
    admin += `token_file = "${join(dir, 'token')}"\n`;
  }
  writeFileSync(join(dir, 'server.toml'),
    `[server]\ndata_dir = "${dataDir || join(dir, 'data')}"\nports_file = "${ports}"\nthreads = 2\n` +
    '[control]\nbind = "127.0.0.1"\nport = 0\n[game]\nbind = "127.0.0.1"\nport = 0\n' + admin +
    `[matches]\ncount = ${matches}\nmaps = ["${source}/server/maps/${map}.toml"]\nrecord = ${record}\n` +
    (toml.matches ?? '') +
    Object.entries(toml).filter(([section]) => section !== 'admin' && section !== 'matches')
      .map(([section, keys]) => `[${section}]\n${keys}`).join(''));
  const log = openSync(join(dir, 'server.log'), 'a');
  const child = spawn(binary, ['--config', join(dir, 'server.toml'), '--password-thread-nice', '0'],
                      { stdio: ['ignore', log, log] });
  const exited = new Promise((resolve) => child.once('exit', resolve));
  const deadline = Date.now() + 20000;
  for (;;) {
    try {
      const bound = JSON.parse(readFileSync(ports, 'utf8'));
      return {
        url: `http://127.0.0.1:${bound.admin_port}`,
        dir,
        controlPort: bound.control_port,
        fingerprint: bound.fingerprint,
        log: () => readFileSync(join(dir, 'server.log'), 'utf8'),
        async stop() {
          if (child.exitCode === null) child.kill('SIGKILL');
          await exited;
          rmSync(dir, { recursive: true, force: true });
        },
      };
    } catch {
      if (child.exitCode !== null || Date.now() > deadline) {
        child.kill('SIGKILL');
        throw new Error(`the server did not listen:\n${readFileSync(join(dir, 'server.log'), 'utf8')}`);
      }
      await sleep(20);
    }
  }
}

/// `count` ricochet-bot players (one process) in match `match` of `server`, for `seconds`.
/// `skill`: their aim, 0..1 (1 kills soonest).
export function startBots(server, { count, match, seconds, skill = 0.5 }) {
  const bot = process.env.RICOCHET_BOT_BINARY;
  if (!bot) throw new Error('RICOCHET_BOT_BINARY must be set');
  const child = spawn(bot, ['--port', String(server.controlPort), '--fingerprint', server.fingerprint,
                            '--bots', String(count), '--match', String(match), '--name', 'webbot',
                            '--duration-s', String(seconds), '--skill', String(skill)],
                      { stdio: ['ignore', 'ignore', 'inherit'] });
  const exited = new Promise((resolve) => child.once('exit', resolve));
  return {
    async stop() {
      if (child.exitCode === null) child.kill('SIGKILL');
      await exited;
    },
  };
}
