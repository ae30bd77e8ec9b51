// dygraphs: 4 plots joined by the synchronizer extra (selection and zoom); rows of [x, y].
window.BENCH = {
  svaj(els, d, w, h) {
    const gs = d.ys.map((y, i) => new Dygraph(els[i], Array.from(d.x, (x, k) => [x, y[k]]),
      { width: w, height: h, labels: ['cam deg', d.names[i]], strokeWidth: 1 }));
    Dygraph.synchronize(gs, { selection: true, zoom: true, range: false });
  },
  family(el, f, w, h) {
    new Dygraph(el, Array.from(f.x, (x, k) => [x, ...f.ys.map(y => y[k])]),
      { width: w, height: h, labels: ['cam deg', ...f.ys.map((_, k) => 'pos ' + k)], strokeWidth: 1 });
  },
};
