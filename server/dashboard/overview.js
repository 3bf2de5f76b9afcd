// The overview page: the server's figures, its matches with their tick times as sparklines, and
// every drop and refusal, from /api/overview/events (one JSON object a second, see
// server/src/net/overview.h). Each top-level section of that object has a renderer below; a new
// section (the fleet's servers) adds one.
import { sparkline } from './sparkline.js';

const $ = (id) => document.getElementById(id);

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

function renderRefusals(refusals) {
  const rows = refusals.map((r) => {
    const tr = document.createElement('tr');
    tr.append(cell(r.channel), cell(r.reason), cell(String(r.count)));
    return tr;
  });
  if (rows.length === 0) {
    const tr = document.createElement('tr');
    const td = cell('None since the start', 'empty');
    td.colSpan = 3;
    tr.append(td);
    rows.push(tr);
  }
  $('refusals').replaceChildren(...rows);
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
