// First render time and memory of a CVVL-sized report page (fixture.mjs --cvvl: 30 line plots
// of 17 series x 721 points, 17 animation positions x 721 frames) in headless Chromium:
//   node tests/report/browser/measure.mjs [--runs 3]
// Prints, per run, the page size, the script time to the drawn page and to its first paint
// (performance.now() inside the page), the load to ready time seen from outside, and the JS
// heap and DOM node count after a forced garbage collection (DevTools protocol).
import { mkdtempSync, writeFileSync, rmSync } from 'node:fs';
import { parseArgs } from 'node:util';
import os from 'node:os';
import path from 'node:path';
import { buildPage, cvvlSizedReport } from './fixture.mjs';
import { launchChromium, openReport } from './check_report.mjs';

const { values: opt } = parseArgs({ options: { runs: { type: 'string', default: '3' } } });
const dir = mkdtempSync(path.join(os.tmpdir(), 'camopt-measure-'));
const file = path.join(dir, 'report.html');
const html = buildPage(cvvlSizedReport());
writeFileSync(file, html);
const rows = [];
try {
  for (let r = 0; r < +opt.runs; r++) {
    const browser = await launchChromium();
    try {
      const t0 = performance.now();
      const { page, problems } = await openReport(browser, file, { width: 1400, height: 900 });
      const load = performance.now() - t0;
      const timing = await page.evaluate(() => window.camoptReport.timing);
      const nav = await page.evaluate(() => performance.getEntriesByType('navigation')[0].toJSON());
      const cdp = await page.context().newCDPSession(page);
      await cdp.send('HeapProfiler.collectGarbage');
      await cdp.send('Performance.enable');
      const m = Object.fromEntries((await cdp.send('Performance.getMetrics')).metrics.map(x => [x.name, x.value]));
      rows.push({ parsed: nav.responseEnd, loaded: nav.loadEventEnd, drawn: timing.drawn_ms, paint: timing.first_paint_ms, load, heap: m.JSHeapUsedSize / 2 ** 20,
        total: m.JSHeapTotalSize / 2 ** 20, nodes: m.Nodes, problems: problems.length });
      console.log(`run ${r + 1}: file read ${nav.responseEnd.toFixed(0)} ms, load event ${nav.loadEventEnd.toFixed(0)} ms after navigation; ` +
        `report.js: drawn ${timing.drawn_ms.toFixed(0)} ms, first paint ${timing.first_paint_ms.toFixed(0)} ms after its start; ` +
        `goto to ready ${load.toFixed(0)} ms, JS heap ${rows.at(-1).heap.toFixed(1)} MB used / ${rows.at(-1).total.toFixed(1)} MB, ` +
        `${m.Nodes} DOM nodes, ${problems.length} console/network problems`);
    } finally {
      await browser.close();
    }
  }
} finally {
  rmSync(dir, { recursive: true, force: true });
}
const med = k => { const v = rows.map(x => x[k]).sort((a, b) => a - b); return v[v.length >> 1]; };
console.log(`page ${(html.length / 2 ** 20).toFixed(2)} MB; Chromium headless, ${os.cpus().length} x ${os.cpus()[0].model}, ` +
  `load average ${os.loadavg().map(x => x.toFixed(1)).join(' ')}; median of ${rows.length}: drawn ${med('drawn').toFixed(0)} ms, ` +
  `first paint ${med('paint').toFixed(0)} ms, load event ${med('loaded').toFixed(0)} ms, heap ${med('heap').toFixed(1)} MB`);
