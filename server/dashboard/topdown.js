// A map and what moves on it, seen from above: the one view the live page and the Recordings page
// draw with. The map is GET .../map's JSON (server/src/web/map_view.h); world axes as the
// server's: metres, x right, z down the screen (+y up, out of it); yaw 0 faces -z, counter-
// clockwise seen from above. The static geometry is drawn once per canvas size into a layer of
// its own; each draw() copies it and draws the players and projectiles on top.

const PLAYER_RADIUS_M = 0.5;  // drawn size of a player (the sphere's, about)
const PICK_RADIUS_PX = 16;    // a click this near a player picks it, CSS px
const MAX_HEALTH = 100;

function colour(name) {
  return getComputedStyle(document.documentElement).getPropertyValue(name).trim();
}

export class TopDown {
  /// `canvas`: sized to its CSS box at each draw; `map`: the map view JSON.
  constructor(canvas, map) {
    this.canvas = canvas;
    this.map = map;
    const [x0, , z0] = map.bounds.min;
    const [x1, , z1] = map.bounds.max;
    this.bounds = { x0, z0, w: x1 - x0 || 1, h: z1 - z0 || 1 };
    this.view = null;  // {scale px per m, width, height, dpr, layer, palette}
    this.centre = null;  // [x, z] drawn at the middle of the canvas by the last draw, m
  }

  /// Draws `players` ([{id, name, x, z, yaw, alive, health, faded?, colour}]) and `projectiles`
  /// ([{kind: 'rocket'|'grenade', x, z}]) centred on the player `followed` (an id), else on the
  /// map's middle; the followed one ringed.
  draw({ players, projectiles, followed = null }) {
    this.#layout();
    const g = this.canvas.getContext('2d');
    const { scale, width, height, dpr } = this.view;
    const b = this.bounds;
    const target = players.find((p) => p.id === followed);
    this.centre = target ? [target.x, target.z] : [b.x0 + b.w / 2, b.z0 + b.h / 2];
    const [sx, sy] = [(x) => this.#x(x), (z) => this.#y(z)];
    const palette = this.view.palette;
    g.fillStyle = palette.panel;
    g.fillRect(0, 0, width, height);
    g.drawImage(this.view.layer, sx(b.x0), sy(b.z0));
    for (const shot of projectiles) {
      g.fillStyle = shot.kind === 'rocket' ? '#bc4c00' : '#4d2d00';
      g.beginPath();
      g.arc(sx(shot.x), sy(shot.z), (shot.kind === 'rocket' ? 3 : 4) * dpr, 0, 2 * Math.PI);
      g.fill();
    }
    const radius = Math.max(5 * dpr, PLAYER_RADIUS_M * scale);
    g.font = `${12 * dpr}px system-ui, sans-serif`;
    g.textAlign = 'center';
    for (const p of players) {
      const [x, y] = [sx(p.x), sy(p.z)];
      g.globalAlpha = p.faded ? 0.5 : 1;
      g.lineWidth = 2 * dpr;
      if (p.alive) {
        g.fillStyle = p.colour;
        g.beginPath();
        g.arc(x, y, radius, 0, 2 * Math.PI);
        g.fill();
        g.strokeStyle = p.colour;
        g.beginPath();
        g.moveTo(x, y);
        g.lineTo(x - Math.sin(p.yaw) * radius * 2, y - Math.cos(p.yaw) * radius * 2);
        g.stroke();
        const bar = 28 * dpr;
        const health = Math.max(0, Math.min(MAX_HEALTH, p.health));
        g.fillStyle = '#d0d7de';
        g.fillRect(x - bar / 2, y + radius + 3 * dpr, bar, 4 * dpr);
        g.fillStyle = p.health > 30 ? '#1a7f37' : '#cf222e';
        g.fillRect(x - bar / 2, y + radius + 3 * dpr, (bar * health) / MAX_HEALTH, 4 * dpr);
      } else {
        g.strokeStyle = '#8b949e';
        g.beginPath();
        g.moveTo(x - radius, y - radius);
        g.lineTo(x + radius, y + radius);
        g.moveTo(x + radius, y - radius);
        g.lineTo(x - radius, y + radius);
        g.stroke();
      }
      if (p.id === followed) {
        g.strokeStyle = palette.accent;
        g.beginPath();
        g.arc(x, y, radius + 4 * dpr, 0, 2 * Math.PI);
        g.stroke();
      }
      g.fillStyle = palette.fg;
      g.fillText(p.name, x, y - radius - 4 * dpr);
      g.globalAlpha = 1;
    }
  }

  /// Where the world point [x, z] was drawn, in the page's CSS pixels (clientX, clientY).
  toScreen([x, z]) {
    const rect = this.canvas.getBoundingClientRect();
    return [rect.left + this.#x(x) / this.view.dpr, rect.top + this.#y(z) / this.view.dpr];
  }

  /// The id of the player of `players` drawn nearest the page point (clientX, clientY), within
  /// PICK_RADIUS_PX; null when none.
  pick(clientX, clientY, players) {
    if (!this.view) return null;
    let best = null;
    let bestDistance = PICK_RADIUS_PX;
    for (const p of players) {
      const [x, y] = this.toScreen([p.x, p.z]);
      const d = Math.hypot(x - clientX, y - clientY);
      if (d <= bestDistance) {
        best = p.id;
        bestDistance = d;
      }
    }
    return best;
  }

  // canvas = (world - centre) * scale + half the canvas, device px
  #x(x) { return (x - this.centre[0]) * this.view.scale + this.view.width / 2; }
  #y(z) { return (z - this.centre[1]) * this.view.scale + this.view.height / 2; }

  /// Sizes the canvas to its box and draws the static geometry once at that scale.
  #layout() {
    const dpr = window.devicePixelRatio || 1;
    const width = Math.max(1, Math.round(this.canvas.clientWidth * dpr));
    const height = Math.max(1, Math.round(this.canvas.clientHeight * dpr));
    if (this.view && this.view.width === width && this.view.height === height) return;
    this.canvas.width = width;
    this.canvas.height = height;
    const b = this.bounds;
    const map = this.map;
    const scale = Math.min(width / b.w, height / b.h) * 0.95;
    const layer = document.createElement('canvas');
    layer.width = Math.ceil(b.w * scale);
    layer.height = Math.ceil(b.h * scale);
    const g = layer.getContext('2d');
    const px = (x, z) => [(x - b.x0) * scale, (z - b.z0) * scale];
    g.fillStyle = colour('--bg');
    g.fillRect(0, 0, layer.width, layer.height);
    g.strokeStyle = colour('--line');
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
    // Kill volumes as dashed outlines: one under the whole floor (a fall out of the map) must not
    // tint everything.
    g.strokeStyle = 'rgba(207, 34, 46, 0.6)';
    g.setLineDash([4 * dpr, 4 * dpr]);
    for (const volume of map.kill_volumes) {
      const [sx, sy] = px(volume.min[0], volume.min[2]);
      g.strokeRect(sx, sy, (volume.max[0] - volume.min[0]) * scale,
                   (volume.max[2] - volume.min[2]) * scale);
    }
    g.setLineDash([]);
    const pickupColour = { health: '#1a7f37', armor: '#0550ae', ammo: '#9a6700' };
    for (const pickup of map.pickups) {
      const [sx, sy] = px(pickup.position[0], pickup.position[2]);
      g.fillStyle = pickupColour[pickup.kind] ?? '#57606a';
      g.fillRect(sx - 3 * dpr, sy - 3 * dpr, 6 * dpr, 6 * dpr);
    }
    g.strokeStyle = colour('--muted');
    for (const spawn of map.spawns) {
      const [sx, sy] = px(spawn.position[0], spawn.position[2]);
      g.beginPath();
      g.arc(sx, sy, 4 * dpr, 0, 2 * Math.PI);
      g.stroke();
    }
    // The page's colours, read once per layout: getComputedStyle per player per frame is not free.
    const palette = { panel: colour('--panel'), accent: colour('--accent'), fg: colour('--fg') };
    this.view = { scale, width, height, dpr, layer, palette };
  }
}
