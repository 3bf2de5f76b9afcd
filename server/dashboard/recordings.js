// The Recordings page: the recordings directory (GET /api/recordings), and one recording
// replayed by the server (POST /api/recordings/<id>/replay, its progress from GET
// /api/recordings/<id>) then played on a canvas from above: frames fetched by tick range in
// chunks about the playhead (GET .../frames?from=&to=), the others dropped (refetched when the
// playhead comes back), the map from GET .../map. The shown tick, the positions drawn and the
// chunks kept are on window.ricochetReplay for the tests.
import { TopDown } from './topdown.js';

const $ = (id) => document.getElementById(id);

/// Ticks per frames request: 300, or ?chunk_ticks=N (30..600, the server allows 600; the tests
/// cross many chunks of a short recording with small ones).
const kChunkTicks = (() => {
  const asked = Number(new URLSearchParams(location.search).get('chunk_ticks'));
  return Number.isInteger(asked) && asked >= 30 && asked <= 600 ? asked : 300;
})();
/// Chunks of frames held about the playhead: the one under it and two ahead (fetched), one
/// behind (kept for stepping back). Others are dropped; only their kills stay (for the kill
/// feed: a few bytes each, fetched for the feed's kKillFeedS behind when not known yet).
const kChunksBehind = 1;
const kChunksAhead = 2;
/// How long a kill stays in the feed, s.
const kKillFeedS = 8;
const kSpeeds = [0.25, 0.5, 1, 2, 4, 8];
const kTeamColours = ['#8250df', '#cf222e', '#0550ae'];
const kWeapons = ['world', 'rifle', 'rocket', 'grenade'];

/// What the tests read: the tick shown, the entities drawn at it, the verdict shown.
/// `kills`: the feed shown ({killer, victim, tick: the Kill event's, step: the frame it shows
/// in}), newest first; `chunks`: the chunks of frames held (loaded or loading), at most maxChunks.
const exposed = {
  tick: 0, positions: [], verdict: '', ready: false, playing: false, speed: 1, kills: [], chunks: 0,
  maxChunks: kChunksBehind + 1 + kChunksAhead,
};
window.ricochetReplay = exposed;

async function getJson(url, options) {
  const response = await fetch(url, options);
  if (!response.ok) throw new Error(`${url}: ${response.status} ${(await response.text()).trim()}`);
  return response.json();
}

function cell(text) {
  const td = document.createElement('td');
  td.textContent = text;
  return td;
}

function size(bytes) {
  if (bytes >= 1 << 20) return `${(bytes / (1 << 20)).toFixed(1)} MiB`;
  if (bytes >= 1 << 10) return `${(bytes / (1 << 10)).toFixed(1)} KiB`;
  return `${bytes} B`;
}

function clock(seconds) {
  if (seconds === null || seconds === undefined) return '—';
  const s = Math.round(seconds);
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`;
}

function renderList(list) {
  const rows = list.recordings.map((r) => {
    const tr = document.createElement('tr');
    tr.dataset.recording = r.id;
    const name = document.createElement('td');
    if (r.unreadable) {
      name.textContent = r.id;
    } else {
      const open = document.createElement('button');
      open.type = 'button';
      open.textContent = `Match ${r.match_id}`;
      open.setAttribute('aria-label', `Replay ${r.id}`);
      open.addEventListener('click', () => openRecording(r));
      name.append(open);
    }
    const file = r.unreadable ? `unreadable: ${r.unreadable}`
      : r.complete ? (r.truncated ? 'complete (truncated)' : 'complete')
        : r.interrupted ? 'interrupted' : 'cut short';
    // players: the server's count, or null (an older recording), or absent (an older server).
    const players = Number.isInteger(r.players) ? String(r.players) : '—';
    tr.append(name, cell(r.map ?? '—'), cell(r.mode ?? '—'), cell(players),
              cell(clock(r.seconds)), cell(size(r.size_bytes)),
              cell(new Date(r.unix_ms).toLocaleString()), cell(file));
    return tr;
  });
  if (rows.length === 0) {
    const tr = document.createElement('tr');
    const td = cell('No recordings yet (set [matches] record = true).');
    td.colSpan = 8;
    td.className = 'empty';
    tr.append(td);
    rows.push(tr);
  }
  $('recordings').replaceChildren(...rows);
}

// ---- the player -------------------------------------------------------------------------

/// The open recording's replay: its summary, map, and the chunks of frames loaded.
let replay = null;

function chunkOf(tick) { return Math.floor((tick - 1) / kChunkTicks); }

/// Whether chunk `index` is within the frames kept about the playhead.
function inWindow(index) {
  const here = chunkOf(replay.tick);
  return index >= here - kChunksBehind && index <= here + kChunksAhead;
}

/// Loads chunk `index` (ticks [1 + index * kChunkTicks, ...)) unless it is loaded or loading:
/// its frames when it is within the window, else only its kills (kept once known).
function loadChunk(index) {
  if (!replay || index < 0 || replay.chunks.has(index)) return;
  if (!inWindow(index) && (replay.kills.has(index) || replay.killsLoading.has(index))) return;
  const first = 1 + index * kChunkTicks;
  if (first > replay.summary.last_tick) return;
  const end = Math.min(first + kChunkTicks, replay.summary.last_tick + 1);
  const current = replay;
  const entry = { loaded: false, scores: [], frames: [] };
  if (inWindow(index)) current.chunks.set(index, entry);
  current.killsLoading.add(index);
  exposed.chunks = current.chunks.size;
  getJson(`/api/recordings/${encodeURIComponent(current.id)}/frames?from=${first}&to=${end}`)
    .then((data) => {
      current.kills.set(index,
                        data.frames.flatMap((f) => f.kills.map((k) => ({ ...k, step: f.tick }))));
      current.killsLoading.delete(index);
      entry.scores = data.scores;
      entry.frames = data.frames;
      entry.loaded = true;
      if (replay === current) draw();
    })
    .catch((error) => {
      current.killsLoading.delete(index);
      if (current.chunks.get(index) === entry) current.chunks.delete(index);
      exposed.chunks = current.chunks.size;
      $('status').textContent = `Frames not loaded: ${error.message}`;
    });
}

/// Drops the frames of the chunks outside the window (a fetch still under way for one fills
/// an entry no longer held).
function dropChunks() {
  for (const index of [...replay.chunks.keys()]) {
    if (!inWindow(index)) replay.chunks.delete(index);
  }
  exposed.chunks = replay.chunks.size;
}

function frameAt(tick) {
  const chunk = replay.chunks.get(chunkOf(tick));
  if (!chunk || !chunk.loaded) return null;
  return chunk.frames[tick - 1 - chunkOf(tick) * kChunkTicks] ?? null;
}

/// Every player's score after step `tick`: the chunk's scores at its start and its changes
/// (a player without any yet: 0).
function scoresAt(tick) {
  const chunk = replay.chunks.get(chunkOf(tick));
  const scores = new Map(replay.summary.players.map(
    (p) => [p.entity, { entity: p.entity, kills: 0, deaths: 0, score: 0 }]));
  if (!chunk || !chunk.loaded) return scores;
  for (const s of chunk.scores) scores.set(s.entity, s);
  for (const frame of chunk.frames) {
    if (frame.tick > tick) break;
    for (const s of frame.scores) scores.set(s.entity, s);
  }
  return scores;
}

/// The kills of the last kKillFeedS up to `tick`, newest first, from the chunks' kills known.
function killsUpTo(tick) {
  const since = tick - kKillFeedS * replay.summary.tick_rate_hz;
  const kills = [];
  for (let index = chunkOf(Math.max(1, since)); index <= chunkOf(tick); ++index) {
    for (const kill of replay.kills.get(index) ?? []) {
      if (kill.step > since && kill.step <= tick) kills.push(kill);
    }
  }
  return kills.reverse();
}

function nameOf(entity) {
  if (entity === 0) return 'the world';
  return replay.names.get(entity) ?? `#${entity}`;
}

function draw() {
  if (!replay) return;
  const tick = replay.tick;
  const frame = frameAt(tick);
  $('tick').textContent = String(tick);
  $('timeline').value = String(tick);
  exposed.tick = tick;
  if (!frame) {
    exposed.positions = [];
    exposed.ready = false;
    $('replay-state').textContent = `Loading tick ${tick}…`;
    return;
  }
  $('replay-state').textContent = `Tick ${tick} of ${replay.summary.last_tick}, ` +
    `${(tick / replay.summary.tick_rate_hz).toFixed(2)} s`;
  replay.view.draw({
    players: frame.players.map((p) => ({
      id: p.id, name: nameOf(p.id), x: p.x, z: p.z, yaw: p.yaw, alive: p.alive, health: p.health,
      faded: p.away, colour: kTeamColours[replay.teams.get(p.id) ?? 0],
    })),
    projectiles: frame.projectiles,
  });
  exposed.positions = [
    ...frame.projectiles.map((p) => ({ id: p.id, kind: p.kind, x: p.x, y: p.y, z: p.z })),
    ...frame.players.map((p) => ({ id: p.id, kind: 'player', x: p.x, y: p.y, z: p.z })),
  ];
  exposed.ready = true;
  renderScores(tick);
  renderKills(tick);
}

function renderScores(tick) {
  const rows = [...scoresAt(tick).values()].sort((a, b) => b.score - a.score).map((s) => {
    const tr = document.createElement('tr');
    tr.dataset.entity = String(s.entity);
    tr.append(cell(nameOf(s.entity)), cell(String(s.score)), cell(`${s.kills} / ${s.deaths}`));
    return tr;
  });
  $('scores').replaceChildren(...rows);
}

function renderKills(tick) {
  const kills = killsUpTo(tick);
  exposed.kills = kills.map((k) => ({
    killer: k.killer, victim: k.victim, tick: k.tick, step: k.step,
  }));
  $('kills').replaceChildren(...kills.map((k) => {
    const li = document.createElement('li');
    li.textContent = `${nameOf(k.killer)} → ${nameOf(k.victim)} (${kWeapons[k.weapon] ?? k.weapon})`;
    return li;
  }));
}

/// Shows `tick` (clamped to the replay) and keeps the chunks about it loaded.
function seek(tick) {
  replay.tick = Math.min(Math.max(1, Math.round(tick)), replay.summary.last_tick);
  replay.playhead = replay.tick;
  const here = chunkOf(replay.tick);
  dropChunks();
  for (let index = here; index <= here + kChunksAhead; ++index) loadChunk(index);
  const since = Math.max(1, replay.tick - kKillFeedS * replay.summary.tick_rate_hz);
  for (let index = chunkOf(since); index < here; ++index) loadChunk(index);
  draw();
}

function setPlaying(playing) {
  replay.playing = playing && replay.tick < replay.summary.last_tick;
  exposed.playing = replay.playing;
  $('play').textContent = replay.playing ? 'Pause' : 'Play';
  replay.last = null;
  if (replay.playing) requestAnimationFrame(advance);
}

function advance(now) {
  if (!replay || !replay.playing) return;
  if (replay.last !== null && frameAt(replay.tick)) {
    const ticks = ((now - replay.last) / 1000) * replay.summary.tick_rate_hz * replay.speed;
    const playhead = replay.playhead + ticks;
    seek(Math.floor(playhead));
    replay.playhead = playhead;
    if (replay.tick >= replay.summary.last_tick) {
      setPlaying(false);
      return;
    }
  }
  replay.last = now;
  requestAnimationFrame(advance);
}

function showVerdict(summary) {
  const verdict = $('verdict');
  if (summary.hashes_matched) {
    verdict.textContent = `Every recorded hash matched (${summary.hashes_checked} checked).`;
    verdict.className = 'verdict-good';
  } else {
    verdict.textContent = `The recorded hash first differs at tick ${summary.first_mismatch_tick}: ` +
      'the replay stops there.';
    verdict.className = 'verdict-bad';
  }
  if (!summary.complete) verdict.textContent += ` The recording is cut short (${summary.cut}).`;
  exposed.verdict = verdict.textContent;
}

async function openRecording(entry) {
  replay = null;
  exposed.ready = false;
  const id = encodeURIComponent(entry.id);
  $('player').hidden = false;
  $('viewer').hidden = true;
  $('player-title').textContent = `Replay of match ${entry.match_id} (${entry.map}, ${entry.mode})`;
  $('replay-progress').hidden = false;
  try {
    let status = await getJson(`/api/recordings/${id}/replay`, { method: 'POST' });
    while (status.state === 'queued' || status.state === 'running') {
      $('replay-state').textContent = status.state === 'queued' ? 'Waiting for a replay worker…'
        : `Replaying: tick ${status.ticks_done} of ${status.ticks_total}`;
      $('replay-progress').value = status.ticks_total ? status.ticks_done / status.ticks_total : 0;
      await new Promise((resolve) => setTimeout(resolve, 200));
      status = (await getJson(`/api/recordings/${id}`)).job;
    }
    if (status.state !== 'done') throw new Error(`the replay ${status.state}: ${status.error}`);
    const [read, map] = await Promise.all([getJson(`/api/recordings/${id}`),
                                            getJson(`/api/recordings/${id}/map`)]);
    const summary = read.summary;
    replay = {
      id: entry.id, summary, view: new TopDown($('view'), map), tick: 1,
      chunks: new Map(), kills: new Map(), killsLoading: new Set(),
      playhead: 1, playing: false,
      speed: Number($('speed').value), last: null,
      names: new Map(summary.players.map((p) => [p.entity, p.name])),
      teams: new Map(summary.players.map((p) => [p.entity, p.team])),
    };
    exposed.speed = replay.speed;
    $('replay-progress').hidden = true;
    $('viewer').hidden = false;
    $('timeline').max = String(summary.last_tick);
    showVerdict(summary);
    seek(1);
    $('play').focus();
  } catch (error) {
    $('replay-state').textContent = `Cannot replay: ${error.message}`;
  }
}

function bindControls() {
  $('play').addEventListener('click', () => replay && setPlaying(!replay.playing));
  $('step').addEventListener('click', () => { if (replay) { setPlaying(false); seek(replay.tick + 1); } });
  $('step-back').addEventListener('click', () => { if (replay) { setPlaying(false); seek(replay.tick - 1); } });
  $('speed').addEventListener('change', () => {
    const speed = Number($('speed').value);
    if (!kSpeeds.includes(speed) || !replay) return;
    replay.speed = speed;
    exposed.speed = speed;
  });
  $('timeline').addEventListener('input', () => replay && seek(Number($('timeline').value)));
  document.addEventListener('keydown', (event) => {
    if (!replay || event.target instanceof HTMLSelectElement || event.ctrlKey || event.metaKey) return;
    if (event.key === ' ' && !(event.target instanceof HTMLButtonElement)) {
      event.preventDefault();
      setPlaying(!replay.playing);
    } else if (event.key === '.') {
      setPlaying(false);
      seek(replay.tick + 1);
    } else if (event.key === ',') {
      setPlaying(false);
      seek(replay.tick - 1);
    }
  });
}

bindControls();
getJson('/api/recordings')
  .then((list) => {
    renderList(list);
    $('status').textContent = `${list.recordings.length} recordings` +
      (list.unreadable ? `, ${list.unreadable} unreadable` : '');
  })
  .catch((error) => { $('status').textContent = `Cannot list the recordings: ${error.message}`; });
