// The handle gizmo with real mouse events: the Handle tool places a handle on the
// box's top face; a drag of the z ring (about the handle's normal) turns the
// target's binormal by the angle swept round the gizmo's centre and keeps its
// position; a drag of the z axis moves the target along its normal only; each drag
// is one undo step and Ctrl+Z brings back the placed handle.
import path from 'node:path';
import { openPage, outDir, check } from './harness.mjs';

const out = outDir();
const { page, errors, close } = await openPage();

const api = (fn, arg) => page.evaluate(fn, arg);
const state = () => api(() => window.vfsd.state());
const gizmo = () => api(() => window.vfsd.gizmo());
const handle = async () => (await api(() => window.vfsd.exportScene())).curve.handle;

const sub = (a, b) => a.map((x, k) => x - b[k]);
const dot = (a, b) => a.reduce((s, x, k) => s + x * b[k], 0);
const norm = (a) => Math.sqrt(dot(a, a));
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];

// A mouse drag through page points.
async function drag(points) {
  await page.mouse.move(points[0][0], points[0][1]);
  await page.mouse.down();
  for (const [x, y] of points.slice(1)) await page.mouse.move(x, y);
  await page.mouse.up();
}

// `p` turned about `c` by `degrees`, counter-clockwise on screen, in 5-degree steps.
function arc(p, c, degrees) {
  const r = Math.hypot(p[0] - c[0], p[1] - c[1]), start = Math.atan2(-(p[1] - c[1]), p[0] - c[0]);
  const steps = Math.ceil(Math.abs(degrees) / 5), points = [p];
  for (let k = 1; k <= steps; k++) {
    const a = start + (degrees * Math.PI / 180) * k / steps;
    points.push([c[0] + r * Math.cos(a), c[1] - r * Math.sin(a)]);
  }
  return points;
}

try {
  check((await gizmo()) === null, 'no gizmo before a handle is placed');
  // The top face's middle (the default scene is fig. 4's box).
  const p = Array.from(await api(() => window.vfsd.positions()));
  const top = Math.max(...p.filter((_, i) => i % 3 === 2));
  const [[tx, ty]] = (await api((pts) => window.vfsd.project(pts), [[0, 0, top]])).pixels;
  await page.getByLabel('Handle').check();
  await page.mouse.click(tx, ty);
  const placed = await state();
  check(placed.is_handle && placed.tool === 'navigate', 'a click with the Handle tool places a handle, then navigate');
  check(placed.undo === 1, 'placing the handle is one undo step');
  const start = await handle();
  check(Math.abs(start.from.position[2] - top) < 1e-9 && start.from.normal[2] > 0.99, 'on the top face, normal up');

  // The z ring: about the normal, as seen from its tip (above) counter-clockwise is positive.
  const g = await gizmo();
  check(g && g.parts['ring-z'] && g.parts.z && g.parts.centre, 'the gizmo has its parts on screen');
  await drag(arc(g.parts['ring-z'], g.centre, 60));
  const turned = await handle();
  const angle = Math.atan2(dot(cross(start.to.binormal, turned.to.binormal), start.to.normal),
                           dot(start.to.binormal, turned.to.binormal)) * 180 / Math.PI;
  check(Math.abs(angle - 60) < 2, `the z ring turned the binormal by ${angle.toFixed(2)} degrees (60 swept)`);
  check(norm(sub(turned.to.normal, start.to.normal)) < 1e-9, 'the normal stays');
  check(norm(sub(turned.to.position, start.to.position)) < 1e-9, 'the position stays');
  check((await state()).undo === 2, 'the ring drag is one undo step');
  await page.screenshot({ path: path.join(out, 'web-gizmo.png') });

  // The z axis, dragged upward on screen: along the normal only.
  const z = (await gizmo()).parts.z;
  await drag([z, [z[0], z[1] - 10], [z[0], z[1] - 25], [z[0], z[1] - 40]]);
  const lifted = await handle();
  const delta = sub(lifted.to.position, turned.to.position);
  check(dot(delta, turned.to.normal) > 0.05, `the z axis moved the target along the normal by ${dot(delta, turned.to.normal).toFixed(3)}`);
  check(norm(cross(delta, turned.to.normal)) < 1e-9 * norm(delta), 'and only along it');
  check((await state()).undo === 3, 'the axis drag is one undo step');

  await page.locator('#vfsd-overlay').focus();
  await page.keyboard.press('Control+z');
  await page.keyboard.press('Control+z');
  const undone = await handle();
  check(JSON.stringify(undone) === JSON.stringify(start), 'Ctrl+Z twice restores the placed handle');
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
