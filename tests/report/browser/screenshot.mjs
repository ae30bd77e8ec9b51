// A screenshot of the top of a report as a reader first sees it (not the full page), offline:
//   node tests/report/browser/screenshot.mjs REPORT.html OUT.png [--width 1200] [--height 900]
// The README's picture (docs/images/report-cvvl-kinematics.png) is made with it from the CVVL
// kinematics report at 17 control positions (docs/testing.md).
import { parseArgs } from 'node:util';
import { launchChromium, openReport } from './check_report.mjs';

const { values: opt, positionals } = parseArgs({ allowPositionals: true, options: {
  width: { type: 'string', default: '1200' }, height: { type: 'string', default: '900' } } });
if (positionals.length !== 2) {
  console.error('usage: screenshot.mjs REPORT.html OUT.png [--width 1200] [--height 900]');
  process.exit(2);
}
const [file, out] = positionals;
const browser = await launchChromium();
try {
  const { page, problems, close } = await openReport(browser, file, { width: +opt.width, height: +opt.height });
  await page.screenshot({ path: out, fullPage: false });
  await close();
  if (problems.length) throw new Error(problems.join('; '));
} finally {
  await browser.close();
}
console.log(`screenshot: ${out}`);
