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

const DELAY_US = 100000;
const KEPT_FRAMES = 60;         // ~3 s at 20 Hz: enough to interpolate DELAY_US behind
const OFFSET_WINDOW = 40;       // arrivals the server clock's estimate looks back on
const KEPT_FRAME_TIMES = 1200;  // rAF intervals and draw times kept for the figures
const FEED_LENGTH = 20;         // kills shown
const PLAYER_RADIUS_M = 0.5;    // drawn size of a player (the sphere's, about)
const PICK_RADIUS_PX = 16;      // a click this near a player follows it
const MAX_HEALTH = 100;

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
let view = null;      // {scale, width, height, dpr, staticLayer}

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

let scoresKey = '';
function renderScores(frame) {
  const players = [...frame.players].sort((p, q) => q.score - p.score || p.id - q.id);
  const key = JSON.stringify([state.followed, players.map((p) =>
    [p.id, p.name, p.score, p.kills, p.deaths, p.alive ? p.health : 0])]);
  if (key === scoresKey) return;  // nothing changed: keep the DOM (and the keyboard focus)
  const focused = document.activeElement?.dataset?.player;
  scoresKey = key;
  const rows = players.map((p) => {
    const tr = document.createElement('tr');
    tr.dataset.player = String(p.id);
    const name = document.createElement('td');
    const button = document.createElement('button');
    button.type = 'button';
    button.textContent = p.name;
    button.dataset.player = String(p.id);
    button.setAttribute('aria-pressed', String(state.followed === p.id));
    button.title = `Follow ${p.name}`;
    button.addEventListener('click', () => follow(state.followed === p.id ? null : p.id));
    name.append(button);
    tr.append(name);
    for (const value of [p.score, p.kills, p.deaths, p.alive ? p.health : 'dead']) {
      const td = document.createElement('td');
      td.textContent = String(value);
      tr.append(td);
    }
    return tr;
  });
  $('scores').replaceChildren(...rows);
  if (focused) $('scores').querySelector(`button[data-player="${focused}"]`)?.focus();
}

function follow(id) {
  state.followed = id;
  $('unfollow').disabled = id === null;
  if (frames.length > 0) renderScores(frames.at(-1));
}

// --- drawing ---

function bounds() {
  const [x0, , z0] = map.bounds.min;
  const [x1, , z1] = map.bounds.max;
  return { x0, z0, x1, z1, w: x1 - x0, h: z1 - z0 };
}

/// Sizes the canvas to its box and draws the map's static geometry once at that scale.
function layout() {
  const canvas = $('map');
  const dpr = window.devicePixelRatio || 1;
  const width = Math.max(1, Math.round(canvas.clientWidth * dpr));
  const height = Math.max(1, Math.round(canvas.clientHeight * dpr));
  if (view && view.width === width && view.height === height) return;
  canvas.width = width;
  canvas.height = height;
  const b = bounds();
  const scale = Math.min(width / b.w, height / b.h) * 0.95;  // px per metre
  const layer = document.createElement('canvas');
  layer.width = Math.ceil(b.w * scale);
  layer.height = Math.ceil(b.h * scale);
  const g = layer.getContext('2d');
  const px = (x, z) => [(x - b.x0) * scale, (z - b.z0) * scale];
  const style = getComputedStyle(document.documentElement);
  g.fillStyle = style.getPropertyValue('--bg');
  g.fillRect(0, 0, layer.width, layer.height);
  g.strokeStyle = style.getPropertyValue('--line');
  g.strokeRect(0.5, 0.5, layer.width - 1, layer.height - 1);
  // Meshes (ramps, terrain) under the boxes, lighter.
  g.fillStyle = 'rgba(120, 130, 140, 0.25)';
  for (const mesh of map.meshes) {
    g.beginPath();
    for (const [i, j, k] of mesh.triangles) {
      for (const [n, v] of [i, j, k].entries()) {
        const [x, y] = px(...mesh.vertices[v]);
        if (n === 0) g.moveTo(x, y); else g.lineTo(x, y);
      }
      g.closePath();
    }
    g.fill();
  }
  // Boxes and walls: the taller, the darker.
  const top = Math.max(1, ...map.boxes.map((box) => box.y_max));
  for (const box of map.boxes) {
    const shade = 0.35 + 0.45 * Math.min(1, Math.max(0, box.y_max / top));
    g.fillStyle = `rgba(87, 96, 106, ${shade.toFixed(2)})`;
    g.beginPath();
    box.corners.forEach(([x, z], n) => {
      const [sx, sy] = px(x, z);
      if (n === 0) g.moveTo(sx, sy); else g.lineTo(sx, sy);
    });
    g.closePath();
    g.fill();
  }
  g.fillStyle = 'rgba(207, 34, 46, 0.15)';
  for (const volume of map.kill_volumes) {
    const [sx, sy] = px(volume.min[0], volume.min[2]);
    g.fillRect(sx, sy, (volume.max[0] - volume.min[0]) * scale, (volume.max[2] - volume.min[2]) * scale);
  }
  const pickupColour = { health: '#1a7f37', armor: '#0550ae', ammo: '#9a6700' };
  for (const pickup of map.pickups) {
    const [sx, sy] = px(pickup.position[0], pickup.position[2]);
    g.fillStyle = pickupColour[pickup.kind] ?? '#57606a';
    g.fillRect(sx - 3 * dpr, sy - 3 * dpr, 6 * dpr, 6 * dpr);
  }
  g.strokeStyle = style.getPropertyValue('--muted');
  for (const spawn of map.spawns) {
    const [sx, sy] = px(spawn.position[0], spawn.position[2]);
    g.beginPath();
    g.arc(sx, sy, 4 * dpr, 0, 2 * Math.PI);
    g.stroke();
  }
  view = { scale, width, height, dpr, layer };
}

/// The world point at the middle of the view: the followed player, else the map's centre.
function centreOf(players) {
  const followed = players.find((p) => p.id === state.followed);
  if (followed) return [followed.x, followed.z];
  const b = bounds();
  return [b.x0 + b.w / 2, b.z0 + b.h / 2];
}

function draw(drawn) {
  layout();
  const ctx = $('map').getContext('2d');
  const { scale, width, height, dpr } = view;
  const b = bounds();
  const centre = centreOf(drawn.players);
  // screen = (world - centre) * scale + half the canvas
  const sx = (x) => (x - centre[0]) * scale + width / 2;
  const sy = (z) => (z - centre[1]) * scale + height / 2;
  const style = getComputedStyle(document.documentElement);
  ctx.fillStyle = style.getPropertyValue('--panel');
  ctx.fillRect(0, 0, width, height);
  ctx.drawImage(view.layer, sx(b.x0), sy(b.z0));
  for (const shot of drawn.projectiles) {
    ctx.fillStyle = shot.kind === 'rocket' ? '#bc4c00' : '#4d2d00';
    ctx.beginPath();
    ctx.arc(sx(shot.x), sy(shot.z), (shot.kind === 'rocket' ? 3 : 4) * dpr, 0, 2 * Math.PI);
    ctx.fill();
  }
  const radius = Math.max(5 * dpr, PLAYER_RADIUS_M * scale);
  ctx.font = `${12 * dpr}px system-ui, sans-serif`;
  ctx.textAlign = 'center';
  for (const p of drawn.players) {
    const x = sx(p.x);
    const y = sy(p.z);
    ctx.globalAlpha = p.connected ? 1 : 0.5;
    if (p.alive) {
      ctx.fillStyle = colourOf(p);
      ctx.beginPath();
      ctx.arc(x, y, radius, 0, 2 * Math.PI);
      ctx.fill();
      // Facing: yaw 0 is -z (up the screen), counter-clockwise seen from above.
      ctx.strokeStyle = ctx.fillStyle;
      ctx.lineWidth = 2 * dpr;
      ctx.beginPath();
      ctx.moveTo(x, y);
      ctx.lineTo(x - Math.sin(p.yaw) * radius * 2, y - Math.cos(p.yaw) * radius * 2);
      ctx.stroke();
      const barWidth = 28 * dpr;
      ctx.fillStyle = '#d0d7de';
      ctx.fillRect(x - barWidth / 2, y + radius + 3 * dpr, barWidth, 4 * dpr);
      ctx.fillStyle = p.health > 30 ? '#1a7f37' : '#cf222e';
      ctx.fillRect(x - barWidth / 2, y + radius + 3 * dpr,
                   (barWidth * Math.max(0, Math.min(MAX_HEALTH, p.health))) / MAX_HEALTH, 4 * dpr);
    } else {
      ctx.strokeStyle = '#8b949e';
      ctx.lineWidth = 2 * dpr;
      ctx.beginPath();
      ctx.moveTo(x - radius, y - radius);
      ctx.lineTo(x + radius, y + radius);
      ctx.moveTo(x + radius, y - radius);
      ctx.lineTo(x - radius, y + radius);
      ctx.stroke();
    }
    if (p.id === state.followed) {
      ctx.strokeStyle = style.getPropertyValue('--accent');
      ctx.lineWidth = 2 * dpr;
      ctx.beginPath();
      ctx.arc(x, y, radius + 4 * dpr, 0, 2 * Math.PI);
      ctx.stroke();
    }
    ctx.fillStyle = style.getPropertyValue('--fg');
    ctx.fillText(p.name, x, y - radius - 4 * dpr);
    ctx.globalAlpha = 1;
  }
  state.centre = centre;
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
  if (!view) return;
  const rect = event.currentTarget.getBoundingClientRect();
  const x = (event.clientX - rect.left) * view.dpr;
  const y = (event.clientY - rect.top) * view.dpr;
  const centre = state.centre ?? [0, 0];
  let best = null;
  let bestDistance = PICK_RADIUS_PX * view.dpr;
  for (const p of state.players) {
    const d = Math.hypot((p.x - centre[0]) * view.scale + view.width / 2 - x,
                         (p.z - centre[1]) * view.scale + view.height / 2 - y);
    if (d <= bestDistance) {
      best = p.id;
      bestDistance = d;
    }
  }
  follow(best);
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
window.ricochetLive.toScreen = ([x, z]) => {
  const rect = $('map').getBoundingClientRect();
  const centre = state.centre ?? [0, 0];
  return [rect.left + ((x - centre[0]) * view.scale + view.width / 2) / view.dpr,
          rect.top + ((z - centre[1]) * view.scale + view.height / 2) / view.dpr];
};
start();
