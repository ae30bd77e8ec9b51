// Report pages built from synthetic data, exactly as the data format says (docs/report.md):
// the template with its six placeholders replaced, uPlot and the page's script and style
// inlined, the data as JSON with numeric arrays as base64 little-endian float32 and every "</"
// written "<\/". The data are closed forms, so the tests know every drawn value.
//   node tests/report/browser/fixture.mjs OUT.html [--cvvl]   writes a page to look at by hand
//   (--cvvl: CVVL-sized, 17 positions x 721 points x 30 quantities, for measuring)
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

export const repoRoot = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../..');

// base64 of the values as little-endian float32 (a NUM field)
export function encodeNum(values) {
  const buf = Buffer.alloc(4 * values.length);
  values.forEach((v, i) => buf.writeFloatLE(v, 4 * i));
  return buf.toString('base64');
}

// the values a NUM field holds, as the page decodes them
export function decodeNum(text) {
  const buf = Buffer.from(text, 'base64');
  return Array.from({ length: buf.length / 4 }, (_, i) => buf.readFloatLE(4 * i));
}

// Math.fround applied to a value: what the page sees of a double
export const f32 = Math.fround;

const escapeHtml = s => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;').replace(/"/g, '&quot;');

// report.html from a data object whose NUM fields are already base64 strings
export function buildPage(data) {
  if (!existsSync(path.join(repoRoot, 'node_modules/uplot/dist'))) {
    throw new Error('node_modules/uplot is missing: run scripts/setup.sh --test (it installs the npm packages)');
  }
  const read = rel => readFileSync(path.join(repoRoot, rel), 'utf8');
  const parts = {
    title: escapeHtml(data.title),
    'uplot.css': read('node_modules/uplot/dist/uPlot.min.css'),
    'report.css': read('src/report/web/report.css'),
    'uplot.js': read('node_modules/uplot/dist/uPlot.iife.min.js'),
    'report.js': read('src/report/web/report.js'),
    data: JSON.stringify(data).replace(/<\//g, '<\\/'),
  };
  let html = read('src/report/web/template.html');
  for (const [name, text] of Object.entries(parts)) {
    const key = `{{camopt:${name}}}`;
    if (html.split(key).length !== 2) throw new Error(`template: ${key} must occur exactly once`);
    html = html.replace(key, () => text);   // a function: "$&" in the inlined code stays as it is
  }
  return html;
}

const range = (n, f) => Array.from({ length: n }, (_, i) => f(i));

// cycloidal rise of height h over beta degrees at theta [deg]: lift, velocity, acceleration,
// jerk per degree (Norton, Cam Design and Manufacturing Handbook, ch. 3)
export function cycloidal(h, beta, theta) {
  const w = 2 * Math.PI / beta, x = theta / beta;
  return [h * (x - Math.sin(w * theta) / (2 * Math.PI)), h / beta * (1 - Math.cos(w * theta)),
    2 * Math.PI * h / beta ** 2 * Math.sin(w * theta), 4 * Math.PI ** 2 * h / beta ** 3 * Math.cos(w * theta)];
}

export const FAMILY = 17;            // control positions of the synthetic family
export const BETA = 120;             // rise duration [deg]
export const riseHeight = k => 2 + 0.5 * k;   // member k's maximum lift [mm]
export const ANGLES = range(241, i => 0.5 * i);   // cam angles of the SVAJ plots [deg]
export const ECCENTRICITY = 5;      // the animation's disc [mm]
export const DISC_RADIUS = 20;       // [mm]
export const PHASES = [0, 40];       // the animation's two positions: cam phase [deg]
export const discLift = t => ECCENTRICITY * (1 - Math.cos(t));   // at cam rotation t [rad]

const SVAJ = [['lift', 'valve lift', 'mm'], ['velocity', 'valve velocity', 'mm/deg'],
  ['acceleration', 'valve acceleration', 'mm/deg^2'], ['jerk', 'valve jerk', 'mm/deg^3']];

// SVAJ plots of the family (one series per member) plus a dashed target on the lift
function svajPlots() {
  return SVAJ.map(([id, label, unit], q) => ({
    id: 'svaj-' + id, title: label, section: 'svaj', kind: 'line',
    x: { label: 'cam angle', unit: 'deg' }, y: { label, unit }, color: { label: '', unit: '' },
    link_group: 'cam', x_values: encodeNum(ANGLES), y_values: '', z: '',
    series: [
      ...range(FAMILY, k => ({ name: `control ${k} deg`, x: '', y: encodeNum(ANGLES.map(t => cycloidal(riseHeight(k), BETA, t)[q])),
        color: '', family_member: k, dashed: false })),
      ...(q === 0 ? [{ name: 'target', x: '', y: encodeNum(ANGLES.map(t => cycloidal(9, BETA, t)[0])), color: '',
        family_member: -1, dashed: true }] : []),
    ],
    bands: q === 2 ? [{ from: 30, to: 40, label: 'acceleration limit active' }] : [],
    limits: q === 2 ? [{ y: 0.004, label: 'acceleration limit' }] : [],
    main: q === 0,
  }));
}

// a plot in another link group, one series on its own coarser x (joined by the page)
function contactPlot() {
  const coarse = range(61, i => 2 * i);
  return {
    id: 'contact-pressure-angle', title: 'Pressure angle', section: 'contacts', kind: 'line',
    x: { label: 'cam angle', unit: 'deg' }, y: { label: 'pressure angle', unit: 'deg' }, color: { label: '', unit: '' },
    link_group: 'contacts', x_values: encodeNum(ANGLES), y_values: '', z: '',
    series: [
      ...range(FAMILY, k => ({ name: `control ${k} deg`, x: '', y: encodeNum(ANGLES.map(t => 10 * cycloidal(riseHeight(k), BETA, t)[1])),
        color: '', family_member: k, dashed: false })),
      { name: 'coarse', x: encodeNum(coarse), y: encodeNum(coarse.map(t => 3 * Math.sin(t / 20))), color: '', family_member: -1, dashed: false },
    ],
    bands: [], limits: [{ y: 30, label: 'pressure angle limit' }], main: false,
  };
}

// an ellipse x = a cos p, y = b sin p coloured by its radius of curvature
// (a b)^-1 (a^2 sin^2 p + b^2 cos^2 p)^(3/2), and a dashed circle of radius 0.8 b inside it
export const ELLIPSE = { a: 30, b: 20, n: 360 };
export const ellipseRadius = p => (ELLIPSE.a ** 2 * Math.sin(p) ** 2 + ELLIPSE.b ** 2 * Math.cos(p) ** 2) ** 1.5 / (ELLIPSE.a * ELLIPSE.b);
function profilePlot() {
  const { a, b, n } = ELLIPSE, phi = range(n + 1, i => 2 * Math.PI * i / n);
  return {
    id: 'profile', title: 'Cam profile', section: 'profile', kind: 'profile',
    x: { label: 'x', unit: 'mm' }, y: { label: 'y', unit: 'mm' }, color: { label: 'radius of curvature', unit: 'mm' },
    link_group: '', x_values: '', y_values: '', z: '',
    series: [
      { name: 'cam', x: encodeNum(phi.map(p => a * Math.cos(p))), y: encodeNum(phi.map(p => b * Math.sin(p))),
        color: encodeNum(phi.map(ellipseRadius)), family_member: -1, dashed: false },
      { name: 'base circle', x: encodeNum(phi.map(p => 0.8 * b * Math.cos(p))), y: encodeNum(phi.map(p => 0.8 * b * Math.sin(p))),
        color: '', family_member: -1, dashed: true },
    ],
    bands: [], limits: [], main: true,
  };
}

// separation speed over rpm (7 columns) x control (5 rows), one hole (NaN)
export const HEAT = { rpm: range(7, i => 1000 + 1000 * i), control: range(5, i => 4 * i),
  z: (r, c) => (r === 2 && c === 3 ? NaN : (1000 + 1000 * c) * (1 + r / 8)) };
function heatmapPlot() {
  return {
    id: 'speed-map', title: 'Separation speed', section: 'speed-map', kind: 'heatmap',
    x: { label: 'engine speed', unit: 'rpm' }, y: { label: 'control', unit: 'deg' },
    color: { label: 'separation speed', unit: 'rpm' }, link_group: '',
    x_values: encodeNum(HEAT.rpm), y_values: encodeNum(HEAT.control),
    z: encodeNum(HEAT.control.flatMap((_, r) => HEAT.rpm.map((__, c) => HEAT.z(r, c)))),
    series: [], bands: [], limits: [], main: true,
  };
}

// an eccentric disc (radius R, centre e below the cam axis in the drawing) under a flat-faced
// follower, turned by a cam phaser: at position k the cam is at theta - phase_k, so the follower
// lifts by e (1 - cos(theta - phase_k)) and the contact is the disc's top point
export function discScene(angles) {
  const R = DISC_RADIUS, e = ECCENTRICITY, face = R - e;
  const circle = range(73, i => [R * Math.cos(i * Math.PI / 36), R * Math.sin(i * Math.PI / 36)]);
  return {
    bodies: ['ground', 'cam', 'follower'], contacts: ['cam_follower'],
    shapes: [
      { kind: 'circle', body: 0, body_b: 0, xy: encodeNum([0, 0]), radius: 2, role: 'pivot' },
      { kind: 'polygon', body: 1, body_b: 1, xy: encodeNum(circle.flatMap(([x, y]) => [x, y - e])), radius: 0, role: 'profile' },
      { kind: 'polyline', body: 2, body_b: 2, xy: encodeNum([-30, face, 30, face, 0, face, 0, face + 40]), radius: 0, role: 'valve' },
      { kind: 'spring', body: 2, body_b: 0, xy: encodeNum([0, face + 10, 0, face + 40]), radius: 0, role: 'spring' },
      { kind: 'polyline', body: 0, body_b: 0, xy: encodeNum([-10, face + 40, 10, face + 40]), radius: 0, role: 'seat' },
    ],
    control_name: 'cam phase', control_unit: 'deg', output_body: 'follower',
    bbox: [-R - e, -R - e, R + e, face + 2 * e + 40],
    positions: PHASES.map(phase => {
      const th = angles.map(a => (a - phase) * Math.PI / 180), lift = th.map(t => discLift(t));
      return {
        control: phase, cam_deg: encodeNum(angles),
        pose: [encodeNum(th.flatMap(() => [0, 0, 0])), encodeNum(th.flatMap(t => [0, 0, t])),
          encodeNum(lift.flatMap(l => [0, l, 0]))],
        contact: [encodeNum(th.flatMap(t => [e * Math.sin(t), R - e * Math.cos(t), 0, 1]))],
        lift_mm: encodeNum(lift),
      };
    }),
  };
}

// the synthetic report: a 17-member SVAJ family, a contact plot, a profile, a heat map, a
// table with a failed row, the eccentric-disc animation
export function syntheticReport() {
  return {
    format: 'camopt-report', version: 1, generator: 'camopt 0.1.0 (test fixture)', command: 'kinematics',
    title: 'camopt kinematics: synthetic </script> & <family>', source_dir: 'out/synthetic',
    facts: [{ key: 'design', value: 'synthetic' }, { key: 'step [deg]', value: '0.5' }],
    notes: ['synthetic data: closed forms written in the test'],
    family: range(FAMILY, k => `control ${k} deg`),
    sections: [{ id: 'svaj', title: 'Valve lift, velocity, acceleration and jerk' }, { id: 'contacts', title: 'Contacts' },
      { id: 'profile', title: 'Cam profile' }, { id: 'speed-map', title: 'Separation speed' },
      { id: 'summary', title: 'Summary' }, { id: 'mechanism', title: 'Mechanism' }],
    plots: [...svajPlots(), contactPlot(), profilePlot(), heatmapPlot()],
    tables: [{ id: 'constraints', title: 'Constraints', section: 'summary', columns: ['constraint', 'margin [mm]', 'satisfied'],
      rows: [['lift', '0.5', 'yes'], ['acceleration', '-0.001', 'no'], ['jerk', '2', 'yes']], failed_rows: [1] }],
    scene: discScene(range(360, i => i)),
    passed: false,
  };
}

// a report the size of the 17-position CVVL kinematics with every output: 30 line plots of
// 17 series x 721 points, and 17 animation positions of 721 frames
export function cvvlSizedReport() {
  const angles = range(721, i => 0.5 * i);
  const plots = range(30, q => ({
    id: `quantity-${q}`, title: `quantity ${q}`, section: 'svaj', kind: 'line',
    x: { label: 'cam angle', unit: 'deg' }, y: { label: `quantity ${q}`, unit: 'mm' }, color: { label: '', unit: '' },
    link_group: 'cam', x_values: encodeNum(angles), y_values: '', z: '',
    series: range(FAMILY, k => ({ name: `control ${k} deg`, x: '',
      y: encodeNum(angles.map(t => (t < 240 ? cycloidal(riseHeight(k), 240, t)[q % 4] : 0))), color: '', family_member: k, dashed: false })),
    bands: [], limits: [], main: false,
  }));
  const scene = discScene(angles);
  const one = scene.positions[0];
  scene.positions = range(FAMILY, k => ({ ...one, control: k }));
  scene.control_name = 'control';
  scene.control_unit = 'deg';
  return { ...syntheticReport(), title: 'camopt kinematics: CVVL-sized synthetic', plots, tables: [], scene,
    sections: [{ id: 'svaj', title: 'SVAJ' }, { id: 'mechanism', title: 'Mechanism' }], passed: null };
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const out = process.argv[2];
  if (!out) {
    console.error('usage: node tests/report/browser/fixture.mjs OUT.html [--cvvl]');
    process.exit(2);
  }
  writeFileSync(out, buildPage(process.argv.includes('--cvvl') ? cvvlSizedReport() : syntheticReport()));
  console.log(out);
}
