/* HuNav-LCM batch page: per scenario, the metrics x planners table (mean, std, 95% CI) overall and
 * per behavior, a chart of one metric with confidence intervals and every run, the paired
 * differences between planners, "paper vs ours" (the HuNavSim paper's means beside ours, orderings
 * that agree and disagree), the verdicts of the scenario's expect: conditions, and the list of runs
 * with links to their pages. */
(function () {
  'use strict';
  var HR = window.HR, el = HR.el;

  function unique(values) {
    var seen = {}, out = [];
    values.forEach(function (v) { if (!seen[v]) { seen[v] = true; out.push(v); } });
    return out;
  }
  function slug(s) { return String(s).replace(/[^A-Za-z0-9_-]/g, '_'); }
  // A paired row (paired.csv) with two or more common seeds; one pair has no interval and no test.
  function testable(p) { return p[4] >= 2; }

  // Metric order: summary.csv's columns first, then any other metric of the statistics.
  function metricOrder(d, names) {
    var inData = {};
    names.forEach(function (n) { inData[n] = true; });
    var out = d.metricNames.filter(function (m) { return inData[m]; });
    names.forEach(function (n) { if (out.indexOf(n) < 0) out.push(n); });
    return out;
  }

  function unitOf(d, metric) { var u = d.units[metric]; return u && u !== 'bool' ? u : ''; }
  function axisLabel(d, metric) { var u = unitOf(d, metric); return metric.replace(/_/g, ' ') + (u ? ' [' + u + ']' : ''); }

  function header(d, app) {
    app.appendChild(el('h1', { text: 'Batch ' + d.dir }));
    var scenarios = unique(d.runs.map(function (r) { return r.scenario; }));
    var planners = unique(d.runs.map(function (r) { return r.planner; }));
    var seeds = unique(d.runs.map(function (r) { return r.seed; })).sort(function (a, b) { return a - b; });
    var byStatus = {};
    d.runs.forEach(function (r) { byStatus[r.status] = (byStatus[r.status] || 0) + 1; });
    var wall = 0;
    d.runs.forEach(function (r) { if (HR.isNum(r.wall_time)) wall += r.wall_time; });
    app.appendChild(el('p', { class: 'subtitle', text: d.runs.length + ' runs: ' + scenarios.length + ' scenario(s) × ' + planners.length +
      ' planner(s) × ' + seeds.length + ' seed(s)' + (seeds.length ? ' (' + seeds[0] + '–' + seeds[seeds.length - 1] + ')' : '') +
      ' · ' + Object.keys(byStatus).sort().map(function (s) { return byStatus[s] + ' ' + s; }).join(', ') +
      ' · ' + HR.fmt(wall, 3) + ' s of run wall-clock time in total' }));
    var links = [el('a', { href: 'summary.csv', text: 'summary.csv' }), ' · ', el('a', { href: 'summary_stats.csv', text: 'summary_stats.csv' })];
    if (d.hasPaired) links.push(' · ', el('a', { href: 'paired.csv', text: 'paired.csv' }));
    if (d.summaryMd) links.push(' · ', el('a', { href: d.summaryMd, text: 'summary.md' }));
    if ((d.expectations || []).length) links.push(' · ', el('a', { href: 'expectations.csv', text: 'expectations.csv' }));
    app.appendChild(el('p', { class: 'crumbs' }, ['Data: '].concat(links)));
    d.notes.forEach(function (n) { app.appendChild(el('div', { class: 'note', text: n })); });
    var toc = el('nav', { class: 'toc' }, ['Scenarios: '].concat(scenarios.map(function (s) {
      return el('a', { href: '#scenario-' + slug(s), text: s });
    })).concat([el('a', { href: '#runs', text: 'all runs' })]));
    app.appendChild(toc);
    return scenarios;
  }

  function statsCell(s) {
    if (!s) return { text: '–' };
    return { text: HR.fmt(s[5]) + (HR.isNum(s[6]) ? ' ± ' + HR.fmt(s[6], 3) : ''),
             sub: (HR.isNum(s[7]) ? '[' + HR.fmt(s[7]) + ', ' + HR.fmt(s[8]) + '] ' : '') + 'n=' + s[4],
             title: 'mean ' + s[5] + ', std ' + s[6] + ', 95% CI [' + s[7] + ', ' + s[8] + '], n ' + s[4] };
  }

  function scenarioSection(d, app, scenario) {
    var section = el('section', { class: 'panel', id: 'scenario-' + slug(scenario) }, [el('h2', { text: 'Scenario ' + scenario })]);
    app.appendChild(section);
    expectationsSection(d, section, scenario);
    var stats = d.stats.filter(function (s) { return s[0] === scenario; });
    var planners = unique(d.runs.filter(function (r) { return r.scenario === scenario; }).map(function (r) { return r.planner; })
      .concat(stats.map(function (s) { return s[1]; })));
    var color = {};
    planners.forEach(function (p, i) { color[p] = HR.seriesColors[i % HR.seriesColors.length]; });
    var behaviors = unique(stats.map(function (s) { return s[2]; }));
    behaviors.sort(function (a, b) { return (a === 'all' ? -1 : HR.behaviorCode(a)) - (b === 'all' ? -1 : HR.behaviorCode(b)); });
    var metricsOf = function (behavior) {
      return metricOrder(d, unique(stats.filter(function (s) { return s[2] === behavior; }).map(function (s) { return s[3]; })));
    };
    var find = function (planner, behavior, metric) {
      for (var i = 0; i < stats.length; i++) {
        var s = stats[i];
        if (s[1] === planner && s[2] === behavior && s[3] === metric) return s;
      }
      return null;
    };

    // Chart of one metric: mean and 95% CI per planner, every run as a dot (overall rows only).
    var chartBox = el('div');
    var overall = metricsOf('all');
    var preferred = ['social_work', 'personal_space_intrusions', 'minimum_distance_to_people', 'time_to_reach_goal'];
    var chosen = preferred.filter(function (m) { return overall.indexOf(m) >= 0; })[0] || overall[0];
    var metricSelect = el('select', { 'aria-label': 'metric' }, overall.map(function (m) {
      return el('option', { value: m, selected: m === chosen, text: m });
    }));
    var drawChart = function () {
      chartBox.textContent = '';
      var m = metricSelect.value;
      if (!m) return;
      var column = d.metricNames.indexOf(m);
      HR.ciChart(chartBox, {
        key: 'ci-' + slug(scenario), title: m + ' by planner (mean, 95% CI, each run)', yLabel: axisLabel(d, m),
        groups: planners.map(function (p) {
          var s = find(p, 'all', m);
          var values = column < 0 ? [] : d.runs.filter(function (r) { return r.scenario === scenario && r.planner === p; })
            .map(function (r) { return r.metrics[column]; });
          return { name: p, color: color[p], mean: s ? s[5] : null, lo: s ? s[7] : null, hi: s ? s[8] : null,
                   n: s ? s[4] : values.length, values: values };
        })
      });
    };
    metricSelect.addEventListener('change', drawChart);
    if (overall.length) {
      section.appendChild(el('div', { class: 'controls' }, [el('label', {}, ['metric ', metricSelect])]));
      var chartRow = el('div', { class: 'plots' }, [chartBox]);
      section.appendChild(chartRow);
      drawChart();
      // Beside the chart: the paired differences for that metric.
      var pairedBox = el('div');
      chartRow.appendChild(pairedBox);
      var drawPairedChart = function () {
        pairedBox.textContent = '';
        var m = metricSelect.value;
        var rows = d.paired.filter(function (p) { return p[0] === scenario && p[3] === m; });
        if (!rows.length) return;
        HR.ciChart(pairedBox, {
          key: 'paired-' + slug(scenario), title: 'paired difference A − B of ' + m, yLabel: 'difference' + (unitOf(d, m) ? ' [' + unitOf(d, m) + ']' : ''),
          groups: rows.map(function (p) {
            return { name: p[1] + ' − ' + p[2] + (p[8] ? '' : testable(p) ? ' (n.s.)' : ' (not testable)'), color: p[8] ? '#0b5cad' : '#9aa1ad', mean: p[5], lo: p[6], hi: p[7], n: p[4], values: [] };
          })
        });
      };
      metricSelect.addEventListener('change', drawPairedChart);
      drawPairedChart();
    }

    // Table: metrics x planners, for the chosen behavior.
    section.appendChild(el('h3', { text: 'Metrics by planner' }));
    var tableBox = el('div');
    var behaviorSelect = el('select', { 'aria-label': 'people' }, behaviors.map(function (b) {
      return el('option', { value: b, text: b === 'all' ? 'all people' : b + ' people only' });
    }));
    var drawTable = function () {
      tableBox.textContent = '';
      var b = behaviorSelect.value;
      var headers = ['metric', { text: 'unit', class: 'text' }].concat(planners);
      var rows = metricsOf(b).map(function (m) {
        return [m, { text: unitOf(d, m), cls: 'text' }].concat(planners.map(function (p) { return statsCell(find(p, b, m)); }));
      });
      tableBox.appendChild(HR.table(headers, rows, { class: 'stats', 'data-behavior': b }));
    };
    behaviorSelect.addEventListener('change', drawTable);
    if (behaviors.length > 1) section.appendChild(el('div', { class: 'controls' }, [el('label', {}, ['people ', behaviorSelect])]));
    section.appendChild(tableBox);
    drawTable();
    section.appendChild(el('p', { class: 'caption', text: 'Each cell: mean ± standard deviation over the seeds, below it the 95% ' +
      'confidence interval of the mean and the number of runs (summary_stats.csv): Student\'s t, cut to the values the metric ' +
      'can take (never below 0 for distances, times, counts, speeds, forces and costs; 0–100 for percentages), and Wilson\'s ' +
      'interval for the success rate (completed). Per-behavior rows are computed over the ' +
      'people of that behavior only, as HuNavSim\'s per-behavior tables.' }));

    // Paired differences: one column per planner pair.
    var paired = d.paired.filter(function (p) { return p[0] === scenario; });
    if (paired.length) {
      section.appendChild(el('h3', { text: 'Paired differences (same seeds)' }));
      var pairs = unique(paired.map(function (p) { return p[1] + '\u0000' + p[2]; }));
      var metrics = metricOrder(d, unique(paired.map(function (p) { return p[3]; })));
      var rows = metrics.map(function (m) {
        return [m].concat(pairs.map(function (pair) {
          var ab = pair.split('\u0000');
          var p = paired.filter(function (x) { return x[1] === ab[0] && x[2] === ab[1] && x[3] === m; })[0];
          if (!p) return { text: '–' };
          if (!testable(p))
            return { text: (p[5] > 0 ? '+' : '') + HR.fmt(p[5]), sub: 'n=' + p[4], cls: 'ns', tag: 'not testable',
                     title: ab[0] + ' − ' + ab[1] + ': mean difference ' + p[5] + ' over one common seed: no interval, no test' };
          return { text: (p[5] > 0 ? '+' : '') + HR.fmt(p[5]), sub: '[' + HR.fmt(p[6]) + ', ' + HR.fmt(p[7]) + '] n=' + p[4],
                   cls: p[8] ? 'sig' : 'ns', tag: p[8] ? null : 'n.s.',
                   title: ab[0] + ' − ' + ab[1] + ': mean difference ' + p[5] + ', 95% CI [' + p[6] + ', ' + p[7] + ']' +
                          (p[8] ? ', significant' : ', not significant') };
        }));
      });
      section.appendChild(HR.table(['metric'].concat(pairs.map(function (p) { return p.replace('\u0000', ' − '); })), rows, { class: 'paired' }));
      section.appendChild(el('p', { class: 'caption', text: 'Mean of the per-seed differences A − B with its 95% confidence interval ' +
        '(paired.csv). Grey, marked n.s.: the interval contains 0, the difference is not significant; not testable: a single ' +
        'common seed, no interval and no test.' }));
    }
    counterfactualSection(d, section, scenario, planners);
    paperSection(d, section, scenario);
  }

  // The robot's effect on people (runs with --counterfactual): the counterfactual_* metrics per
  // planner, the lowest mean in bold, and the planners from least to most disturbing (summary.md's
  // order: mean deviation, then delay, then extra effort).
  function counterfactualSection(d, section, scenario, planners) {
    var stats = d.stats.filter(function (s) { return s[0] === scenario && s[2] === 'all' && s[3].indexOf('counterfactual_') === 0; });
    if (!stats.length) return;
    var metrics = metricOrder(d, unique(stats.map(function (s) { return s[3]; })));
    var mine = planners.filter(function (p) { return stats.some(function (s) { return s[1] === p; }); });
    var find = function (p, m) { return stats.filter(function (s) { return s[1] === p && s[3] === m; })[0]; };
    section.appendChild(el('h3', { text: 'The robot\'s effect on people (counterfactual)' }));
    var rows = metrics.map(function (m) {
      var best = Math.min.apply(null, mine.map(function (p) { var s = find(p, m); return s ? s[5] : Infinity; }));
      return [m, { text: unitOf(d, m), cls: 'text' }].concat(mine.map(function (p) {
        var s = find(p, m), cell = statsCell(s);
        if (s && mine.length > 1 && s[5] === best) cell.cls = 'best';
        return cell;
      }));
    });
    section.appendChild(HR.table(['metric', { text: 'unit', class: 'text' }].concat(mine), rows,
                                 { class: 'stats counterfactual', 'data-scenario': scenario }));
    var mean = function (p, m) { var s = find(p, m); return s ? s[5] : Infinity; };
    var order = mine.slice().sort(function (a, b) {
      var keys = ['counterfactual_mean_deviation', 'counterfactual_delay', 'counterfactual_extra_effort'];
      for (var i = 0; i < keys.length; ++i) if (mean(a, keys[i]) !== mean(b, keys[i])) return mean(a, keys[i]) - mean(b, keys[i]);
      return 0;
    });
    section.appendChild(el('p', { class: 'caption', 'data-counterfactual-order': order.join(','),
      text: 'Each episode run again with the same seed without the robot: how far people were moved off their robot-free ' +
            'paths, delayed, made to walk further and to change velocity (docs/metrics.md, "Counterfactual"). Lower is ' +
            'better; the lowest mean in bold. Least to most disturbing: ' + order.join(' < ') + '.' }));
  }

  // The verdicts of the scenario's expect: conditions (expectations.csv): per planner a badge with the
  // runs that held every condition, then the conditions some run failed, with the seeds and values.
  function expectationsSection(d, section, scenario) {
    var rows = (d.expectations || []).filter(function (e) { return e[0] === scenario; });
    if (!rows.length) return;
    var planners = unique(rows.map(function (e) { return e[1]; }));
    section.appendChild(el('h3', { text: 'Expectations' }));
    section.appendChild(el('div', { class: 'expect-badges' }, planners.map(function (p) {
      var mine = rows.filter(function (e) { return e[1] === p; });
      var judged = unique(mine.map(function (e) { return e[2]; })).length;
      var failed = unique(mine.filter(function (e) { return !e[6]; }).map(function (e) { return e[2]; })).length;
      return el('span', { class: 'badge ' + (failed ? 'bad' : 'ok'), 'data-planner': p, 'data-passed': String(judged - failed),
        'data-failed': String(failed), title: p + ': ' + (judged - failed) + ' of ' + judged + ' judged runs held every condition',
        text: p + ' ' + (failed ? '✗' : '✓') + ' ' + (judged - failed) + '/' + judged + ' passed' });
    })));
    var failing = unique(rows.filter(function (e) { return !e[6]; }).map(function (e) { return e[1] + '\u0000' + e[3] + ' ' + e[4]; }));
    if (!failing.length) {
      section.appendChild(el('p', { class: 'caption', text: 'Every condition held in every judged run.' }));
      return;
    }
    var body = failing.map(function (key) {
      var pc = key.split('\u0000');
      var mine = rows.filter(function (e) { return e[1] === pc[0] && e[3] + ' ' + e[4] === pc[1]; });
      var bad = mine.filter(function (e) { return !e[6]; });
      return [{ text: pc[0], cls: 'text' }, { text: pc[1], cls: 'text mono' }, bad.length + ' of ' + mine.length,
              { text: bad.map(function (e) { return e[2] + ' (' + e[5] + ')'; }).join(', '), cls: 'text' }];
    });
    section.appendChild(HR.table([{ text: 'planner', class: 'text' }, { text: 'condition', class: 'text' }, 'runs failed',
                                  { text: 'seeds (value)', class: 'text' }], body, { class: 'expectations', 'data-scenario': scenario }));
    section.appendChild(el('p', { class: 'caption', text: 'The scenario\'s expect: conditions judged on each run when its episode ' +
      'ended (expectations.csv; docs/metrics.md, "Expectations"). A run passes when every condition holds; runs that did not ' +
      'finish are not judged (junit.xml lists them as errors).' }));
  }

  // The HuNavSim paper's means beside ours (paper_comparison.csv) and, per pair of planners, whether
  // the paper's ordering holds in ours (paper_orderings.csv); one table per behavior of the paper.
  var RELATION_TEXT = { '<': '<', '>': '>', '=': '=' };
  function paperSection(d, section, scenario) {
    var rows = (d.paper || []).filter(function (r) { return r[0] === scenario; });
    if (!rows.length) return;
    var orderings = (d.paperOrderings || []).filter(function (o) { return o[0] === scenario; });
    var count = { agree: 0, disagree: 0, paper_tie: 0, missing: 0 };
    orderings.forEach(function (o) { count[o[7]] = (count[o[7]] || 0) + 1; });
    section.appendChild(el('h3', { text: 'Paper vs ours' }));
    section.appendChild(el('p', { class: 'caption', 'data-paper-agree': String(count.agree), 'data-paper-disagree': String(count.disagree),
      text: 'Orderings between planners: ' + count.agree + ' agree, ' + count.disagree + ' disagree, ' + count.paper_tie +
            ' equal in the paper' + (count.missing ? ', ' + count.missing + ' without our value' : '') + '.' }));
    unique(rows.map(function (r) { return r[1]; })).forEach(function (behavior) {
      var mine = rows.filter(function (r) { return r[1] === behavior; });
      var planners = unique(mine.map(function (r) { return r[4]; }));
      var mineOrd = orderings.filter(function (o) { return o[1] === behavior; });
      var pairs = unique(mineOrd.map(function (o) { return o[3] + '\u0000' + o[4]; }));
      var metrics = unique(mine.map(function (r) { return r[2]; }));
      var headers = ['metric', { text: 'paper\'s name', class: 'text' }];
      planners.forEach(function (p) { headers.push(p + ' paper', p + ' ours'); });
      pairs.forEach(function (pair) { headers.push(pair.replace('\u0000', ' vs ')); });
      var body = metrics.map(function (m) {
        var first = mine.filter(function (r) { return r[2] === m; })[0];
        var line = [m, { text: first[3], cls: 'text' }];
        planners.forEach(function (p) {
          var r = mine.filter(function (x) { return x[2] === m && x[4] === p; })[0];
          if (!r) { line.push({ text: '–' }, { text: '–' }); return; }
          line.push(HR.fmt(r[5]));
          line.push({ text: r[6] ? HR.fmt(r[7]) : '–', sub: HR.isNum(r[8]) ? '[' + HR.fmt(r[8]) + ', ' + HR.fmt(r[9]) + '] n=' + r[6] : 'n=' + r[6],
                      tag: r[10] === 'true' ? '≈' : null, cls: r[10] === 'true' ? 'paper-in' : null,
                      title: 'ours: mean ' + r[7] + ', 95% CI [' + r[8] + ', ' + r[9] + '], n ' + r[6] + '; paper ' + r[5] +
                             (r[10] === 'true' ? ' (inside our interval)' : '') });
        });
        pairs.forEach(function (pair) {
          var ab = pair.split('\u0000');
          var o = mineOrd.filter(function (x) { return x[2] === m && x[3] === ab[0] && x[4] === ab[1]; })[0];
          if (!o) { line.push({ text: '–' }); return; }
          var ns = o[8] === 'false' ? ' n.s.' : '';
          var text = o[7] === 'agree' ? '✓ ' + RELATION_TEXT[o[5]] : o[7] === 'disagree' ? '✗ paper ' + o[5] + ', ours ' + o[6]
            : o[7] === 'paper_tie' ? '= (ours ' + o[6] + ')' : '–';
          line.push({ text: text + (o[7] === 'missing' ? '' : ns), cls: 'verdict-' + o[7],
                      title: ab[0] + ' vs ' + ab[1] + ': paper ' + o[5] + (o[6] ? ', ours ' + o[6] : ', no value of ours') +
                             (o[8] === 'true' ? ' (our paired difference is significant)' : o[8] === 'false' ? ' (our paired difference is not significant)' : '') });
        });
        return line;
      });
      section.appendChild(el('h4', { text: behavior === 'all' ? 'All people' : behavior + ' people only' }));
      section.appendChild(HR.table(headers, body, { class: 'paper', 'data-behavior': behavior }));
    });
    section.appendChild(el('p', { class: 'caption', text: 'The paper\'s means (HuNavSim paper, tables tab:passing, tab:crossing, ' +
      'tab:combined; experiments/data/hunav_paper_means.yaml) beside ours: mean, 95% confidence interval and runs; ≈ when the ' +
      'paper\'s mean lies inside our interval. ✓ the paper\'s ordering of the two planners holds in ours, ✗ it does not, = equal ' +
      'in the paper (not counted); n.s.: our paired difference is not significant. Forces, social work, collisions, acceleration ' +
      'and jerk are defined or sampled differently (summary.md says how): compare their orderings, not their values.' }));
  }

  // The people models (docs/people_models.md): how each scores on real pedestrians (hunav_realism's
  // realism.csv: per data set and split the errors, the speed and nearest-neighbour distributions as
  // 10-50-90 % bars, overlaps) and whether the paper's planner orderings hold under every model
  // (model_robustness.csv).
  function whisker(q10, q50, q90, mean, lo, hi) {
    var w = 140, h = 14, x = function (v) { return 4 + (Math.min(Math.max(v, lo), hi) - lo) / (hi - lo) * (w - 8); };
    var svg = document.createElementNS('http://www.w3.org/2000/svg', 'svg');
    svg.setAttribute('width', w); svg.setAttribute('height', h); svg.setAttribute('class', 'whisker');
    function add(tag, attrs) {
      var e = document.createElementNS('http://www.w3.org/2000/svg', tag);
      Object.keys(attrs).forEach(function (k) { e.setAttribute(k, attrs[k]); });
      svg.appendChild(e);
    }
    if (!HR.isNum(q10) || !HR.isNum(q90)) return svg;
    add('line', { x1: x(q10), x2: x(q90), y1: h / 2, y2: h / 2, stroke: '#555', 'stroke-width': 2 });
    add('line', { x1: x(q50), x2: x(q50), y1: 2, y2: h - 2, stroke: '#1f77b4', 'stroke-width': 2 });
    if (HR.isNum(mean)) add('circle', { cx: x(mean), cy: h / 2, r: 2.5, fill: '#d62728' });
    return svg;
  }
  function peopleModelsSection(d, app) {
    var realism = d.realism || [], robust = d.robustness || [];
    if (!realism.length && !robust.length) return;
    var section = el('section', { class: 'panel', id: 'people-models' }, [el('h2', { text: 'People models' })]);
    app.appendChild(section);
    if (robust.length) {
      var models = d.robustnessModels;
      var count = {};
      robust.forEach(function (r) { count[r[r.length - 1]] = (count[r[r.length - 1]] || 0) + 1; });
      section.appendChild(el('h3', { text: 'Does the human model change the verdict?' }));
      section.appendChild(el('p', { class: 'caption', 'data-holds': String(count.holds || 0), 'data-flips': String(count.flips || 0),
        text: 'The paper\'s planner orderings in one batch per people model: ' + (count.holds || 0) + ' hold under every model, ' +
              (count.fails || 0) + ' fail under every model, ' + (count.flips || 0) + ' flip between models' +
              (count.paper_tie ? ', ' + count.paper_tie + ' equal in the paper' : '') + (count.missing ? ', ' + count.missing + ' missing' : '') + '.' }));
      var headers = [{ text: 'scenario', class: 'text' }, { text: 'behavior', class: 'text' }, 'metric', { text: 'a vs b', class: 'text' }, 'paper']
        .concat(models).concat([{ text: 'verdict', class: 'text' }]);
      var body = robust.map(function (r) {
        var verdict = r[r.length - 1];
        return [{ text: r[0], cls: 'text' }, { text: r[1], cls: 'text' }, r[2], { text: r[3] + ' vs ' + r[4], cls: 'text' }, r[5]]
          .concat(r.slice(6, 6 + models.length)).concat([{ text: verdict, cls: 'text verdict-' + (verdict === 'holds' ? 'agree' : verdict === 'flips' ? 'disagree' : verdict) }]);
      });
      section.appendChild(HR.table(headers, body, { class: 'robustness' }));
    }
    if (realism.length) {
      section.appendChild(el('h3', { text: 'How they walk: real pedestrians (ETH/UCY)' }));
      var keys = unique(realism.map(function (r) { return r[0] + '\u0000' + r[2]; }));
      keys.forEach(function (key) {
        var k = key.split('\u0000');
        var rows = realism.filter(function (r) { return r[0] === k[0] && r[2] === k[1]; });
        var speeds = rows.map(function (r) { return r[9]; }).concat([0]), nns = rows.map(function (r) { return r[14]; }).concat([0]);
        var sMax = Math.max.apply(null, speeds.filter(HR.isNum)) * 1.1 || 1, nMax = Math.max.apply(null, nns.filter(HR.isNum)) * 1.1 || 1;
        var headers = [{ text: 'method', class: 'text' }, 'ADE [m]', 'FDE [m]', { text: 'speed 10-50-90 % [m/s]', class: 'text' }, 'speed W1',
                       { text: 'nn distance 10-50-90 % [m]', class: 'text' }, 'nn W1', 'overlaps'];
        var body = rows.map(function (r) {
          return [{ text: r[1], cls: 'text mono' }, HR.fmt(r[4], 3), HR.fmt(r[5], 3),
                  { node: whisker(r[7], r[8], r[9], r[6], 0, sMax), cls: 'text', title: 'mean ' + HR.fmt(r[6], 3) + ', 10/50/90 %: ' + [r[7], r[8], r[9]].map(function (v) { return HR.fmt(v, 3); }).join(' / ') },
                  HR.fmt(r[10], 3),
                  { node: whisker(r[12], r[13], r[14], r[11], 0, nMax), cls: 'text', title: 'mean ' + HR.fmt(r[11], 3) + ', 10/50/90 %: ' + [r[12], r[13], r[14]].map(function (v) { return HR.fmt(v, 3); }).join(' / ') },
                  HR.fmt(r[15], 3), HR.isNum(r[16]) ? (100 * r[16]).toFixed(2) + ' %' : '–'];
        });
        section.appendChild(el('h4', { text: k[0] + ', split ' + k[1] + ' (' + rows[0][3] + ' samples)' }));
        section.appendChild(HR.table(headers, body, { class: 'realism', 'data-data': k[0], 'data-split': k[1] }));
      });
      section.appendChild(el('p', { class: 'caption', text: 'From ' + d.realismFile + ' (hunav_realism, realism/README.md): every person ' +
        'seen in 20 frames, 8 observed and 12 predicted among the others as recorded. M: goal extrapolated; M_goal: the recorded ' +
        'final position is the goal (as in a scenario); _alone: without the others; split test: parameters fitted on the other ' +
        'scenes. Bars: 10-90 % of the predicted frames, blue the median, red the mean; W1: distance to the data\'s distribution; ' +
        'overlaps: share of frames within 0.3 m of a recorded person.' }));
    }
  }

  function runsTable(d, app) {
    var section = el('section', { class: 'panel', id: 'runs' }, [el('h2', { text: 'All runs' })]);
    app.appendChild(section);
    var keyMetrics = ['completed', 'time_to_reach_goal', 'minimum_distance_to_people', 'personal_space_intrusions', 'social_work']
      .filter(function (m) { return d.metricNames.indexOf(m) >= 0; });
    var headers = [{ text: 'scenario', class: 'text' }, { text: 'planner', class: 'text' }, 'seed', { text: 'status', class: 'text' },
                   'sim time [s]', 'wall time [s]'].concat(keyMetrics.map(function (m) { return m; })).concat([{ text: 'report', class: 'text' }]);
    var rows = d.runs.map(function (r) {
      var status = HR.statusBadge(r.status, r.statusClass);
      var link = r.link ? el('a', { href: r.link, text: 'run page' }) : el('span', { class: 'sub', title: r.note, text: 'none' });
      return [{ text: r.scenario, cls: 'text' }, { text: r.planner, cls: 'text' }, r.seed, { node: status, cls: 'text' },
              HR.fmt(r.sim_time), HR.fmt(r.wall_time, 3)].concat(keyMetrics.map(function (m) {
        var v = r.metrics[d.metricNames.indexOf(m)];
        return m === 'completed' ? (v === 1 ? 'yes' : v === 0 ? 'no' : '–') : HR.fmt(v);
      })).concat([{ node: link, cls: 'text', title: r.run_dir }]);
    });
    section.appendChild(HR.table(headers, rows, { id: 'runs-table' }));
  }

  HR.start(function (d, app) {
    var scenarios = header(d, app);
    scenarios.forEach(function (s) { scenarioSection(d, app, s); });
    peopleModelsSection(d, app);
    runsTable(d, app);
    app.appendChild(el('footer', { text: 'Written by hunav_report (HuNav-LCM) from ' + d.path + '. Self-contained: open it from disk, no network needed.' }));
  });
})();
