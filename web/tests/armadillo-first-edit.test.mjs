// A new user's first edit of their own mesh, with real pointer and keyboard
// events, as the desktop editor's `desktop_armadillo_first_edit` ctest does it: open
// CGAL's armadillo through the file input, Y up, the Back view (its face), New
// region, paint the right hand inner and the body outer, the inner motion a
// translation, drag the curve's end up in one drag, Space.
// Then: the volume error at most 0.5 %, the hand moved up and rigidly, the body
// (s = 1) not at all; the folded triangles are printed. Printed, not asserted
// (timings flake on a busy machine): the seconds from the last pointer event to
// t = 1, the main thread's long tasks on the way, the idle page's CPU (docs/web.md).
// Last, back at t = 0, the end knot dragged over the chest lands on the surface
// under the pointer (depth snapping; off the mesh it kept its view plane).
// Needs scripts/get-cgal-meshes (scripts/test runs it).
import fs from 'node:fs';
import path from 'node:path';
import { openPage, outDir, check, cpuSeconds, recordFrames } from './harness.mjs';

const mesh = path.resolve('assets/cgal/armadillo.off');
if (!fs.existsSync(mesh)) throw new Error(`${mesh} is absent: run scripts/get-cgal-meshes`);

const out = outDir();
const { page, errors, close, userData } = await openPage('', { width: 1280, height: 720 });
const api = (fn, arg) => page.evaluate(fn, arg);
const state = () => api(() => window.vfsd.state());
const project = async (points) => (await api((p) => window.vfsd.project(p), points)).pixels;

async function stroke(points) {
  await page.mouse.move(points[0][0], points[0][1]);
  await page.mouse.down();
  for (const [x, y] of points.slice(1)) await page.mouse.move(x, y, { steps: 6 });
  await page.mouse.up();
}

const sub = (a, b) => a.map((x, k) => x - b[k]);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

// The distance from p to the nearest point of triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
function toTriangle(p, a, b, c) {
  const ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(ap);
  const bp = sub(p, b), d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(bp);
  const vc = d1 * d4 - d3 * d2;
  const along = (q, e, t) => norm(sub(p, q.map((x, k) => x + t * e[k])));
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
  const cp = sub(p, c), d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(cp);
  const vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
  const va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const denom = 1 / (va + vb + vc), v = vb * denom, w = vc * denom;
  return norm(sub(p, a.map((x, k) => x + v * ab[k] + w * ac[k])));
}

// The distance from p to the surface of an OFF mesh (text).
function distanceToSurface(p, off) {
  const words = off.split(/\s+/).filter((w) => w && w !== 'OFF').map(Number);
  const [nv, nf] = words;
  const vertex = (i) => words.slice(3 + 3 * i, 6 + 3 * i);
  let best = Infinity;
  for (let f = 0, at = 3 + 3 * nv; f < nf; f++, at += words[at] + 1)
    best = Math.min(best, toTriangle(p, vertex(words[at + 1]), vertex(words[at + 2]), vertex(words[at + 3])));
  return best;
}
const norm = (a) => Math.hypot(...a);
const at = (p, v) => [p[3 * v], p[3 * v + 1], p[3 * v + 2]];

try {
  // ---- open, orient, look at its face ----
  await page.setInputFiles('#open-mesh', mesh);
  await page.waitForFunction(() => /armadillo\.off$/.test(window.vfsd.state().mesh), null, { timeout: 60000 });
  await page.selectOption('#up-axis', 'y');
  await page.click('#view-back');
  await api(() => window.vfsd.frames(2));
  const rest = Array.from(await api(() => window.vfsd.positions()));
  const n = rest.length / 3;
  const { diagonal: d, up } = await state();
  check(n === 26002 && up === 'y', `the armadillo opened (${n} vertices), Y up`);

  // The right hand and the body, in the mesh's coordinates (CGAL's armadillo faces -z).
  const hand = [56.5, 74.5, -34];
  await page.click('#new-region');
  await page.selectOption('#inner-motion', 'translation');
  await page.getByLabel('Paint inner').check();
  await page.getByLabel('Brush radius').fill(String(0.03 * d));
  await stroke(await project([[57, 81, -34], [56, 76, -34], [56, 71, -34], [57, 66, -34]]));
  await page.getByLabel('Paint outer').check();
  await page.getByLabel('Brush radius').fill(String(0.08 * d));
  await stroke(await project([[0, 50, -20], [0, 25, -20], [0, 0, -20], [-15, -30, -20], [15, -30, -20]]));
  const s = Array.from(await api(() => window.vfsd.regionS()));
  const inner = [], outer = [];
  for (let v = 0; v < n; v++) {
    if (s[v] === 0) inner.push(v);
    if (s[v] === 1) outer.push(v);
  }
  const strayInner = inner.filter((v) => norm(sub(at(rest, v), hand)) > 0.1 * d).length;
  check(inner.length > 100 && strayInner === 0,
        `the hand is the inner region (${inner.length} vertices, ${strayInner} beyond 0.1 D of it)`);
  const nearHand = outer.filter((v) => norm(sub(at(rest, v), hand)) < 0.15 * d).length;
  check(outer.length > 3000 && nearHand === 0, `the body is the outer region (${outer.length} vertices, ${nearHand} near the hand)`);
  const curve = (await state()).control_points;
  check(norm(sub(curve[0], hand)) < 0.05 * d, 'the curve starts at the hand');
  await page.screenshot({ path: path.join(out, 'armadillo-painted.png') });

  // ---- one drag of the curve's end to above the hand (off the mesh: the view plane through the end) ----
  await page.getByLabel('Curve drag').check();
  const last = curve.length - 1;
  const above = [hand[0], hand[1] + 0.2 * d, hand[2]];
  const [[x0, y0], [x1, y1]] = await project([curve[last], above]);
  // Drawn frames, and the main thread's long tasks.
  await recordFrames(page);
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  await page.mouse.move(x1, y1, { steps: 8 });
  await page.mouse.up();
  const released = await api(() => performance.now());
  const dragged = (await state()).control_points;
  const [[xe, ye]] = await project([dragged[last]]);
  check(Math.hypot(xe - x1, ye - y1) < 2 && dragged[last][1] - hand[1] > 0.1 * d && norm(sub(dragged[0], curve[0])) === 0,
        `the end is under the pointer (${Math.hypot(xe - x1, ye - y1).toFixed(2)} px), ` +
        `${((dragged[last][1] - hand[1]) / d).toFixed(3)} D above the hand; the start stayed`);

  // ---- play to t = 1 ----
  await page.keyboard.press(' ');
  await page.waitForFunction(() => {
    const st = window.vfsd.state();
    return st.stats.time === 1 && !st.moving;
  }, null, { polling: 50, timeout: 300000 });
  const done = await api(() => performance.now());
  const frames = await api(() => window.frameTimes);
  const drawn = frames.filter((t) => t >= released && t <= done).length;
  const timed = (await api(() => window.longTasks)).filter(([t]) => t >= released && t <= done);
  const tasks = timed.map(([, ms]) => ms);
  const longest = Math.max(0, ...tasks);
  // When the tasks over 100 ms started (ms after the last pointer event), to tell the preparation from the steps.
  const over = timed.filter(([, ms]) => ms > 100).map(([t, ms]) => `${ms.toFixed(0)} ms at ${(t - released).toFixed(0)} ms`);
  const stats = await api(() => window.vfsd.stats());

  const p = Array.from(await api(() => window.vfsd.positions()));
  let bodyMoved = 0;
  for (const v of outer) bodyMoved = Math.max(bodyMoved, norm(sub(at(p, v), at(rest, v))));
  let lift = 0;
  for (const v of inner) lift += p[3 * v + 1] - rest[3 * v + 1];
  lift /= inner.length;
  // Rigid: every distance between hand vertices kept (a sample of pairs).
  let stretch = 0;
  for (let k = 0; k < inner.length; k += 3) {
    const a = inner[k], b = inner[(k * 7 + 11) % inner.length];
    stretch = Math.max(stretch, Math.abs(norm(sub(at(p, a), at(p, b))) - norm(sub(at(rest, a), at(rest, b)))));
  }
  console.log(`armadillo first edit (page, ${stats.backend}): volume error ${stats.volume_error_percent.toFixed(4)} %, ` +
              `hand lifted ${(lift / d).toFixed(3)} D, hand distances kept to ${(stretch / d).toExponential(2)} D, ` +
              `body moved ${(bodyMoved / d).toExponential(2)} D, folded triangles ${stats.flipped_triangles}`);
  console.log(`  t = 1 reached ${((done - released) / 1000).toFixed(2)} s after the last pointer event, ` +
              `${drawn} frames drawn, ${tasks.filter((ms) => ms > 100).length} of ${tasks.length} long tasks over 100 ms, ` +
              `the longest ${longest.toFixed(0)} ms, ${stats.ms_per_step.toFixed(2)} ms/step` +
              (over.length ? ` (over 100 ms: ${over.join(', ')})` : ''));
  check(stats.volume_error_percent <= 0.5, `volume error ${stats.volume_error_percent.toFixed(4)} % <= 0.5 %`);
  check(lift > 0.05 * d, `the hand rose ${(lift / d).toFixed(3)} D`);
  check(stretch <= 1e-4 * d, `the hand moved rigidly (distances kept to ${(stretch / d).toExponential(2)} D)`);
  check(bodyMoved <= 1e-6 * d, `the body stayed (${(bodyMoved / d).toExponential(2)} D)`);
  check(stats.flipped_triangles === 0, `no folded triangles (${stats.flipped_triangles})`);
  await page.screenshot({ path: path.join(out, 'armadillo-lifted.png') });

  // ---- idle afterwards: no frames, and the CPU it costs ----
  await page.mouse.move(0, 0);
  await page.waitForTimeout(1000);
  const f0 = (await api(() => window.frameTimes)).length, c0 = cpuSeconds(userData);
  await page.waitForTimeout(3000);
  const f1 = (await api(() => window.frameTimes)).length, c1 = cpuSeconds(userData);
  console.log(`  idle for 3 s: ${f1 - f0} frames, Chromium CPU ${(100 * (c1 - c0) / 3).toFixed(0)} % of one core`);
  check(f1 - f0 <= 2, `idle: ${f1 - f0} frames drawn in 3 s (at most 2)`);

  // ---- the end knot dragged over the mesh lands on its surface under the pointer ----
  // (Off the mesh it moved in the view plane through its old point, above: that plane
  // lies about a third of the diagonal in front of the chest, so a drag that kept its
  // depth would miss the surface by that much.)
  await page.keyboard.press('r');
  await page.waitForFunction(() => window.vfsd.state().stats.time === 0, null, { timeout: 60000 });
  const chest = [-9.37, 39.8, -14.16];  // a vertex on the chest, facing the view
  const before = (await state()).control_points;
  const [[cx0, cy0], [cx1, cy1]] = await project([before[last], chest]);
  await page.mouse.move(cx0, cy0);
  await page.mouse.down();
  await page.mouse.move(cx1, cy1, { steps: 8 });
  await page.mouse.up();
  const end = (await state()).control_points[last];
  const [[ex, ey]] = await project([end]);
  const off = await api(() => window.vfsd.exportMesh('off'));
  const fromSurface = distanceToSurface(end, off);
  check(Math.hypot(ex - cx1, ey - cy1) < 2 && fromSurface < 1e-4 * d && Math.abs(end[2] - before[last][2]) > 0.05 * d,
        `the end dragged over the chest is on its surface (${(fromSurface / d).toExponential(1)} D from it), ` +
        `under the pointer (${Math.hypot(ex - cx1, ey - cy1).toFixed(2)} px), ` +
        `${(Math.abs(end[2] - before[last][2]) / d).toFixed(3)} D from its old depth`);
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
