// Fast where it runs, quiet when idle. On a software WebGL renderer (SwiftShader,
// what headless Chromium gives) the page runs the CPU path and says why, unless
// ?backend=gpu asks for the GPU path; there it draws without multisampling (each
// sample would be shaded on the CPU) unless ?antialias=on asks. Once the deformation has stopped the page
// draws no frames; the pointer over the view draws its overlay again (the canvas
// only where the camera turns), then it stops again.
// An unknown ?antialias= or ?backend= is reported in the page's log, its default taken.
import { openPage, check } from './harness.mjs';

const software = /swiftshader|llvmpipe|software|softpipe/i;
const { page, errors, close } = await openPage();
const api = (fn, arg) => page.evaluate(fn, arg);
// Frames drawn over `ms` of wall time.
// The canvas's own WebGL context attribute (getContext hands back the page's context).
const antialiased = (p) => p.evaluate(() => document.getElementById('vfsd-canvas').getContext('webgl2').getContextAttributes().antialias);
const framesOver = async (ms) => {
  const f0 = await api(() => window.vfsd.framesDrawn());
  await page.waitForTimeout(ms);
  return (await api(() => window.vfsd.framesDrawn())) - f0;
};

try {
  const s = await api(() => window.vfsd.state());
  console.log(`  WebGL renderer: ${s.renderer}`);
  const note = await page.locator('#backend-note').textContent();
  if (software.test(s.renderer)) {
    check(s.stats.backend === 'cpu', `a software renderer runs the CPU path (backend ${s.stats.backend})`);
    check(await page.locator('#backend-note').isVisible() && /software renderer/.test(note) && software.test(note),
          `the page says why: "${note}"`);
    check(!s.multisampled && !(await antialiased(page)), 'a software renderer draws without multisampling');
  } else {
    check(s.multisampled && (await antialiased(page)), 'a hardware renderer draws multisampled');
    check(!/software/.test(note), `a hardware renderer is not called software: "${note}"`);
  }

  // Idle: no frames once the deformation stopped.
  const stats = await api(() => window.vfsd.runTo(0.2));
  check(stats.time === 0.2, 'the deformation ran to t = 0.2 and stopped');
  await page.waitForTimeout(300);
  const idle = await framesOver(2000);
  check(idle <= 2, `idle for 2 s: ${idle} frames drawn (at most 2)`);

  // The pointer over the view draws the overlay (the hover highlight follows it)
  // but not the view's canvas, whose image did not change; then quiet again.
  const box = await page.locator('#vfsd-overlay').boundingBox();
  const f0 = await api(() => window.vfsd.framesDrawn());
  const c0 = (await api(() => window.vfsd.state())).canvas_draws;
  for (let k = 0; k < 5; k++) await page.mouse.move(box.x + box.width * (0.3 + 0.05 * k), box.y + box.height / 2);
  await api(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const moved = (await api(() => window.vfsd.framesDrawn())) - f0;
  const canvas = (await api(() => window.vfsd.state())).canvas_draws - c0;
  check(moved >= 1, `moving the pointer over the view draws the overlay (${moved} frames)`);
  check(canvas === 0, `and not the view's canvas (${canvas} draws)`);
  // An orbit (the right button held) turns the camera: the canvas draws.
  await page.mouse.move(box.x + box.width * 0.5, box.y + box.height * 0.5);
  await page.mouse.down({ button: 'right' });
  for (let k = 1; k <= 5; k++) await page.mouse.move(box.x + box.width * (0.5 + 0.02 * k), box.y + box.height * 0.5);
  await page.mouse.up({ button: 'right' });
  await api(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  const orbit = (await api(() => window.vfsd.state())).canvas_draws - c0;
  check(orbit >= 1, `an orbit draws the canvas (${orbit} draws)`);
  await page.mouse.move(0, 0);
  await page.waitForTimeout(300);
  const after = await framesOver(2000);
  check(after <= 2, `quiet again: ${after} frames in 2 s`);
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}

{
  // An unknown value of a URL option is reported, and its default taken.
  const { page, log, close } = await openPage('?antialias=sometimes&backend=fast');
  try {
    const s = await page.evaluate(() => window.vfsd.state());
    for (const [name, list, taken] of [['antialias', 'auto, on, off', 'auto'], ['backend', 'auto, cpu, gpu', 'auto']])
      check(log.some((l) => l.includes(`?${name}=`) && l.includes(`expected one of ${list}; ${taken} taken`)),
            `?${name}= with an unknown value is reported, ${taken} taken`);
    check(!s.multisampled, 'the default antialias on a software renderer: not multisampled');
  } finally {
    await close();
  }
}

{
  // ?backend=gpu: the GPU path even on a software renderer, with the default scheme;
  // ?antialias=on: multisampled whatever the renderer.
  const { page: gpuPage, errors: gpuErrors, close: gpuClose } = await openPage('?backend=gpu&antialias=on');
  try {
    const s = await gpuPage.evaluate(() => window.vfsd.state());
    check(s.multisampled && (await antialiased(gpuPage)), '?antialias=on draws multisampled');
    const c = s.control_points, d = s.diagonal;
    await gpuPage.evaluate((scene) => window.vfsd.loadScene(scene), {
      region: { kind: 'geodesic', seed: c[0], g_min: 0.1 * d, g_max: 0.4 * d }, curve: { bezier: c },
    });
    const stats = await gpuPage.evaluate(() => window.vfsd.runTo(0.1));
    check(stats.backend === 'gpu', `?backend=gpu runs the GPU path (${stats.backend})`);
    check(gpuErrors.length === 0, 'no console errors' + (gpuErrors.length ? ': ' + gpuErrors.join(' | ') : ''));
  } finally {
    await gpuClose();
  }
}
