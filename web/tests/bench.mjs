// ms/step of the page on a larger mesh in headless Chromium, GPU path (WebGL2,
// SwiftShader here: a software renderer) and CPU path (wasm, one thread):
//   VFSD_WEB_SITE=build/web/site node web/tests/bench.mjs [builtin:sphere:6 ...]
// (scripts/build-web first; docs/web.md has the figures.)
import { openPage } from './harness.mjs';

const meshes = process.argv.slice(2).length ? process.argv.slice(2) : ['builtin:sphere:6'];
for (const mesh of meshes) {
  for (const query of ['', '?backend=cpu']) {
    const { page, close } = await openPage(query);
    try {
      await page.evaluate((m) => window.vfsd.open(m), mesh);
      const s = await page.evaluate(() => window.vfsd.state());
      const c = s.control_points;
      await page.evaluate((scene) => window.vfsd.loadScene(scene), {
        region: { kind: 'geodesic', seed: c[0], g_min: 0.1 * s.diagonal, g_max: 0.45 * s.diagonal },
        curve: { bezier: c }, steps: 250, smoothing_steps: 10,
      });
      const t0 = Date.now();
      const stats = await page.evaluate(() => window.vfsd.runTo(1));
      const wall = (Date.now() - t0) / 1000;
      console.log(`${mesh}: ${stats.vertices} vertices, backend ${stats.backend}: ${stats.ms_per_step.toFixed(2)} ms/step ` +
                  `(250 steps in ${wall.toFixed(1)} s wall, volume error ${stats.volume_error_percent.toFixed(3)} %)`);
    } finally {
      await close();
    }
  }
}
