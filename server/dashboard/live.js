// A match, live: the map seen from above (/api/matches/ID/map, server/src/web/map_view.h) with
// every player, rocket and grenade of the frames /api/matches/ID/live streams
// (server/src/web/frame_json.h), a kill feed and a scoreboard; click a player to follow it.
//
// Drawn DELAY_US behind the server's time on the frames' own clock (server_time_us), each
// position interpolated between the two frames around that time and never extrapolated: past
// the newest frame (frames stopped) the newest is held. The server's time now is estimated from
// the frames' arrival: server_time_us minus the local time it came at, the largest of the last
// ones (the least delayed).
//
// World axes as the server's: metres, x right, z down the screen, seen from above (+y up).
// What was drawn is on window.ricochetLive for tests (read it, not pixels).

import { TopDown } from './topdown.js';

const DELAY_US = 100000;
const KEPT_FRAMES = 60;         // ~3 s at 20 Hz: enough to interpolate DELAY_US behind
const OFFSET_WINDOW = 40;       // arrivals the server clock's estimate looks back on
const KEPT_FRAME_TIMES = 1200;  // rAF intervals and draw times kept for the figures
const FEED_LENGTH = 20;         // kills shown

const $ = (id) => document.getElementById(id);
const matchId = new URLSearchParams(location.search).get('match') ?? '';

/// What the page drew last, for tests.
const state = {
  match: matchId,
  ready: false,       // the map loaded and a frame drawn
  newestTick: null,   // of the newest frame received
  newestTimeUs: null, // its server_time_us
  renderTimeUs: null, // the server time drawn
  players: [],        // [{id, name, x, z, alive, health}] as drawn (interpolated)
  projectiles: [],    // [{id, kind, x, z}] as drawn
  followed: null,     // the followed player's id
  centre: null,       // [x, z] at the middle of the view, m
  kills: 0,           // kills the feed received
  frameTimesMs: [],   // intervals between animation frames
  drawMs: [],         // time each draw took
};
window.ricochetLive = state;

let map = null;
let frames = [];      // received, oldest first
const offsets = [];   // server_time_us - local µs at each arrival
const names = new Map();  // entity id -> name, kept for players who left
let view = null;      // the TopDown, once the map is there

function localUs() {
  return performance.now() * 1000;
}

function colourOf(player) {
  if (player.team === 'red') return '#cf222e';
  if (player.team === 'blue') return '#0969da';
  const hue = (player.id * 137.508) % 360;
  return `hsl(${hue} 65% 45%)`;
}

// --- the frames ---

function receive(frame) {
  frames.push(frame);
  if (frames.length > KEPT_FRAMES) frames.shift();
  offsets.push(frame.server_time_us - localUs());
  if (offsets.length > OFFSET_WINDOW) offsets.shift();
  state.newestTick = frame.tick;
  state.newestTimeUs = frame.server_time_us;
  for (const player of frame.players) names.set(player.id, player.name);
  if (frame.kills.length > 0) addKills(frame.kills);
  renderScores(frame);
  $('phase').textContent = phaseText(frame);
}

function phaseText(frame) {
  let text = `${frame.mode}, ${frame.phase}, tick ${frame.tick}`;
  if (frame.time_left_s !== null) text += `, ${Math.ceil(frame.time_left_s)} s left`;
  if (frame.mode === 'tdm') text += ` — red ${frame.team_scores.red}, blue ${frame.team_scores.blue}`;
  return text;
}

/// The server time to draw now: DELAY_US behind the estimated server clock, within the frames.
function renderTime() {
  const newest = frames.at(-1).server_time_us;
  const oldest = frames[0].server_time_us;
  const now = localUs() + Math.max(...offsets);
  return Math.max(oldest, Math.min(newest, now - DELAY_US));
}

function lerp(a, b, t) {
  return a + (b - a) * t;
}

/// Entities of the frames around `time`, positions interpolated: those of the earlier frame,
/// moved toward the later one's (not across a death or a respawn: a jump, not a path).
function interpolate(time) {
  let after = frames.findIndex((f) => f.server_time_us >= time);
  if (after < 0) after = frames.length - 1;
  const b = frames[after];
  const a = after > 0 ? frames[after - 1] : b;
  const span = b.server_time_us - a.server_time_us;
  const t = span > 0 ? Math.min(1, Math.max(0, (time - a.server_time_us) / span)) : 1;
  const source = t >= 1 ? b : a;
  const later = new Map(b.players.map((p) => [p.id, p]));
  const players = source.players.map((p) => {
    const q = later.get(p.id);
    const moving = q && q.alive === p.alive && source === a;
    return {
      id: p.id, name: p.name, team: p.team, alive: p.alive, connected: p.connected,
      health: p.health, yaw: p.yaw,
      x: moving ? lerp(p.position[0], q.position[0], t) : p.position[0],
      z: moving ? lerp(p.position[2], q.position[2], t) : p.position[2],
    };
  });
  const laterShots = new Map(b.projectiles.map((p) => [p.id, p]));
  const projectiles = source.projectiles.map((p) => {
    const q = source === a ? laterShots.get(p.id) : undefined;
    return {
      id: p.id, kind: p.kind,
      x: q ? lerp(p.position[0], q.position[0], t) : p.position[0],
      z: q ? lerp(p.position[2], q.position[2], t) : p.position[2],
    };
  });
  return { players, projectiles };
}

// --- the kill feed and the scoreboard ---

function addKills(kills) {
  const list = $('kills');
  for (const kill of kills) {
    state.kills += 1;
    const li = document.createElement('li');
    const killer = kill.killer === 0 ? 'the world' : (names.get(kill.killer) ?? `#${kill.killer}`);
    const victim = names.get(kill.victim) ?? `#${kill.victim}`;
    li.textContent = kill.killer === kill.victim
      ? `${victim} died (${kill.weapon ?? 'world'})`
      : `${killer} killed ${victim}${kill.weapon ? ` (${kill.weapon.replace('_', ' ')})` : ''}`;
    li.dataset.victim = String(kill.victim);
    list.prepend(li);
  }
  while (list.children.length > FEED_LENGTH) list.lastElementChild.remove();
}

// The scoreboard's rows by player id, made once and updated in place: with 64 players someone's
// health changes in nearly every frame, and rebuilding every row 20 times a second costs the
// page more than drawing the map.
const scoreRows = new Map();  // id -> {tr, button, cells: [score, kills, deaths, health]}

function scoreRow(player) {
  let row = scoreRows.get(player.id);
  if (row) return row;
  const tr = document.createElement('tr');
  tr.dataset.player = String(player.id);
  const name = document.createElement('td');
  const button = document.createElement('button');
  button.type = 'button';
  button.dataset.player = String(player.id);
  button.addEventListener('click', () => follow(state.followed === player.id ? null : player.id));
  name.append(button);
  const cells = [0, 1, 2, 3].map(() => document.createElement('td'));
  tr.append(name, ...cells);
  row = { tr, button, cells };
  scoreRows.set(player.id, row);
  return row;
}

function setText(node, text) {
  if (node.textContent !== text) node.textContent = text;
}

function renderScores(frame) {
  const players = [...frame.players].sort((p, q) => q.score - p.score || p.id - q.id);
  const present = new Set(players.map((p) => p.id));
  for (const [id, row] of scoreRows) {
    if (!present.has(id)) {
      row.tr.remove();
      scoreRows.delete(id);
    }
  }
  const body = $('scores');
  const rows = players.map((p) => {
    const row = scoreRow(p);
    setText(row.button, p.name);
    row.button.title = `Follow ${p.name}`;
    row.button.setAttribute('aria-pressed', String(state.followed === p.id));
    [p.score, p.kills, p.deaths, p.alive ? p.health : 'dead']
      .forEach((value, n) => setText(row.cells[n], String(value)));
    return row.tr;
  });
  // Reordered only when the order changed; a moved row loses the keyboard focus: given back.
  if (rows.some((tr, n) => body.children[n] !== tr)) {
    const focused = document.activeElement?.dataset?.player;
    body.replaceChildren(...rows);
    if (focused) body.querySelector(`button[data-player="${focused}"]`)?.focus();
  }
}

function follow(id) {
  state.followed = id;
  $('unfollow').disabled = id === null;
  if (frames.length > 0) renderScores(frames.at(-1));
}

// --- drawing ---

function draw(drawn) {
  view.draw({
    players: drawn.players.map((p) => ({ ...p, colour: colourOf(p), faded: !p.connected })),
    projectiles: drawn.projectiles,
    followed: state.followed,
  });
  state.centre = view.centre;
  state.players = drawn.players.map(({ id, name, x, z, alive, health }) => ({ id, name, x, z, alive, health }));
  state.projectiles = drawn.projectiles;
}

let lastFrameAt = null;
function animate(now) {
  if (lastFrameAt !== null) push(state.frameTimesMs, now - lastFrameAt);
  lastFrameAt = now;
  if (map && frames.length > 0) {
    const started = performance.now();
    state.renderTimeUs = renderTime();
    draw(interpolate(state.renderTimeUs));
    push(state.drawMs, performance.now() - started);
    state.ready = true;
  }
  requestAnimationFrame(animate);
}

function push(list, value) {
  list.push(value);
  if (list.length > KEPT_FRAME_TIMES) list.shift();
}

// --- input ---

$('map').addEventListener('click', (event) => {
  if (view) follow(view.pick(event.clientX, event.clientY, state.players));
});
$('unfollow').addEventListener('click', () => follow(null));
document.addEventListener('keydown', (event) => {
  if (event.key === 'Escape') follow(null);
});

// --- start ---

async function start() {
  if (!/^[1-9][0-9]{0,9}$/.test(matchId)) {
    $('status').textContent = 'No match: open this page from the overview.';
    return;
  }
  $('here').href = `/live.html?match=${matchId}`;
  document.title = `Ricochet: match ${matchId}, live`;
  const response = await fetch(`/api/matches/${matchId}/map`);
  if (!response.ok) {
    $('status').textContent = `Match ${matchId}: ${(await response.text()).trim()}`;
    return;
  }
  map = await response.json();
  view = new TopDown($('map'), map);
  $('view-title').textContent = `Match ${matchId} on ${map.map}`;
  const events = new EventSource(`/api/matches/${matchId}/live`);
  events.onopen = () => {
    $('status').textContent = 'Live';
  };
  events.onmessage = (event) => {
    const frame = JSON.parse(event.data);
    if (frame.refused) {
      events.close();
      $('status').textContent = `Refused: ${frame.refused.replaceAll('_', ' ')}`;
      return;
    }
    receive(frame);
  };
  events.onerror = () => {
    $('status').textContent = 'Connection lost; reconnecting…';
  };
  requestAnimationFrame(animate);
}

window.ricochetLive.follow = follow;
/// Where the world point [x, z] was drawn, in the page's CSS pixels (clientX, clientY).
window.ricochetLive.toScreen = (point) => view.toScreen(point);
start();
