// The overview page: the server's figures, its matches with their tick times as sparklines, and
// every drop and refusal, from /api/overview/events (one JSON object a second, see
// server/src/net/overview.h). Each top-level section of that object has a renderer below. When
// the server is in a fleet directory (server.fleet), the page also reads GET /fleet itself
// (server/src/net/fleet_view.h) every FLEET_PERIOD_MS while it is open: a directory read per
// open page, not one per overview sample.
import { sparkline } from './sparkline.js';

const $ = (id) => document.getElementById(id);
const FLEET_PERIOD_MS = 5000;

function cell(text, className) {
  const td = document.createElement('td');
  td.textContent = text;
  if (className) td.className = className;
  return td;
}

function bytesPerSecond(value) {
  if (value >= 1e6) return `${(value / 1e6).toFixed(2)} MB/s`;
  if (value >= 1e3) return `${(value / 1e3).toFixed(1)} kB/s`;
  return `${value.toFixed(0)} B/s`;
}

function duration(seconds) {
  if (seconds === null) return '—';
  const s = Math.ceil(seconds);
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`;
}

function renderServer(server) {
  if (server.fleet) watchFleet();
  const figures = [
    ['Matches', server.matches],
    ['Players', server.players],
    ['In', bytesPerSecond(server.bytes_in_per_s)],
    ['Out', bytesPerSecond(server.bytes_out_per_s)],
    ['DB queue', server.db_queue_depth],
  ];
  $('server').replaceChildren(...figures.map(([name, value]) => {
    const div = document.createElement('div');
    const dt = document.createElement('dt');
    const dd = document.createElement('dd');
    dt.textContent = name;
    dd.textContent = String(value);
    div.append(dt, dd);
    return div;
  }));
}

function renderMatches(matches) {
  const rows = matches.map((match) => {
    const tr = document.createElement('tr');
    tr.dataset.match = String(match.id);
    const p50 = match.tick_p50_ms.at(-1) ?? 0;
    const p99 = match.tick_p99_ms.at(-1) ?? 0;
    const ticks = document.createElement('td');
    const spark = document.createElement('span');
    spark.className = 'spark';
    const figures = document.createElement('span');
    figures.textContent = `${p50.toFixed(2)} / ${p99.toFixed(2)}`;
    spark.append(sparkline([{ name: 'p50', values: match.tick_p50_ms },
                            { name: 'p99', values: match.tick_p99_ms }],
                           `tick time of ${match.name}: p50 ${p50.toFixed(2)} ms, p99 ${p99.toFixed(2)} ms`),
                 figures);
    ticks.append(spark);
    const name = cell('');
    const live = document.createElement('a');
    live.href = `/live.html?match=${match.id}`;
    live.textContent = match.name;
    live.title = `Watch ${match.name} live`;
    name.append(live);
    tr.append(name, cell(match.map), cell(match.mode), cell(match.phase),
              cell(`${match.connected} / ${match.max_players}`),
              cell(match.leader === null ? '—' : `${match.leader} (${match.leader_score})`),
              cell(duration(match.time_left_s)), ticks, cell(String(match.overruns)));
    return tr;
  });
  if (rows.length === 0) {
    const tr = document.createElement('tr');
    const td = cell('No matches', 'empty');
    td.colSpan = 9;
    tr.append(td);
    rows.push(tr);
  }
  $('matches').replaceChildren(...rows);
}

// Expected drops (an input repeated by a later packet: the redundancy) are not problems; they
// are listed under the table, apart.
function renderRefusals(refusals) {
  const problems = refusals.filter((r) => !r.expected);
  const expected = refusals.filter((r) => r.expected);
  const rows = problems.map((r) => {
    const tr = document.createElement('tr');
    tr.append(cell(r.channel), cell(r.reason), cell(String(r.count)));
    return tr;
  });
  $('expected').textContent = expected.length === 0 ? '' :
    `Expected, not problems: ${expected.map((r) => `${r.count} ${r.channel} ${r.reason}`).join(', ')} ` +
    '(every packet repeats the last inputs, so most arrive more than once).';
  if (rows.length === 0) {
    const tr = document.createElement('tr');
    const td = cell('None since the start', 'empty');
    td.colSpan = 3;
    tr.append(td);
    rows.push(tr);
  }
  $('refusals').replaceChildren(...rows);
}

function seconds(ms) {
  return `${(ms / 1000).toFixed(1)} s`;
}

function renderFleet(fleet) {
  const rows = fleet.servers.map((server) => {
    const tr = document.createElement('tr');
    tr.dataset.server = server.server_id;
    const id = cell(server.server_id);
    if (server.self) {
      id.append(' (this server)');
      tr.className = 'self';
    }
    const dashboard = cell('');
    if (!server.self && server.admin_port !== null) {
      const link = document.createElement('a');
      link.href = `http://${server.host}:${server.admin_port}/`;
      link.textContent = 'Open';
      link.title = `The dashboard of ${server.server_id}`;
      dashboard.append(link);
    } else {
      dashboard.textContent = server.self ? 'here' : '—';
    }
    const open = server.matches.filter((m) => m.open).length;
    tr.append(id, cell(`${server.host}:${server.control_port}`), cell(server.version),
              cell(`${server.players} / ${server.capacity}`),
              cell(`${server.matches.length} (${open} open)`),
              cell(seconds(server.heartbeat_age_ms)), dashboard);
    return tr;
  });
  $('fleet').replaceChildren(...rows);
  $('fleet-status').textContent = `${fleet.servers.length} servers in the directory`;
}

let fleetTimer = null;

async function readFleet() {
  try {
    const response = await fetch('/fleet');
    if (!response.ok) {
      $('fleet-status').textContent = `The directory did not answer (${response.status}): ${await response.text()}`;
      return;
    }
    renderFleet(await response.json());
  } catch (error) {
    $('fleet-status').textContent = `The directory could not be read: ${error.message}`;
  }
}

function watchFleet() {
  if (fleetTimer !== null) return;
  $('fleet-section').hidden = false;
  readFleet();
  fleetTimer = setInterval(readFleet, FLEET_PERIOD_MS);
}

const sections = { server: renderServer, matches: renderMatches, refusals: renderRefusals };

export function render(overview) {
  for (const [key, draw] of Object.entries(sections)) {
    if (key in overview) draw(overview[key]);
  }
  $('status').textContent = `Updated ${new Date().toLocaleTimeString()}`;
}

const events = new EventSource('/api/overview/events');
events.onmessage = (event) => render(JSON.parse(event.data));
events.onerror = () => {
  $('status').textContent = 'Connection lost; reconnecting…';
};
