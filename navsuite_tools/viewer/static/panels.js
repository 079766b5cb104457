// Side panels: battery, navigation status, SMACC2 state machines (layered SVG graph, current state
// highlighted, recent transitions with tags), behavior tree node statuses, subscribed topics.
// All text goes through textContent: message strings are never parsed as HTML.
'use strict';

const SVG_NS = 'http://www.w3.org/2000/svg';
const POWER_STATUS = {1: 'charging', 2: 'discharging', 3: 'not charging', 4: 'full'};

function el(tag, attrs = {}, text) {
  const node = tag.startsWith('svg:') ? document.createElementNS(SVG_NS, tag.slice(4)) : document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  if (text !== undefined) node.textContent = text;
  return node;
}

function battery(v) {
  const text = document.getElementById('battery-text'), fill = document.getElementById('battery-fill');
  if (v.percentage === null || v.percentage === undefined) { text.textContent = 'percentage unknown'; return; }
  const pct = Math.max(0, Math.min(1, v.percentage)) * 100;
  fill.style.width = `${pct}%`;
  fill.style.background = pct < 20 ? 'var(--failure)' : pct < 40 ? 'var(--running)' : 'var(--success)';
  const parts = [`${pct.toFixed(1)} %`];
  if (v.voltage !== null && v.voltage > 0) parts.push(`${v.voltage.toFixed(2)} V`);
  if (POWER_STATUS[v.status]) parts.push(POWER_STATUS[v.status]);
  text.textContent = parts.join(' · ');
  text.className = '';
}

function navStatus(v) {
  const box = document.getElementById('nav-status');
  box.textContent = v.status ? `navigate_to_pose: ${v.status}` : 'navigate_to_pose: no goal';
  box.className = '';
}

function topics(info) {
  const list = document.getElementById('topics');
  list.replaceChildren(...Object.entries(info.topics).map(([topic, t]) =>
    el('li', {}, t.error ? `${topic}: ${t.error}` : `${topic}  ${t.type.replace('/msg/', '/')}  ${t.reliability}/${t.durability}`)));
}

// ---------------------------------------------------------------- state machines
const NODE_H = 28, LAYER_GAP = 64, NODE_GAP = 18, PAD = 14, SIDE = 70;  // SIDE: room for back edges

function layout(snap) {
  const layers = new Map();
  for (const n of snap.nodes) {
    n.w = Math.max(72, n.id.length * 7 + 20);
    if (!layers.has(n.layer)) layers.set(n.layer, []);
    layers.get(n.layer).push(n);
  }
  let width = 0;
  for (const row of layers.values()) {
    row.sort((a, b) => a.order - b.order);
    row.total = row.reduce((sum, n) => sum + n.w, 0) + NODE_GAP * (row.length - 1);
    width = Math.max(width, row.total);
  }
  const pos = {};
  for (const [depth, row] of layers) {
    let x = SIDE + (width - row.total) / 2;
    for (const n of row) {
      pos[n.id] = {x, y: PAD + depth * (NODE_H + LAYER_GAP), w: n.w, node: n};
      x += n.w + NODE_GAP;
    }
  }
  const depth = Math.max(0, ...snap.nodes.map((n) => n.layer));
  return {pos, width: width + 2 * SIDE, height: (depth + 1) * (NODE_H + LAYER_GAP) - LAYER_GAP + 2 * PAD};
}

function edgePath(a, b, width) {
  if (a === b) {  // self transition: a loop on the right
    const x = a.x + a.w, y = a.y + NODE_H / 2;
    return {d: `M${x},${y - 6} C${x + 40},${y - 30} ${x + 40},${y + 30} ${x},${y + 6}`, lx: x + 34, ly: y};
  }
  if (b.node.layer > a.node.layer) {  // downwards: bottom centre → top centre
    const x1 = a.x + a.w / 2, y1 = a.y + NODE_H, x2 = b.x + b.w / 2, y2 = b.y, my = (y1 + y2) / 2;
    return {d: `M${x1},${y1} C${x1},${my} ${x2},${my} ${x2},${y2}`, lx: (x1 + x2) / 2, ly: my};
  }
  // back or sideways edge: out of the side of the graph nearer to the source, around the nodes, back in
  const right = a.x + a.w / 2 >= width / 2, y1 = a.y + NODE_H / 2, y2 = b.y + NODE_H / 2;
  const x1 = right ? a.x + a.w : a.x, x2 = right ? b.x + b.w : b.x;
  const bulge = right ? width - SIDE / 3 : SIDE / 3;
  return {d: `M${x1},${y1} C${bulge},${y1} ${bulge},${y2} ${x2},${y2}`, lx: (bulge + (x1 + x2) / 2) / 2,
    ly: (y1 + y2) / 2};
}

function machine(key, snap) {
  const box = document.getElementById('machines');
  if (box.querySelector('p.muted')) box.replaceChildren();
  let card = box.querySelector(`div[data-key="${CSS.escape(key)}"]`);
  if (!card) {
    card = el('div', {class: 'machine', 'data-key': key});
    box.append(card);
  }
  const {pos, width, height} = layout(snap);
  const id = `arrow-${key.replace(/[^A-Za-z0-9]/g, '_')}`;
  const svg = el('svg:svg', {viewBox: `0 0 ${width} ${height}`, width, height, 'data-machine': snap.name});
  const defs = el('svg:defs');
  const marker = el('svg:marker', {id, viewBox: '0 0 10 10', refX: 9, refY: 5, markerWidth: 7, markerHeight: 7,
    orient: 'auto-start-reverse'});
  marker.append(el('svg:path', {d: 'M0,0 L10,5 L0,10 z', fill: '#9aa3ad'}));
  defs.append(marker);
  svg.append(defs);
  const last = snap.transitions.length ? snap.transitions[snap.transitions.length - 1] : null;
  for (const e of snap.edges) {
    const a = pos[e.source], b = pos[e.target];
    if (!a || !b) continue;
    const recent = last && e.kind === 'transition' && last.source === e.source && last.target === e.target;
    const g = el('svg:g', {class: `edge ${e.kind}${recent ? ' recent' : ''}`});
    const p = edgePath(a, b, width);
    g.append(el('svg:path', {d: p.d, 'marker-end': `url(#${id})`}));
    const label = e.tag || e.event;
    if (label) g.append(el('svg:text', {x: p.lx, y: p.ly - 3}, label));
    if (e.event) g.append(el('svg:title', {}, `${e.event} → ${e.target}`));
    svg.append(g);
  }
  const current = snap.current || [], leaf = current[current.length - 1];
  for (const [name, p] of Object.entries(pos)) {
    const cls = name === leaf ? 'current' : current.includes(name) ? 'active' : '';
    const g = el('svg:g', {class: `node ${cls}`, 'data-state': name});
    g.append(el('svg:rect', {x: p.x, y: p.y, width: p.w, height: NODE_H, rx: 5}));
    g.append(el('svg:text', {x: p.x + p.w / 2, y: p.y + NODE_H / 2 + 1}, name));
    const orth = p.node.orthogonals.map(([o, bs]) => `${o}: ${bs.join(', ') || '—'}`).join('\n');
    if (orth) g.append(el('svg:title', {}, orth));
    svg.append(g);
  }
  const history = el('ol', {reversed: ''});
  for (const t of snap.transitions.slice(-8).reverse()) {
    const li = el('li', {}, `${t.source} → ${t.target} `);
    li.append(el('span', {class: 'tag'}, t.tag || 'transition'));
    if (t.event) li.append(` ${t.event}`);
    history.append(li);
  }
  card.replaceChildren(el('h3', {}, `${snap.name}: ${current.join(' / ') || '(no status)'}`), svg,
    el('div', {class: 'muted'}, 'recent transitions'), history);
}

// ---------------------------------------------------------------- behavior tree
function statusChip(status) { return el('span', {class: `st st-${status || 'IDLE'}`}, status || 'IDLE'); }

function btTree(node, byUid, byName) {
  const status = (node.uid !== undefined && byUid[node.uid]) || byName[node.name];
  const li = el('li', {'data-bt-node': node.name});
  li.append(statusChip(status && status.status), ` ${node.name}`);
  if (node.type) li.append(el('span', {class: 'muted'}, ` ${node.type}`));
  if (node.children && node.children.length) {
    const ul = el('ul');
    for (const child of node.children) ul.append(btTree(child, byUid, byName));
    li.append(ul);
  }
  return li;
}

function bt(snap) {
  const box = document.getElementById('bt');
  const byUid = {}, byName = {};
  for (const n of snap.nodes) { byUid[n.uid] = n; byName[n.name] = n; }
  let body;
  if (snap.structure) {
    body = el('ul', {class: 'bt-tree'});
    body.append(btTree(snap.structure, byUid, byName));
  } else {
    body = el('table', {class: 'bt-nodes'});
    for (const n of snap.nodes) {
      const row = el('tr', {'data-bt-node': n.name});
      const chip = el('td');
      chip.append(statusChip(n.status));
      row.append(el('td', {class: 'muted'}, String(n.uid)), el('td', {}, n.name), chip,
        el('td', {class: 'muted'}, `${n.changes}×`));
      body.append(row);
    }
  }
  const recent = el('ol', {class: 'recent', reversed: ''});
  for (const e of snap.recent.slice(-10).reverse()) recent.append(el('li', {}, `${e.name}: ${e.previous} → ${e.current}`));
  box.replaceChildren(body, el('div', {class: 'muted'}, 'recent changes'), recent);
}

window.Panels = {
  update(key, value) {
    if (!value || value.error) return;
    if (key === 'battery') battery(value);
    else if (key === 'nav_status') navStatus(value);
    else if (key === 'info') topics(value);
    else if (key === 'bt') bt(value);
    else if (key.startsWith('sm:')) machine(key, value);
  },
};
