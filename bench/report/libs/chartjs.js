// Chart.js: 4 line charts with min-max decimation (the documented way to 100k points); no built-in
// linked cursor, so a small plugin draws a cursor line and point and a mousemove on chart 0 redraws all 4.
(function () {
  const cursor = {
    id: 'cursor',
    afterDraw(chart) {
      if (chart.$cx == null) return;
      const { ctx, chartArea: ar, scales } = chart, px = scales.x.getPixelForValue(chart.$cx);
      const raw = chart.data.datasets[0].data; let lo = 0, hi = raw.length - 1;
      while (hi - lo > 1) { const m = (lo + hi) >> 1; if (raw[m].x < chart.$cx) lo = m; else hi = m; }
      ctx.save(); ctx.strokeStyle = '#c00'; ctx.beginPath(); ctx.moveTo(px, ar.top); ctx.lineTo(px, ar.bottom); ctx.stroke();
      ctx.beginPath(); ctx.arc(px, scales.y.getPixelForValue(raw[hi].y), 3, 0, 2 * Math.PI); ctx.stroke(); ctx.restore();
    },
  };
  const options = (w, h) => ({
    responsive: false, animation: false, parsing: false, normalized: true, events: [], devicePixelRatio: 1,
    plugins: { decimation: { enabled: true, algorithm: 'min-max' }, legend: { display: false }, tooltip: { enabled: false } },
    scales: { x: { type: 'linear', min: 0, max: 360 } },
    elements: { point: { radius: 0 }, line: { borderWidth: 1, borderColor: '#1f77b4' } },
  });
  const canvas = (el, w, h) => { const c = document.createElement('canvas'); c.width = w; c.height = h; el.appendChild(c); return c; };
  window.BENCH = {
    svaj(els, d, w, h) {
      const charts = d.ys.map((y, i) => new Chart(canvas(els[i], w, h), {
        type: 'line', plugins: [cursor], options: options(w, h),
        data: { datasets: [{ label: d.names[i], data: Array.from(d.x, (x, k) => ({ x, y: y[k] })) }] },
      }));
      charts[0].canvas.addEventListener('mousemove', e => {
        const cx = charts[0].scales.x.getValueForPixel(e.clientX - charts[0].canvas.getBoundingClientRect().left);
        for (const c of charts) { c.$cx = cx; c.draw(); }
      });
    },
    family(el, f, w, h) {
      new Chart(canvas(el, w, h), {
        type: 'line', options: { ...options(w, h), plugins: { legend: { display: false }, tooltip: { enabled: false } } },
        data: { datasets: f.ys.map((y, k) => ({ label: 'pos ' + k, borderColor: `hsl(${k * 20},70%,45%)`, data: Array.from(f.x, (x, i) => ({ x, y: y[i] })) })) },
      });
    },
  };
})();
