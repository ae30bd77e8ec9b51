// Page tests on synthetic data (fixture.mjs: closed forms) in headless Chromium, network off:
// the hooks of the data format, decoding against the closed form, the family highlight, zoom and
// reset, the heat map and the profile against their data, and the animation against the
// eccentric disc's analytic lift. Run: node --test tests/report/browser/ (from the repo root).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, writeFileSync, rmSync, readFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import * as fx from './fixture.mjs';
import { launchChromium, openReport, checkPlotsAndTables, checkPlayPause, checkLift, csvLift, readReportData } from './check_report.mjs';

const HIGHLIGHT_WIDTH = 2.75, BASE_WIDTH = 1.25, DIM_ALPHA = 0.18;   // report.js' family styles
const F32_TOL = v => 4 * 2 ** -24 * Math.max(Math.abs(v), 1);           // float32 rounding of v, with room

let browser, dir, file, report;
const html = fx.buildPage(fx.syntheticReport());
const data = readReportData(html);   // as the page holds it: NUM fields decoded

before(async () => {
  dir = mkdtempSync(path.join(os.tmpdir(), 'camopt-page-'));
  file = path.join(dir, 'report.html');
  writeFileSync(file, html);
  browser = await launchChromium();
  report = await openReport(browser, file);
});

after(async () => {
  try {
    if (report) assert.deepEqual(report.problems, [], 'console errors, page errors or network requests');
  } finally {
    if (browser) await browser.close();
    if (dir) rmSync(dir, { recursive: true, force: true });
  }
});

const page = () => report.page;

// per plot: [member of each uPlot series (x excluded), alpha, width] and the data-highlight
function familyStyles() {
  return page().evaluate(() => Object.fromEntries([...document.querySelectorAll('.camopt-plot[data-kind="line"]')].map(e => {
    const u = window.camoptReport.plots[e.dataset.plotId];
    const p = window.camoptReport.data.plots.find(x => x.id === e.dataset.plotId);
    return [e.dataset.plotId, { highlight: e.dataset.highlight,
      series: p.series.map((s, i) => ({ m: s.family_member, alpha: u.series[i + 1].alpha, width: u.series[i + 1].width })) }];
  })));
}

// every line plot shows member k highlighted and the other members dimmed (k = -1: none)
function assertHighlight(styles, k) {
  for (const [id, st] of Object.entries(styles)) {
    assert.equal(st.highlight, String(k), `${id}: data-highlight`);
    for (const s of st.series) {
      const on = k < 0 || s.m < 0 || s.m === k;
      assert.equal(s.alpha, on ? 1 : DIM_ALPHA, `${id}: alpha of member ${s.m} with ${k} highlighted`);
      assert.equal(s.width, k >= 0 && s.m === k ? HIGHLIGHT_WIDTH : BASE_WIDTH, `${id}: width of member ${s.m}`);
    }
  }
}

// page coordinates of data point (x, y) of a uPlot plot
function uplotPoint(id, x, y) {
  return page().evaluate(([pid, px, py]) => {
    const u = window.camoptReport.plots[pid], r = u.over.getBoundingClientRect();
    return [r.left + u.valToPos(px, 'x'), r.top + u.valToPos(py, 'y')];
  }, [id, x, y]);
}

test('hooks: every plot and table with its counts and axis titles, play and pause, the title escaped', async () => {
  assert.deepEqual(await checkPlotsAndTables(page(), data), []);
  assert.deepEqual(await checkPlayPause(page()), []);
  const head = await page().evaluate(() => ({ title: document.title, h1: document.querySelector('h1').textContent,
    verdict: document.getElementById('camopt-verdict').className, sections: [...document.querySelectorAll('main > section')].map(s => s.id) }));
  assert.equal(head.title, data.title);
  assert.equal(head.h1, data.title);
  assert.equal(head.verdict, 'failed');
  assert.deepEqual(head.sections, data.sections.map(s => 'section-' + s.id));
});

test('hooks: a checker fed a wrong plot count or a wrong lift reports it', async () => {
  const wrong = structuredClone(data);
  wrong.plots[0].series.pop();
  wrong.tables[0].failed_rows = [2];
  const failures = await checkPlotsAndTables(page(), wrong);
  assert.ok(failures.some(f => f.startsWith('plot svaj-lift: data-series')), failures.join('\n'));
  assert.ok(failures.some(f => f.startsWith('table constraints: rows marked failed')), failures.join('\n'));
  // a CSV whose lift is 1e-5 relative off: above float32 rounding, so every picked angle fails
  const scene = { output_body: 'follower', positions: [{ control: 0, cam_deg: [0, 90, 180, 270] }] };
  const lift = new Map([0, 90, 180, 270].map(a => [a, fx.discLift(a * Math.PI / 180) * (1 + 1e-5) + 1e-5]));
  assert.equal((await checkLift(page(), scene, lift, 0, 4)).length, 8);
});

test('hooks: the output body moves by the CSV lift at every checked angle (phase position)', async () => {
  const phase = fx.PHASES[1];
  const rows = ['control_deg,cam_deg,lift_mm', ...fx.PHASES.flatMap(ph => Array.from({ length: 360 }, (_, a) =>
    `${ph},${a},${fx.discLift((a - ph) * Math.PI / 180)}`))];
  const lift = csvLift(rows.join('\n') + '\n', 'lift_mm', phase);
  assert.equal(lift.size, 360);
  assert.deepEqual(await checkLift(page(), data.scene, lift, 1), []);
});

test('SVAJ: the decoded family equals the cycloidal rise in float32', async () => {
  const plotted = await page().evaluate(() => ['lift', 'velocity', 'acceleration', 'jerk'].map(q =>
    Array.from(window.camoptReport.plots['svaj-' + q].data, a => Array.from(a))));
  plotted.forEach((d, q) => {
    assert.deepEqual(d[0], fx.ANGLES.map(fx.f32));
    for (let k = 0; k < fx.FAMILY; k++) {
      assert.deepEqual(d[k + 1], fx.ANGLES.map(t => fx.f32(fx.cycloidal(fx.riseHeight(k), fx.BETA, t)[q])), `quantity ${q} member ${k}`);
    }
  });
});

test('family: hovering a legend entry or a curve highlights that member in every plot', async () => {
  // legend row i is series i (row 0: x); member 5 is series 6
  await page().hover('.camopt-plot[data-plot-id="svaj-lift"] .u-legend .u-series:nth-child(7) th');
  assertHighlight(await familyStyles(), 5);
  await page().hover('#camopt-header h1');
  assertHighlight(await familyStyles(), -1);

  // the velocity curve of member 12 at its peak (60 deg): members are 0.5 * 2/120 mm/deg apart
  const v12 = fx.cycloidal(fx.riseHeight(12), fx.BETA, 60)[1];
  const [x, y] = await uplotPoint('svaj-velocity', 60, v12);
  await page().mouse.move(x, y);
  assertHighlight(await familyStyles(), 12);
  await page().mouse.click(x, y);   // pins it
  await page().hover('#camopt-header h1');
  assertHighlight(await familyStyles(), 12);
  assert.equal(await page().inputValue('#camopt-family'), '12');
  await page().selectOption('#camopt-family', '-1');
  assertHighlight(await familyStyles(), -1);

  // a click on a legend entry pins that member and leaves the series shown
  await page().click('.camopt-plot[data-plot-id="contact-pressure-angle"] .u-legend .u-series:nth-child(4) th');
  await page().hover('#camopt-header h1');
  assertHighlight(await familyStyles(), 2);
  assert.equal(await page().evaluate(() => window.camoptReport.plots['contact-pressure-angle'].series[3].show), true);
  await page().selectOption('#camopt-family', '-1');
});

test('zoom: a drag zooms x in every plot of its link group only, a double click resets them', async () => {
  const xs = () => page().evaluate(() => Object.fromEntries(Object.entries(window.camoptReport.plots)
    .filter(([, u]) => u).map(([id, u]) => [id, [u.scales.x.min, u.scales.x.max]])));
  const full = await xs();
  const [x0, y] = await uplotPoint('svaj-lift', 20, 1);
  const [x1] = await uplotPoint('svaj-lift', 60, 1);
  await page().mouse.move(x0, y);
  await page().mouse.down();
  await page().mouse.move((x0 + x1) / 2, y);
  await page().mouse.move(x1, y);
  await page().mouse.up();
  const zoomed = await xs();
  const degPerPx = await page().evaluate(() => { const u = window.camoptReport.plots['svaj-lift']; return 120 / u.over.clientWidth; });
  assert.ok(Math.abs(zoomed['svaj-lift'][0] - 20) <= 1.5 * degPerPx && Math.abs(zoomed['svaj-lift'][1] - 60) <= 1.5 * degPerPx,
    `svaj-lift zoomed to ${zoomed['svaj-lift']}`);
  for (const id of ['svaj-velocity', 'svaj-acceleration', 'svaj-jerk']) assert.deepEqual(zoomed[id], zoomed['svaj-lift'], id);
  assert.deepEqual(zoomed['contact-pressure-angle'], full['contact-pressure-angle']);
  await page().mouse.dblclick(x0, y);
  const reset = await xs();
  for (const id of ['svaj-lift', 'svaj-jerk']) assert.deepEqual(reset[id], [0, 120], id);
  await page().hover('#camopt-header h1');
});

// the RGBA of a canvas pixel at CSS position (x, y) of a plot box's n-th canvas (read from a
// copy made for reading, so the page's canvas is not switched to software readback)
function pixel(id, n, x, y) {
  return page().evaluate(([pid, i, px, py]) => {
    const c = document.querySelectorAll(`.camopt-plot[data-plot-id="${pid}"] canvas`)[i];
    const copy = document.createElement('canvas');
    copy.width = copy.height = 1;
    const ctx = copy.getContext('2d', { willReadFrequently: true });
    ctx.drawImage(c, Math.floor(px), Math.floor(py), 1, 1, 0, 0, 1, 1);
    return Array.from(ctx.getImageData(0, 0, 1, 1).data);
  }, [id, n, x, y]);
}

test('heat map: cells coloured at the colour bar ends for the extremes, the hole empty, the readout', async () => {
  const id = 'speed-map', at = (r, c) => page().evaluate(([pid, x, y]) => window.camoptReport.views[pid].toPixel(x, y), [id, fx.HEAT.rpm[c], fx.HEAT.control[r]]);
  const [lo, hi] = [await pixel(id, 1, 0.5, 6), await pixel(id, 1, 159.5, 6)];   // canvas 1: the colour bar
  assert.deepEqual(await pixel(id, 0, ...await at(0, 0)), lo);   // z min: 1000 rpm, control 0
  assert.deepEqual(await pixel(id, 0, ...await at(4, 6)), hi);   // z max: 7000 rpm, control 16
  assert.equal((await pixel(id, 0, ...await at(2, 3)))[3], 0);   // NaN: nothing drawn
  const [x, y] = await at(1, 4);
  await page().locator(`.camopt-plot[data-plot-id="${id}"] canvas`).first().hover({ position: { x, y } });
  assert.equal(await page().textContent(`.camopt-plot[data-plot-id="${id}"] .camopt-readout`),
    `engine speed 5000 rpm, control 4 deg: separation speed ${fx.HEAT.z(1, 4)} rpm`);
});

test('profile: drawn to scale and coloured by radius of curvature at the colour bar ends', async () => {
  const id = 'profile', at = (x, y) => page().evaluate(([pid, px, py]) => window.camoptReport.views[pid].toPixel(px, py), [id, x, y]);
  const [o, ex, ey] = [await at(0, 0), await at(30, 0), await at(0, 30)];
  assert.ok(ex[0] - o[0] > 100, 'the profile is drawn large');
  const size = await page().evaluate(pid => { const c = document.querySelector(`.camopt-plot[data-plot-id="${pid}"] canvas`); return [c.clientWidth, c.clientHeight]; }, id);
  for (const [x, y] of [[-fx.ELLIPSE.a, -fx.ELLIPSE.b], [fx.ELLIPSE.a, fx.ELLIPSE.b]]) {
    const [px, py] = await at(x, y);
    assert.ok(px > 0 && px < size[0] && py > 0 && py < size[1], `(${x}, ${y}) mm drawn at ${px}, ${py} px: outside the ${size} px canvas`);
  }
  assert.ok(Math.abs((ex[0] - o[0]) - (o[1] - ey[1])) < 1e-9, `equal aspect: ${ex[0] - o[0]} px vs ${o[1] - ey[1]} px per 30 mm`);
  const [lo, hi] = [await pixel(id, 1, 0.5, 6), await pixel(id, 1, 159.5, 6)];
  const near = (a, b) => a.every((v, i) => Math.abs(v - b[i]) <= 3);
  // (a, 0): radius b^2/a, the smallest; (0, -b): a^2/b, the largest
  const flank = await pixel(id, 0, ...await at(fx.ELLIPSE.a, 0)), nose = await pixel(id, 0, ...await at(0, -fx.ELLIPSE.b));
  assert.ok(near(flank, lo), `(a, 0) drawn ${flank}, colour bar start ${lo}`);
  assert.ok(near(nose, hi), `(0, -b) drawn ${nose}, colour bar end ${hi}`);
});

test('animation: follower, cam, contact and spring at each frame against the disc closed form', async () => {
  for (const [k, phase] of fx.PHASES.entries()) {
    await page().selectOption('#camopt-position', String(k));
    for (const i of [0, 45, 90, 181, 300]) {
      await page().locator('#camopt-frame').fill(String(i));
      const got = await page().evaluate(() => {
        const svg = document.getElementById('camopt-mechanism');
        const m = b => svg.querySelector(`g[data-body="${b}"]`).transform.baseVal.consolidate().matrix;
        const c = svg.querySelector('.camopt-contact circle'), spring = svg.querySelector('polyline.role-spring').points;
        return { ...svg.dataset, follower: [m('follower').e, m('follower').f], cam: [m('cam').a, m('cam').b],
          contact: [+c.getAttribute('cx'), +c.getAttribute('cy')], spring: [spring[0].y, spring[spring.numberOfItems - 1].y] };
      });
      const t = (i - phase) * Math.PI / 180, lift = fx.discLift(t), e = fx.ECCENTRICITY, R = fx.DISC_RADIUS;
      assert.equal(got.frame, String(i));
      assert.equal(got.position, String(k));
      assert.equal(+got.camDeg, i);
      assert.equal(+got.liftMm, fx.f32(lift));
      assert.equal(got.follower[0], 0);
      assert.ok(Math.abs(got.follower[1] - lift) <= F32_TOL(lift), `frame ${i}: follower at ${got.follower[1]}, lift ${lift}`);
      assert.ok(Math.abs(got.cam[0] - Math.cos(t)) < 1e-6 && Math.abs(got.cam[1] - Math.sin(t)) < 1e-6, `frame ${i}: cam rotation`);
      assert.ok(Math.abs(got.contact[0] - e * Math.sin(t)) <= F32_TOL(R) && Math.abs(got.contact[1] - (R - e * Math.cos(t))) <= F32_TOL(R));
      // the spring's follower end rides with the face, its ground end stays
      assert.ok(Math.abs(got.spring[0] - (R - e + 10 + lift)) <= F32_TOL(R + 10), `frame ${i}: spring end ${got.spring[0]}`);
      assert.ok(Math.abs(got.spring[1] - (R - e + 40)) <= F32_TOL(R + 40));
    }
  }
  await page().evaluate(() => window.camoptReport.animation.setCamDeg(359.7));
  assert.equal(await page().getAttribute('#camopt-mechanism', 'data-frame'), '0');   // nearest modulo 360
});

test('resize: plots follow their box when the window narrows; printing stacks them in one column', async () => {
  // [box width, drawn width] per plot: equal once drawn
  const widths = () => page().evaluate(() => [...document.querySelectorAll('.camopt-plot')].map(e =>
    [Math.floor(e.clientWidth), e.querySelector('canvas').clientWidth]));
  const wide = await widths();
  wide.forEach(([box, drawn], i) => assert.equal(drawn, box, `plot ${i} at 1200 px`));
  await page().setViewportSize({ width: 700, height: 900 });
  await page().waitForFunction(() => [...document.querySelectorAll('.camopt-plot')].every(e =>
    e.querySelector('canvas').clientWidth === Math.floor(e.clientWidth)));
  const narrow = await widths();
  narrow.forEach(([box], i) => assert.ok(box < 700 && box !== wide[i][0], `plot ${i}: box ${wide[i][0]} px -> ${box} px`));
  await page().setViewportSize({ width: 1200, height: 900 });
  await page().emulateMedia({ media: 'print' });
  const print = await page().evaluate(() => [getComputedStyle(document.querySelector('.camopt-grid')).display,
    getComputedStyle(document.getElementById('camopt-nav')).display]);
  await page().emulateMedia({ media: 'screen' });
  assert.deepEqual(print, ['block', 'none']);
});

test('offline: a page that fetches is reported', async () => {
  const bad = path.join(dir, 'fetching.html');
  writeFileSync(bad, readFileSync(file, 'utf8').replace('<script type="application/json"', '<img src="http://127.0.0.1:9/x.png"><script type="application/json"'));
  const r = await openReport(browser, bad);
  await r.close();
  assert.ok(r.problems.length > 0, 'no problem reported for a page that loads an image over the network');
});
