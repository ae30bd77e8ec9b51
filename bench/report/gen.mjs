// Writes pages/<lib>.html: one self-contained page per library (library, adapter and harness
// inlined, no network), and pages/libraries.json with each library's version and inlined size.
import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { gzipSync } from 'node:zlib';

const here = new URL('.', import.meta.url).pathname;
const npm = p => here + 'node_modules/' + p;
const deb = p => '/usr/share/javascript/' + p;
const pkgVersion = p => JSON.parse(readFileSync(npm(p + '/package.json'))).version;
const debVersion = p => readFileSync('/var/lib/dpkg/status', 'utf8').split('\n\n')
  .find(s => s.startsWith(`Package: ${p}\n`)).match(/^Version: (.*)$/m)[1];

// name -> where from, version, the files inlined (scripts, then styles)
export const libraries = {
  none: { from: '-', version: '-', js: [], css: [] },
  uplot: { from: 'npm uplot', version: pkgVersion('uplot'), js: [npm('uplot/dist/uPlot.iife.min.js')], css: [npm('uplot/dist/uPlot.min.css')] },
  dygraphs: { from: 'Debian libjs-dygraphs', version: debVersion('libjs-dygraphs'),
    js: [deb('dygraphs/dygraph.min.js'), deb('dygraphs/extras/synchronizer.js')], css: [deb('dygraphs/dygraph.min.css')] },
  chartjs: { from: 'Debian libjs-chart.js', version: debVersion('libjs-chart.js'), js: [deb('chart.js/chart.min.js')], css: [] },
  d3: { from: 'Debian libjs-d3', version: debVersion('libjs-d3'), js: [deb('d3/d3.min.js')], css: [] },
  plotly: { from: 'npm plotly.js-cartesian-dist-min', version: pkgVersion('plotly.js-cartesian-dist-min'),
    js: [npm('plotly.js-cartesian-dist-min/plotly-cartesian.min.js')], css: [] },
  // Debian's libjs-vega ships 31 separate UMD modules and no browser bundle; this is upstream's
  // bundle of the same version, from npm.
  vega: { from: 'npm vega (Debian: 5.22.1, no bundle)', version: pkgVersion('vega'), js: [npm('vega/build/vega.min.js')], css: [] },
};

// Installed before any library, so the harness can time the libraries' animation-frame callbacks.
const rafWrap = `window.__raf = window.requestAnimationFrame.bind(window); window.__rafWork = 0;
window.requestAnimationFrame = cb => window.__raf(ts => { const s = performance.now(); try { cb(ts); } finally { window.__rafWork += performance.now() - s; } });`;
const script = s => `<script>${s.replace(/<\/script/gi, '<\\/script')}</script>\n`;

mkdirSync(here + 'pages', { recursive: true });
const info = {};
for (const [name, lib] of Object.entries(libraries)) {
  const code = lib.js.map(f => readFileSync(f, 'utf8')).join('\n');
  const css = lib.css.map(f => readFileSync(f, 'utf8')).join('\n');
  const bytes = Buffer.byteLength(code) + Buffer.byteLength(css);
  info[name] = { from: lib.from, version: lib.version, bytes, gzip: gzipSync(code + css, { level: 9 }).length };
  const html = `<!doctype html><html><head><meta charset="utf-8"><title>${name}</title><style>${css}
body { margin: 8px; font: 12px sans-serif; } .p { width: 1000px; min-height: 200px; }</style>\n${script(rafWrap)}${script(code)}</head><body>
<div id="p0" class="p"></div><div id="p1" class="p"></div><div id="p2" class="p"></div><div id="p3" class="p"></div><div id="fam" class="p"></div>
${script(readFileSync(here + `libs/${name}.js`, 'utf8'))}${script(readFileSync(here + 'harness.js', 'utf8'))}</body></html>\n`;
  writeFileSync(here + `pages/${name}.html`, html);
}
writeFileSync(here + 'pages/libraries.json', JSON.stringify(info, null, 1));
console.table(info);
