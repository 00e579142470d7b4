// ms/step of the page on a larger mesh in headless Chromium, GPU path (WebGL2,
// SwiftShader here: a software renderer) and CPU path (wasm, one thread), on the
// default scheme (a run that lands on another backend fails):
//   VFSD_WEB_SITE=build/web/site node web/tests/bench.mjs [builtin:sphere:6 ...]
// (scripts/build-web first; docs/web.md has the figures.) With VFSD_NATIVE set to
// a native `vfsd`, the CPU run's scene is also deformed natively on one thread
// and the wasm / native ratio printed.
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { openPage } from './harness.mjs';

// ms/step of `vfsd deform` on one thread for the same scene.
function nativeMsPerStep(scene) {
  const dir = mkdtempSync(join(tmpdir(), 'vfsd-bench-'));
  writeFileSync(join(dir, 'scene.json'), JSON.stringify(scene));
  execFileSync(process.env.VFSD_NATIVE, ['deform', join(dir, 'scene.json'), '--out', join(dir, 'out.ply'),
                                         '--report', join(dir, 'report.json'), '--threads', '1']);
  return JSON.parse(readFileSync(join(dir, 'report.json'), 'utf8')).ms_per_step;
}

const meshes = process.argv.slice(2).length ? process.argv.slice(2) : ['builtin:sphere:6'];
for (const mesh of meshes) {
  for (const query of ['?backend=gpu', '?backend=cpu']) {
    const { page, close } = await openPage(query);
    try {
      await page.evaluate((m) => window.vfsd.open(m), mesh);
      const s = await page.evaluate(() => window.vfsd.state());
      const c = s.control_points;
      await page.evaluate((scene) => window.vfsd.loadScene(scene), {
        region: { kind: 'geodesic', seed: c[0], g_min: 0.1 * s.diagonal, g_max: 0.45 * s.diagonal },
        curve: { bezier: c }, steps: 250, smoothing_steps: 10, target_time: 0,  // at rest until runTo
      });
      const t0 = Date.now();
      const stats = await page.evaluate(() => window.vfsd.runTo(1));
      const wall = (Date.now() - t0) / 1000;
      if (stats.backend !== query.slice('?backend='.length)) {
        const { backend_reason: why } = await page.evaluate(() => window.vfsd.state());
        throw new Error(`${query} ran on ${stats.backend}: ${why}`);
      }
      console.log(`${mesh}: ${stats.vertices} vertices, backend ${stats.backend}: ${stats.ms_per_step.toFixed(2)} ms/step ` +
                  `(250 steps in ${wall.toFixed(1)} s wall, volume error ${stats.volume_error_percent.toFixed(3)} %)`);
      if (stats.backend === 'cpu' && process.env.VFSD_NATIVE) {
        const native = nativeMsPerStep(await page.evaluate(() => window.vfsd.exportScene()));
        console.log(`${mesh}: native vfsd deform, one thread: ${native.toFixed(2)} ms/step; ` +
                    `wasm / native = ${(stats.ms_per_step / native).toFixed(2)}`);
      }
    } finally {
      await close();
    }
  }
}
