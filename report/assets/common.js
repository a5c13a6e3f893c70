/* HuNav-LCM report: helpers shared by the run and the batch page (window.HR).
 * Plain DOM and SVG, no library: the page must open from a file with no network. */
(function () {
  'use strict';
  var SVG_NS = 'http://www.w3.org/2000/svg';
  var HR = {};

  // HuNavSim behavior codes 1..6 (index 0: the robot). Okabe-Ito colours, distinguishable by most
  // colour-blind readers.
  HR.behaviorNames = ['robot', 'regular', 'impassive', 'surprised', 'scared', 'curious', 'threatening'];
  HR.behaviorColors = ['#111111', '#0072B2', '#009E73', '#E69F00', '#CC79A7', '#56B4E9', '#D55E00'];
  HR.behaviorColor = function (b) { return HR.behaviorColors[b] || '#777777'; };
  HR.behaviorName = function (b) { return HR.behaviorNames[b] || ('behavior ' + b); };
  HR.behaviorCode = function (name) { var i = HR.behaviorNames.indexOf(String(name)); return i > 0 ? i : 0; };
  HR.seriesColors = ['#0072B2', '#D55E00', '#009E73', '#CC79A7', '#E69F00', '#56B4E9', '#6a3d9a', '#b15928'];

  // An episode status as a coloured badge; `cls` is the page data's statusClass (html_page.hpp:
  // ok, warn, stuck, bad), so the colours follow one list, the C++ one.
  HR.statusBadge = function (status, cls) {
    return HR.el('span', { class: 'badge ' + (cls || 'bad'), text: status || 'unknown' });
  };
  HR.data = function () { return JSON.parse(document.getElementById('hunav-data').textContent); };

  // el('div', {class: 'x', text: 'hello'}, [children...]): an HTML element.
  HR.el = function (tag, attrs, children) {
    var e = document.createElement(tag);
    attrs = attrs || {};
    Object.keys(attrs).forEach(function (k) {
      var v = attrs[k];
      if (v === undefined || v === null || v === false) return;
      if (k === 'text') e.textContent = v;
      else if (k === 'html') throw new Error('HR.el: no html attribute (text only)');
      else if (k.slice(0, 2) === 'on') e.addEventListener(k.slice(2), v);
      else e.setAttribute(k, v === true ? '' : String(v));
    });
    (children || []).forEach(function (c) {
      if (c === null || c === undefined) return;
      e.appendChild(typeof c === 'string' ? document.createTextNode(c) : c);
    });
    return e;
  };

  HR.svg = function (tag, attrs, parent) {
    var e = document.createElementNS(SVG_NS, tag);
    Object.keys(attrs || {}).forEach(function (k) {
      if (k === 'text') e.textContent = attrs[k];
      else if (attrs[k] !== undefined && attrs[k] !== null) e.setAttribute(k, String(attrs[k]));
    });
    if (parent) parent.appendChild(e);
    return e;
  };

  HR.isNum = function (v) { return typeof v === 'number' && isFinite(v); };

  // A number for a table or a label: 4 significant digits, no exponent for ordinary magnitudes.
  HR.fmt = function (v, digits) {
    if (!HR.isNum(v)) return '–';
    digits = digits || 4;
    if (v === 0) return '0';
    var a = Math.abs(v);
    if (a >= 1e6 || a < 1e-4) return v.toExponential(digits - 1);
    var s = v.toPrecision(digits);
    if (s.indexOf('e') < 0 && s.indexOf('.') >= 0) s = s.replace(/0+$/, '').replace(/\.$/, '');
    return s;
  };
  HR.fmtTime = function (t) { return HR.isNum(t) ? t.toFixed(2) + ' s' : '–'; };

  // Tick positions for an axis from lo to hi: about `count` ticks at 1, 2 or 5 times a power of ten.
  HR.ticks = function (lo, hi, count) {
    if (!(hi > lo)) { hi = lo + 1; }
    var raw = (hi - lo) / Math.max(1, count || 5);
    var p = Math.pow(10, Math.floor(Math.log10(raw)));
    var m = raw / p;
    var step = (m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10) * p;
    var out = [];
    for (var v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    return { step: step, values: out };
  };
  HR.tickLabel = function (v, step) {
    var decimals = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
    return v.toFixed(Math.min(decimals, 6));
  };

  // Index of the last element of the sorted array `a` that is <= x (0 when x is before the first).
  HR.floorIndex = function (a, x) {
    var lo = 0, hi = a.length - 1;
    if (hi < 0 || x <= a[0]) return 0;
    if (x >= a[hi]) return hi;
    while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (a[mid] <= x) lo = mid; else hi = mid; }
    return lo;
  };

  // Union of [t0, t1] spans.
  HR.mergeSpans = function (spans) {
    var s = spans.slice().sort(function (a, b) { return a[0] - b[0]; });
    var out = [];
    s.forEach(function (x) {
      if (out.length && x[0] <= out[out.length - 1][1]) out[out.length - 1][1] = Math.max(out[out.length - 1][1], x[1]);
      else out.push([x[0], x[1]]);
    });
    return out;
  };

  HR.legend = function (items) {
    return HR.el('div', { class: 'legend' }, items.map(function (it) {
      var cls = 'swatch' + (it.kind ? ' ' + it.kind : '');
      var style = 'background:' + it.color + (it.opacity ? ';opacity:' + it.opacity : '') + (it.border ? ';border:1px solid ' + it.border : '');
      return HR.el('span', {}, [HR.el('span', { class: cls, style: style }), it.label]);
    }));
  };

  HR.table = function (headers, rows, attrs) {
    var thead = HR.el('thead', {}, [HR.el('tr', {}, headers.map(function (h) {
      return typeof h === 'string' ? HR.el('th', { text: h }) : HR.el('th', h);
    }))]);
    var tbody = HR.el('tbody', {}, rows.map(function (r) {
      return HR.el('tr', {}, r.map(function (c) {
        if (c instanceof Node) return HR.el('td', {}, [c]);
        if (c !== null && typeof c === 'object') {
          var td = HR.el('td', { class: c.cls, title: c.title }, [c.node || c.text]);
          if (c.sub) td.appendChild(HR.el('span', { class: 'sub', text: c.sub }));
          if (c.tag) td.appendChild(HR.el('span', { class: 'tag', text: c.tag }));
          return td;
        }
        return HR.el('td', { text: c === undefined || c === null ? '' : String(c) });
      }));
    }));
    var t = HR.el('table', attrs || {}, [thead, tbody]);
    t.setAttribute('data-rows', String(rows.length));
    return HR.el('div', { class: 'table-wrap' }, [t]);
  };

  // A time plot in SVG: axes with units, grid, legend, shaded bands and spans, a cursor, and a
  // readout of every series' value under the mouse. opts:
  //   key, title, xLabel, yLabel, series [{name, color, t, v, width, dash}], bands [{y0, y1, color, label}],
  //   spans [{t0, t1, color}], xMin, xMax, yMin, yMax, onSeek(t)
  // Returns {svg, setCursor(t)}. After drawing, the svg carries data-plot, data-points (points of the
  // series drawn) and data-drawn="true".
  HR.linePlot = function (parent, opts) {
    var W = 560, H = 290, ml = 62, mr = 16, mt = 30, mb = 44;
    var pw = W - ml - mr, ph = H - mt - mb;
    var svg = HR.svg('svg', { class: 'plot', viewBox: '0 0 ' + W + ' ' + H, role: 'img', 'aria-label': opts.title });
    parent.appendChild(svg);
    var series = opts.series || [];
    var xMin = opts.xMin, xMax = opts.xMax, yLo = Infinity, yHi = -Infinity;
    series.forEach(function (s) {
      s.v.forEach(function (v) { if (HR.isNum(v)) { if (v < yLo) yLo = v; if (v > yHi) yHi = v; } });
      if (!HR.isNum(xMin) && s.t.length) xMin = s.t[0];
      if (!HR.isNum(xMax) && s.t.length) xMax = s.t[s.t.length - 1];
    });
    if (!HR.isNum(xMin)) xMin = 0;
    if (!HR.isNum(xMax) || xMax <= xMin) xMax = xMin + 1;
    if (!HR.isNum(yLo)) { yLo = 0; yHi = 1; }
    if (HR.isNum(opts.yMin)) yLo = Math.min(yLo, opts.yMin);
    if (HR.isNum(opts.yMinFloor)) yLo = opts.yMinFloor;
    if (HR.isNum(opts.yMax)) yHi = Math.max(yHi, opts.yMax);
    if (yHi <= yLo) yHi = yLo + 1;
    var pad = (yHi - yLo) * 0.06;
    if (!HR.isNum(opts.yMin) && !HR.isNum(opts.yMinFloor)) yLo -= pad;
    yHi += pad;
    var yt = HR.ticks(yLo, yHi, 5), xt = HR.ticks(xMin, xMax, 7);
    var X = function (t) { return ml + (t - xMin) / (xMax - xMin) * pw; };
    var Y = function (v) { return mt + (1 - (v - yLo) / (yHi - yLo)) * ph; };

    HR.svg('text', { x: ml, y: 18, class: 'title', text: opts.title }, svg);
    var clipId = 'clip-' + opts.key;
    var defs = HR.svg('defs', {}, svg);
    var clip = HR.svg('clipPath', { id: clipId }, defs);
    HR.svg('rect', { x: ml, y: mt, width: pw, height: ph }, clip);
    var plotArea = HR.svg('g', { 'clip-path': 'url(#' + clipId + ')' }, svg);

    (opts.bands || []).forEach(function (b) {
      var y0 = Math.max(yLo, b.y0), y1 = Math.min(yHi, b.y1);
      if (y1 <= y0) return;
      HR.svg('rect', { x: ml, y: Y(y1), width: pw, height: Y(y0) - Y(y1), fill: b.color, opacity: 0.5 }, plotArea);
      if (b.label) HR.svg('text', { x: ml + pw - 4, y: Y(y1) + 11, 'text-anchor': 'end', 'font-size': 10.5, fill: '#8a6d3b', text: b.label }, plotArea);
    });
    (opts.spans || []).forEach(function (s) {
      var x0 = X(s.t0), x1 = Math.max(X(s.t1), x0 + 1);
      HR.svg('rect', { x: x0, y: mt, width: x1 - x0, height: ph, fill: s.color, opacity: 0.16 }, plotArea);
    });
    var grid = HR.svg('g', { class: 'grid' }, svg);
    var axis = HR.svg('g', { class: 'axis' }, svg);
    yt.values.forEach(function (v) {
      if (v < yLo || v > yHi) return;
      HR.svg('line', { x1: ml, x2: ml + pw, y1: Y(v), y2: Y(v) }, grid);
      HR.svg('line', { x1: ml - 4, x2: ml, y1: Y(v), y2: Y(v) }, axis);
      HR.svg('text', { x: ml - 7, y: Y(v) + 4, 'text-anchor': 'end', text: HR.tickLabel(v, yt.step) }, svg);
    });
    xt.values.forEach(function (v) {
      if (v < xMin || v > xMax) return;
      HR.svg('line', { x1: X(v), x2: X(v), y1: mt, y2: mt + ph }, grid);
      HR.svg('line', { x1: X(v), x2: X(v), y1: mt + ph, y2: mt + ph + 4 }, axis);
      HR.svg('text', { x: X(v), y: mt + ph + 17, 'text-anchor': 'middle', text: HR.tickLabel(v, xt.step) }, svg);
    });
    HR.svg('path', { d: 'M' + ml + ',' + mt + 'V' + (mt + ph) + 'H' + (ml + pw), fill: 'none' }, axis);
    HR.svg('text', { x: ml + pw / 2, y: H - 6, 'text-anchor': 'middle', text: opts.xLabel || 'time [s]' }, svg);
    HR.svg('text', { x: 14, y: mt + ph / 2, 'text-anchor': 'middle', transform: 'rotate(-90 14 ' + (mt + ph / 2) + ')', text: opts.yLabel }, svg);

    var points = 0;
    series.forEach(function (s) {
      var d = '', pen = false;
      for (var i = 0; i < s.t.length; i++) {
        var v = s.v[i];
        if (!HR.isNum(v)) { pen = false; continue; }
        d += (pen ? 'L' : 'M') + X(s.t[i]).toFixed(1) + ',' + Y(v).toFixed(1);
        pen = true;
        points++;
      }
      if (d) HR.svg('path', { d: d, fill: 'none', stroke: s.color, 'stroke-width': s.width || 1.6,
                              'stroke-dasharray': s.dash, 'stroke-linejoin': 'round' }, plotArea);
    });

    if (points === 0)
      HR.svg('text', { x: ml + pw / 2, y: mt + ph / 2, 'text-anchor': 'middle', class: 'readout', text: opts.emptyText || 'no values' }, svg);
    var cursor = HR.svg('line', { x1: ml, x2: ml, y1: mt, y2: mt + ph, stroke: '#111', 'stroke-width': 1, 'stroke-dasharray': '3,3', visibility: 'hidden' }, svg);
    var readout = HR.svg('text', { x: ml + pw, y: 18, 'text-anchor': 'end', class: 'readout' }, svg);
    var valueAt = function (s, t) {
      var i = HR.floorIndex(s.t, t);
      if (i + 1 < s.t.length && Math.abs(s.t[i + 1] - t) < Math.abs(s.t[i] - t)) i++;
      return s.v[i];
    };
    var showReadout = function (t) {
      readout.textContent = 't = ' + t.toFixed(2) + ' s: ' + series.map(function (s) {
        return (series.length > 1 ? s.short || s.name : '') + (series.length > 1 ? ' ' : '') + HR.fmt(valueAt(s, t), 3);
      }).join(', ') + (opts.unit ? ' ' + opts.unit : '');
    };
    var overlay = HR.svg('rect', { x: ml, y: mt, width: pw, height: ph, fill: 'transparent', cursor: 'crosshair' }, svg);
    var tAt = function (ev) {
      var r = svg.getBoundingClientRect();
      var x = (ev.clientX - r.left) / r.width * W;
      return Math.min(xMax, Math.max(xMin, xMin + (x - ml) / pw * (xMax - xMin)));
    };
    overlay.addEventListener('mousemove', function (ev) { showReadout(tAt(ev)); });
    overlay.addEventListener('mouseleave', function () { readout.textContent = ''; });
    overlay.addEventListener('click', function (ev) { if (opts.onSeek) opts.onSeek(tAt(ev)); });

    svg.setAttribute('data-plot', opts.key);
    svg.setAttribute('data-points', String(points));
    svg.setAttribute('data-drawn', 'true');
    return {
      svg: svg,
      setCursor: function (t) {
        if (!HR.isNum(t)) { cursor.setAttribute('visibility', 'hidden'); return; }
        var x = X(Math.min(xMax, Math.max(xMin, t)));
        cursor.setAttribute('x1', x); cursor.setAttribute('x2', x);
        cursor.setAttribute('visibility', 'visible');
      }
    };
  };

  // Means with 95% confidence intervals per group, and the individual values as dots. opts:
  //   key, title, yLabel, groups [{name, color, mean, lo, hi, n, values: [numbers]}]
  // The svg carries data-plot, data-points (bars and dots drawn) and data-drawn="true".
  HR.ciChart = function (parent, opts) {
    var groups = opts.groups || [];
    var W = 560, H = 300, ml = 66, mr = 16, mt = 30, mb = 50;
    var pw = W - ml - mr, ph = H - mt - mb;
    var svg = HR.svg('svg', { class: 'plot', viewBox: '0 0 ' + W + ' ' + H, role: 'img', 'aria-label': opts.title });
    parent.appendChild(svg);
    var lo = Infinity, hi = -Infinity;
    var grow = function (v) { if (HR.isNum(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); } };
    groups.forEach(function (g) { grow(g.mean); grow(g.lo); grow(g.hi); (g.values || []).forEach(grow); });
    if (!HR.isNum(lo)) { lo = 0; hi = 1; }
    lo = Math.min(lo, 0); hi = Math.max(hi, 0);
    if (hi <= lo) hi = lo + 1;
    var pad = (hi - lo) * 0.08;
    hi += pad; if (lo < 0) lo -= pad;
    var yt = HR.ticks(lo, hi, 5);
    var Y = function (v) { return mt + (1 - (v - lo) / (hi - lo)) * ph; };
    HR.svg('text', { x: ml, y: 18, class: 'title', text: opts.title }, svg);
    var grid = HR.svg('g', { class: 'grid' }, svg), axis = HR.svg('g', { class: 'axis' }, svg);
    yt.values.forEach(function (v) {
      if (v < lo || v > hi) return;
      HR.svg('line', { x1: ml, x2: ml + pw, y1: Y(v), y2: Y(v) }, grid);
      HR.svg('text', { x: ml - 7, y: Y(v) + 4, 'text-anchor': 'end', text: HR.tickLabel(v, yt.step) }, svg);
    });
    HR.svg('path', { d: 'M' + ml + ',' + mt + 'V' + (mt + ph) + 'H' + (ml + pw), fill: 'none' }, axis);
    HR.svg('line', { x1: ml, x2: ml + pw, y1: Y(0), y2: Y(0), stroke: '#9aa1ad' }, svg);
    HR.svg('text', { x: 14, y: mt + ph / 2, 'text-anchor': 'middle', transform: 'rotate(-90 14 ' + (mt + ph / 2) + ')', text: opts.yLabel }, svg);
    var slot = pw / Math.max(1, groups.length), bw = Math.min(70, slot * 0.5), drawn = 0;
    groups.forEach(function (g, i) {
      var cx = ml + slot * (i + 0.5);
      HR.svg('text', { x: cx, y: mt + ph + 17, 'text-anchor': 'middle', text: g.name }, svg);
      HR.svg('text', { x: cx, y: mt + ph + 32, 'text-anchor': 'middle', 'font-size': 11, fill: '#8a93a3', text: 'n = ' + g.n }, svg);
      if (HR.isNum(g.mean)) {
        var y0 = Y(0), y1 = Y(g.mean);
        var bar = HR.svg('rect', { x: cx - bw / 2, y: Math.min(y0, y1), width: bw, height: Math.max(1, Math.abs(y1 - y0)), fill: g.color, opacity: 0.35, stroke: g.color }, svg);
        HR.svg('title', { text: g.name + ': mean ' + HR.fmt(g.mean) + (HR.isNum(g.lo) ? ', 95% CI [' + HR.fmt(g.lo) + ', ' + HR.fmt(g.hi) + ']' : '') }, bar);
        drawn++;
      }
      if (HR.isNum(g.lo) && HR.isNum(g.hi)) {
        HR.svg('line', { x1: cx, x2: cx, y1: Y(g.lo), y2: Y(g.hi), stroke: '#111', 'stroke-width': 1.4 }, svg);
        [g.lo, g.hi].forEach(function (v) { HR.svg('line', { x1: cx - 9, x2: cx + 9, y1: Y(v), y2: Y(v), stroke: '#111', 'stroke-width': 1.4 }, svg); });
      }
      (g.values || []).forEach(function (v, k) {
        if (!HR.isNum(v)) return;
        var jitter = ((k * 0.618034) % 1 - 0.5) * bw * 0.7;
        HR.svg('circle', { cx: cx + jitter, cy: Y(v), r: 2.6, fill: g.color, stroke: '#fff', 'stroke-width': 0.6 }, svg);
        drawn++;
      });
    });
    svg.setAttribute('data-plot', opts.key);
    svg.setAttribute('data-points', String(drawn));
    svg.setAttribute('data-drawn', 'true');
    return svg;
  };

  // Runs `render` and marks the page: <html data-report-status="drawn"> after it, "error" (and the
  // message in data-js-errors / the error box) when it throws.
  HR.start = function (render) {
    try {
      render(HR.data(), document.getElementById('app'));
      if (!window.HUNAV_ERRORS.length) document.documentElement.setAttribute('data-report-status', 'drawn');
    } catch (e) {
      window.hunavRecordError((e && e.stack) ? e.stack : e);
    }
  };

  window.HR = HR;
})();
