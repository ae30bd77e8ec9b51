// Checks a report.html in headless Chromium with the network off:
//   node tests/report/browser/check_report.mjs REPORT.html [--csv FILE --lift-column lift_mm]
//        [--position K] [--expect EXPECT.json] [--screenshot OUT.png]
// - no console error or warning, no page error, no request other than file: (every other one
//   is aborted and counted as a failure);
// - every plot of the embedded data present with its series and point counts and its axis
//   titles "label [unit]" (units non-empty); every table present, its failed rows marked;
// - the animation (when the data has a scene): play advances data-frame within 1 s, pause stops
//   it; with --csv, setCamDeg(a) at several of the CSV's angles moves the output body's
//   <g data-body> by the CSV's lift at a, and data-lift-mm is that lift (control position K of
//   the scene, default 0; the CSV's rows of that control value);
// - --expect: {"plots": [{"id", "series"}], "tables": ["id"]} that must be present.
// Exit 0 when every check holds, 1 with one line per failure, 2 on a usage error.
import { existsSync, readFileSync } from 'node:fs';
import { parseArgs } from 'node:util';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { decodeNum } from './fixture.mjs';

const SETUP_HINT = 'run scripts/setup.sh --test (it installs chromium and the npm packages)';

// playwright-core's chromium, or an error saying how to install what is missing
export async function launchChromium() {
  const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!existsSync(executablePath)) throw new Error(`no Chromium at ${executablePath}: ${SETUP_HINT}`);
  let chromium;
  try {
    ({ chromium } = await import('playwright-core'));
  } catch (err) {
    throw new Error(`playwright-core is not installed (${err.code}): ${SETUP_HINT}`);
  }
  return chromium.launch({ executablePath, args: ['--headless=new'] });
}

// opens a report file offline; `problems` collects console errors and warnings, page errors
// and every request that is not for a file: or data: URL
export async function openReport(browser, file, viewport = { width: 1200, height: 900 }) {
  const context = await browser.newContext({ offline: true, viewport, deviceScaleFactor: 1 });
  const problems = [];
  await context.route('**/*', route => {
    const url = route.request().url();
    if (url.startsWith('file:') || url.startsWith('data:')) return route.continue();
    problems.push(`network request to ${url}`);
    return route.abort();
  });
  const page = await context.newPage();
  page.on('console', msg => {
    if (msg.type() === 'error' || msg.type() === 'warning') problems.push(`console ${msg.type()}: ${msg.text()}`);
  });
  page.on('pageerror', err => problems.push(`page error: ${err.message}`));
  page.on('requestfailed', req => {
    if (!req.url().startsWith('file:')) problems.push(`request failed: ${req.url()}`);
  });
  await page.goto(pathToFileURL(path.resolve(file)).href);
  await page.evaluate(() => window.camoptReport.ready.then(() => true));   // not the api object: it holds the data
  return { page, problems, close: () => context.close() };
}

// the data embedded in a report, as the page reads it (NUM fields decoded to arrays)
export function readReportData(html) {
  const m = html.match(/<script type="application\/json" id="camopt-data">([\s\S]*?)<\/script>/);
  if (!m) throw new Error('no <script id="camopt-data"> in the report');
  const d = JSON.parse(m[1]);
  const num = decodeNum;
  for (const p of d.plots) {
    for (const k of ['x_values', 'y_values', 'z']) p[k] = num(p[k]);
    for (const s of p.series) for (const k of ['x', 'y', 'color']) s[k] = num(s[k]);
  }
  if (d.scene) {
    for (const pos of d.scene.positions) {
      for (const k of ['cam_deg', 'lift_mm']) pos[k] = num(pos[k]);
      pos.pose = pos.pose.map(num);
    }
  }
  return d;
}

// the points a plot draws, as data-points counts them: every series' values, a heat map's cells
export function expectedPoints(p) {
  return p.kind === 'heatmap' ? p.z.length : p.series.reduce((n, s) => n + s.y.length, 0);
}

// plots and tables against the data: returns failure messages
export async function checkPlotsAndTables(page, data) {
  const failures = [];
  const dom = await page.evaluate(() => ({
    plots: [...document.querySelectorAll('.camopt-plot')].map(e => ({ ...e.dataset,
      drawn: [...e.querySelectorAll('canvas')].some(c => c.width > 0 && c.height > 0),
      uplot: window.camoptReport.plots[e.dataset.plotId] ? window.camoptReport.plots[e.dataset.plotId].series.length - 1 : null })),
    tables: [...document.querySelectorAll('table[data-table-id]')].map(t => ({ id: t.dataset.tableId,
      rows: t.tBodies[0].rows.length, failed: [...t.tBodies[0].rows].flatMap((r, i) => (r.classList.contains('failed') ? [i] : [])) })),
  }));
  for (const p of data.plots) {
    const e = dom.plots.find(x => x.plotId === p.id);
    if (!e) { failures.push(`plot ${p.id}: not on the page`); continue; }
    const want = { series: String(p.series.length), points: String(expectedPoints(p)), kind: p.kind,
      xLabel: `${p.x.label} [${p.x.unit}]`, yLabel: `${p.y.label} [${p.y.unit}]` };
    for (const [k, v] of Object.entries(want)) if (e[k] !== v) failures.push(`plot ${p.id}: data-${k} '${e[k]}', expected '${v}'`);
    for (const axis of ['x', 'y']) if (!p[axis].unit) failures.push(`plot ${p.id}: the ${axis} axis has no unit`);
    if (!e.drawn) failures.push(`plot ${p.id}: nothing drawn (no canvas with a size)`);
    if (p.kind === 'line' && e.uplot !== p.series.length) failures.push(`plot ${p.id}: uPlot has ${e.uplot} series, expected ${p.series.length}`);
  }
  for (const t of data.tables) {
    const e = dom.tables.find(x => x.id === t.id);
    if (!e) { failures.push(`table ${t.id}: not on the page`); continue; }
    if (e.rows !== t.rows.length) failures.push(`table ${t.id}: ${e.rows} rows, expected ${t.rows.length}`);
    if (e.failed.join() !== [...t.failed_rows].sort((a, b) => a - b).join()) {
      failures.push(`table ${t.id}: rows marked failed [${e.failed}], expected [${t.failed_rows}]`);
    }
  }
  return failures;
}

// play advances data-frame within 1 s; pause stops it
export async function checkPlayPause(page) {
  const failures = [];
  const frame = () => page.evaluate(() => document.getElementById('camopt-mechanism').dataset.frame);
  await page.evaluate(() => window.camoptReport.animation.setFrame(0));
  await page.click('#camopt-play');
  try {
    await page.waitForFunction(() => document.getElementById('camopt-mechanism').dataset.frame !== '0', null, { timeout: 1000 });
  } catch {
    failures.push('animation: data-frame did not advance within 1 s of pressing play');
  }
  await page.click('#camopt-play');
  const paused = await frame();
  await page.waitForTimeout(300);
  if ((await frame()) !== paused) failures.push('animation: data-frame still advances after pause');
  if (await page.evaluate(() => window.camoptReport.animation.playing)) failures.push('animation: playing after pause');
  return failures;
}

// lift per cam angle of one control position from a camopt CSV (control_deg or control_mm,
// cam_deg, the lift column); all rows when the CSV has no control column
export function csvLift(text, liftColumn, control) {
  const [head, ...rows] = text.trim().split('\n').map(l => l.split(','));
  const col = name => head.indexOf(name);
  const cam = col('cam_deg'), lift = col(liftColumn), ctl = head.findIndex(h => h.startsWith('control_'));
  if (cam < 0 || lift < 0) throw new Error(`CSV: needs columns cam_deg and ${liftColumn}, has ${head.join(',')}`);
  const out = new Map();
  for (const r of rows) {
    if (ctl >= 0 && Math.abs(+r[ctl] - control) > 1e-9 * Math.max(1, Math.abs(control))) continue;
    out.set(+r[cam], +r[lift]);
  }
  return out;
}

// setCamDeg(a) at `count` of the CSV's angles (the largest lift among them): the output body's
// drawn displacement |(tx, ty)| and data-lift-mm against the CSV's lift at a
export async function checkLift(page, scene, liftByAngle, position = 0, count = 9) {
  const failures = [];
  // the CSV's angles that are frames of the animation (its frames may be every k-th row)
  const frames = Array.from(scene.positions[position].cam_deg);
  const isFrame = a => frames.some(f => Math.abs(f - a) <= 4 * 2 ** -24 * Math.max(Math.abs(a), 1));
  const angles = [...liftByAngle.keys()].filter(isFrame);
  if (!angles.length) return [`CSV: no rows at the animation's frames for control position ${position} (${scene.positions[position].control})`];
  const peak = angles.reduce((a, b) => (Math.abs(liftByAngle.get(b)) > Math.abs(liftByAngle.get(a)) ? b : a));
  const picks = [...new Set([peak, ...Array.from({ length: count - 1 }, (_, i) => angles[Math.floor(i * (angles.length - 1) / (count - 2))])])];
  await page.evaluate(k => window.camoptReport.animation.setPosition(k), position);
  for (const a of picks) {
    const got = await page.evaluate(([deg, body]) => {
      window.camoptReport.animation.setCamDeg(deg);
      const svg = document.getElementById('camopt-mechanism');
      const g = svg.querySelector(`g[data-body="${body}"]`);
      const m = g.transform.baseVal.consolidate().matrix;   // translate(tx ty) rotate(): e = tx, f = ty
      return { tx: m.e, ty: m.f, cam: +svg.dataset.camDeg, lift: +svg.dataset.liftMm, position: svg.dataset.position };
    }, [a, scene.output_body]);
    const want = liftByAngle.get(a);
    // the page draws float32 values: each of tx, ty and lift_mm is within 2^-24 relative of the
    // run's double; 4 * 2^-24 * max(|tx|, |ty|, 1 mm) bounds that with room for hypot's rounding
    const tol = 4 * 2 ** -24 * Math.max(Math.abs(got.tx), Math.abs(got.ty), Math.abs(want), 1);
    const shown = Math.hypot(got.tx, got.ty);
    if (got.position !== String(position)) failures.push(`animation: data-position ${got.position}, expected ${position}`);
    // the page shows angles modulo one revolution (360 deg is drawn as 0 deg)
    const turn = x => ((x % 360) + 360) % 360;
    const off = Math.abs(turn(got.cam) - turn(a));
    if (Math.min(off, 360 - off) > 4 * 2 ** -24 * Math.max(Math.abs(a), 1)) failures.push(`animation: setCamDeg(${a}) shows cam ${got.cam} deg`);
    if (Math.abs(shown - Math.abs(want)) > tol) failures.push(`animation at ${a} deg: ${scene.output_body} drawn ${shown} mm from rest, CSV lift ${want} mm (tolerance ${tol.toExponential(2)})`);
    if (Math.abs(got.lift - want) > tol) failures.push(`animation at ${a} deg: data-lift-mm ${got.lift}, CSV lift ${want} mm`);
  }
  return failures;
}

// plots (with series counts) and tables an expectations file requires
export function checkExpectations(data, expect) {
  const failures = [];
  for (const { id, series } of expect.plots || []) {
    const p = data.plots.find(x => x.id === id);
    if (!p) failures.push(`expected plot ${id}: not in the report`);
    else if (series !== undefined && p.series.length !== series) failures.push(`expected plot ${id}: ${p.series.length} series, expected ${series}`);
  }
  for (const id of expect.tables || []) if (!data.tables.some(t => t.id === id)) failures.push(`expected table ${id}: not in the report`);
  return failures;
}

async function main() {
  const { values: opt, positionals } = parseArgs({ allowPositionals: true, options: {
    csv: { type: 'string' }, 'lift-column': { type: 'string', default: 'lift_mm' }, position: { type: 'string', default: '0' },
    expect: { type: 'string' }, screenshot: { type: 'string' } } });
  if (positionals.length !== 1) {
    console.error('usage: check_report.mjs REPORT.html [--csv FILE --lift-column lift_mm] [--position K] [--expect EXPECT.json] [--screenshot OUT.png]');
    process.exit(2);
  }
  const file = positionals[0], position = +opt.position;
  const data = readReportData(readFileSync(file, 'utf8'));
  const failures = opt.expect ? checkExpectations(data, JSON.parse(readFileSync(opt.expect, 'utf8'))) : [];
  const browser = await launchChromium();
  try {
    const { page, problems } = await openReport(browser, file);
    failures.push(...await checkPlotsAndTables(page, data));
    if (data.scene) {
      failures.push(...await checkPlayPause(page));
      if (opt.csv) {
        const control = data.scene.positions[position].control;
        failures.push(...await checkLift(page, data.scene, csvLift(readFileSync(opt.csv, 'utf8'), opt['lift-column'], control), position));
      }
    } else if (opt.csv) {
      failures.push('--csv given but the report has no mechanism animation (scene is null)');
    }
    if (opt.screenshot) await page.screenshot({ path: opt.screenshot, fullPage: true });
    failures.push(...problems);
  } finally {
    await browser.close();
  }
  for (const f of failures) console.error(`check_report: ${file}: ${f}`);
  console.log(`check_report: ${file}: ${failures.length ? failures.length + ' failure(s)' : 'ok'} ` +
    `(${data.plots.length} plots, ${data.tables.length} tables, ${data.scene ? 'animation' : 'no animation'})`);
  process.exit(failures.length ? 1 : 0);
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  main().catch(err => { console.error(`check_report: ${err.message}`); process.exit(1); });
}
