// hunav_view's page: draws a run (live over server-sent events, or a replay) on a canvas, and edits
// scenarios. Plain JavaScript, no library. window.hunavView exposes what was drawn (tests read it).
'use strict';

const BEHAVIORS = { 1: 'regular', 2: 'impassive', 3: 'surprised', 4: 'scared', 5: 'curious', 6: 'threatening' };
const COLORS = { 0: '#444444', 1: '#1f77b4', 2: '#7f7f7f', 3: '#e6b800', 4: '#9467bd', 5: '#2ca02c', 6: '#d62728' };
const STATES = { 0: 'inactive', 1: 'reaction active (1)', 2: 'reaction active (2)' };
const ACTIVE_RING = '#ff7f0e';
const TRAIL_STEP = 0.1;  // s of simulated time between kept trail points
const CROWD = 300, CROWD_TRAIL_STEP = 0.5;  // more people than CROWD: coarser trails
const TRAIL_SECONDS = 6;

const $ = (id) => document.getElementById(id);
const canvas = $('canvas');
const ctx = canvas.getContext('2d');

const view = { scale: 40, ox: 0, oy: 0, fitted: false };  // px per m, pixel of the world origin
const app = {
  mode: 'live', scene: null, sceneVersion: -1, frame: null, dirty: true, selected: null, trails: new Map(),
  replay: null, replayTime: 0, playing: false, speed: 1, lastTick: 0,
  editing: false, ed: null, errors: [], framesDrawn: 0, fpsTimes: [], received: 0,
};
const drawn = { t: null, tick: null, robot: null, people: [], frames: 0 };

window.addEventListener('error', (e) => app.errors.push(String(e.message)));

// ------------------------------------------------------------------------------------------------
// Coordinates
// ------------------------------------------------------------------------------------------------
function toPx(x, y) { return [view.ox + x * view.scale, view.oy - y * view.scale]; }
function toWorld(px, py) { return [(px - view.ox) / view.scale, (view.oy - py) / view.scale]; }
function resize() {
  const dpr = window.devicePixelRatio || 1;
  const r = canvas.getBoundingClientRect();
  canvas.width = Math.max(1, Math.round(r.width * dpr));
  canvas.height = Math.max(1, Math.round(r.height * dpr));
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  if (!view.fitted) fit();
  app.dirty = true;
}
function sceneBounds() {
  if (app.scene && app.scene.bounds) return app.scene.bounds;
  return [-5, -5, 5, 5];
}
function fit() {
  const [x0, y0, x1, y1] = sceneBounds();
  const r = canvas.getBoundingClientRect();
  if (r.width < 2 || r.height < 2) return;
  view.scale = Math.min(r.width / (x1 - x0), r.height / (y1 - y0));
  view.ox = r.width / 2 - ((x0 + x1) / 2) * view.scale;
  view.oy = r.height / 2 + ((y0 + y1) / 2) * view.scale;
  view.fitted = true;
  app.dirty = true;
}

// ------------------------------------------------------------------------------------------------
// Drawing
// ------------------------------------------------------------------------------------------------
function drawShapes(scene, fill, stroke) {
  if (!scene) return;
  ctx.lineWidth = 2;
  for (const s of scene.shapes) {
    ctx.beginPath();
    if (s.kind === 'circle') {
      const [cx, cy] = toPx(s.center[0], s.center[1]);
      ctx.arc(cx, cy, s.radius * view.scale, 0, 2 * Math.PI);
      ctx.fillStyle = fill; ctx.fill();
      continue;
    }
    s.points.forEach((p, i) => { const [x, y] = toPx(p[0], p[1]); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    if (s.kind === 'polygon') { ctx.closePath(); ctx.fillStyle = fill; ctx.fill(); }
    else { ctx.strokeStyle = stroke; ctx.stroke(); }
  }
}
function cross(x, y, size, color) {
  const [px, py] = toPx(x, y);
  ctx.strokeStyle = color; ctx.lineWidth = 1.5;
  ctx.beginPath(); ctx.moveTo(px - size, py - size); ctx.lineTo(px + size, py + size);
  ctx.moveTo(px - size, py + size); ctx.lineTo(px + size, py - size); ctx.stroke();
}
// Crosses of one colour added to one path: a thousand goals are one stroke, not a thousand.
function addCross(path, x, y, size) {
  const [px, py] = toPx(x, y);
  path.moveTo(px - size, py - size); path.lineTo(px + size, py + size);
  path.moveTo(px - size, py + size); path.lineTo(px + size, py - size);
}
function strokeCrosses(byColor) {
  ctx.lineWidth = 1.5;
  for (const [color, path] of byColor) { ctx.strokeStyle = color; ctx.stroke(path); }
}
function ring(x, y, r, color, width) {
  const [px, py] = toPx(x, y);
  ctx.strokeStyle = color; ctx.lineWidth = width;
  ctx.beginPath(); ctx.arc(px, py, r, 0, 2 * Math.PI); ctx.stroke();
}
function disc(px, py, r, color) { ctx.fillStyle = color; ctx.beginPath(); ctx.arc(px, py, r, 0, 2 * Math.PI); ctx.fill(); }
// A heading tick from 45% of the radius to just beyond it (the centre keeps the body's colour).
function heading(px, py, yaw, r, color) {
  const c = Math.cos(yaw), s = -Math.sin(yaw);
  ctx.strokeStyle = color; ctx.lineWidth = Math.max(1.5, r * 0.25);
  ctx.beginPath(); ctx.moveTo(px + c * r * 0.45, py + s * r * 0.45); ctx.lineTo(px + c * r * 1.3, py + s * r * 1.3); ctx.stroke();
}

function updateTrails(frame) {
  const t = frame.t;
  const add = (id, x, y) => {
    let tr = app.trails.get(id);
    if (!tr) { tr = []; app.trails.set(id, tr); }
    if (tr.length && tr[tr.length - 1][2] > t) tr.length = 0;  // time went back: a new episode or a seek
    if (tr.length && tr[tr.length - 1][2] === t) return;
    // A point per TRAIL_STEP of simulated time, plus the moving head: a thousand trails stay a few
    // tens of thousands of segments to raster, whatever the frame rate.
    if (tr.length >= 2 && t - tr[tr.length - 2][2] < step) tr[tr.length - 1] = [x, y, t];
    else tr.push([x, y, t]);
    while (tr.length && tr[0][2] < t - TRAIL_SECONDS) tr.shift();
  };
  // Crowds: a point per 0.5 s (a thousand 6 s trails are 12,000 segments for the software rasterizer).
  const step = frame.people.length > CROWD ? CROWD_TRAIL_STEP : TRAIL_STEP;
  add('robot', frame.robot.x, frame.robot.y);
  for (const p of frame.people) add(p[0], p[1], p[2]);
}
// Trails fade in 4 steps of opacity; the segments of one colour and step are stroked as one path
// (thousands of people stay cheap to draw: no allocation per segment).
function drawTrails(t) {
  const paths = new Map();  // colour -> 4 paths, one per opacity step
  const s = view.scale, ox = view.ox, oy = view.oy;
  for (const [id, tr] of app.trails) {
    if (tr.length < 2) continue;
    const color = id === 'robot' ? COLORS[0] : colorOfId(id);
    let bands = paths.get(color);
    if (!bands) { bands = [new Path2D(), new Path2D(), new Path2D(), new Path2D()]; paths.set(color, bands); }
    for (let i = 1; i < tr.length; i++) {
      const a = 1 - (t - tr[i][2]) / TRAIL_SECONDS;
      if (a <= 0) continue;
      const path = bands[Math.min(3, Math.floor(a * 4))];
      path.moveTo(ox + tr[i - 1][0] * s, oy - tr[i - 1][1] * s);
      path.lineTo(ox + tr[i][0] * s, oy - tr[i][1] * s);
    }
  }
  ctx.lineWidth = 2;
  for (const [color, bands] of paths) {
    ctx.strokeStyle = color;
    for (let b = 0; b < 4; b++) { ctx.globalAlpha = 0.5 * (b + 1) / 4; ctx.stroke(bands[b]); }
  }
  ctx.globalAlpha = 1;
}
function colorOfId(id) {
  const f = app.frame;
  if (!f) return '#999';
  if (f.colorById === undefined) { f.colorById = new Map(); for (const p of f.people) f.colorById.set(p[0], COLORS[p[5]] || '#000'); }
  return f.colorById.get(id) || '#999';
}

function drawRobot(robot) {
  const [px, py] = toPx(robot.x, robot.y);
  const sc = app.scene && app.scene.robot;
  ctx.fillStyle = COLORS[0];
  if (sc && sc.shape === 'box' && sc.length > 0) {
    ctx.save(); ctx.translate(px, py); ctx.rotate(-robot.yaw);
    ctx.fillRect(-sc.length * view.scale / 2, -sc.width * view.scale / 2, sc.length * view.scale, sc.width * view.scale);
    ctx.restore();
  } else {
    disc(px, py, robot.r * view.scale, COLORS[0]);
  }
  heading(px, py, robot.yaw, robot.r * view.scale, '#ffffff');
  return [px, py];
}

function drawFrame(f) {
  const t = f.t;
  drawTrails(t);
  // The configured goals of the scene, then each person's current goal and the robot's.
  // Goals: crosses; in a crowd only the current goals, as small squares (one fill per colour): the
  // software rasterizer of headless Chromium spends most of a crowd's frame on thin strokes.
  const crowd = f.people.length > CROWD;
  const crosses = new Map([['#bbbbbb', new Path2D()]]);
  if (app.scene && !crowd) for (const a of app.scene.agents) for (const g of a.goals) addCross(crosses.get('#bbbbbb'), g[0], g[1], 3);
  for (const p of f.people) {
    if (p[9] === null) continue;
    const color = COLORS[p[5]] || '#000';
    if (!crosses.has(color)) crosses.set(color, new Path2D());
    if (crowd) { const [gx, gy] = toPx(p[9], p[10]); crosses.get(color).rect(gx - 1.5, gy - 1.5, 3, 3); }
    else addCross(crosses.get(color), p[9], p[10], 4);
  }
  if (crowd) for (const [color, path] of crosses) { ctx.fillStyle = color; ctx.fill(path); }
  else strokeCrosses(crosses);
  if (f.robot.goal) { ring(f.robot.goal[0], f.robot.goal[1], Math.max(4, f.robot.goal[2] * view.scale), '#2e7d32', 2); cross(f.robot.goal[0], f.robot.goal[1], 5, '#2e7d32'); }
  if (f.path && f.path.points.length > 1) {
    ctx.strokeStyle = '#00acc1'; ctx.lineWidth = 2; ctx.setLineDash([6, 4]); ctx.beginPath();
    f.path.points.forEach((p, i) => { const [x, y] = toPx(p[0], p[1]); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    ctx.stroke(); ctx.setLineDash([]);
  }
  if (f.laser) {
    ctx.fillStyle = 'rgba(229,57,53,0.8)';
    const l = f.laser;
    for (let i = 0; i < l.ranges.length; i++) {
      const r = l.ranges[i];
      if (!(r < l.rmax - 1e-3)) continue;
      const a = l.yaw + l.a0 + i * l.da;
      const [x, y] = toPx(l.x + r * Math.cos(a), l.y + r * Math.sin(a));
      ctx.fillRect(x - 1, y - 1, 2, 2);
    }
  }
  // Groups: a line between the members of each group.
  const groups = new Map();
  for (const p of f.people) if (p[7] >= 0) { if (!groups.has(p[7])) groups.set(p[7], []); groups.get(p[7]).push(p); }
  ctx.strokeStyle = '#8d6e63'; ctx.lineWidth = 1.5; ctx.setLineDash([3, 3]);
  for (const members of groups.values()) {
    for (let i = 1; i < members.length; i++) {
      const [x0, y0] = toPx(members[i - 1][1], members[i - 1][2]);
      const [x1, y1] = toPx(members[i][1], members[i][2]);
      ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(x1, y1); ctx.stroke();
    }
  }
  ctx.setLineDash([]);
  // People: one path per colour for the discs, one for the heading ticks, one for the rings of
  // active reactions.
  const people = [];
  const showIds = $('show-ids').checked;
  const discs = new Map();
  const ticks = new Path2D(), rings = new Path2D();
  let tickWidth = 1.5;
  const active = [];
  for (const p of f.people) {
    const [id, x, y, yaw, , beh, state, , r] = p;
    const [px, py] = toPx(x, y);
    const rp = Math.max(2, r * view.scale);
    const color = COLORS[beh] || '#000';
    let path = discs.get(color);
    if (!path) { path = new Path2D(); discs.set(color, path); }
    path.moveTo(px + rp, py); path.arc(px, py, rp, 0, 2 * Math.PI);
    if (rp > 3) {
      const c = Math.cos(yaw), s = -Math.sin(yaw);
      ticks.moveTo(px + c * rp * 0.45, py + s * rp * 0.45); ticks.lineTo(px + c * rp * 1.3, py + s * rp * 1.3);
      tickWidth = Math.max(tickWidth, Math.min(4, rp * 0.25));
    }
    if (state > 0) { rings.moveTo(px + rp + 4, py); rings.arc(px, py, rp + 4, 0, 2 * Math.PI); active.push([px, py, rp]); }
    people.push({ id, x, y, px, py, r: rp, behavior: beh, state, color });
  }
  for (const [color, path] of discs) { ctx.fillStyle = color; ctx.fill(path); }
  ctx.strokeStyle = '#ffffff'; ctx.lineWidth = tickWidth; ctx.stroke(ticks);
  ctx.strokeStyle = ACTIVE_RING; ctx.lineWidth = 3; ctx.stroke(rings);
  ctx.fillStyle = ACTIVE_RING; ctx.font = 'bold 14px sans-serif';
  for (const [px, py, rp] of active) ctx.fillText('!', px + rp + 5, py - rp - 2);
  for (const p of people) {
    if (app.selected === p.id) { ctx.strokeStyle = '#000'; ctx.lineWidth = 1; ctx.beginPath(); ctx.arc(p.px, p.py, p.r + 8, 0, 2 * Math.PI); ctx.stroke(); }
    if (showIds) { ctx.fillStyle = '#000'; ctx.font = '11px sans-serif'; ctx.fillText(String(p.id), p.px + p.r + 2, p.py + p.r + 10); }
  }
  const [rx, ry] = drawRobot(f.robot);
  drawn.t = t; drawn.tick = f.tick === undefined ? null : f.tick;
  drawn.robot = { x: f.robot.x, y: f.robot.y, px: rx, py: ry, r: f.robot.r * view.scale };
  drawn.people = people;
}

function draw() {
  const r = canvas.getBoundingClientRect();
  ctx.clearRect(0, 0, r.width, r.height);
  if (app.editing && app.ed) { drawEditor(); return; }
  drawShapes(app.scene, '#9e9e9e', '#616161');
  if (app.frame) drawFrame(app.frame);
  drawn.frames = ++app.framesDrawn;
  const now = performance.now();
  app.fpsTimes.push(now);
  while (app.fpsTimes.length && app.fpsTimes[0] < now - 2000) app.fpsTimes.shift();
}

function loop() {
  if (app.mode === 'replay' && app.replay && app.playing) {
    const now = performance.now();
    const dt = (now - app.lastTick) / 1000;
    app.lastTick = now;
    setReplayTime(app.replayTime + dt * app.speed, false);
  }
  if (app.dirty) { app.dirty = false; draw(); }
  requestAnimationFrame(loop);
}

// ------------------------------------------------------------------------------------------------
// Panels
// ------------------------------------------------------------------------------------------------
function fmt(v, digits = 2) { return v === null || v === undefined ? '–' : Number(v).toFixed(digits); }
function showStatus(f) {
  $('clock').textContent = 't = ' + fmt(f.t, 2) + ' s';
  $('rtf').textContent = f.rtf ? 'real-time factor ' + fmt(f.rtf, f.rtf < 10 ? 2 : 0) + 'x' : '';
  const run = f.run || (app.replay && app.replay.info) || {};
  $('run').textContent = [run.scenario, run.planner, run.status].filter(Boolean).join(' · ');
}
function showMetrics(m) {
  const body = $('metrics').tBodies[0];
  if (!m) { body.innerHTML = '<tr><td>no metrics yet (LIVE_METRICS, 1 Hz)</td></tr>'; $('metrics-time').textContent = ''; return; }
  $('metrics-time').textContent = 'at t = ' + fmt(m.t, 1) + ' s';
  const rows = Object.entries(m.values).map(([k, v]) => '<tr><td>' + k + '</td><td>' + (typeof v === 'number' ? Number(v.toPrecision(5)) : '–') + '</td></tr>');
  body.innerHTML = rows.join('');
}
function showSelected() {
  const f = app.frame;
  const box = $('selected');
  if (!f || app.selected === null) { box.textContent = 'click a person'; return; }
  const p = f.people.find((q) => q[0] === app.selected);
  if (!p) { box.textContent = 'person ' + app.selected + ' is not in this frame'; return; }
  box.innerHTML = '<b>person ' + p[0] + '</b><br>behavior: ' + (BEHAVIORS[p[5]] || p[5]) + '<br>state: ' + (STATES[p[6]] || p[6]) +
    '<br>speed: ' + fmt(p[4]) + ' m/s<br>position: (' + fmt(p[1]) + ', ' + fmt(p[2]) + ')<br>group: ' + (p[7] >= 0 ? p[7] : 'none') +
    '<br>goal: ' + (p[9] !== null ? '(' + fmt(p[9]) + ', ' + fmt(p[10]) + ')' : 'none');
}
function legend() {
  $('legend').innerHTML = Object.entries(BEHAVIORS).map(([k, n]) => '<span><i style="background:' + COLORS[k] + '"></i>' + n + '</span>').join('') +
    '<span><i style="background:' + COLORS[0] + '"></i>robot</span><span><i style="border:3px solid ' + ACTIVE_RING + ';width:12px;height:12px"></i>reacting</span>';
}

function setFrame(f) {
  app.frame = f;
  app.received++;
  updateTrails(f);
  showStatus(f);
  showSelected();
  app.dirty = true;
}

// ------------------------------------------------------------------------------------------------
// Live and replay
// ------------------------------------------------------------------------------------------------
async function loadScene() {
  const r = await fetch('/api/scene');
  const s = await r.json();
  app.sceneVersion = s.version;
  app.scene = s.scene;
  $('banner').textContent = s.error ? 'map not shown: ' + s.error : (s.scene ? s.scene.name + ' (' + s.scene.file + ')' : 'no scenario: the map is not shown (--scenario FILE)');
  view.fitted = false; fit();
}
function startLive() {
  showMetrics(null);
  const es = new EventSource('/api/stream');
  es.onmessage = (e) => {
    const f = JSON.parse(e.data);
    if (f.scene_version !== app.sceneVersion) loadScene();
    if (f.metrics) showMetrics(f.metrics);
    setFrame(f);
    if (f.ended) {  // the episode is over: the last frame stays on the page
      es.close();
      $('banner').textContent = 'the run has ended: ' + ((f.run && f.run.status) || '') + ' ' + ((f.run && f.run.reason) || '');
    }
  };
  es.onerror = () => { $('banner').textContent = 'connection to hunav_view lost; retrying'; };
}
function lastAtOrBefore(list, t) {  // binary search on .t
  let lo = 0, hi = list.length - 1, best = -1;
  while (lo <= hi) { const mid = (lo + hi) >> 1; if (list[mid].t <= t + 1e-9) { best = mid; lo = mid + 1; } else hi = mid - 1; }
  return best;
}
// A replay arrives in chunks (view/README.md, "Replays that open at once"): the header lays out the slider, and each chunk
// holds the frames of a stretch of time with the scans, paths and metrics of it, each list led by the
// last one before the chunk. A chunk is fetched when the time reaches it (the next one while playing
// through the second half of the current one); at most KEEP_CHUNKS stay in the page.
const KEEP_CHUNKS = 8;
function chunkAtTime(rp, t) {  // the last chunk starting at or before t (0 before the first)
  let lo = 0, hi = rp.chunks.length - 1, best = 0;
  while (lo <= hi) { const mid = (lo + hi) >> 1; if (rp.chunks[mid].t0 <= t + 1e-9) { best = mid; lo = mid + 1; } else hi = mid - 1; }
  return best;
}
function chunkOfFrame(rp, k) {
  let lo = 0, hi = rp.chunks.length - 1, best = 0;
  while (lo <= hi) { const mid = (lo + hi) >> 1; if (rp.chunks[mid].first_frame <= k) { best = mid; lo = mid + 1; } else hi = mid - 1; }
  return best;
}
function frameAt(rp, k) {  // frame k of the replay, or undefined while its chunk is not in the page
  const ci = chunkOfFrame(rp, k);
  const c = rp.loaded.get(ci);
  return c ? c.frames[k - rp.chunks[ci].first_frame] : undefined;
}
function loadChunk(rp, i) {
  if (i < 0 || i >= rp.chunks.length) return Promise.resolve(null);
  if (rp.loaded.has(i)) return Promise.resolve(rp.loaded.get(i));
  if (!rp.pending.has(i)) {
    rp.pending.set(i, fetch(rp.url + i).then((r) => {
      if (!r.ok) throw new Error('replay chunk ' + i + ': HTTP ' + r.status);
      return r.json();
    }).then((c) => {
      rp.pending.delete(i);
      rp.loaded.set(i, c);
      rp.fetched += 1;
      // Keep the chunks nearest the time shown.
      while (rp.loaded.size > KEEP_CHUNKS) {
        const now = chunkAtTime(rp, app.replayTime);
        let far = -1;
        for (const j of rp.loaded.keys()) if (far < 0 || Math.abs(j - now) > Math.abs(far - now)) far = j;
        rp.loaded.delete(far);
      }
      // Show the time now if it was waiting for this chunk, or ask for its chunk if a drag of the
      // slider moved on meanwhile (requestChunk fetched at most two at a time).
      const now = chunkAtTime(rp, app.replayTime);
      if (app.replay === rp && (now === i || !rp.loaded.has(now))) setReplayTime(app.replayTime, false);
      return c;
    }, (e) => { rp.pending.delete(i); app.errors.push(String(e)); $('banner').textContent = String(e); return null; }));
  }
  return rp.pending.get(i);
}
// What setReplayTime fetches: at most two chunks at a time (the one shown and the next), so that a
// fast drag of the slider over a crowd's replay does not fetch every chunk it passes.
function requestChunk(rp, i) {
  if (rp.pending.has(i) || rp.loaded.has(i) || rp.pending.size < 2) loadChunk(rp, i);
}
function setReplayTime(t, fromSlider) {
  const rp = app.replay;
  if (t >= rp.t1) { t = rp.t1; if (app.playing) togglePlay(); }
  t = Math.max(rp.t0, t);
  app.replayTime = t;
  if (!fromSlider) $('slider').value = t;
  $('replay-time').textContent = fmt(t, 2) + ' / ' + fmt(rp.t1, 2) + ' s';
  const ci = chunkAtTime(rp, t);
  const info = rp.chunks[ci];
  const chunk = rp.loaded.get(ci);
  if (!chunk) { requestChunk(rp, ci); return; }  // drawn when it arrives
  if (ci + 1 < rp.chunks.length && t >= (info.t0 + info.t1) / 2) requestChunk(rp, ci + 1);
  const local = Math.max(0, lastAtOrBefore(chunk.frames, t));
  const k = info.first_frame + local;
  const f = Object.assign({}, chunk.frames[local]);
  const li = lastAtOrBefore(chunk.laser, t), pi = lastAtOrBefore(chunk.paths, t), mi = lastAtOrBefore(chunk.metrics, t);
  f.laser = li >= 0 ? chunk.laser[li] : null;
  f.path = pi >= 0 ? chunk.paths[pi] : null;
  // Trails: the frames of the last seconds, about 10 per second; while playing forward only the
  // frames since the last one shown are added. Frames of a chunk no longer in the page are skipped.
  const step = Math.max(1, Math.round(0.1 / Math.max(1e-3, (rp.t1 - rp.t0) / rp.frameCount)));
  const prev = app.replayK === undefined ? -1 : app.replayK;
  const prevFrame = prev >= 0 ? frameAt(rp, prev) : undefined;
  const add = (j) => { const g = frameAt(rp, j); if (g) updateTrails(g); };
  if (k >= prev && prevFrame && f.t - prevFrame.t < TRAIL_SECONDS) {
    for (let j = prev + step - (prev % step); j < k; j += step) add(j);
  } else {
    app.trails.clear();
    const ti = chunkAtTime(rp, t - TRAIL_SECONDS), tc = rp.loaded.get(ti);
    const from = tc ? rp.chunks[ti].first_frame + Math.max(0, lastAtOrBefore(tc.frames, t - TRAIL_SECONDS)) : info.first_frame;
    for (let j = from; j < k; j += step) add(j);
  }
  app.replayK = k;
  app.frame = f;
  updateTrails(f);
  showStatus(f);
  showSelected();
  const metric = mi >= 0 ? chunk.metrics[mi] : null;
  if (metric !== app.replayMetric) { app.replayMetric = metric; showMetrics(metric); }
  app.dirty = true;
}
function togglePlay() {
  app.playing = !app.playing;
  app.lastTick = performance.now();
  $('play').textContent = app.playing ? 'pause' : 'play';
  if (app.playing && app.replayTime >= app.replay.t1) setReplayTime(app.replay.t0, false);
}
// header: /api/replay's answer; chunkUrl + i fetches chunk i. Resolves when the first frame shows.
function startReplay(header, chunkUrl) {
  app.mode = 'replay';
  const rp = { info: header.info, t0: header.t0, t1: header.t1, frameCount: header.frames, rate: header.rate,
               chunks: header.chunks, url: chunkUrl, loaded: new Map(), pending: new Map(), fetched: 0 };
  app.replay = rp;
  $('mode').textContent = 'replay of ' + (rp.info.source || '');
  $('replay-panel').hidden = false;
  $('slider').min = rp.t0; $('slider').max = rp.t1;
  $('slider').step = Math.max(0.001, (rp.t1 - rp.t0) / Math.max(1, rp.frameCount - 1));
  showMetrics(null);
  app.playing = false;
  app.replayK = undefined;
  app.replayMetric = null;
  app.replayTime = rp.t0;
  return loadChunk(rp, 0).then(() => setReplayTime(rp.t0, false));
}

// ------------------------------------------------------------------------------------------------
// Mouse: pan, zoom, select (and the editor's dragging)
// ------------------------------------------------------------------------------------------------
let drag = null;
function mousePos(e) { const r = canvas.getBoundingClientRect(); return [e.clientX - r.left, e.clientY - r.top]; }
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  const [mx, my] = mousePos(e);
  const k = Math.exp(-e.deltaY * 0.0015);
  view.ox = mx - (mx - view.ox) * k; view.oy = my - (my - view.oy) * k; view.scale *= k;
  app.dirty = true;
}, { passive: false });
canvas.addEventListener('mousedown', (e) => {
  const [mx, my] = mousePos(e);
  if (app.editing && app.ed) {
    const h = edHit(mx, my);
    if (h) {  // keep the offset between the pointer and the point: a click does not move it
      const [wx, wy] = toWorld(mx, my);
      drag = { kind: 'handle', handle: h, dx: h.x - wx, dy: h.y - wy, moved: false };
      edSelect(h.select);
      return;
    }
  }
  drag = { kind: 'pan', x: mx, y: my, ox: view.ox, oy: view.oy, moved: false };
});
window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  const [mx, my] = mousePos(e);
  if (drag.kind === 'pan') {
    if (Math.abs(mx - drag.x) + Math.abs(my - drag.y) > 3) drag.moved = true;
    view.ox = drag.ox + mx - drag.x; view.oy = drag.oy + my - drag.y;
  } else {
    const [x, y] = toWorld(mx, my);
    drag.handle.set(Math.round((x + drag.dx) * 100) / 100, Math.round((y + drag.dy) * 100) / 100);
    drag.moved = true;
  }
  app.dirty = true;
});
window.addEventListener('mouseup', (e) => {
  if (!drag) return;
  const d = drag;
  drag = null;
  if (d.kind === 'handle') { if (d.moved) edChanged(); return; }
  if (d.moved || app.editing) { if (app.editing && !d.moved) edSelect(null); return; }
  const [mx, my] = mousePos(e);
  let best = null, bestD = Infinity;
  for (const p of drawn.people) {
    const dd = Math.hypot(p.px - mx, p.py - my);
    if (dd <= p.r + 6 && dd < bestD) { best = p.id; bestD = dd; }
  }
  app.selected = best;
  showSelected();
  app.dirty = true;
});

// ------------------------------------------------------------------------------------------------
// Scenario editor. The document is the file's YAML tree: maps are {"__map": [[key, value], ...]} and
// scalars are strings; numbers the page sets are numbers.
// ------------------------------------------------------------------------------------------------
function isMap(n) { return n && typeof n === 'object' && Array.isArray(n.__map); }
function mget(n, key) { if (!isMap(n)) return undefined; const kv = n.__map.find((e) => e[0] === key); return kv ? kv[1] : undefined; }
function mset(n, key, value) { const kv = n.__map.find((e) => e[0] === key); if (kv) kv[1] = value; else n.__map.push([key, value]); }
function mdel(n, key) { n.__map = n.__map.filter((e) => e[0] !== key); }
function mapOf(obj) { return { __map: Object.entries(obj).map(([k, v]) => [k, v]) }; }
function mpath(n, keys) { for (const k of keys) { n = Array.isArray(n) ? n[k] : mget(n, k); if (n === undefined) return undefined; } return n; }
function ensureMap(n, key) { let v = mget(n, key); if (!isMap(v)) { v = { __map: [] }; mset(n, key, v); } return v; }
function num(v, dflt = 0) { const x = parseFloat(v); return Number.isFinite(x) ? x : dflt; }

// The people's document: the agents file the scenario names (opened and saved with it), or the
// scenario's own `people:` mapping.
function edPeopleRoot() { return app.ed.peopleDoc || mget(app.ed.doc, 'people'); }
function edPeopleParams() { const r = edPeopleRoot(); return isMap(r) ? mpath(r, ['hunav_loader', 'ros__parameters']) : undefined; }
// The generator entries (`people: generate:`, one mapping or a list of them).
function edGenerators() {
  const r = edPeopleRoot(), g = isMap(r) ? mget(r, 'generate') : undefined;
  if (isMap(g)) return [g];
  return Array.isArray(g) ? g.filter(isMap) : [];
}
// A generator's region {x: [lo, hi] | v, y: ...} as a draggable centre that moves the whole box.
function intervalOf(v) { return Array.isArray(v) ? [num(v[0]), num(v[1])] : [num(v), num(v)]; }
function regionHandle(gen, index) {
  const region = mget(gen, 'region');
  if (!isMap(region)) return null;
  const ox = mget(region, 'x'), oy = mget(region, 'y');
  const [x0, x1] = intervalOf(ox), [y0, y1] = intervalOf(oy);
  const shift = (v, d) => (Array.isArray(v) ? v.map((e) => Math.round((num(e) + d) * 100) / 100) : Math.round((num(v) + d) * 100) / 100);
  return { x: (x0 + x1) / 2, y: (y0 + y1) / 2, box: [x0, y0, x1, y1], role: 'region', select: { kind: 'generator', index },
    // From the values when the handle was made: a drag calls set() with each new position.
    set: (x, y) => { mset(region, 'x', shift(ox, x - (x0 + x1) / 2)); mset(region, 'y', shift(oy, y - (y0 + y1) / 2)); } };
}
function edAgents() {
  const params = edPeopleParams();
  const names = params ? mget(params, 'agents') : undefined;
  if (!Array.isArray(names)) return [];
  return names.map((name) => ({ name: String(name), node: mget(params, String(name)) })).filter((a) => isMap(a.node));
}
function behaviorCode(node) {
  const b = mget(node, 'behavior');
  let t = isMap(b) ? mget(b, 'type') : b;
  if (t === undefined) return 1;
  const n = parseInt(t, 10);
  if (Number.isFinite(n)) return n;
  const name = String(t).toLowerCase();
  for (const [k, v] of Object.entries(BEHAVIORS)) if (v === name) return Number(k);
  return 1;
}
function pointHandle(node, select, xk = 'x', yk = 'y') {
  return { x: num(mget(node, xk)), y: num(mget(node, yk)), select, set: (x, y) => { mset(node, xk, x); mset(node, yk, y); } };
}
// Every draggable point of the document, with what selecting it selects.
function edHandles() {
  const doc = app.ed.doc, hs = [];
  const robot = mget(doc, 'robot');
  if (isMap(robot)) {
    const start = mget(robot, 'start'), goal = mget(robot, 'goal');
    if (isMap(start)) hs.push(Object.assign(pointHandle(start, { kind: 'robot' }), { role: 'robot-start' }));
    if (isMap(goal)) hs.push(Object.assign(pointHandle(goal, { kind: 'robot' }), { role: 'robot-goal' }));
  }
  for (const a of edAgents()) {
    const pose = mget(a.node, 'init_pose');
    if (isMap(pose)) hs.push(Object.assign(pointHandle(pose, { kind: 'person', name: a.name }), { role: 'person', behavior: behaviorCode(a.node), name: a.name }));
    const goals = mget(a.node, 'goals');
    if (Array.isArray(goals)) goals.forEach((g) => {
      const gn = mget(a.node, String(g));
      if (isMap(gn)) hs.push(Object.assign(pointHandle(gn, { kind: 'person', name: a.name }), { role: 'goal', behavior: behaviorCode(a.node), name: a.name }));
    });
  }
  edGenerators().forEach((g, gi) => { const h = regionHandle(g, gi); if (h) hs.push(h); });
  const map = mget(doc, 'map');
  const walls = isMap(map) ? mget(map, 'walls') : undefined;
  if (Array.isArray(walls)) walls.forEach((w, wi) => Array.isArray(w) && w.forEach((p) => {
    if (Array.isArray(p)) hs.push({ x: num(p[0]), y: num(p[1]), role: 'wall', wall: wi, select: { kind: 'wall', index: wi }, set: (x, y) => { p[0] = x; p[1] = y; } });
  }));
  const boxes = isMap(map) ? mget(map, 'boxes') : undefined;
  if (Array.isArray(boxes)) boxes.forEach((b, bi) => { if (isMap(b)) hs.push(Object.assign(pointHandle(b, { kind: 'box', index: bi }), { role: 'box', box: b })); });
  return hs;
}
function edHit(mx, my) {
  let best = null, bestD = 12;
  for (const h of edHandles()) {
    const [px, py] = toPx(h.x, h.y);
    const d = Math.hypot(px - mx, py - my);
    if (d < bestD) { best = h; bestD = d; }
  }
  return best;
}
function drawEditor() {
  drawShapes(app.ed.scene, '#d6d6d6', '#b0b0b0');
  const hs = edHandles();
  // Walls of the document over the checked scene (they move while dragged).
  const walls = new Map();
  for (const h of hs) if (h.role === 'wall') { if (!walls.has(h.wall)) walls.set(h.wall, []); walls.get(h.wall).push(h); }
  for (const [wi, pts] of walls) {
    const sel = app.ed.selected && app.ed.selected.kind === 'wall' && app.ed.selected.index === wi;
    ctx.strokeStyle = sel ? '#ff6f00' : '#37474f'; ctx.lineWidth = 3; ctx.beginPath();
    pts.forEach((h, i) => { const [x, y] = toPx(h.x, h.y); if (i) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    ctx.stroke();
  }
  // People the loader made that are not handles (the generator's): shown, edited through its entry.
  const listed = new Set(edAgents().map((a) => a.name));
  if (app.ed.scene && Array.isArray(app.ed.scene.agents)) {
    ctx.globalAlpha = 0.35;
    for (const a of app.ed.scene.agents) {
      if (listed.has(a.name) || !Array.isArray(a.start)) continue;
      const [px, py] = toPx(a.start[0], a.start[1]);
      disc(px, py, Math.max(2, a.radius * view.scale), COLORS[a.behavior] || '#000');
    }
    ctx.globalAlpha = 1;
  }
  const drawnEd = [];
  for (const h of hs) {
    const [px, py] = toPx(h.x, h.y);
    const sel = app.ed.selected && JSON.stringify(app.ed.selected) === JSON.stringify(h.select);
    if (h.role === 'box') {
      const w = num(mget(h.box, 'width'), 1) * view.scale, hh = num(mget(h.box, 'height'), 1) * view.scale;
      ctx.save(); ctx.translate(px, py); ctx.rotate(-num(mget(h.box, 'yaw'), 0));
      ctx.fillStyle = sel ? '#ffcc80' : '#8d6e63'; ctx.fillRect(-w / 2, -hh / 2, w, hh); ctx.restore();
    } else if (h.role === 'robot-start') {
      disc(px, py, Math.max(5, 0.3 * view.scale), COLORS[0]);
    } else if (h.role === 'robot-goal') {
      ring(h.x, h.y, Math.max(6, 0.3 * view.scale), '#2e7d32', 3);
    } else if (h.role === 'person') {
      disc(px, py, Math.max(5, 0.35 * view.scale), COLORS[h.behavior]);
      ctx.fillStyle = '#000'; ctx.font = '11px sans-serif'; ctx.fillText(h.name, px + 8, py - 8);
    } else if (h.role === 'goal') {
      ctx.fillStyle = COLORS[h.behavior]; ctx.fillRect(px - 4, py - 4, 8, 8);
    } else if (h.role === 'wall') {
      ctx.fillStyle = '#37474f'; ctx.fillRect(px - 3, py - 3, 6, 6);
    } else if (h.role === 'region') {
      const [ax, ay] = toPx(h.box[0], h.box[3]), [bx, by] = toPx(h.box[2], h.box[1]);
      ctx.save(); ctx.setLineDash([6, 4]); ctx.strokeStyle = sel ? '#ff6f00' : '#5c6bc0'; ctx.lineWidth = 2;
      ctx.strokeRect(ax, ay, bx - ax, by - ay); ctx.restore();
      ctx.fillStyle = '#5c6bc0'; ctx.beginPath(); ctx.moveTo(px, py - 7); ctx.lineTo(px + 7, py); ctx.lineTo(px, py + 7); ctx.lineTo(px - 7, py); ctx.fill();
    }
    if (sel) ring(h.x, h.y, 10, '#ff6f00', 2);
    drawnEd.push({ role: h.role, name: h.name || null, x: h.x, y: h.y, px, py });
  }
  drawn.editor = drawnEd;
}

function edSelect(sel) { if (!app.ed) return; app.ed.selected = sel; edProps(); app.dirty = true; }
function edStatus(text, error) { const s = $('ed-status'); s.textContent = text; s.className = error ? 'error' : 'ok'; }

// A form field bound to a key of a map node; `key` is also matched against the loader's error key.
function field(node, key, label, opts = {}) {
  const div = document.createElement('div');
  div.className = 'field';
  div.dataset.key = key;
  const lab = document.createElement('label');
  lab.textContent = label;
  let input;
  if (opts.choices) {
    input = document.createElement('select');
    for (const [v, t] of opts.choices) { const o = document.createElement('option'); o.value = v; o.textContent = t; input.appendChild(o); }
  } else { input = document.createElement('input'); }
  const cur = mget(node, key);
  input.value = cur === undefined || cur === null ? (opts.dflt !== undefined ? opts.dflt : '') : showValue(cur);
  input.name = key;
  input.addEventListener('change', () => {
    const v = input.value.trim();
    if (v === '' && !opts.choices) mdel(node, key);
    else mset(node, key, opts.number ? numberOrInterval(v) : v);
    edChanged();
  });
  div.appendChild(lab); div.appendChild(input);
  const err = document.createElement('div'); err.className = 'field-error'; div.appendChild(err);
  return div;
}
// A number, or an interval written [low, high] (the generator's max_vel): else the text as typed,
// for the loader to name.
function numberOrInterval(v) {
  if (Number.isFinite(Number(v))) return Number(v);
  const m = /^\[\s*([^,\]]+)\s*,\s*([^\]]+)\]$/.exec(v);
  if (m && Number.isFinite(Number(m[1])) && Number.isFinite(Number(m[2]))) return [Number(m[1]), Number(m[2])];
  return v;
}
function showValue(v) { return Array.isArray(v) ? '[' + v.join(', ') + ']' : String(v); }
function edProps() {
  const box = $('ed-props');
  box.innerHTML = '';
  const sel = app.ed && app.ed.selected;
  if (!sel) { box.textContent = 'drag the robot, its goal, people, their goals (squares), walls and generated people\'s regions (diamonds); click one to edit it'; return; }
  const doc = app.ed.doc;
  const h = document.createElement('h2');
  box.appendChild(h);
  if (sel.kind === 'robot') {
    h.textContent = 'robot';
    const robot = mget(doc, 'robot');
    const start = mget(robot, 'start'), goal = mget(robot, 'goal');
    if (isMap(start)) box.appendChild(field(start, 'yaw', 'start heading (rad)', { number: true }));
    if (isMap(goal)) box.appendChild(field(goal, 'radius', 'goal radius (m)', { number: true }));
    box.appendChild(field(robot, 'radius', 'radius (m)', { number: true }));
  } else if (sel.kind === 'person') {
    const node = mget(edPeopleParams(), sel.name);
    if (!isMap(node)) return;
    h.textContent = 'person ' + sel.name;
    let beh = mget(node, 'behavior');
    if (!isMap(beh)) { beh = mapOf({ type: beh === undefined ? 'regular' : BEHAVIORS[behaviorCode(node)] }); mset(node, 'behavior', beh); }
    box.appendChild(field(beh, 'type', 'behavior', { choices: Object.values(BEHAVIORS).map((n) => [n, n]), dflt: 'regular' }));
    box.appendChild(field(beh, 'configuration', 'configuration', { choices: [['0', 'default'], ['1', 'custom'], ['2', 'random normal'], ['3', 'random uniform']], dflt: '0' }));
    for (const [k, l] of [['duration', 'reaction duration (s)'], ['vel', 'reaction speed (m/s)'], ['dist', 'reaction distance (m)'], ['once', 'react once (true/false)']])
      box.appendChild(field(beh, k, l, { number: k !== 'once' }));
    for (const [k, l] of [['id', 'id'], ['group_id', 'group (-1: none)'], ['max_vel', 'speed (m/s)'], ['radius', 'radius (m)'], ['goal_radius', 'goal radius (m)'], ['cyclic_goals', 'cyclic goals (true/false)']])
      box.appendChild(field(node, k, l, { number: k !== 'cyclic_goals' }));
    const row = document.createElement('div'); row.className = 'row';
    const add = document.createElement('button'); add.textContent = '+ goal';
    add.onclick = () => {
      const goals = mget(node, 'goals') || []; const pose = mget(node, 'init_pose');
      let k = goals.length; while (mget(node, 'g' + k) !== undefined) k++;
      const last = goals.length ? mget(node, String(goals[goals.length - 1])) : pose;
      goals.push('g' + k); mset(node, 'goals', goals);
      mset(node, 'g' + k, mapOf({ x: num(mget(last, 'x')) + 1, y: num(mget(last, 'y')), h: 1.25 }));
      edChanged();
    };
    const rm = document.createElement('button'); rm.textContent = '- last goal';
    rm.onclick = () => { const goals = mget(node, 'goals') || []; if (goals.length > 1) { mdel(node, String(goals.pop())); edChanged(); } };
    row.appendChild(add); row.appendChild(rm); box.appendChild(row);
  } else if (sel.kind === 'generator') {
    const gen = edGenerators()[sel.index];
    if (!isMap(gen)) return;
    h.textContent = 'generated people ' + sel.index + ' (drag the region)';
    for (const [k, l] of [['count', 'how many'], ['max_vel', 'speed (m/s, or [low, high])'], ['radius', 'radius (m)'], ['goal_radius', 'goal radius (m)'],
      ['min_spacing', 'start spacing (m)'], ['group_id', 'group (-1: none)']])
      box.appendChild(field(gen, k, l, { number: true }));
    let beh = mget(gen, 'behavior');
    if (!isMap(beh)) { beh = mapOf({ type: beh === undefined ? 'regular' : String(beh) }); mset(gen, 'behavior', beh); }
    box.appendChild(field(beh, 'type', 'behavior', { choices: Object.values(BEHAVIORS).map((n) => [n, n]), dflt: 'regular' }));
    box.appendChild(field(beh, 'configuration', 'configuration', { choices: [['0', 'default'], ['1', 'custom'], ['2', 'random normal'], ['3', 'random uniform']], dflt: '0' }));
  } else if (sel.kind === 'box') {
    h.textContent = 'box ' + sel.index;
    const b = mget(mget(doc, 'map'), 'boxes')[sel.index];
    for (const [k, l] of [['width', 'width (m)'], ['height', 'height (m)'], ['yaw', 'rotation (rad)']]) box.appendChild(field(b, k, l, { number: true }));
  } else if (sel.kind === 'wall') {
    h.textContent = 'wall ' + sel.index + ' (drag its points)';
  }
  edShowFieldErrors();
}
function edShowFieldErrors() {
  const e = app.ed && app.ed.error;
  for (const div of document.querySelectorAll('#ed-props .field')) {
    const bad = !!(e && e.key && (e.key === div.dataset.key || e.key.endsWith('.' + div.dataset.key)));
    div.classList.toggle('bad', bad);
    div.querySelector('.field-error').textContent = bad ? e.message : '';
  }
}
let edTimer = null;
function edChanged() {
  app.dirty = true;
  edProps();
  clearTimeout(edTimer);
  edTimer = setTimeout(edValidate, 250);
}
// Writes and runs carry the token of the server's start that served this page (view/README.md).
const apiToken = document.querySelector('meta[name="hunav-token"]').content;
async function edPost(url, body) {
  const r = await fetch(url, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json', 'X-HuNav-Token': apiToken },
    body: JSON.stringify(body),
  });
  return r.json();
}
function edTarget() { return $('ed-path').value.trim() || (app.ed && app.ed.path) || ''; }
function edResult(res, what) {
  if (res.error && typeof res.error === 'string') { edStatus(res.error, true); return false; }
  app.ed.error = res.error || null;
  if (res.scene) app.ed.scene = res.scene;
  if (res.ok) edStatus(what, false); else edStatus((res.error && res.error.message) || 'error', true);
  edShowFieldErrors();
  app.dirty = true;
  return !!res.ok;
}
// Each check or save of the document is numbered: a check answered after a later request (the
// server generates a large crowd slowly) describes an older document and is dropped, and so is an
// answer about a document no longer open (another file opened meanwhile).
let edRequests = 0;
async function edValidate() {
  const ed = app.ed;
  if (!ed) return false;
  const request = ++edRequests;
  const res = await edPost('/api/editor/validate', { path: edTarget(), doc: ed.doc, people_doc: ed.peopleDoc || null });
  if (request !== edRequests || app.ed !== ed) return false;
  return edResult(res, 'the scenario loads');
}
async function edSave() {
  const ed = app.ed;
  if (!ed) return false;
  const path = edTarget();
  clearTimeout(edTimer);  // the save checks the document itself
  ++edRequests;
  const res = await edPost('/api/editor/save', { path, doc: ed.doc, people_doc: ed.peopleDoc || null });
  if (app.ed !== ed) return false;
  const ok = edResult(res, 'saved ' + path + (res.people_path ? ' and ' + res.people_path : ''));
  if (ok) { ed.path = path; ed.saved = (ed.saved || 0) + 1; }
  return ok;
}
async function edRun() {
  if (!(await edSave())) return;
  const ed = app.ed;  // the replay shows the run of this document, whatever is opened meanwhile
  edStatus('running ' + ed.path + ' …', false);
  const res = await edPost('/api/editor/run', { path: ed.path, planner: $('ed-planner').value });
  if (!res.ok) { edStatus((res.error && (res.error.message || res.error)) || 'the run failed', true); return; }
  edStatus('ran: ' + res.status + ' after ' + fmt(res.sim_time, 1) + ' s, fingerprint ' + res.fingerprint + '; results in ' + res.out_dir, false);
  const path = encodeURIComponent(res.out_dir);
  const header = await (await fetch('/api/editor/replay?path=' + path)).json();
  await showRunReplay(ed, res, header, '/api/editor/replay/chunk?path=' + path + '&i=');
}
// The replay of a run the editor started, in place of the editor.
async function showRunReplay(ed, run, header, chunkUrl) {
  app.scene = ed.scene;
  setEditing(false);
  $('banner').textContent = 'replay of the run of ' + ed.path + ' (' + run.out_dir + ')';
  app.lastRun = run;
  await startReplay(header, chunkUrl);
}
async function edFiles() {
  const r = await fetch('/api/editor/files');
  const j = await r.json();
  const sel = $('ed-files');
  sel.innerHTML = '';
  for (const f of j.files || []) { const o = document.createElement('option'); o.value = f; o.textContent = f; sel.appendChild(o); }
  return j.files || [];
}
async function edOpen(path) {
  const r = await fetch('/api/editor/open?path=' + encodeURIComponent(path));
  const j = await r.json();
  if (!r.ok || j.error && typeof j.error === 'string') { edStatus(j.error || 'cannot open ' + path, true); return false; }
  const people = j.people || {};
  app.ed = { path, doc: j.doc, peopleDoc: people.doc || null, peoplePath: people.path || null, scene: j.scene, selected: null, error: j.error };
  $('ed-path').value = path;
  $('banner').textContent = 'editing ' + path + (people.path ? ' and ' + people.path : '');
  if (j.error) edStatus(j.error.message, true);
  else if (people.error) edStatus('opened ' + path + '; its people are read only: ' + people.error, true);
  else edStatus('opened ' + path + (people.path ? ' with its people in ' + people.path + ' (saved with it)' : ''), false);
  if (j.scene) { app.scene = j.scene; view.fitted = false; fit(); }
  edProps();
  app.dirty = true;
  return true;
}
function relativeTo(fromFile, target) {  // target (relative to the root) as seen from fromFile's folder
  const a = fromFile.split('/').slice(0, -1), b = target.split('/');
  let i = 0; while (i < a.length && i < b.length - 1 && a[i] === b[i]) i++;
  return '../'.repeat(a.length - i) + b.slice(i).join('/');
}
function edNew() {
  const mapFile = $('ed-files').value;
  const path = $('ed-path').value.trim() || 'new_scenario.yaml';
  const c = toWorld(canvas.clientWidth / 2, canvas.clientHeight / 2);
  const map = { __map: [] };
  if (mapFile && /map/i.test(mapFile)) mset(map, 'map_server', relativeTo(path, mapFile));
  else mset(map, 'walls', [[[c[0] - 5, c[1] - 4], [c[0] + 5, c[1] - 4], [c[0] + 5, c[1] + 4], [c[0] - 5, c[1] + 4], [c[0] - 5, c[1] - 4]]]);
  const doc = mapOf({ name: path.split('/').pop().replace(/\.ya?ml$/, ''), dt: 0.01, time_limit: 60, seed: 1, map,
    robot: mapOf({ radius: 0.3, start: mapOf({ x: c[0] - 3, y: c[1], yaw: 0 }), goal: mapOf({ x: c[0] + 3, y: c[1], radius: 0.3 }) }) });
  app.ed = { path, doc, peopleDoc: null, peoplePath: null, scene: null, selected: null, error: null };
  $('ed-path').value = path;
  $('banner').textContent = 'editing ' + path + ' (new)';
  edChanged();
}
function edUniqueAgent() {
  const params = edPeopleParams();
  let k = 1; while (mget(params, 'agent' + k) !== undefined) k++;
  let id = 1; for (const a of edAgents()) id = Math.max(id, num(mget(a.node, 'id')) + 1);
  return ['agent' + k, id];
}
function edAddPerson() {
  if (!app.ed) return;
  const named = mget(app.ed.doc, 'people');
  if (!app.ed.peopleDoc && named !== undefined && !isMap(named)) { edStatus('the people of ' + named + ' are outside the editor folder: edit them there', true); return; }
  const people = app.ed.peopleDoc || ensureMap(app.ed.doc, 'people'), loader = ensureMap(people, 'hunav_loader'), params = ensureMap(loader, 'ros__parameters');
  if (!Array.isArray(mget(params, 'agents'))) mset(params, 'agents', []);
  const [name, id] = edUniqueAgent();
  const [x, y] = toWorld(canvas.clientWidth / 2, canvas.clientHeight / 2).map((v) => Math.round(v * 100) / 100);
  mget(params, 'agents').push(name);
  mset(params, name, mapOf({ id, skin: 0, behavior: mapOf({ type: 'regular', configuration: 0 }), group_id: -1, max_vel: 1.0, radius: 0.35,
    init_pose: mapOf({ x, y, z: 1.25, h: 0 }), goal_radius: 0.3, cyclic_goals: true, goals: ['g0'], g0: mapOf({ x: x + 2, y, h: 1.25 }) }));
  app.ed.selected = { kind: 'person', name };
  edChanged();
}
function edAddWall() {
  if (!app.ed) return;
  const map = ensureMap(app.ed.doc, 'map');
  if (!Array.isArray(mget(map, 'walls'))) mset(map, 'walls', []);
  const [x, y] = toWorld(canvas.clientWidth / 2, canvas.clientHeight / 2).map((v) => Math.round(v * 100) / 100);
  mget(map, 'walls').push([[x - 1, y], [x + 1, y]]);
  app.ed.selected = { kind: 'wall', index: mget(map, 'walls').length - 1 };
  edChanged();
}
function edAddBox() {
  if (!app.ed) return;
  const map = ensureMap(app.ed.doc, 'map');
  if (!Array.isArray(mget(map, 'boxes'))) mset(map, 'boxes', []);
  const [x, y] = toWorld(canvas.clientWidth / 2, canvas.clientHeight / 2).map((v) => Math.round(v * 100) / 100);
  mget(map, 'boxes').push(mapOf({ x, y, width: 1, height: 1 }));
  app.ed.selected = { kind: 'box', index: mget(map, 'boxes').length - 1 };
  edChanged();
}
function edDelete() {
  const sel = app.ed && app.ed.selected;
  if (!sel) return;
  const map = mget(app.ed.doc, 'map');
  if (sel.kind === 'generator') {
    const r = edPeopleRoot(), g = mget(r, 'generate');
    if (Array.isArray(g)) g.splice(g.indexOf(edGenerators()[sel.index]), 1); else mdel(r, 'generate');
  } else if (sel.kind === 'person') {
    const params = edPeopleParams();
    mset(params, 'agents', mget(params, 'agents').filter((n) => String(n) !== sel.name));
    mdel(params, sel.name);
  } else if (sel.kind === 'wall') mget(map, 'walls').splice(sel.index, 1);
  else if (sel.kind === 'box') mget(map, 'boxes').splice(sel.index, 1);
  else return;
  app.ed.selected = null;
  edChanged();
}
function setEditing(on) {
  app.editing = on;
  $('editor-panel').hidden = !on;
  $('toggle-editor').textContent = on ? 'view' : 'editor';
  if (on && !app.ed) edFiles();
  app.dirty = true;
}

// ------------------------------------------------------------------------------------------------
// Start
// ------------------------------------------------------------------------------------------------
async function main() {
  legend();
  resize();
  window.addEventListener('resize', resize);
  $('fit').onclick = fit;
  $('show-ids').onchange = () => { app.dirty = true; };
  $('play').onclick = togglePlay;
  $('speed').onchange = () => { app.speed = Number($('speed').value); };
  $('slider').oninput = () => setReplayTime(Number($('slider').value), true);
  $('toggle-editor').onclick = () => setEditing(!app.editing);
  $('ed-open').onclick = () => edOpen($('ed-files').value);
  $('ed-new').onclick = edNew;
  $('ed-save').onclick = edSave;
  $('ed-validate').onclick = edValidate;
  $('ed-run').onclick = edRun;
  $('ed-add-person').onclick = edAddPerson;
  $('ed-add-wall').onclick = edAddWall;
  $('ed-add-box').onclick = edAddBox;
  $('ed-delete').onclick = edDelete;
  const info = await (await fetch('/api/info')).json();
  app.mode = info.mode;
  $('toggle-editor').hidden = !info.editor;
  await loadScene();
  if (info.mode === 'live') { $('mode').textContent = 'live'; startLive(); }
  else if (info.mode === 'replay') await startReplay(await (await fetch('/api/replay')).json(), '/api/replay/chunk?i=');
  else { $('mode').textContent = 'editor'; setEditing(true); }
  requestAnimationFrame(loop);
}

window.hunavView = {
  drawn, view, app, toPx,
  ready: false,
  // The RGBA of the canvas at a CSS pixel.
  pixel(px, py) { const d = window.devicePixelRatio || 1; return Array.from(ctx.getImageData(Math.round(px * d), Math.round(py * d), 1, 1).data); },
  // Shows time t of the replay now, with the chunks in the page (a chunk not yet in the page is fetched
  // and shown when it arrives); seekLoaded waits for the chunk first (a promise of what was drawn).
  seek(t) { setReplayTime(t, false); draw(); return drawn; },
  async seekLoaded(t) { await loadChunk(app.replay, chunkAtTime(app.replay, t)); return this.seek(t); },
  // Fetches the chunks of [t0, t1] (at most KEEP_CHUNKS stay).
  async preload(t0, t1) {
    const rp = app.replay;
    const jobs = [];
    for (let i = chunkAtTime(rp, t0); i <= chunkAtTime(rp, t1); ++i) jobs.push(loadChunk(rp, i));
    await Promise.all(jobs);
  },
  fps() { const n = app.fpsTimes.length; return n < 2 ? 0 : (n - 1) * 1000 / (app.fpsTimes[n - 1] - app.fpsTimes[0]); },
  redraw() { draw(); return drawn; },
  errors: app.errors,
  editor: { open: edOpen, save: edSave, validate: edValidate, files: edFiles, setEditing, state: () => app.ed, handles: () => (app.ed ? edHandles() : []) },
};
main().then(() => { window.hunavView.ready = true; }, (e) => { app.errors.push(String(e && e.stack || e)); });
