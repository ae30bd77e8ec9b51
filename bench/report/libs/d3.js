// d3 (v3, Debian): SVG axes and one path per curve; a mousemove on plot 0 moves a cursor line and
// point in all 4 (all of it by hand: d3 is a toolkit, not a charting library).
(function () {
  const M = { l: 50, r: 10, t: 10, b: 25 };
  function plot(el, w, h, x, ys, colors) {
    const xs = d3.scale.linear().domain([0, 360]).range([0, w - M.l - M.r]);
    let lo = Infinity, hi = -Infinity; for (const y of ys) for (const v of y) { if (v < lo) lo = v; if (v > hi) hi = v; }
    const yss = d3.scale.linear().domain([lo, hi]).nice().range([h - M.t - M.b, 0]);
    const g = d3.select(el).append('svg').attr('width', w).attr('height', h).append('g').attr('transform', `translate(${M.l},${M.t})`);
    g.append('g').attr('transform', `translate(0,${h - M.t - M.b})`).call(d3.svg.axis().scale(xs));
    g.append('g').call(d3.svg.axis().scale(yss).orient('left').ticks(5));
    g.selectAll('.domain').attr('fill', 'none').attr('stroke', '#000');
    const idx = d3.range(x.length);
    ys.forEach((y, k) => g.append('path').attr('fill', 'none').attr('stroke', colors(k))
      .attr('d', d3.svg.line().x(i => xs(x[i])).y(i => yss(y[i]))(idx)));
    return { g, xs, yss };
  }
  window.BENCH = {
    svaj(els, d, w, h) {
      const ps = d.ys.map((y, i) => {
        const p = plot(els[i], w, h, d.x, [y], () => '#1f77b4');
        p.line = p.g.append('line').attr('y1', 0).attr('y2', h - M.t - M.b).attr('stroke', '#c00');
        p.dot = p.g.append('circle').attr('r', 3).attr('fill', 'none').attr('stroke', '#c00');
        p.y = y; return p;
      });
      ps[0].g.append('rect').attr('width', w - M.l - M.r).attr('height', h - M.t - M.b).attr('fill', 'none')
        .attr('pointer-events', 'all').on('mousemove', function () {
          const cx = ps[0].xs.invert(d3.mouse(this)[0]);
          const i = Math.min(d.x.length - 1, Math.max(0, Math.round(cx / 360 * (d.x.length - 1))));
          for (const p of ps) { const px = p.xs(d.x[i]); p.line.attr('x1', px).attr('x2', px); p.dot.attr('cx', px).attr('cy', p.yss(p.y[i])); }
        });
    },
    family(el, f, w, h) { plot(el, w, h, f.x, f.ys, k => `hsl(${k * 20},70%,45%)`); },
  };
})();
