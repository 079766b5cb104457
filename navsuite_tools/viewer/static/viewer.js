// The map view: layers from the /events stream drawn on a canvas (+y up, like RViz's top view),
// pan/zoom, and RViz's "2D Pose Estimate" / "Nav2 Goal" tools. Payload formats: navsuite_tools/viewer/encode.py.
'use strict';

const LAYERS = [  // [key, label, on by default] in drawing order
  ['map', 'Map', true], ['global_costmap', 'Global costmap', true], ['local_costmap', 'Local costmap', true],
  ['particles', 'Particle cloud', true], ['plan', 'Global plan', true], ['local_plan', 'Local plan', true],
  ['waypoints', 'Waypoints', true], ['goal', 'Goal', true], ['scan', 'Laser scan', true],
  ['trajectories', 'MPPI trajectories', true], ['collision_polygons', 'Collision polygons', true],
  ['collision_points', 'Collision points', true],
  ['footprint', 'Footprint', true], ['truth', 'Ground truth', true], ['amcl', 'AMCL pose', true],
];
const GRIDS = new Set(['map', 'global_costmap', 'local_costmap']);
const COLORS = {
  background: '#303338', scan: '#ff3b30', plan: '#3fb950', local_plan: '#f0b429', particles: '#d2a8ff',
  truth: '#40c463', amcl: '#ff9f1c', goal: '#ff4fd8', waypoints: '#4aa3ff', footprint: '#00e5ff', drag: '#ffffff',
  collision_polygons: '#ff6b6b',
};

const viewer = {
  layers: {},            // key → latest payload
  images: {},            // grid key → {canvas, payload}
  visible: Object.fromEntries(LAYERS.map(([k, , on]) => [k, on])),
  view: {cx: 0, cy: 0, scale: 50, fitted: false},  // centre (m), pixels per metre
  tool: 'pan',
  drag: null,
  batches: 0,
  drawn: {},             // what the last frame drew (for tests and the curious)
  published: [],         // clicks the server accepted
};
window.viewer = viewer;

const canvas = document.getElementById('map');
const ctx = canvas.getContext('2d');

// ---------------------------------------------------------------- coordinates
function size() { return {w: canvas.clientWidth, h: canvas.clientHeight}; }
viewer.worldToScreen = (x, y) => {
  const {w, h} = size(), v = viewer.view;
  return [w / 2 + (x - v.cx) * v.scale, h / 2 - (y - v.cy) * v.scale];
};
viewer.screenToWorld = (sx, sy) => {
  const {w, h} = size(), v = viewer.view;
  return [v.cx + (sx - w / 2) / v.scale, v.cy - (sy - h / 2) / v.scale];
};

// ---------------------------------------------------------------- grids → offscreen canvases
const MAP_LUT = (() => {  // free light, occupied dark, unknown blue-grey; 101..254 are invalid: transparent
  const lut = new Uint8ClampedArray(256 * 4);
  for (let v = 0; v <= 100; v++) {
    const g = Math.round(247 - v * 2.3);
    lut.set([g, g, g, 255], v * 4);
  }
  lut.set([120, 126, 136, 255], 255 * 4);
  return lut;
})();
const COSTMAP_LUT = (() => {  // RViz "costmap" scheme: blue→red ramp, inscribed cyan, lethal magenta
  const lut = new Uint8ClampedArray(256 * 4);
  for (let v = 1; v <= 98; v++) {
    const t = (v - 1) / 97;
    lut.set([Math.round(255 * t), 0, Math.round(255 * (1 - t)), 110], v * 4);
  }
  lut.set([0, 255, 255, 150], 99 * 4);
  lut.set([255, 0, 255, 170], 100 * 4);
  return lut;  // 0 (free) and 255 (unknown) stay transparent
})();

function gridImage(key, grid) {
  const bytes = Uint8Array.from(atob(grid.data), (c) => c.charCodeAt(0));
  const off = document.createElement('canvas');
  off.width = Math.max(grid.width, 1);
  off.height = Math.max(grid.height, 1);
  const image = off.getContext('2d').createImageData(off.width, off.height);
  const lut = key === 'map' ? MAP_LUT : COSTMAP_LUT;
  for (let row = 0; row < grid.height; row++) {  // grid row 0 is the bottom: it becomes the last image row
    const src = row * grid.width, dst = (grid.height - 1 - row) * grid.width;
    for (let col = 0; col < grid.width; col++) {
      image.data.set(lut.subarray(bytes[src + col] * 4, bytes[src + col] * 4 + 4), (dst + col) * 4);
    }
  }
  off.getContext('2d').putImageData(image, 0, 0);
  return {canvas: off, grid};
}

// ---------------------------------------------------------------- drawing
let pending = false;
function requestDraw() {
  if (!pending) { pending = true; requestAnimationFrame(draw); }
}
viewer.requestDraw = requestDraw;

function draw() {
  pending = false;
  const dpr = window.devicePixelRatio || 1, {w, h} = size();
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
  }
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.fillStyle = COLORS.background;
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  const v = viewer.view, s = v.scale;
  ctx.setTransform(dpr * s, 0, 0, -dpr * s, dpr * (w / 2 - v.cx * s), dpr * (h / 2 + v.cy * s));  // world, +y up
  const px = 1 / s;  // one screen pixel in metres
  const drawn = {};
  for (const [key] of LAYERS) {
    const value = viewer.layers[key];
    if (!viewer.visible[key] || !value || value.error) continue;
    drawn[key] = DRAW[key](value, px, key);
  }
  if (viewer.drag && viewer.drag.kind !== 'pan') drawArrow(viewer.drag.start, viewer.drag.end, COLORS.drag, px, 0.5);
  viewer.drawn = drawn;
}

function drawGrid(value, px, key) {
  const img = viewer.images[key];
  if (!img) return 0;
  const g = img.grid, [ox, oy, oyaw] = g.origin;
  ctx.save();
  ctx.imageSmoothingEnabled = false;
  ctx.translate(ox, oy);
  ctx.rotate(oyaw);
  ctx.scale(g.resolution, -g.resolution);  // image rows run downwards, +y runs up
  ctx.drawImage(img.canvas, 0, -g.height);
  ctx.restore();
  return g.width * g.height;
}

function polyline(flat, stride, color, width) {
  if (flat.length < 2 * stride) return;
  ctx.beginPath();
  ctx.moveTo(flat[0], flat[1]);
  for (let i = stride; i < flat.length; i += stride) ctx.lineTo(flat[i], flat[i + 1]);
  ctx.strokeStyle = color;
  ctx.lineWidth = width;
  ctx.stroke();
}

function drawArrow([x, y], [x2, y2], color, px, length) {
  const yaw = Math.atan2(y2 - y, x2 - x);
  const len = Math.max(length, Math.hypot(x2 - x, y2 - y));
  const ex = x + len * Math.cos(yaw), ey = y + len * Math.sin(yaw), head = Math.min(0.15, len / 3);
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(ex, ey);
  ctx.lineTo(ex - head * Math.cos(yaw - 0.45), ey - head * Math.sin(yaw - 0.45));
  ctx.moveTo(ex, ey);
  ctx.lineTo(ex - head * Math.cos(yaw + 0.45), ey - head * Math.sin(yaw + 0.45));
  ctx.strokeStyle = color;
  ctx.lineWidth = 3 * px;
  ctx.stroke();
}

function poseArrow(x, y, yaw, color, px, length) {
  drawArrow([x, y], [x + Math.cos(yaw) * length, y + Math.sin(yaw) * length], color, px, length);
}

function drawRobot([x, y, yaw], color, px, fill) {
  const r = (viewer.layers.info && viewer.layers.info.robot_radius) || 0.22;
  ctx.beginPath();
  ctx.arc(x, y, r, 0, 2 * Math.PI);
  ctx.fillStyle = fill;
  ctx.fill();
  ctx.strokeStyle = color;
  ctx.lineWidth = 2.5 * px;
  ctx.stroke();
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(x + r * Math.cos(yaw), y + r * Math.sin(yaw));
  ctx.stroke();
}

function drawDots(v, px) {  // groups of [x, y, ...] dots, each in its own colour (layers.marker_dots)
  const d = 2.5 * px;
  let n = 0;
  for (const g of v.groups) {
    ctx.fillStyle = g.color;
    for (let i = 0; i < g.points.length; i += 2) ctx.fillRect(g.points[i] - d / 2, g.points[i + 1] - d / 2, d, d);
    n += g.points.length / 2;
  }
  return n;
}

const DRAW = {
  map: drawGrid, global_costmap: drawGrid, local_costmap: drawGrid,
  particles(v, px) {
    const p = v.poses;
    ctx.beginPath();
    for (let i = 0; i < p.length; i += 3) {
      ctx.moveTo(p[i], p[i + 1]);
      ctx.lineTo(p[i] + 0.12 * Math.cos(p[i + 2]), p[i + 1] + 0.12 * Math.sin(p[i + 2]));
    }
    ctx.strokeStyle = COLORS.particles;
    ctx.lineWidth = 1.2 * px;
    ctx.stroke();
    return p.length / 3;
  },
  plan(v, px) {  // the plan's last pose is where navigation is heading: ring it
    const p = v.poses, n = p.length;
    polyline(p, 3, COLORS.plan, 3 * px);
    if (n >= 3) {
      ctx.beginPath();
      ctx.arc(p[n - 3], p[n - 2], 7 * px, 0, 2 * Math.PI);
      ctx.strokeStyle = COLORS.plan;
      ctx.lineWidth = 2 * px;
      ctx.stroke();
    }
    return n / 3;
  },
  local_plan(v, px) { polyline(v.poses, 3, COLORS.local_plan, 3 * px); return v.poses.length / 3; },
  waypoints(v, px) {
    const p = v.poses;
    for (let i = 0; i < p.length; i += 3) {
      ctx.beginPath();
      ctx.arc(p[i], p[i + 1], 6 * px, 0, 2 * Math.PI);
      ctx.fillStyle = COLORS.waypoints;
      ctx.fill();
      poseArrow(p[i], p[i + 1], p[i + 2], COLORS.waypoints, px, 0.3);
    }
    return p.length / 3;
  },
  goal(v, px) {
    const [x, y, yaw] = v.pose;
    poseArrow(x, y, yaw, COLORS.goal, px, 0.45);
    return 1;
  },
  scan(v, px) {
    const p = v.points, d = 3 * px;
    ctx.fillStyle = COLORS.scan;
    for (let i = 0; i < p.length; i += 2) ctx.fillRect(p[i] - d / 2, p[i + 1] - d / 2, d, d);
    return p.length / 2;
  },
  trajectories: drawDots,       // MPPI's sampled and optimal trajectories, in their markers' colours
  collision_points: drawDots,   // the points the collision monitor used, one group per source
  collision_polygons(v, px) {   // the collision monitor's zones (Stop, Slowdown, ...), one outline per topic
    let n = 0;
    for (const p of Object.values(v.polygons)) {
      if (p.length < 6) continue;
      polyline([...p, p[0], p[1]], 2, COLORS.collision_polygons, 1.5 * px);
      n += 1;
    }
    return n;
  },
  footprint(v, px) {
    const p = v.points;
    if (p.length < 6) return 0;
    polyline([...p, p[0], p[1]], 2, COLORS.footprint, 1.5 * px);
    return p.length / 2;
  },
  truth(v, px) { drawRobot(v.pose, COLORS.truth, px, 'rgba(64,196,99,0.35)'); return 1; },
  amcl(v, px) {
    const [x, y] = v.pose, [xx, , yy] = v.covariance;
    drawRobot(v.pose, COLORS.amcl, px, 'rgba(255,159,28,0.15)');
    ctx.beginPath();  // 2σ position uncertainty (axis-aligned approximation)
    ctx.ellipse(x, y, 2 * Math.sqrt(Math.max(xx, 0)), 2 * Math.sqrt(Math.max(yy, 0)), 0, 0, 2 * Math.PI);
    ctx.setLineDash([6 * px, 4 * px]);
    ctx.lineWidth = 1.5 * px;
    ctx.stroke();
    ctx.setLineDash([]);
    return 1;
  },
};

// ---------------------------------------------------------------- view fitting
function fit() {
  const {w, h} = size(), img = viewer.images.map, v = viewer.view;
  if (img) {
    const g = img.grid, mw = g.width * g.resolution, mh = g.height * g.resolution;
    v.scale = Math.max(1, Math.min(w / mw, h / mh) * 0.95);
    v.cx = g.origin[0] + mw / 2;
    v.cy = g.origin[1] + mh / 2;
    v.fitted = true;
  } else {
    const robot = viewer.layers.truth || viewer.layers.amcl;
    if (robot && robot.pose) { [v.cx, v.cy] = robot.pose; v.scale = 80; v.fitted = true; }
  }
  requestDraw();
}
viewer.fit = fit;

// ---------------------------------------------------------------- the stream
function onLayer(key, value) {
  viewer.layers[key] = value;
  if (GRIDS.has(key) && value && !value.error) {
    viewer.images[key] = gridImage(key, value);
    if (key === 'map' && !viewer.view.fitted) fit();
  }
  if ((key === 'truth' || key === 'amcl') && !viewer.view.fitted) fit();
  const label = document.querySelector(`#layers label[data-key="${key}"]`);
  if (label) label.classList.toggle('absent', !!value.error);
  window.Panels.update(key, value, viewer);
}

function connect() {
  const status = document.getElementById('connection');
  const events = new EventSource('/events');
  events.onopen = () => { status.textContent = 'live'; status.className = 'ok'; };
  events.onerror = () => { status.textContent = 'reconnecting…'; status.className = 'bad'; };
  events.onmessage = (e) => {
    const batch = JSON.parse(e.data);
    viewer.batches += 1;
    for (const [key, value] of Object.entries(batch.layers)) onLayer(key, value);
    requestDraw();
  };
}

// ---------------------------------------------------------------- tools and input
function setTool(tool) {
  viewer.tool = tool;
  for (const b of document.querySelectorAll('button[data-tool]')) b.classList.toggle('active', b.dataset.tool === tool);
  canvas.classList.toggle('posing', tool !== 'pan');
}
viewer.setTool = setTool;

function say(text) { document.getElementById('message').textContent = text; }

async function publishPose(tool, [x, y], yaw) {
  const endpoint = tool === 'goal' ? '/api/goal' : '/api/initial_pose';
  try {
    const response = await fetch(endpoint, {method: 'POST', headers: {'Content-Type': 'application/json'},
      body: JSON.stringify({x, y, yaw})});
    const reply = await response.json();
    if (!response.ok) throw new Error(reply.error || response.statusText);
    viewer.published.push({tool, x, y, yaw});
    say(`${reply.topic}: x ${x.toFixed(2)} y ${y.toFixed(2)} yaw ${(yaw * 180 / Math.PI).toFixed(0)}°`);
  } catch (err) {
    say(`publish failed: ${err.message}`);
  }
}

function eventPoint(e) {
  const r = canvas.getBoundingClientRect();
  return [e.clientX - r.left, e.clientY - r.top];
}

canvas.addEventListener('mousedown', (e) => {
  const sp = eventPoint(e);
  if (viewer.tool === 'pan' || e.button !== 0) {
    viewer.drag = {kind: 'pan', last: sp};
  } else {
    const wp = viewer.screenToWorld(...sp);
    viewer.drag = {kind: viewer.tool, start: wp, end: wp};
  }
});
window.addEventListener('mousemove', (e) => {
  const sp = eventPoint(e), wp = viewer.screenToWorld(...sp);
  document.getElementById('cursor').textContent = `x ${wp[0].toFixed(2)}  y ${wp[1].toFixed(2)}`;
  const d = viewer.drag;
  if (!d) return;
  if (d.kind === 'pan') {
    viewer.view.cx -= (sp[0] - d.last[0]) / viewer.view.scale;
    viewer.view.cy += (sp[1] - d.last[1]) / viewer.view.scale;
    d.last = sp;
  } else {
    d.end = wp;
  }
  requestDraw();
});
window.addEventListener('mouseup', (e) => {
  const d = viewer.drag;
  viewer.drag = null;
  if (!d || d.kind === 'pan') return;
  const end = viewer.screenToWorld(...eventPoint(e));
  const dx = end[0] - d.start[0], dy = end[1] - d.start[1];
  const yaw = Math.hypot(dx, dy) * viewer.view.scale > 4 ? Math.atan2(dy, dx) : 0;  // a click without drag faces +x
  publishPose(d.kind, d.start, yaw);
  setTool('pan');  // like RViz, a pose tool is used once
  requestDraw();
});
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  const sp = eventPoint(e), before = viewer.screenToWorld(...sp);
  viewer.view.scale = Math.min(2000, Math.max(2, viewer.view.scale * Math.exp(-e.deltaY * 0.0015)));
  const after = viewer.screenToWorld(...sp);
  viewer.view.cx += before[0] - after[0];
  viewer.view.cy += before[1] - after[1];
  requestDraw();
}, {passive: false});

// ---------------------------------------------------------------- start
(function init() {
  const box = document.getElementById('layers');
  for (const [key, label, on] of LAYERS) {
    const row = document.createElement('label');
    row.dataset.key = key;
    const check = document.createElement('input');
    check.type = 'checkbox';
    check.checked = on;
    check.addEventListener('change', () => { viewer.visible[key] = check.checked; requestDraw(); });
    row.append(check, ' ', label);
    box.append(row);
  }
  for (const b of document.querySelectorAll('button[data-tool]')) b.addEventListener('click', () => setTool(b.dataset.tool));
  document.getElementById('fit').addEventListener('click', fit);
  window.addEventListener('resize', requestDraw);
  connect();
  requestDraw();
})();
