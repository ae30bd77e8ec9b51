// Runs pages/<lib>.html (from gen.mjs) in headless Chromium, RUNS times, the libraries interleaved
// (run r visits them in an order rotated by r), each measurement in a fresh browser; prints the
// median and range of every figure and writes the raw runs to a CSV.
// Usage: node run.mjs [--runs 7] [--libs uplot,plotly] [--csv FILE] [--shots DIR]
import { chromium } from 'playwright-core';
import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { parseArgs } from 'node:util';
import os from 'node:os';

const here = new URL('.', import.meta.url).pathname;
const { values: opt } = parseArgs({ options: {
  runs: { type: 'string', default: '7' }, libs: { type: 'string' }, csv: { type: 'string' },
  shots: { type: 'string' }, chromium: { type: 'string', default: '/usr/bin/chromium' } } });
const info = JSON.parse(readFileSync(here + 'pages/libraries.json'));
const libs = opt.libs ? opt.libs.split(',') : Object.keys(info);
const runs = +opt.runs;

async function measure(lib) {
  const browser = await chromium.launch({ executablePath: opt.chromium, args: ['--headless=new'] });
  try {
    const page = await browser.newPage({ viewport: { width: 1100, height: 1300 }, deviceScaleFactor: 1 });
    await page.goto('file://' + here + `pages/${lib}.html`);
    await page.waitForFunction(() => window.benchResult || window.benchError, null, { timeout: 300000, polling: 100 });
    const err = await page.evaluate(() => window.benchError);
    if (err) throw new Error(`${lib}: ${err}`);
    const r = await page.evaluate(() => window.benchResult);
    const cdp = await page.context().newCDPSession(page);
    await cdp.send('HeapProfiler.collectGarbage');
    await cdp.send('Performance.enable');
    const m = Object.fromEntries((await cdp.send('Performance.getMetrics')).metrics.map(x => [x.name, x.value]));
    r.heapMB = m.JSHeapUsedSize / 2 ** 20;
    r.nodes = m.Nodes;
    if (opt.shots) { mkdirSync(opt.shots, { recursive: true }); await page.screenshot({ path: `${opt.shots}/${lib}.png`, fullPage: true }); }
    return r;
  } finally { await browser.close(); }
}

const cols = ['load', 'firstRender', 'hoverScript', 'hoverLatency', 'family', 'heapMB', 'nodes'];
const rows = [];
for (let r = 0; r < runs; r++) {
  for (let i = 0; i < libs.length; i++) {
    const lib = libs[(i + r) % libs.length];
    const res = await measure(lib);
    rows.push({ run: r + 1, lib, ...res });
    console.error(`run ${r + 1} ${lib}: ` + cols.map(c => `${c} ${res[c].toFixed(1)}`).join(', '));
  }
}

const fmt = (a, d) => { const s = [...a].sort((p, q) => p - q), f = x => x.toFixed(d);
  return `${f(s[s.length >> 1])} (${f(s[0])}–${f(s[s.length - 1])})`; };
const digits = { load: 0, firstRender: 0, hoverScript: 1, hoverLatency: 1, family: 0, heapMB: 1, nodes: 0 };
console.log(`${runs} runs per library, interleaved; median (min–max); ms unless stated; ` +
  `${await (async () => { const b = await chromium.launch({ executablePath: opt.chromium }); const v = b.version(); await b.close(); return 'Chromium ' + v; })()}, ` +
  `${os.cpus().length} × ${os.cpus()[0].model}, load average ${os.loadavg().map(x => x.toFixed(1)).join(' ')}\n`);
console.log('| library | version | from | min. KB | gzip KB | page load | SVAJ 4×100k first render | hover: script | hover: to next frame | family 17×721 | JS heap MB | DOM nodes |');
console.log('|---|---|---|---|---|---|---|---|---|---|---|---|');
for (const lib of libs) {
  const mine = rows.filter(x => x.lib === lib), l = info[lib];
  console.log(`| ${lib} | ${l.version} | ${l.from} | ${(l.bytes / 1024).toFixed(0)} | ${(l.gzip / 1024).toFixed(0)} | ` +
    cols.map(c => fmt(mine.map(x => x[c]), digits[c])).join(' | ') + ' |');
}
if (opt.csv) writeFileSync(opt.csv, ['run,lib,' + cols.join(','), ...rows.map(x => [x.run, x.lib, ...cols.map(c => x[c].toFixed(3))].join(','))].join('\n') + '\n');
