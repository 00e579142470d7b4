// Edit to final shape in the page, headless Chromium: on a mesh (default the
// 41k sphere, builtin:sphere:6), a scene run to t = 1, then an edit of its curve;
// the time from the edit to t = 1 reached, the steps, and the main thread's
// longest task and longest gap between drawn frames meanwhile, on the CPU path
// (wasm, one thread) and the GPU path (WebGL2; SwiftShader here, a software
// renderer). With VFSD_NATIVE set to a native `vfsd`, the same edited scene is
// also timed natively (`vfsd bench --latency`'s measure: prepared, then
// integrated) on one thread and on all, and the ratios printed.
//   VFSD_WEB_SITE=build/web/site VFSD_NATIVE=$PWD/build/release/vfsd node web/tests/latency.mjs [builtin:sphere:6 ...]
// (scripts/build-web first; docs/web.md has the figures.)
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { openPage, recordFrames } from './harness.mjs';

// Native: the scene deformed by `vfsd deform` with `threads` threads; its total_ms
// (read, prepared, integrated) and steps.
function native(scene, threads) {
  const dir = mkdtempSync(join(tmpdir(), 'vfsd-latency-'));
  writeFileSync(join(dir, 'scene.json'), JSON.stringify(scene));
  const args = ['deform', join(dir, 'scene.json'), '--out', join(dir, 'out.ply'), '--report', join(dir, 'report.json')];
  if (threads) args.push('--threads', String(threads));
  execFileSync(process.env.VFSD_NATIVE, args);
  const report = JSON.parse(readFileSync(join(dir, 'report.json'), 'utf8'));
  return { ms: report.total_ms, steps: report.steps };
}

const meshes = process.argv.slice(2).length ? process.argv.slice(2) : ['builtin:sphere:6'];
for (const mesh of meshes) {
  let edited = null;
  for (const backend of ['cpu', 'gpu']) {
    const { page, close } = await openPage(`?backend=${backend}`);
    try {
      await page.evaluate((m) => window.vfsd.open(m), mesh);
      const s = await page.evaluate(() => window.vfsd.state());
      const c = s.control_points;
      const region = { kind: 'geodesic', seed: c[0], g_min: 0.1 * s.diagonal, g_max: 0.45 * s.diagonal };
      await page.evaluate((scene) => window.vfsd.loadScene(scene), { region, curve: { bezier: c }, target_time: 1 });
      await page.evaluate(() => window.vfsd.runTo(1));
      // The edit: the curve's end moved sideways by a tenth of the diagonal.
      const moved = c.map((p, i) => (i === c.length - 1 ? [p[0], p[1] + 0.1 * s.diagonal, p[2]] : p));
      edited = { mesh, region, curve: { bezier: moved } };
      await recordFrames(page);
      const start = await page.evaluate(() => performance.now());
      await page.evaluate((scene) => window.vfsd.loadScene(scene), { region, curve: edited.curve, target_time: 1 });
      await page.waitForFunction(() => {
        const st = window.vfsd.state();
        return st.stats.time === 1 && !st.moving;
      }, null, { polling: 10, timeout: 300000 });
      const done = await page.evaluate(() => performance.now());
      const frames = await page.evaluate(() => window.frameTimes);
      const tasks = (await page.evaluate(() => window.longTasks)).map(([, ms]) => ms);
      const stats = await page.evaluate(() => window.vfsd.stats());
      if (stats.backend !== backend) throw new Error(`?backend=${backend} ran on ${stats.backend}`);
      let gap = 0;
      for (let i = 1; i < frames.length; ++i) gap = Math.max(gap, frames[i] - frames[i - 1]);
      const ms = done - start;
      let line = `${mesh} page ${backend}: edit to t = 1 in ${ms.toFixed(0)} ms (${stats.ms_per_step.toFixed(2)} ms/step, ` +
                 `${frames.length} frames, longest gap between frames ${gap.toFixed(0)} ms, ` +
                 `longest task ${Math.max(0, ...tasks).toFixed(0)} ms)`;
      if (backend === 'cpu' && process.env.VFSD_NATIVE) {
        const one = native(edited, 1), all = native(edited, 0);
        line += `; native ${one.ms.toFixed(0)} ms on one thread, ${all.ms.toFixed(0)} ms on all (${all.steps} steps): ` +
                `page / native ${(ms / one.ms).toFixed(2)} (one thread), ${(ms / all.ms).toFixed(2)} (all)`;
      }
      console.log(line);
    } finally {
      await close();
    }
  }
}
