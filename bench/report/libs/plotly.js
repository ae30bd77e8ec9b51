// Plotly (cartesian partial bundle): 4 scatter-line plots; hover on plot 0 calls Fx.hover on the
// other 3 (Plotly's recipe for linked hover across separate plots); zoom built in.
window.BENCH = {
  async svaj(els, d, w, h) {
    const layout = { width: w, height: h, margin: { l: 50, r: 10, t: 10, b: 30 }, hovermode: 'x', showlegend: false,
      xaxis: { showspikes: true, spikemode: 'across', spikethickness: 1 } };
    for (let i = 0; i < 4; i++)
      await Plotly.newPlot(els[i], [{ x: d.x, y: d.ys[i], type: 'scatter', mode: 'lines', line: { width: 1 }, name: d.names[i] }],
        layout, { displayModeBar: false });
    els[0].on('plotly_hover', e => { for (let i = 1; i < 4; i++) Plotly.Fx.hover(els[i], { xval: e.xvals[0] }); });
  },
  async family(el, f, w, h) {
    await Plotly.newPlot(el, f.ys.map((y, k) => ({ x: f.x, y, type: 'scatter', mode: 'lines', line: { width: 1 }, name: 'pos ' + k })),
      { width: w, height: h, margin: { l: 50, r: 10, t: 10, b: 30 }, showlegend: false }, { displayModeBar: false });
  },
};
