// Measurement harness, inlined into every page after the library and its adapter (libs/*.js).
// The adapter sets window.BENCH = { svaj(els, d, w, h), family(el, f, w, h), settle() }.
'use strict';
(async function () {
  const tLoad = performance.now(); // navigation start -> here: HTML parse + library evaluation
  const N = 100000, W = 1000, H = 200, K = 17, M = 721, MOVES = 25;
  const now = () => performance.now();
  const frame = () => new Promise(r => window.__raf(() => setTimeout(r, 0))); // after the next paint
  const sleep = ms => new Promise(r => setTimeout(r, ms));
  const median = a => { const s = [...a].sort((p, q) => p - q); return s[s.length >> 1]; };

  // SVAJ: a smooth 9 mm lift over 180 cam deg; velocity, acceleration, jerk by central differences.
  function lift(x, h, open, dur) { const u = (x - open) / dur; return u > 0 && u < 1 ? h * Math.sin(Math.PI * u) ** 4 : 0; }
  function diff(y, dx) { const n = y.length, o = new Float64Array(n); for (let i = 1; i < n - 1; i++) o[i] = (y[i + 1] - y[i - 1]) / (2 * dx); return o; }
  const x = new Float64Array(N); for (let i = 0; i < N; i++) x[i] = 360 * i / (N - 1);
  const l = x.map(v => lift(v, 9, 90, 180)), dx = 360 / (N - 1);
  const v = diff(l, dx), a = diff(v, dx), j = diff(a, dx);
  const svaj = { x, ys: [l, v, a, j], names: ['lift mm', 'vel mm/deg', 'acc mm/deg2', 'jerk mm/deg3'] };
  const fx = new Float64Array(M); for (let i = 0; i < M; i++) fx[i] = 0.5 * i;
  const fam = { x: fx, ys: Array.from({ length: K }, (_, k) => fx.map(t => lift(t, 9 * (k + 1) / K, 130 - 2 * k, 100 + 4 * k))) };

  const els = [0, 1, 2, 3].map(i => document.getElementById('p' + i));
  await frame();

  let t0 = now();
  await BENCH.svaj(els, svaj, W, H);
  await frame();
  const firstRender = now() - t0;

  // Linked highlight: mouse moves over plot 0 (mid-height, 10 %..90 % of its width, in a scattered
  // order); each waits 80 ms first, so that no library's hover throttle (Plotly: 50 ms) applies.
  const box = els[0].getBoundingClientRect(), cy = box.top + box.height / 2;
  const target = document.elementFromPoint(box.left + box.width / 2, cy);
  for (const type of ['mouseover', 'mouseenter'])
    target.dispatchEvent(new MouseEvent(type, { clientX: box.left + box.width / 2, clientY: cy, bubbles: type !== 'mouseenter' }));
  const script = [], latency = [];
  for (let i = 0; i < MOVES; i++) {
    await sleep(80);
    const cx = box.left + box.width * (0.1 + 0.8 * ((i * 7) % MOVES) / (MOVES - 1));
    const el = document.elementFromPoint(cx, cy);
    window.__rafWork = 0;
    t0 = now();
    el.dispatchEvent(new MouseEvent('mousemove', { clientX: cx, clientY: cy, bubbles: true, cancelable: true, view: window }));
    if (BENCH.settle) await BENCH.settle();
    const t1 = now();
    await frame();
    script.push(t1 - t0 + window.__rafWork); // handler + the library's animation-frame callbacks
    latency.push(now() - t0);                // to the end of the next painted frame (60 Hz frame clock)
  }

  t0 = now();
  await BENCH.family(document.getElementById('fam'), fam, W, 2 * H);
  await frame();
  const family = now() - t0;

  window.benchResult = { load: tLoad, firstRender, hoverScript: median(script), hoverLatency: median(latency), family };
})().catch(e => { window.benchError = String((e && e.stack) || e); });
