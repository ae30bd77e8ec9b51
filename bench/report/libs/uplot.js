// uPlot: 4 plots sharing a cursor sync key (linked cursor, points and legend values); drag to zoom.
window.BENCH = {
  svaj(els, d, w, h) {
    d.ys.forEach((y, i) => new uPlot({
      width: w, height: h, scales: { x: { time: false } },
      cursor: { sync: { key: 'svaj' } },
      series: [{ label: 'cam deg' }, { label: d.names[i], stroke: '#1f77b4', width: 1 }],
    }, [d.x, y], els[i]));
  },
  family(el, f, w, h) {
    new uPlot({
      width: w, height: h, scales: { x: { time: false } },
      series: [{ label: 'cam deg' }, ...f.ys.map((_, k) => ({ label: 'pos ' + k, stroke: `hsl(${k * 20},70%,45%)`, width: 1 }))],
    }, [f.x, ...f.ys], el);
  },
};
