// The page loads on 127.0.0.1 with no console errors, the default scene (the
// default scheme: stream gauge fit, volume keeper, fold repair) runs on the GPU
// path where it is asked for, with no backend note, and the default scene is
// visible: the canvas is not blank and shows both region colours (s = 0 blue,
// s = 1 red).
import path from 'node:path';
import { openPage, outDir, check } from './harness.mjs';
import { canvasColours } from './pixels.mjs';

const out = outDir();
// ?backend=gpu: the GPU path even on a software renderer.
const { page, errors, close } = await openPage('?backend=gpu');
try {
  const stats = await page.evaluate(() => window.vfsd.stats());
  check(stats.vertices > 0 && stats.triangles > 0, `default scene loaded (${stats.vertices} vertices)`);
  const renderer = await page.evaluate(() => {
    const gl = document.createElement('canvas').getContext('webgl2');
    const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
    return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : '';
  });
  console.log('  WebGL2 renderer: ' + renderer);
  await page.evaluate(() => window.vfsd.runTo(0.01));
  const after = await page.evaluate(() => window.vfsd.stats());
  check(after.backend === 'gpu', `GPU path for the default scheme (backend ${after.backend})`);
  const note = await page.locator('#backend-note').textContent();
  check(!(await page.locator('#backend-note').isVisible()) || note.trim() === '', `no backend note: "${note}"`);
  await page.evaluate(() => window.vfsd.runTo(0));

  const shot = path.join(out, 'web-default.png');
  await page.screenshot({ path: shot });
  const colours = await canvasColours(page);
  console.log(`  canvas: ${JSON.stringify(colours)}`);
  check(colours.distinct > 50, 'the canvas is not blank');
  check(colours.blue > 500 && colours.red > 500, 'both region colours present (blue inner, red outer)');
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
