// SPDX-License-Identifier: MIT
// Draws a navbench report's plots with uPlot from the specifications in #nav-plots, which
// navbench writes (reports/src/plot_spec.hpp has their form; run_plots*.cpp and
// campaign_page.cpp decide what is plotted). Nothing is computed from the data here but
// the axis ranges of a track, whose east and north get the same metres per pixel.
(function () {
  'use strict';

  var specs = JSON.parse(document.getElementById('nav-plots').textContent);
  var byId = {};
  specs.forEach(function (s) { byId[s.id] = s; });
  var charts = [];
  // For the browser tests: every chart with its spec.
  window.navbenchCharts = charts;

  // An A4 page less its margins, in CSS pixels (report.css sets 15 mm margins).
  var PRINT_WIDTH = 680;
  var FAULT_FILL = 'rgba(224,123,0,0.15)';

  // A line through the points of an xy series in their order (a track turns back on itself;
  // uPlot's own line builder expects x to grow, as in a time series).
  function polyline(u, seriesIdx) {
    var xs = u.data[seriesIdx][0], ys = u.data[seriesIdx][1];
    var stroke = new Path2D(), open = false;
    for (var i = 0; i < xs.length; i++) {
      if (xs[i] === null || ys[i] === null) { open = false; continue; }
      var x = u.valToPos(xs[i], 'x', true), y = u.valToPos(ys[i], 'y', true);
      if (open) stroke.lineTo(x, y);
      else { stroke.moveTo(x, y); open = true; }
    }
    return { stroke: stroke, fill: null, clip: null, band: null, gaps: null, flags: 0 };
  }

  function pathsOf(name, xy) {
    if (xy && name === 'linear') return polyline;
    if (name === 'stepped') return uPlot.paths.stepped({ align: 1 });
    if (name === 'bars') return uPlot.paths.bars({ size: [0.85, Infinity], align: 1 });
    if (name === 'points') return uPlot.paths.points();
    return uPlot.paths.linear();
  }

  function seriesOptions(s, xy) {
    var o = {
      label: s.label,
      stroke: s.color,
      width: s.width === undefined ? 1.5 : s.width,
      paths: pathsOf(s.paths, xy),
      scale: s.axis === 'y2' ? 'y2' : 'y',
      spanGaps: false,
      points: { show: false }
    };
    if (s.dash) o.dash = [6, 4];
    if (s.fill) o.fill = s.fill;
    if (s.fill_to !== undefined) o.fillTo = function () { return s.fill_to; };
    if (s.paths === 'points') {
      // Markers only: the path is the markers, filled with the series' colour.
      o.fill = s.color;
      o.width = 0;
      o.points = { show: false, size: s.points || 4, width: 0 };
    } else if (s.points) {
      o.points = { show: true, size: s.points, fill: s.color, stroke: s.color, width: 0 };
    }
    if (s.paths === 'bars') o.fill = s.fill || s.color;
    if (s.label === '') o.label = ' ';
    return o;
  }

  // Extent of the finite values of xy data, per facet (0: x, 1: y).
  function extent(spec, facet) {
    var lo = Infinity, hi = -Infinity;
    spec.data.forEach(function (xy) {
      xy[facet].forEach(function (v) {
        if (v !== null && isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
      });
    });
    if (!(hi >= lo)) return [0, 1];
    if (hi === lo) return [lo - 1, hi + 1];
    return [lo, hi];
  }

  // The same scale on x and y: widen the narrower range about its middle.
  function equalRanges(spec, width, height) {
    var x = extent(spec, 0), y = extent(spec, 1);
    var pad = 0.05;
    var w = (x[1] - x[0]) * (1 + 2 * pad), h = (y[1] - y[0]) * (1 + 2 * pad);
    var plotW = Math.max(width - 70, 50), plotH = Math.max(height - 60, 50);
    var perPx = Math.max(w / plotW, h / plotH);
    var cx = (x[0] + x[1]) / 2, cy = (y[0] + y[1]) / 2;
    return {
      x: [cx - perPx * plotW / 2, cx + perPx * plotW / 2],
      y: [cy - perPx * plotH / 2, cy + perPx * plotH / 2]
    };
  }

  function drawWindows(u, spec) {
    if (!spec.windows || !spec.windows.length) return;
    var ctx = u.ctx, b = u.bbox;
    ctx.save();
    ctx.fillStyle = FAULT_FILL;
    spec.windows.forEach(function (w) {
      var a = u.valToPos(w.x0, 'x', true), z = u.valToPos(w.x1, 'x', true);
      var l = Math.max(b.left, Math.min(a, z)), r = Math.min(b.left + b.width, Math.max(a, z));
      if (r >= l) ctx.fillRect(l, b.top, Math.max(r - l, 2), b.height);
    });
    ctx.restore();
  }

  function drawLines(u, spec) {
    var ctx = u.ctx, b = u.bbox, ratio = window.devicePixelRatio || 1;
    ctx.save();
    ctx.lineWidth = 1.5 * ratio;
    ctx.setLineDash([5 * ratio, 4 * ratio]);
    ctx.font = (11 * ratio) + 'px sans-serif';
    // Labels start at the line (uPlot leaves the context right-aligned after its axes).
    ctx.textAlign = 'left';
    ctx.textBaseline = 'alphabetic';
    (spec.vlines || []).forEach(function (l) {
      var x = u.valToPos(l.x, 'x', true);
      if (!(x >= b.left && x <= b.left + b.width)) return;
      ctx.strokeStyle = ctx.fillStyle = l.color || '#000';
      ctx.beginPath(); ctx.moveTo(x, b.top); ctx.lineTo(x, b.top + b.height); ctx.stroke();
      ctx.fillText(l.label || '', x + 4 * ratio, b.top + 12 * ratio);
    });
    (spec.hlines || []).forEach(function (l) {
      var y = u.valToPos(l.y, 'y', true);
      if (!(y >= b.top && y <= b.top + b.height)) return;
      ctx.strokeStyle = ctx.fillStyle = l.color || '#000';
      ctx.beginPath(); ctx.moveTo(b.left, y); ctx.lineTo(b.left + b.width, y); ctx.stroke();
      ctx.fillText(l.label || '', b.left + 4 * ratio, y - 4 * ratio);
    });
    ctx.restore();
  }

  // Tick labels of a log axis: 0.001 to 10 000 as plain numbers, smaller or larger with an
  // exponent (uPlot's own labels round 0.0001 to "0").
  function logTicks(u, splits) {
    return splits.map(function (v) {
      if (v == null) return '';
      var a = Math.abs(v);
      if (a === 0 || (a >= 1e-3 && a < 1e4)) return String(+v.toPrecision(3));
      return v.toExponential(0).replace('+', '');
    });
  }

  function options(spec, width) {
    var xy = spec.mode === 'xy';
    var height = spec.height || 260;
    var scales = { x: { time: false }, y: {} };
    if (spec.x.log) { scales.x.distr = 3; scales.x.log = 10; }
    if (spec.y.log) { scales.y.distr = 3; scales.y.log = 10; }
    if (spec.y.invert) scales.y.dir = -1;
    if (spec.x.range) scales.x.range = spec.x.range;
    if (spec.y.range) scales.y.range = spec.y.range;
    if (spec.equal) {
      var r = equalRanges(spec, width, height);
      scales.x.range = r.x;
      scales.y.range = r.y;
    }
    var axes = [{ label: spec.x.label, scale: 'x' }, { label: spec.y.label, scale: 'y' }];
    if (spec.x.log) axes[0].values = logTicks;
    if (spec.y.log) axes[1].values = logTicks;
    if (spec.y2) {
      scales.y2 = { range: function (u, lo, hi) { return [0, Math.max(hi || 0, 1) * 1.1]; } };
      axes.push({ label: spec.y2.label, scale: 'y2', side: 1, grid: { show: false } });
    }
    var series = [xy ? {} : { label: spec.x.label }];
    spec.series.forEach(function (s) { series.push(seriesOptions(s, xy)); });
    var o = {
      width: width,
      height: height,
      mode: xy ? 2 : 1,
      scales: scales,
      axes: axes,
      series: series,
      legend: { live: !xy },
      cursor: { drag: { x: true, y: xy } },
      hooks: {
        drawClear: [function (u) { drawWindows(u, spec); }],
        draw: [function (u) { drawLines(u, spec); }]
      }
    };
    return o;
  }

  function pointCount(spec) {
    var n = 0;
    if (spec.mode === 'xy') spec.data.forEach(function (xy) { n += xy[0].length; });
    else n = spec.data.length ? spec.data[0].length : 0;
    return n;
  }

  function draw(el, width) {
    var spec = byId[el.getAttribute('data-plot')];
    if (!spec) return;
    var old = charts.filter(function (c) { return c.el === el; })[0];
    if (old) {
      old.plot.destroy();
      charts.splice(charts.indexOf(old), 1);
    }
    el.textContent = '';
    var data = spec.mode === 'xy' ? [null].concat(spec.data) : spec.data;
    var plot = new uPlot(options(spec, width), data, el);
    charts.push({ el: el, spec: spec, plot: plot, points: pointCount(spec) });
    el.setAttribute('data-drawn', String(pointCount(spec)));
  }

  function widthOf(el) {
    return Math.max(Math.floor(el.getBoundingClientRect().width), 240);
  }

  function drawAll(width) {
    var els = document.querySelectorAll('[data-plot]');
    for (var i = 0; i < els.length; i++) draw(els[i], width || widthOf(els[i]));
  }

  drawAll();

  // Screen: follow the window's width. Print: the print layout is in place when the media
  // query changes (a ResizeObserver does not run for print), so redraw at the paper's width.
  var pending = null;
  window.addEventListener('resize', function () {
    clearTimeout(pending);
    pending = setTimeout(function () { drawAll(); }, 150);
  });
  var print = window.matchMedia('print');
  var onPrint = function (e) {
    if (e.matches) {
      document.querySelectorAll('[data-plot]').forEach(function (el) {
        draw(el, Math.min(widthOf(el), PRINT_WIDTH));
      });
    } else {
      drawAll();
    }
  };
  if (print.addEventListener) print.addEventListener('change', onPrint);
  else print.addListener(onPrint);
})();
