// camopt report page. Reads the run's description from the JSON script element #camopt-data (the data format
// of docs/report.md: ReportData as JSON, numeric arrays as base64 little-endian float32) and draws
// the header, one section per ReportData section with its plots and tables, and the mechanism
// animation. Line plots are uPlot (the global `uPlot`, inlined before this script); profiles,
// heat maps and the mechanism are drawn here on a canvas or in SVG. Nothing is fetched.
(function () {
  'use strict';

  const LINE_HEIGHT = 260;       // line plot height [px]
  const BASE_WIDTH = 1.25;       // series stroke [px]
  const HIGHLIGHT_WIDTH = 2.75;  // the highlighted family member's stroke [px]
  const DIM_ALPHA = 0.18;        // the other family members while one is highlighted
  const DEG_PER_S = 90;          // animation speed: one cam revolution in 4 s
  const PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#17becf'];
  // viridis at 10 stops (matplotlib's colour map), interpolated linearly
  const VIRIDIS = [[68, 1, 84], [72, 40, 120], [62, 73, 137], [49, 104, 142], [38, 130, 142],
    [31, 158, 137], [53, 183, 121], [109, 205, 89], [180, 222, 44], [253, 231, 37]];

  // the page's hooks (docs/report.md); views: the canvas plots' data -> pixel maps, for tests;
  // timing: milliseconds from this script's start to the drawn page and to its first paint
  const api = { ready: null, data: null, plots: {}, views: {}, animation: null, timing: {} };
  const started = performance.now();
  window.camoptReport = api;
  const views = [];   // every drawn plot: { el, members, restyle(k), resize(width) }
  const pending = [];  // plot boxes waiting for their drawing: { p, box }
  const family = { hover: -1, pinned: -1, select: null };
  const SVG_NS = 'http://www.w3.org/2000/svg';


  // reads the data, builds the page, then draws into the laid-out boxes
  function init() {
    const data = decodeData(JSON.parse(document.getElementById('camopt-data').textContent));
    api.data = data;
    const root = document.getElementById('camopt-report');
    root.textContent = '';
    const sections = sectionList(data);
    root.append(renderHeader(data), renderNav(data, sections));
    const main = el('main');
    root.append(main);
    for (const s of sections) main.append(renderSection(data, s));
    // plots are drawn once their boxes are laid out, so each knows its width
    for (const { p, box } of pending) drawPlot(data, p, box);
    window.addEventListener('resize', onResize);
    window.addEventListener('beforeprint', () => resizeAll(() => 680));
    window.addEventListener('afterprint', () => resizeAll());
  }

  // ---- data ------------------------------------------------------------------------------

  // a NUM field: base64 of little-endian float32 values ("" when empty)
  function decodeNum(text) {
    const bin = atob(text || '');
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    const view = new DataView(bytes.buffer);
    const out = new Float64Array(bytes.length >> 2);
    for (let i = 0; i < out.length; i++) out[i] = view.getFloat32(4 * i, true);
    return out;
  }

  // replaces every NUM field of the data by its Float64Array
  function decodeData(d) {
    for (const p of d.plots) {
      for (const k of ['x_values', 'y_values', 'z']) p[k] = decodeNum(p[k]);
      for (const s of p.series) for (const k of ['x', 'y', 'color']) s[k] = decodeNum(s[k]);
    }
    if (d.scene) {
      for (const sh of d.scene.shapes) sh.xy = decodeNum(sh.xy);
      for (const pos of d.scene.positions) {
        for (const k of ['cam_deg', 'lift_mm']) pos[k] = decodeNum(pos[k]);
        pos.pose = pos.pose.map(decodeNum);
        pos.contact = pos.contact.map(decodeNum);
      }
    }
    return d;
  }

  // "label [unit]", as the tests and the static figures write it
  function axisTitle(axis) {
    return `${axis.label} [${axis.unit}]`;
  }

  // points a series draws: its own x, else the plot's shared x_values
  function seriesX(p, s) {
    return s.x.length ? s.x : p.x_values;
  }

  // ---- small DOM helpers -----------------------------------------------------------------

  // an HTML element; attrs: attributes, plus `text` for its text content
  function el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === 'text') e.textContent = v;
      else e.setAttribute(k, v);
    }
    e.append(...children);
    return e;
  }

  function svgEl(tag, attrs) {
    const e = document.createElementNS(SVG_NS, tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    return e;
  }

  // a canvas of CSS size w x h, drawn at the device's pixel ratio; returns its 2-D context
  function sizeCanvas(canvas, w, h) {
    const r = window.devicePixelRatio || 1;
    canvas.width = Math.round(w * r);
    canvas.height = Math.round(h * r);
    canvas.style.width = w + 'px';
    canvas.style.height = h + 'px';
    const ctx = canvas.getContext('2d');
    ctx.setTransform(r, 0, 0, r, 0, 0);
    return ctx;
  }

  // ---- colours ---------------------------------------------------------------------------

  function colormap(t) {
    const u = Math.min(Math.max(Number.isFinite(t) ? t : 0, 0), 1) * (VIRIDIS.length - 1);
    const i = Math.min(Math.floor(u), VIRIDIS.length - 2), f = u - i;
    const c = VIRIDIS[i].map((a, j) => Math.round(a + f * (VIRIDIS[i + 1][j] - a)));
    return `rgb(${c[0]},${c[1]},${c[2]})`;
  }

  // family member k of n along viridis (its pale yellow end left out), others from the palette
  function seriesColor(s, index, familySize) {
    if (s.family_member >= 0) return colormap(familySize > 1 ? 0.85 * s.family_member / (familySize - 1) : 0);
    return PALETTE[index % PALETTE.length];
  }

  // the colour scale of a set of values: min..max of the finite ones, clipped to the 2nd..98th
  // percentile when more than 50 (a flat flank's radius of curvature would wash out the rest)
  function colorRange(values) {
    const v = Array.from(values).filter(Number.isFinite).sort((a, b) => a - b);
    if (!v.length) return [0, 1];
    const clip = v.length > 50 ? Math.floor(0.02 * v.length) : 0;
    const lo = v[clip], hi = v[v.length - 1 - clip];
    return hi > lo ? [lo, hi] : [lo - 1, hi + 1];
  }

  // a horizontal colour bar: min, the gradient, max, and the colour axis title
  function colorBar(axis, range) {
    const canvas = el('canvas', { class: 'camopt-colorbar-scale' });
    const ctx = sizeCanvas(canvas, 160, 12);
    for (let i = 0; i < 160; i++) {
      ctx.fillStyle = colormap(i / 159);
      ctx.fillRect(i, 0, 1, 12);
    }
    return el('div', { class: 'camopt-colorbar' }, el('span', { text: fmt(range[0]) }), canvas,
      el('span', { text: fmt(range[1]) }), el('span', { class: 'camopt-colorbar-title', text: axisTitle(axis) }));
  }

  // ---- numbers and axes on a canvas ------------------------------------------------------

  function fmt(v) {
    if (!Number.isFinite(v)) return String(v);
    return Math.abs(v) >= 1e5 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(3) : String(+v.toPrecision(5));
  }

  // about n round tick values in [lo, hi]
  function ticks(lo, hi, n) {
    const raw = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map(m => m * mag).find(s => s >= raw) || raw;
    const out = [];
    for (let t = Math.ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step) out.push(+t.toPrecision(12));
    return out;
  }

  // frame, ticks and axis titles of a canvas plot; area = {left, top, width, height} [px],
  // xr/yr = data ranges mapped onto it
  function drawAxes(ctx, area, xr, yr, xTitle, yTitle) {
    const { left, top, width, height } = area;
    ctx.save();
    ctx.strokeStyle = '#888';
    ctx.fillStyle = '#222';
    ctx.font = '11px sans-serif';
    ctx.strokeRect(left, top, width, height);
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    for (const t of ticks(xr[0], xr[1], Math.max(2, width / 90))) {
      const x = left + (t - xr[0]) / (xr[1] - xr[0]) * width;
      ctx.fillRect(x, top + height, 1, 4);
      ctx.fillText(fmt(t), x, top + height + 6);
    }
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    for (const t of ticks(yr[0], yr[1], Math.max(2, height / 60))) {
      const y = top + height - (t - yr[0]) / (yr[1] - yr[0]) * height;
      ctx.fillRect(left - 4, y, 4, 1);
      ctx.fillText(fmt(t), left - 6, y);
    }
    ctx.font = 'bold 12px sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'bottom';
    ctx.fillText(xTitle, left + width / 2, top + height + 40);
    ctx.translate(14, top + height / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textBaseline = 'middle';
    ctx.fillText(yTitle, 0, 0);
    ctx.restore();
  }

  // ---- header, navigation, sections ------------------------------------------------------

  function renderHeader(d) {
    const h = el('header', { id: 'camopt-header' }, el('h1', { text: d.title }));
    if (d.passed === true || d.passed === false) {
      h.append(el('p', { id: 'camopt-verdict', class: d.passed ? 'passed' : 'failed',
        text: d.passed ? 'Verification passed' : 'Verification FAILED' }));
    }
    const facts = [...d.facts, { key: 'command', value: d.command }, { key: 'result folder', value: d.source_dir },
      { key: 'generator', value: d.generator }];
    const dl = el('dl', { class: 'camopt-facts' });
    for (const f of facts) if (f.value) dl.append(el('dt', { text: f.key }), el('dd', { text: f.value }));
    h.append(dl);
    if (d.notes.length) h.append(el('ul', { class: 'camopt-notes' }, ...d.notes.map(n => el('li', { text: n }))));
    return h;
  }

  // the sections to draw: the data's, plus "other" for plots or tables naming no known section
  // and "mechanism" for the animation when the data has a scene but no such section
  function sectionList(d) {
    const list = d.sections.slice();
    const known = new Set(list.map(s => s.id));
    const orphans = [...d.plots, ...d.tables].filter(x => !known.has(x.section));
    if (orphans.length) {
      orphans.forEach(x => { x.section = 'other'; });
      if (!known.has('other')) list.push({ id: 'other', title: 'Other' });
    }
    if (d.scene && !known.has('mechanism')) list.push({ id: 'mechanism', title: 'Mechanism' });
    return list;
  }

  // section links, and the family selector when the run has a family (control positions)
  function renderNav(d, sections) {
    const nav = el('nav', { id: 'camopt-nav' },
      ...sections.map(s => el('a', { href: '#section-' + s.id, text: s.title })));
    if (d.family.length) {
      const select = el('select', { id: 'camopt-family', 'aria-label': 'highlight a family member' },
        el('option', { value: '-1', text: 'all members' }),
        ...d.family.map((name, k) => el('option', { value: String(k), text: name })));
      select.addEventListener('change', () => setPinned(+select.value));
      family.select = select;
      nav.append(el('label', { class: 'camopt-family', text: 'highlight ' }, select));
    }
    return nav;
  }

  // a section's heading, animation, plots (in a responsive grid) and tables
  function renderSection(d, s) {
    const sec = el('section', { id: 'section-' + s.id }, el('h2', { text: s.title }));
    if (s.id === 'mechanism' && d.scene) sec.append(renderAnimation(d.scene));
    const grid = el('div', { class: 'camopt-grid' });
    sec.append(grid);
    for (const p of d.plots.filter(x => x.section === s.id)) grid.append(renderPlot(d, p));
    for (const t of d.tables.filter(x => x.section === s.id)) sec.append(renderTable(t));
    return sec;
  }

  // ---- plots -----------------------------------------------------------------------------

  // the plot's box with the hooks of the data format; its drawing is added once laid out
  function renderPlot(d, p) {
    const points = p.kind === 'heatmap' ? p.z.length : p.series.reduce((n, s) => n + s.y.length, 0);
    const box = el('div', { class: 'camopt-plot', 'data-plot-id': p.id, 'data-kind': p.kind,
      'data-series': String(p.series.length), 'data-points': String(points),
      'data-x-label': axisTitle(p.x), 'data-y-label': axisTitle(p.y), 'data-highlight': '-1' },
    el('h3', { text: p.title }));
    if (p.main) box.classList.add('main');
    api.plots[p.id] = null;
    pending.push({ p, box });
    return box;
  }

  // draws a plot into its laid-out box
  function drawPlot(d, p, box) {
    const make = { line: linePlot, profile: profilePlot, heatmap: heatmapPlot }[p.kind];
    if (!make) throw new Error(`plot ${p.id}: unknown kind '${p.kind}'`);
    const view = make(d, p, box, plotWidth(box));
    view.el = box;
    views.push(view);
    if (p.kind !== 'line') api.views[p.id] = view;
  }

  function plotWidth(box) {
    return Math.max(280, Math.floor(box.clientWidth));
  }

  // uPlot's data: [x, y1, y2, ...] on one x; series with their own x are joined (gaps spanned)
  function lineData(p) {
    const ys = p.series.map(s => Array.from(s.y, v => (Number.isNaN(v) ? null : v)));
    if (p.series.every(s => !s.x.length)) return [p.x_values, ...ys];
    return uPlot.join(p.series.map((s, i) => [seriesX(p, s), ys[i]]));
  }

  // a uPlot line plot: legend, drag zoom / double-click reset, cursor and zoom shared with the
  // plots of its link_group (uPlot's cursor sync carries the drag and the reset), dashed
  // reference series, bands and limit lines, family highlight
  function linePlot(d, p, box, width) {
    const members = [null, ...p.series.map(s => s.family_member)];
    const series = [{ label: axisTitle(p.x) }, ...p.series.map((s, i) => ({
      label: s.name, stroke: seriesColor(s, i, d.family.length), width: BASE_WIDTH,
      dash: s.dashed ? [6, 4] : undefined, spanGaps: true, points: { show: false },
    }))];
    const group = p.link_group ? 'camopt-' + p.link_group : null;
    const u = new uPlot({
      width, height: LINE_HEIGHT, series,
      scales: { x: { time: false }, y: { range: (self, lo, hi) => yRange(p, lo, hi) } },
      axes: [{ label: axisTitle(p.x) }, { label: axisTitle(p.y), size: 64 }],
      cursor: { sync: group ? { key: group } : undefined, focus: { prox: 12 } },
      focus: { alpha: 1 },   // the family highlight dims, not uPlot's focus
      hooks: {
        drawClear: [self => drawBands(self, p.bands)],
        draw: [self => drawLimits(self, p.limits)],
        setSeries: [(self, i, opts) => { if (opts.focus != null) setHover(i == null ? -1 : members[i]); }],
      },
    }, lineData(p), box);
    api.plots[p.id] = u;
    pinOnClick(u, i => members[i]);
    return {
      members: members.slice(1),
      restyle(k) {
        u.series.forEach((s, i) => {
          if (i === 0) return;
          const m = members[i], on = k < 0 || m < 0 || m === k;
          s.alpha = on ? 1 : DIM_ALPHA;
          s.width = k >= 0 && m === k ? HIGHLIGHT_WIDTH : BASE_WIDTH;
          const row = u.root.querySelectorAll('.u-legend .u-series')[i];
          if (row) row.classList.toggle('camopt-dim', !on);
        });
        u.redraw(false);
      },
      resize(w) { u.setSize({ width: w, height: LINE_HEIGHT }); },
    };
  }

  // the y range: the data's, widened to show every limit line, padded
  function yRange(p, lo, hi) {
    for (const l of p.limits) {
      if (l.y === null) continue;
      lo = lo === null ? l.y : Math.min(lo, l.y);
      hi = hi === null ? l.y : Math.max(hi, l.y);
    }
    if (lo === null) return [0, 1];
    return uPlot.rangeNum(lo, hi, 0.1, true);
  }

  // shaded x intervals (active constraints, undercut windows) under the series, labelled
  function drawBands(u, bands) {
    const { ctx, bbox } = u, r = window.devicePixelRatio || 1;
    ctx.save();
    ctx.font = `${Math.round(10 * r)}px sans-serif`;
    ctx.textBaseline = 'top';
    for (const b of bands) {
      const x0 = u.valToPos(b.from, 'x', true), x1 = u.valToPos(b.to, 'x', true);
      const l = Math.max(bbox.left, Math.min(x0, x1)), rgt = Math.min(bbox.left + bbox.width, Math.max(x0, x1));
      if (rgt <= l) continue;
      ctx.fillStyle = 'rgba(255, 160, 0, 0.16)';
      ctx.fillRect(l, bbox.top, rgt - l, bbox.height);
      ctx.fillStyle = '#a65f00';
      if (b.label) ctx.fillText(b.label, l + 2 * r, bbox.top + 2 * r);
    }
    ctx.restore();
  }

  // horizontal dashed lines at limits, labelled at the right end
  function drawLimits(u, limits) {
    const { ctx, bbox } = u, r = window.devicePixelRatio || 1;
    ctx.save();
    ctx.strokeStyle = ctx.fillStyle = '#c00';
    ctx.lineWidth = r;
    ctx.setLineDash([4 * r, 3 * r]);
    ctx.font = `${Math.round(10 * r)}px sans-serif`;
    ctx.textAlign = 'right';
    ctx.textBaseline = 'bottom';
    for (const l of limits) {
      if (l.y === null) continue;
      const y = Math.round(u.valToPos(l.y, 'y', true)) + 0.5;
      ctx.beginPath();
      ctx.moveTo(bbox.left, y);
      ctx.lineTo(bbox.left + bbox.width, y);
      ctx.stroke();
      if (l.label) ctx.fillText(l.label, bbox.left + bbox.width - 2 * r, y - 2 * r);
    }
    ctx.restore();
  }

  // a click on a family curve (without dragging) or on its legend entry pins its highlight;
  // other legend entries keep uPlot's show/hide toggle
  function pinOnClick(u, memberOf) {
    let downX = 0;
    u.over.addEventListener('mousedown', e => { downX = e.clientX; });
    u.over.addEventListener('click', e => {
      if (Math.abs(e.clientX - downX) < 3 && family.hover >= 0) setPinned(family.hover === family.pinned ? -1 : family.hover);
    });
    const legend = u.root.querySelector('.u-legend');
    if (!legend) return;
    legend.addEventListener('click', e => {
      const row = e.target.closest('.u-series');
      const m = row ? memberOf(Array.prototype.indexOf.call(row.parentNode.children, row)) : -1;
      if (m === null || m < 0) return;
      e.stopPropagation();
      setPinned(m === family.pinned ? -1 : m);
    }, true);
  }

  // a cam profile (x-y to scale, equal aspect) on a canvas: series coloured by their color
  // values through the colour bar's scale, the others in one colour (dashed when a reference)
  function profilePlot(d, p, box, width) {
    const canvas = el('canvas');
    const all = p.series.flatMap(s => Array.from(s.color));
    const crange = colorRange(all);
    box.append(canvas);
    if (all.length) box.append(colorBar(p.color, crange));
    box.append(el('div', { class: 'camopt-legend' }, ...p.series.map((s, i) =>
      el('span', { style: `border-color:${seriesColor(s, i, d.family.length)}`, class: s.dashed ? 'dashed' : '', text: s.name }))));
    let xr = [Infinity, -Infinity], yr = [Infinity, -Infinity];
    for (const s of p.series) {
      const xs = seriesX(p, s);
      for (let i = 0; i < s.y.length; i++) {
        if (!Number.isFinite(xs[i]) || !Number.isFinite(s.y[i])) continue;
        xr = [Math.min(xr[0], xs[i]), Math.max(xr[1], xs[i])];
        yr = [Math.min(yr[0], s.y[i]), Math.max(yr[1], s.y[i])];
      }
    }
    if (!(xr[1] > xr[0])) xr = [xr[0] - 1 || -1, xr[0] + 1 || 1];
    if (!(yr[1] > yr[0])) yr = [yr[0] - 1 || -1, yr[0] + 1 || 1];
    const view = { members: p.series.map(s => s.family_member), width, k: -1 };
    const draw = () => {
      const w = view.width, h = Math.min(Math.round(w * 0.75), 560);
      const ctx = sizeCanvas(canvas, w, h);
      const area = { left: 64, top: 10, width: w - 74, height: h - 56 };
      // equal aspect: one scale for x and y, the data centred in the area
      const s = Math.min(area.width / (xr[1] - xr[0]), area.height / (yr[1] - yr[0])) * 0.96;
      const cx = (xr[0] + xr[1]) / 2, cy = (yr[0] + yr[1]) / 2;
      const ox = area.left + area.width / 2, oy = area.top + area.height / 2;
      view.toPixel = (x, y) => [ox + (x - cx) * s, oy - (y - cy) * s];
      const vx = [cx - area.width / 2 / s, cx + area.width / 2 / s], vy = [cy - area.height / 2 / s, cy + area.height / 2 / s];
      drawAxes(ctx, area, vx, vy, axisTitle(p.x), axisTitle(p.y));
      p.series.forEach((ser, i) => drawProfileSeries(ctx, view, ser, seriesX(p, ser),
        seriesColor(ser, i, d.family.length), crange));
    };
    view.restyle = k => { view.k = k; draw(); };
    view.resize = w => { view.width = w; draw(); };
    draw();
    return view;
  }

  // one profile series: by segments coloured by the mean color value, or one stroke
  function drawProfileSeries(ctx, view, s, xs, stroke, crange) {
    const k = view.k, m = s.family_member;
    ctx.save();
    ctx.globalAlpha = k < 0 || m < 0 || m === k ? 1 : DIM_ALPHA;
    ctx.lineWidth = k >= 0 && m === k ? 3.5 : 2.5;
    ctx.lineJoin = ctx.lineCap = 'round';
    ctx.setLineDash(s.dashed ? [6, 4] : []);
    const n = s.y.length, colored = s.color.length === n;
    ctx.strokeStyle = stroke;
    ctx.beginPath();
    for (let i = 0; i < n; i++) {
      if (!Number.isFinite(xs[i]) || !Number.isFinite(s.y[i])) continue;
      const [px, py] = view.toPixel(xs[i], s.y[i]);
      if (colored && i + 1 < n) {
        const [qx, qy] = view.toPixel(xs[i + 1], s.y[i + 1]);
        ctx.strokeStyle = colormap(((s.color[i] + s.color[i + 1]) / 2 - crange[0]) / (crange[1] - crange[0]));
        ctx.beginPath();
        ctx.moveTo(px, py);
        ctx.lineTo(qx, qy);
        ctx.stroke();
      } else if (!colored) {
        ctx.lineTo(px, py);
      }
    }
    if (!colored) ctx.stroke();
    ctx.restore();
  }

  // cell edges of a heat map axis: midway between values, half a step beyond the ends
  function cellEdges(v) {
    if (v.length === 1) return [v[0] - 0.5, v[0] + 0.5];
    const e = [v[0] - (v[1] - v[0]) / 2];
    for (let i = 1; i < v.length; i++) e.push((v[i - 1] + v[i]) / 2);
    e.push(v[v.length - 1] + (v[v.length - 1] - v[v.length - 2]) / 2);
    return e;
  }

  // a heat map: z over x_values (columns) x y_values (rows) in canvas cells (NaN: left empty),
  // a colour bar, and a readout of x, y, z under the pointer
  function heatmapPlot(d, p, box, width) {
    const canvas = el('canvas'), readout = el('div', { class: 'camopt-readout', text: 'point at a cell for its value' });
    const crange = colorRange(p.z);
    box.append(canvas, colorBar(p.color, crange), readout);
    const ex = cellEdges(p.x_values), ey = cellEdges(p.y_values), nx = p.x_values.length;
    const view = { members: [], width };
    let area = null;
    const draw = () => {
      const w = view.width, h = Math.min(Math.round(w * 0.6), 420);
      const ctx = sizeCanvas(canvas, w, h);
      area = { left: 64, top: 10, width: w - 74, height: h - 56 };
      const X = x => area.left + (x - ex[0]) / (ex[nx] - ex[0]) * area.width;
      const Y = y => area.top + area.height - (y - ey[0]) / (ey[ey.length - 1] - ey[0]) * area.height;
      view.toPixel = (x, y) => [X(x), Y(y)];
      for (let r = 0; r < p.y_values.length; r++) {
        for (let c = 0; c < nx; c++) {
          const z = p.z[r * nx + c];
          if (Number.isNaN(z)) continue;
          ctx.fillStyle = colormap((z - crange[0]) / (crange[1] - crange[0]));
          const x0 = Math.round(X(ex[c])), x1 = Math.round(X(ex[c + 1]));
          const y0 = Math.round(Y(ey[r + 1])), y1 = Math.round(Y(ey[r]));
          ctx.fillRect(x0, y0, x1 - x0, y1 - y0);
        }
      }
      drawAxes(ctx, area, [ex[0], ex[nx]], [ey[0], ey[ey.length - 1]], axisTitle(p.x), axisTitle(p.y));
    };
    canvas.addEventListener('mousemove', e => {
      const rect = canvas.getBoundingClientRect();
      const x = ex[0] + (e.clientX - rect.left - area.left) / area.width * (ex[nx] - ex[0]);
      const y = ey[0] + (area.top + area.height - (e.clientY - rect.top)) / area.height * (ey[ey.length - 1] - ey[0]);
      const c = ex.findIndex((v, i) => i < nx && x >= v && x < ex[i + 1]);
      const r = ey.findIndex((v, i) => i < ey.length - 1 && y >= v && y < ey[i + 1]);
      readout.textContent = c < 0 || r < 0 ? '' : `${p.x.label} ${fmt(p.x_values[c])} ${p.x.unit}, ` +
        `${p.y.label} ${fmt(p.y_values[r])} ${p.y.unit}: ${p.color.label} ${fmt(p.z[r * nx + c])} ${p.color.unit}`;
    });
    view.restyle = () => {};
    view.resize = w => { view.width = w; draw(); };
    draw();
    return view;
  }

  // ---- family highlight ------------------------------------------------------------------

  function currentMember() {
    return family.hover >= 0 ? family.hover : family.pinned;
  }

  // restyles every plot holding family members: member k highlighted, the others dimmed
  function applyHighlight() {
    const k = currentMember();
    for (const v of views) {
      if (!v.members.some(m => m >= 0)) continue;
      v.el.dataset.highlight = String(k);
      v.restyle(k);
    }
    if (family.select) family.select.value = String(family.pinned);
  }

  function setHover(m) {
    const k = m === null || m === undefined ? -1 : m;
    if (k !== family.hover) {
      family.hover = k;
      applyHighlight();
    }
  }

  function setPinned(k) {
    family.pinned = k;
    family.hover = -1;
    applyHighlight();
  }

  // ---- window size -----------------------------------------------------------------------

  let resizeQueued = false;
  function onResize() {
    if (resizeQueued) return;
    resizeQueued = true;
    requestAnimationFrame(() => { resizeQueued = false; resizeAll(); });
  }

  // every plot to its box's width, or to widthOf(view) (printing)
  function resizeAll(widthOf) {
    for (const v of views) v.resize(widthOf ? widthOf(v) : plotWidth(v.el));
  }

  // ---- tables ----------------------------------------------------------------------------

  function renderTable(t) {
    const failed = new Set(t.failed_rows);
    const table = el('table', { 'data-table-id': t.id },
      el('caption', { text: t.title }),
      el('thead', {}, el('tr', {}, ...t.columns.map(c => el('th', { text: c })))));
    const body = el('tbody');
    t.rows.forEach((row, i) => {
      const tr = el('tr', {}, ...row.map(c => el('td', { text: c })));
      if (failed.has(i)) {
        tr.className = 'failed';
        tr.title = 'failed';
      }
      body.append(tr);
    });
    table.append(body);
    return el('div', { class: 'camopt-table' }, table);
  }

  // ---- mechanism animation ---------------------------------------------------------------

  // the mechanism in SVG: every shape in its body's group, moved per frame by the body's pose
  // (translate, then rotate, in an outer group that flips y up), springs and contacts drawn per
  // frame in the world; play/pause, a frame slider and the control position select
  function renderAnimation(scene) {
    const [x0, y0, x1, y1] = scene.bbox;
    const diag = Math.hypot(x1 - x0, y1 - y0) || 1, margin = 0.05 * diag;
    const svg = svgEl('svg', { id: 'camopt-mechanism', role: 'img', 'aria-label': 'mechanism animation',
      viewBox: `${x0 - margin} ${-y1 - margin} ${x1 - x0 + 2 * margin} ${y1 - y0 + 2 * margin}`,
      preserveAspectRatio: 'xMidYMid meet' });
    const world = svgEl('g', { transform: 'scale(1 -1)' });
    svg.append(world);
    const bodies = scene.bodies.map(name => svgEl('g', { 'data-body': name, class: 'body-' + name }));
    world.append(...bodies);
    const springs = [];
    for (const sh of scene.shapes) {
      if (sh.kind === 'spring') springs.push({ sh, line: world.appendChild(svgEl('polyline', { class: 'role-spring' })) });
      else bodies[sh.body].append(shapeElement(sh));
    }
    const contacts = scene.contacts.map(name => {
      const g = svgEl('g', { class: 'camopt-contact', 'data-contact': name });
      g.append(svgEl('circle', { r: 0.008 * diag }), svgEl('polyline', {}));
      world.append(g);
      return g;
    });
    const st = { k: 0, frame: 0, playing: false, angle: 0, last: 0 };
    const controls = animationControls(scene, st);

    // a point of body b at frame i, drawing -> world
    const place = (pos, b, i, x, y) => {
      const [tx, ty, a] = [pos.pose[b][3 * i], pos.pose[b][3 * i + 1], pos.pose[b][3 * i + 2]];
      return [Math.cos(a) * x - Math.sin(a) * y + tx, Math.sin(a) * x + Math.cos(a) * y + ty];
    };
    const show = i => {
      const pos = scene.positions[st.k], n = pos.cam_deg.length;
      i = Math.min(Math.max(Math.round(i), 0), n - 1);
      st.frame = i;
      bodies.forEach((g, b) => {
        const tx = pos.pose[b][3 * i], ty = pos.pose[b][3 * i + 1], deg = pos.pose[b][3 * i + 2] * 180 / Math.PI;
        g.setAttribute('transform', `translate(${tx} ${ty}) rotate(${deg})`);
      });
      for (const { sh, line } of springs) {
        line.setAttribute('points', zigzag(place(pos, sh.body, i, sh.xy[0], sh.xy[1]),
          place(pos, sh.body_b, i, sh.xy[2], sh.xy[3]), 0.02 * diag));
      }
      contacts.forEach((g, c) => {
        const [x, y, nx, ny] = [0, 1, 2, 3].map(j => pos.contact[c][4 * i + j]);
        g.firstChild.setAttribute('cx', x);
        g.firstChild.setAttribute('cy', y);
        g.lastChild.setAttribute('points', arrow(x, y, nx, ny, 0.07 * diag));
      });
      Object.assign(svg.dataset, { frame: String(i), position: String(st.k),
        camDeg: String(pos.cam_deg[i]), liftMm: String(pos.lift_mm[i]) });
      controls.update(pos, i);
    };

    // playing: the cam angle advances at DEG_PER_S, wrapping over the frames' span
    const tick = now => {
      if (!st.playing) return;
      const cam = scene.positions[st.k].cam_deg, n = cam.length;
      const step = n > 1 ? (cam[n - 1] - cam[0]) / (n - 1) : 1;
      st.angle = (st.angle + (now - st.last) / 1000 * DEG_PER_S) % (n * step);
      st.last = now;
      show(st.angle / step);
      requestAnimationFrame(tick);
    };
    const anim = {
      play() {
        if (st.playing) return;
        const cam = scene.positions[st.k].cam_deg;
        st.playing = true;
        st.angle = st.frame * (cam.length > 1 ? (cam[cam.length - 1] - cam[0]) / (cam.length - 1) : 1);
        st.last = performance.now();
        controls.playing(true);
        requestAnimationFrame(tick);
      },
      pause() { st.playing = false; controls.playing(false); },
      get playing() { return st.playing; },
      get frame() { return st.frame; },
      setFrame(i) { show(i); },
      // the frame nearest to cam angle deg (angles compared modulo 360)
      setCamDeg(deg) {
        const cam = scene.positions[st.k].cam_deg;
        let best = 0;
        for (let i = 1; i < cam.length; i++) if (angleGap(cam[i], deg) < angleGap(cam[best], deg)) best = i;
        show(best);
      },
      setPosition(k) { st.k = Math.min(Math.max(k | 0, 0), scene.positions.length - 1); show(st.frame); },
    };
    controls.bind(anim);
    api.animation = anim;
    show(0);
    return el('div', { class: 'camopt-animation' }, svg, controls.el);
  }

  function angleGap(a, b) {
    return Math.abs(((a - b) % 360 + 540) % 360 - 180);
  }

  // one scene shape in drawing coordinates [mm]
  function shapeElement(sh) {
    const cls = 'role-' + (sh.role || sh.kind);
    if (sh.kind === 'circle') return svgEl('circle', { cx: sh.xy[0], cy: sh.xy[1], r: sh.radius, class: cls });
    const pts = [];
    for (let i = 0; i + 1 < sh.xy.length; i += 2) pts.push(sh.xy[i] + ',' + sh.xy[i + 1]);
    return svgEl(sh.kind === 'polygon' ? 'polygon' : 'polyline', { points: pts.join(' '), class: cls });
  }

  // a coil spring from a to b: short straight ends and 8 zig-zags of half width w
  function zigzag(a, b, w) {
    const dx = b[0] - a[0], dy = b[1] - a[1], len = Math.hypot(dx, dy) || 1;
    const ux = dx / len, uy = dy / len, n = 16;
    const pts = [a, [a[0] + 0.1 * dx, a[1] + 0.1 * dy]];
    for (let j = 1; j < n; j++) {
      const t = 0.1 + 0.8 * j / n, side = j % 2 ? w : -w;
      pts.push([a[0] + t * dx - uy * side, a[1] + t * dy + ux * side]);
    }
    pts.push([a[0] + 0.9 * dx, a[1] + 0.9 * dy], b);
    return pts.map(p => p[0] + ',' + p[1]).join(' ');
  }

  // a normal of length len from (x, y) along (nx, ny), with an arrow head
  function arrow(x, y, nx, ny, len) {
    const tx = x + nx * len, ty = y + ny * len, h = 0.3 * len;
    return `${x},${y} ${tx},${ty} ${tx - h * (nx + 0.5 * ny)},${ty - h * (ny - 0.5 * nx)} ` +
      `${tx},${ty} ${tx - h * (nx - 0.5 * ny)},${ty - h * (ny + 0.5 * nx)}`;
  }

  // play/pause button, frame slider with the cam angle and lift readout, control position select
  function animationControls(scene, st) {
    const play = el('button', { id: 'camopt-play', type: 'button', text: 'Play' });
    const slider = el('input', { id: 'camopt-frame', type: 'range', min: '0', step: '1', value: '0',
      'aria-label': 'frame' });
    const readout = el('span', { class: 'camopt-readout' });
    const box = el('div', { class: 'camopt-controls' }, play, slider, readout);
    let select = null;
    if (scene.control_name) {
      select = el('select', { id: 'camopt-position', 'aria-label': 'control position' },
        ...scene.positions.map((p, k) => el('option', { value: String(k),
          text: `${scene.control_name} ${fmt(p.control)} ${scene.control_unit}` })));
      box.append(select);
    }
    return {
      el: box,
      bind(anim) {
        play.addEventListener('click', () => (anim.playing ? anim.pause() : anim.play()));
        slider.addEventListener('input', () => anim.setFrame(+slider.value));
        if (select) select.addEventListener('change', () => anim.setPosition(+select.value));
      },
      update(pos, i) {
        slider.max = String(pos.cam_deg.length - 1);
        slider.value = String(i);
        if (select) select.value = String(st.k);
        readout.textContent = `cam ${pos.cam_deg[i].toFixed(1)} deg, lift ${pos.lift_mm[i].toFixed(3)} mm`;
      },
      playing(on) { play.textContent = on ? 'Pause' : 'Play'; },
    };
  }

  // ---- start: draw the page once everything above is defined ----------------------------
  api.ready = new Promise((resolve, reject) => {
    try {
      init();
      api.timing.drawn_ms = performance.now() - started;
      requestAnimationFrame(() => {   // after the first paint
        api.timing.first_paint_ms = performance.now() - started;
        resolve(api);
      });
    } catch (err) {
      const root = document.getElementById('camopt-report');
      root.append(el('p', { class: 'camopt-error', text: 'The report could not be drawn: ' + err.message }));
      console.error(err);
      reject(err);
    }
  });
  api.ready.catch(() => {});   // the failure is already on the console and on the page
})();
