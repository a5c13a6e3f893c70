/* HuNav-LCM run page: the map with trajectories and a replay, the per-tick plots, the metrics. */
(function () {
  'use strict';
  var HR = window.HR, el = HR.el;

  function metricValue(d, name) {
    for (var i = 0; i < d.metrics.length; i++) if (d.metrics[i][0] === name) return d.metrics[i];
    return null;
  }

  function header(d, app) {
    var info = d.info;
    if (d.batchLink) app.appendChild(el('div', { class: 'crumbs' }, [el('a', { href: d.batchLink, text: '← batch report' })]));
    app.appendChild(el('h1', { text: 'Run ' + (info.run_id || '') }));
    app.appendChild(el('p', { class: 'subtitle' }, [
      'scenario ', el('b', { text: info.scenario || '?' }), ' · planner ', el('b', { text: info.planner || '?' }),
      ' · seed ', el('b', { text: String(info.seed) }), ' · mode ' + (info.mode || '?') + ' · profile ' + (info.profile || '?') + ' · ',
      HR.statusBadge(info.status, info.statusClass), ' ', info.reason || '']));
    var cards = el('div', { class: 'cards' });
    var card = function (label, value, unit) {
      cards.appendChild(el('div', { class: 'card' }, [el('div', { class: 'label', text: label }),
        el('div', {}, [el('span', { class: 'value', text: value }), unit ? el('span', { class: 'unit', text: unit }) : null])]));
    };
    card('simulated time', HR.fmt(info.sim_time), 's');
    card('wall-clock time', HR.fmt(info.wall_time, 3), 's');
    [['completed', 'goal reached'], ['path_length', 'path length'], ['minimum_distance_to_people', 'closest approach'],
     ['personal_space_intrusions', 'personal space intrusions'], ['social_work', 'social work'],
     ['robot_on_person_collision', 'robot-on-person collisions']].forEach(function (m) {
      var v = metricValue(d, m[0]);
      if (!v) return;
      var num = Number(v[2]);
      card(m[1], v[2] === 'true' || v[2] === 'false' ? (v[2] === 'true' ? 'yes' : 'no') : HR.fmt(num), v[1] === 'bool' ? '' : v[1]);
    });
    app.appendChild(cards);
    d.notes.forEach(function (n) { app.appendChild(el('div', { class: 'note', text: n })); });
  }

  // The map: static layer (walls, goals, whole trajectories, faint) drawn once; every frame adds the
  // trails walked so far and the bodies at the frame's time.
  function mapView(d, panel, onFrame) {
    var frames = d.frameT.length;
    var wrap = el('div');
    panel.appendChild(wrap);
    var canvas = el('canvas', { class: 'map', 'data-frames': String(frames) });
    wrap.appendChild(canvas);
    var lo = [d.bounds[0], d.bounds[1]], hi = [d.bounds[2], d.bounds[3]];
    var ml = 52, mr = 12, mt = 12, mb = 40;
    var cssW = Math.max(420, Math.min(1130, panel.clientWidth || 1100) - 2);
    var worldW = hi[0] - lo[0], worldH = hi[1] - lo[1];
    var scale = (cssW - ml - mr) / worldW;
    var cssH = worldH * scale + mt + mb;
    if (cssH > 640) { scale = (640 - mt - mb) / worldH; cssH = 640; }
    cssH = Math.max(cssH, 220);
    var ox = ml + ((cssW - ml - mr) - worldW * scale) / 2;
    var oy = mt + ((cssH - mt - mb) - worldH * scale) / 2;
    var dpr = window.devicePixelRatio || 1;
    canvas.width = Math.round(cssW * dpr); canvas.height = Math.round(cssH * dpr);
    canvas.style.height = cssH + 'px';
    canvas.style.maxWidth = cssW + 'px';
    var PX = function (x) { return ox + (x - lo[0]) * scale; };
    var PY = function (y) { return oy + (hi[1] - y) * scale; };

    var staticLayer = document.createElement('canvas');
    staticLayer.width = canvas.width; staticLayer.height = canvas.height;
    var s = staticLayer.getContext('2d');
    s.scale(dpr, dpr);
    s.fillStyle = '#ffffff'; s.fillRect(0, 0, cssW, cssH);
    // Grid and axes in metres.
    var xt = HR.ticks(lo[0], hi[0], Math.max(4, Math.round(worldW * scale / 90)));
    var yt = HR.ticks(lo[1], hi[1], Math.max(3, Math.round(worldH * scale / 70)));
    var step = Math.max(xt.step, yt.step);
    xt = HR.ticks(lo[0], hi[0], Math.max(1, worldW / step)); yt = HR.ticks(lo[1], hi[1], Math.max(1, worldH / step));
    s.strokeStyle = '#eceff3'; s.lineWidth = 1;
    s.font = '11px system-ui, sans-serif'; s.fillStyle = '#4b5563';
    var x0 = PX(lo[0]), x1 = PX(hi[0]), y0 = PY(lo[1]), y1 = PY(hi[1]);
    xt.values.forEach(function (v) {
      s.beginPath(); s.moveTo(PX(v), y1); s.lineTo(PX(v), y0); s.stroke();
      s.textAlign = 'center'; s.fillText(HR.tickLabel(v, xt.step), PX(v), y0 + 14);
    });
    yt.values.forEach(function (v) {
      s.beginPath(); s.moveTo(x0, PY(v)); s.lineTo(x1, PY(v)); s.stroke();
      s.textAlign = 'right'; s.fillText(HR.tickLabel(v, yt.step), x0 - 6, PY(v) + 4);
    });
    s.strokeStyle = '#6b7280'; s.strokeRect(x0, y1, x1 - x0, y0 - y1);
    s.fillStyle = '#374151'; s.font = '12px system-ui, sans-serif'; s.textAlign = 'center';
    s.fillText('x [m]', (x0 + x1) / 2, y0 + 31);
    s.save(); s.translate(14, (y0 + y1) / 2); s.rotate(-Math.PI / 2); s.fillText('y [m]', 0, 0); s.restore();

    s.save();
    s.beginPath(); s.rect(x0, y1, x1 - x0, y0 - y1); s.clip();
    // Static map.
    s.fillStyle = '#c9ced6'; s.strokeStyle = '#3f4652'; s.lineWidth = 2.5; s.lineCap = 'round'; s.lineJoin = 'round';
    d.map.polylines.forEach(function (p) {
      s.beginPath();
      for (var i = 0; i < p.length; i += 2) (i ? s.lineTo : s.moveTo).call(s, PX(p[i]), PY(p[i + 1]));
      s.stroke();
    });
    s.lineWidth = 1.2;
    d.map.polygons.forEach(function (p) {
      s.beginPath();
      for (var i = 0; i < p.length; i += 2) (i ? s.lineTo : s.moveTo).call(s, PX(p[i]), PY(p[i + 1]));
      s.closePath(); s.fill(); s.stroke();
    });
    d.map.circles.forEach(function (c) { s.beginPath(); s.arc(PX(c[0]), PY(c[1]), c[2] * scale, 0, 2 * Math.PI); s.fill(); s.stroke(); });
    s.fillStyle = '#3f4652';
    for (var i = 0; i < d.map.points.length; i += 2) s.fillRect(PX(d.map.points[i]) - 1, PY(d.map.points[i + 1]) - 1, 2, 2);

    var manyPeople = d.tracks.length > 60;
    var staticPoints = 0;
    var path = function (ctx, t, from, to) {
      var pen = false, n = 0;
      ctx.beginPath();
      for (var f = from; f <= to; f++) {
        var x = t.x[f], y = t.y[f];
        if (x === null || y === null) { pen = false; continue; }
        if (pen) ctx.lineTo(PX(x), PY(y)); else ctx.moveTo(PX(x), PY(y));
        pen = true; n++;
      }
      ctx.stroke();
      return n;
    };
    // Whole trajectories, faint: where everyone went.
    s.lineWidth = 1.2;
    d.tracks.forEach(function (t) {
      s.strokeStyle = HR.behaviorColor(t.robot ? 0 : t.behavior);
      s.globalAlpha = t.robot ? 0.25 : (manyPeople ? 0.08 : 0.22);
      staticPoints += path(s, t, 0, frames - 1);
    });
    s.globalAlpha = 1;
    // Goals: the robot's as a target with its radius, the people's as small diamonds.
    d.tracks.forEach(function (t) {
      var c = HR.behaviorColor(t.robot ? 0 : t.behavior);
      for (var g = 0; g < t.goals.length; g += 2) {
        var gx = PX(t.goals[g]), gy = PY(t.goals[g + 1]);
        if (t.robot) {
          s.strokeStyle = '#111'; s.lineWidth = 1.5;
          s.beginPath(); s.arc(gx, gy, Math.max(5, 0.3 * scale), 0, 2 * Math.PI); s.stroke();
          s.beginPath(); s.moveTo(gx - 7, gy); s.lineTo(gx + 7, gy); s.moveTo(gx, gy - 7); s.lineTo(gx, gy + 7); s.stroke();
        } else if (!manyPeople) {
          s.fillStyle = c; s.globalAlpha = 0.55;
          s.beginPath(); s.moveTo(gx, gy - 4); s.lineTo(gx + 4, gy); s.lineTo(gx, gy + 4); s.lineTo(gx - 4, gy); s.closePath(); s.fill();
          s.globalAlpha = 1;
        }
      }
    });
    s.restore();
    canvas.setAttribute('data-points', String(staticPoints));

    var ctx = canvas.getContext('2d');
    // Whole trails of a crowd hide everything else: crowds start with the last 5 s.
    var trailMode = d.tracks.length > 30 ? '5s' : 'full';
    var activeByTrack = {};
    d.active.forEach(function (a) { (activeByTrack[a[0]] = activeByTrack[a[0]] || []).push([a[2], a[3]]); });
    var isActive = function (k, t) {
      var spans = activeByTrack[k];
      if (!spans) return false;
      for (var i = 0; i < spans.length; i++) if (t >= spans[i][0] - 1e-9 && t <= spans[i][1] + 1e-9) return true;
      return false;
    };
    var trailFrames = function () {
      if (trailMode === 'none') return 0;
      if (trailMode === 'full') return frames;
      var dtFrame = frames > 1 ? (d.frameT[frames - 1] - d.frameT[0]) / (frames - 1) : 1;
      return Math.max(1, Math.round(5 / Math.max(dtFrame, 1e-6)));
    };
    var drawFrame = function (f) {
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.drawImage(staticLayer, 0, 0);
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      ctx.save();
      ctx.beginPath(); ctx.rect(x0, y1, x1 - x0, y0 - y1); ctx.clip();
      var tNow = d.frameT[f], back = trailFrames();
      ctx.lineWidth = manyPeople ? 1.2 : 2; ctx.lineCap = 'round'; ctx.lineJoin = 'round';
      if (back > 0) {
        for (var k = d.tracks.length - 1; k >= 0; k--) {
          var t = d.tracks[k];
          ctx.strokeStyle = HR.behaviorColor(t.robot ? 0 : t.behavior);
          ctx.globalAlpha = t.robot ? 0.95 : 0.8;
          path(ctx, t, Math.max(0, f - back), f);
        }
      }
      ctx.globalAlpha = 1;
      var labels = d.tracks.length <= 40;
      for (var j = d.tracks.length - 1; j >= 0; j--) {
        var e = d.tracks[j], x = e.x[f], y = e.y[f];
        if (x === null || y === null) continue;
        var px = PX(x), py = PY(y), r = Math.max(3, e.radius * scale);
        var color = HR.behaviorColor(e.robot ? 0 : e.behavior);
        if (!e.robot && isActive(j, tNow)) {
          ctx.strokeStyle = color; ctx.lineWidth = 2; ctx.setLineDash([3, 2]);
          ctx.beginPath(); ctx.arc(px, py, r + 4, 0, 2 * Math.PI); ctx.stroke(); ctx.setLineDash([]);
        }
        ctx.fillStyle = e.robot ? '#ffffff' : color;
        ctx.globalAlpha = e.robot ? 1 : 0.85;
        ctx.beginPath(); ctx.arc(px, py, r, 0, 2 * Math.PI); ctx.fill();
        ctx.globalAlpha = 1;
        ctx.strokeStyle = e.robot ? '#111' : '#ffffff'; ctx.lineWidth = e.robot ? 2.2 : 1;
        ctx.stroke();
        if (e.yaw && e.yaw[f] !== null && r >= 4) {
          ctx.strokeStyle = e.robot ? '#111' : '#ffffff'; ctx.lineWidth = e.robot ? 2.2 : 1.5;
          ctx.beginPath(); ctx.moveTo(px, py); ctx.lineTo(px + Math.cos(e.yaw[f]) * r, py - Math.sin(e.yaw[f]) * r); ctx.stroke();
        }
        if (labels) {
          ctx.fillStyle = '#1f2937'; ctx.font = '11px system-ui, sans-serif'; ctx.textAlign = 'left';
          ctx.fillText(e.robot ? 'robot' : String(e.id), px + r + 3, py - r - 1);
        }
      }
      ctx.restore();
      ctx.fillStyle = '#111'; ctx.font = '600 12px system-ui, sans-serif'; ctx.textAlign = 'right';
      ctx.fillText('t = ' + tNow.toFixed(2) + ' s', x1 - 6, y1 + 16);
    };

    // Replay controls.
    var playing = false, simT = d.frameT[0], frame = 0, lastWall = null, speed = 1;
    var button = el('button', { type: 'button', title: 'play / pause (space)', text: '▶ play' });
    var slider = el('input', { type: 'range', min: 0, max: Math.max(0, frames - 1), step: 1, value: 0, 'aria-label': 'replay time' });
    var timeLabel = el('span', { class: 'time' });
    var speedSelect = el('select', { 'aria-label': 'replay speed' }, [0.25, 0.5, 1, 2, 5, 10, 25].map(function (v) {
      return el('option', { value: v, selected: v === 1, text: v + '×' });
    }));
    var trailSelect = el('select', { 'aria-label': 'trails' }, [['full', 'whole trail'], ['5s', 'last 5 s'], ['none', 'no trail']].map(function (o) {
      return el('option', { value: o[0], selected: o[0] === trailMode, text: o[1] });
    }));
    var end = d.frameT[frames - 1];
    var show = function (f) {
      frame = f;
      slider.value = String(f);
      timeLabel.textContent = 't = ' + d.frameT[f].toFixed(2) + ' s / ' + end.toFixed(2) + ' s';
      drawFrame(f);
      onFrame(d.frameT[f]);
    };
    var tick = function (now) {
      if (!playing) return;
      if (lastWall !== null) simT += (now - lastWall) / 1000 * speed;
      lastWall = now;
      if (simT >= end) { simT = end; show(frames - 1); setPlaying(false); return; }
      var f = HR.floorIndex(d.frameT, simT);
      if (f !== frame) show(f);
      window.requestAnimationFrame(tick);
    };
    var setPlaying = function (p) {
      playing = p;
      button.textContent = p ? '❚❚ pause' : '▶ play';
      if (p) {
        if (frame >= frames - 1) { show(0); }
        simT = d.frameT[frame]; lastWall = null;
        window.requestAnimationFrame(tick);
      }
    };
    button.addEventListener('click', function () { setPlaying(!playing); });
    slider.addEventListener('input', function () { show(Number(slider.value)); simT = d.frameT[frame]; });
    speedSelect.addEventListener('change', function () { speed = Number(speedSelect.value); });
    trailSelect.addEventListener('change', function () { trailMode = trailSelect.value; drawFrame(frame); });
    document.addEventListener('keydown', function (ev) {
      if (ev.target && /INPUT|SELECT|TEXTAREA/.test(ev.target.tagName) && ev.target !== slider) return;
      if (ev.key === ' ') { ev.preventDefault(); setPlaying(!playing); }
      else if (ev.key === 'ArrowRight') { show(Math.min(frames - 1, frame + 1)); simT = d.frameT[frame]; }
      else if (ev.key === 'ArrowLeft') { show(Math.max(0, frame - 1)); simT = d.frameT[frame]; }
    });
    panel.appendChild(el('div', { class: 'controls' }, [button, slider, timeLabel,
      el('label', {}, ['speed ', speedSelect]), el('label', {}, ['trails ', trailSelect])]));

    var behaviors = {};
    d.tracks.forEach(function (t) { if (!t.robot) behaviors[t.behavior] = true; });
    var items = [{ label: 'robot (white disc, black outline; heading line)', color: '#ffffff', border: '#111', kind: 'dot' },
                 { label: 'robot goal (⊕, goal radius)', color: '#111', kind: 'line' }];
    Object.keys(behaviors).sort().forEach(function (b) {
      items.push({ label: HR.behaviorName(Number(b)) + ' person', color: HR.behaviorColor(Number(b)), kind: 'dot' });
    });
    items.push({ label: 'reaction active (dashed ring)', color: '#ffffff', border: '#555', kind: 'dot' });
    items.push({ label: d.map.points.length ? 'recorded obstacle points' : 'walls and furniture', color: '#3f4652' });
    panel.appendChild(HR.legend(items));
    panel.appendChild(el('p', { class: 'caption', text: 'Bodies drawn to scale (radius from states.csv). Faint lines: whole trajectories; ' +
      'bold: the trail up to the replay time. Map: ' + d.map.source + '. ' + frames + ' frames from ' + d.samples + ' samples' +
      (d.frameStride > 1 ? ' (one sample in ' + d.frameStride + ')' : '') + '. Keys: space plays or pauses, ← → step; report.html#t=12.5 opens at t = 12.5 s.' }));
    // A link to a moment: report.html#t=12.5 opens the replay at t = 12.5 s.
    var atHash = /(?:^#|&)t=([0-9.]+)/.exec(window.location.hash || '');
    show(atHash ? HR.floorIndex(d.frameT, Number(atHash[1])) : 0);
    return { seek: function (t) { show(HR.floorIndex(d.frameT, t)); simT = d.frameT[frame]; } };
  }

  function plots(d, panel, seek) {
    var byKey = {};
    d.series.forEach(function (s) { byKey[s.key] = s; });
    var grid = el('div', { class: 'plots' });
    panel.appendChild(grid);
    var tEnd = d.frameT[d.frameT.length - 1], tStart = d.frameT[0];
    var spansByBehavior = {};
    d.active.forEach(function (a) { (spansByBehavior[a[1]] = spansByBehavior[a[1]] || []).push([a[2], a[3]]); });
    var spans = [];
    Object.keys(spansByBehavior).forEach(function (b) {
      HR.mergeSpans(spansByBehavior[b]).forEach(function (s) { spans.push({ t0: s[0], t1: s[1], color: HR.behaviorColor(Number(b)) }); });
    });
    var made = [];
    var cell = function () { var c = el('div'); grid.appendChild(c); return c; };
    var metric = function (name) { var m = metricValue(d, name); return m ? HR.fmt(Number(m[2])) + ' ' + m[1] : '–'; };
    var s;
    if ((s = byKey.closest_distance)) {
      var c1 = cell();
      made.push(HR.linePlot(c1, {
        key: 'closest_distance', title: 'Distance to the closest person', yLabel: 'distance [m]', unit: 'm',
        xMin: tStart, xMax: tEnd, yMinFloor: 0, onSeek: seek, spans: spans, emptyText: 'nobody in the scene at any time',
        bands: [{ y0: 0, y1: 0.45, color: '#f8c9c4', label: 'intimate' }, { y0: 0.45, y1: 1.2, color: '#fde2c0', label: 'personal' },
                { y0: 1.2, y1: 3.6, color: '#fdf3c8', label: 'social' }],
        series: [{ name: 'closest person', color: '#1f2937', t: s.t, v: s.v }]
      }));
      var legendItems = [{ label: 'surface-to-surface distance (gaps: nobody present)', color: '#1f2937', kind: 'line' },
                         { label: 'proxemic zones (0.45 / 1.2 / 3.6 m)', color: '#fde2c0' }];
      Object.keys(spansByBehavior).forEach(function (b) {
        legendItems.push({ label: HR.behaviorName(Number(b)) + ' reaction active', color: HR.behaviorColor(Number(b)), opacity: 0.3 });
      });
      c1.appendChild(HR.legend(legendItems));
    }
    if ((s = byKey.robot_speed)) {
      var c2 = cell();
      made.push(HR.linePlot(c2, {
        key: 'robot_speed', title: 'Robot linear speed', yLabel: 'speed [m/s]', unit: 'm/s', xMin: tStart, xMax: tEnd,
        yMinFloor: 0, onSeek: seek, spans: spans, series: [{ name: 'robot', color: '#0072B2', t: s.t, v: s.v }]
      }));
      c2.appendChild(HR.legend([{ label: '|v| of the robot; mean ' + metric('avg_robot_linear_speed'), color: '#0072B2', kind: 'line' }]));
    }
    if ((s = byKey.social_work)) {
      var c3 = cell();
      made.push(HR.linePlot(c3, {
        key: 'social_work', title: 'Social work', yLabel: 'social work per sample [m/s²]', unit: 'm/s²', xMin: tStart, xMax: tEnd,
        yMinFloor: 0, onSeek: seek, spans: spans, series: [{ name: 'social work', color: '#D55E00', t: s.t, v: s.v }]
      }));
      c3.appendChild(HR.legend([{ label: 'social forces between robot and people + obstacle force on the robot; integral ' + metric('social_work'),
                                  color: '#D55E00', kind: 'line' }]));
    }
    var bands = [['intimate_cum', 'intimate', '#b42318'], ['personal_cum', 'personal', '#E69F00'], ['social_cum', 'social', '#9a8c00']];
    var lines = [];
    bands.forEach(function (b) {
      if (byKey[b[0]]) lines.push({ name: b[1], short: b[1].slice(0, 4) + '.', color: b[2], t: byKey[b[0]].t, v: byKey[b[0]].v });
    });
    if (lines.length) {
      var c4 = cell();
      made.push(HR.linePlot(c4, {
        key: 'intrusions', title: 'Space intrusions (share of time so far)', yLabel: 'time in zone [%]', unit: '%',
        xMin: tStart, xMax: tEnd, yMinFloor: 0, onSeek: seek, spans: spans, series: lines
      }));
      c4.appendChild(HR.legend(lines.map(function (l) {
        return { label: l.name + ' zone: ' + metric(l.name + '_space_intrusions') + ' at the end', color: l.color, kind: 'line' };
      })));
    }
    panel.appendChild(el('p', { class: 'caption', text: 'Per-tick values (' + d.seriesSource + '), downsampled keeping each ' +
      'interval\'s extremes. Shaded columns: a person\'s reaction to the robot is active. Click a plot to move the replay there.' }));
    return function (t) { made.forEach(function (p) { p.setCursor(t); }); };
  }

  function metricsTable(d, panel) {
    var behaviors = Object.keys(d.behaviorMetrics).map(Number).sort();
    var headers = ['metric', { text: 'unit', class: 'text' }, 'run (all people)'].concat(behaviors.map(function (b) { return HR.behaviorName(b); }));
    var show = function (text) {
      if (text === undefined) return '';
      if (text === 'true' || text === 'false') return text;
      return HR.fmt(Number(text), 5);
    };
    var rows = d.metrics.map(function (m) {
      return [m[0], { text: m[1], cls: 'text' }, { text: show(m[2]), title: m[2] }].concat(behaviors.map(function (b) {
        var v = d.behaviorMetrics[String(b)][m[0]];
        return { text: show(v), title: v };
      }));
    });
    panel.appendChild(HR.table(headers, rows, { id: 'metrics-table' }));
    panel.appendChild(el('p', { class: 'caption', text: 'Values of run.json (profile ' + d.info.profile + ')' +
      (behaviors.length ? '; per behavior: metrics_beh_<b>.csv, computed over the people of that behavior only' : '') +
      '. Definitions: docs/metrics.md.' }));
  }

  // counterfactual.csv: each person against its robot-free run (hunav_run --counterfactual).
  function counterfactualTable(d, panel) {
    var cf = d.counterfactual;
    if (!cf || !cf.rows.length) return false;
    var units = { delay: 's', path_with: 'm', path_without: 'm', path_added: 'm', mean_deviation: 'm',
                  max_deviation: 'm', extra_effort: 'm/s' };
    var headers = cf.header.map(function (h) { return units[h] ? h + ' [' + units[h] + ']' : h; });
    var rows = cf.rows.map(function (r) {
      return r.map(function (v, i) {
        if (cf.header[i] === 'behavior') return { text: HR.behaviorName(Number(v)), cls: 'text' };
        if (v === 'true' || v === 'false' || i <= 4) return v;
        return { text: HR.fmt(Number(v), 4), title: v };
      });
    });
    panel.appendChild(HR.table(headers, rows, { id: 'counterfactual-table' }));
    var affected = cf.rows.filter(function (r) { return r[cf.header.indexOf('affected')] === 'true'; }).length;
    panel.appendChild(el('p', { class: 'caption', text: affected + ' of ' + cf.rows.length + ' people moved more than 0.1 m ' +
      'off the path they walk when the robot is absent (same seed, robot removed). counterfactual.csv; ' +
      'definitions: docs/metrics.md, "Counterfactual".' }));
    return true;
  }

  function provenance(d, panel) {
    var info = d.info, dl = el('dl', { class: 'kv' });
    [['run id', info.run_id], ['experiment tag', info.experiment_tag], ['scenario file', info.scenario_file],
     ['status', info.status + ' (' + info.reason + ')'], ['ticks', info.ticks + ' (' + info.recorded_ticks + ' recorded, ' + info.lost_ticks + ' lost)'],
     ['dropped messages', info.dropped_messages], ['fingerprint', info.fingerprint], ['git commit', info.git_commit],
     ['complete', info.complete ? 'yes' : 'no'], ['map', d.map.source]].forEach(function (kv) {
      dl.appendChild(el('dt', { text: kv[0] }));
      dl.appendChild(el('dd', { class: 'mono', text: String(kv[1] === undefined ? '' : kv[1]) }));
    });
    panel.appendChild(dl);
  }

  HR.start(function (d, app) {
    header(d, app);
    var mapPanel = el('section', { class: 'panel', id: 'map' }, [el('h2', { text: 'Map and replay' })]);
    app.appendChild(mapPanel);
    var plotPanel = el('section', { class: 'panel', id: 'plots' }, [el('h2', { text: 'Over time' })]);
    app.appendChild(plotPanel);
    var replay = null;
    var setCursor = plots(d, plotPanel, function (t) { if (replay) replay.seek(t); });
    replay = mapView(d, mapPanel, setCursor);
    var metricsPanel = el('section', { class: 'panel', id: 'metrics' }, [el('h2', { text: 'Metrics' })]);
    app.appendChild(metricsPanel);
    metricsTable(d, metricsPanel);
    var cfPanel = el('section', { class: 'panel', id: 'counterfactual' }, [el('h2', { text: 'The robot\'s effect on people' })]);
    if (counterfactualTable(d, cfPanel)) app.appendChild(cfPanel);
    var provPanel = el('section', { class: 'panel', id: 'provenance' }, [el('h2', { text: 'Provenance' })]);
    app.appendChild(provPanel);
    provenance(d, provPanel);
    app.appendChild(el('footer', { text: 'Written by hunav_report (HuNav-LCM). Self-contained: open it from disk, no network needed.' }));
  });
})();
