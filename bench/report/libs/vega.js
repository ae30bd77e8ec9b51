// Vega: one view of 4 stacked groups over one data set of 100k rows; a signal set by mousemove
// moves a rule in every group (the linked cursor); canvas renderer.
(function () {
  let view;
  const ch = ['l', 'v', 'a', 'j'];
  window.BENCH = {
    async svaj(els, d, w, h) {
      const iw = w - 60, ih = h - 35;
      const rows = Array.from(d.x, (x, k) => ({ x, l: d.ys[0][k], v: d.ys[1][k], a: d.ys[2][k], j: d.ys[3][k] }));
      const spec = {
        width: iw, height: 4 * h - 35, padding: { left: 50, right: 10, top: 5, bottom: 30 }, autosize: 'none',
        data: [{ name: 'd', values: rows }],
        signals: [{ name: 'cx', value: -1, on: [{ events: 'mousemove', update: "clamp(invert('x', x()), 0, 360)" }] }],
        scales: [{ name: 'x', type: 'linear', domain: [0, 360], range: 'width' }],
        marks: ch.map((c, i) => ({
          type: 'group', encode: { enter: { y: { value: i * h }, width: { value: iw }, height: { value: ih } } },
          scales: [{ name: 'y', type: 'linear', domain: { data: 'd', field: c }, range: [ih, 0], nice: true }],
          axes: [{ orient: 'bottom', scale: 'x' }, { orient: 'left', scale: 'y', tickCount: 5 }],
          marks: [
            { type: 'line', from: { data: 'd' }, encode: { enter: { x: { scale: 'x', field: 'x' }, y: { scale: 'y', field: c }, stroke: { value: '#1f77b4' }, strokeWidth: { value: 1 } } } },
            { type: 'rule', encode: { update: { x: { scale: 'x', signal: 'cx' }, y: { value: 0 }, y2: { value: ih }, stroke: { value: '#c00' } } } },
          ],
        })),
      };
      els.slice(1).forEach(e => { e.style.display = 'none'; });
      view = new vega.View(vega.parse(spec), { renderer: 'canvas', container: els[0], hover: false });
      await view.runAsync();
    },
    settle() { return view.runAsync(); },
    async family(el, f, w, h) {
      const rows = []; f.ys.forEach((y, k) => f.x.forEach((x, i) => rows.push({ x, y: y[i], s: k })));
      const spec = {
        width: w - 60, height: h - 35, padding: { left: 50, right: 10, top: 5, bottom: 30 }, autosize: 'none',
        data: [{ name: 'f', values: rows }],
        scales: [{ name: 'x', type: 'linear', domain: [0, 360], range: 'width' },
          { name: 'y', type: 'linear', domain: { data: 'f', field: 'y' }, range: 'height' },
          { name: 'c', type: 'ordinal', domain: { data: 'f', field: 's' }, range: 'category' }],
        axes: [{ orient: 'bottom', scale: 'x' }, { orient: 'left', scale: 'y' }],
        marks: [{ type: 'group', from: { facet: { name: 's', data: 'f', groupby: 's' } },
          marks: [{ type: 'line', from: { data: 's' }, encode: { enter: { x: { scale: 'x', field: 'x' }, y: { scale: 'y', field: 'y' }, stroke: { scale: 'c', field: 's' }, strokeWidth: { value: 1 } } } }] }],
      };
      await new vega.View(vega.parse(spec), { renderer: 'canvas', container: el }).runAsync();
    },
  };
})();
