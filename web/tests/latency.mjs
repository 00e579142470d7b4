// Edit to final shape in the page, headless Chromium: on a mesh (default the
// 41k sphere, builtin:sphere:6) with a geodesic region and the starting curve run
// to t = 1, two edits a user makes:
// - a curve edit: the curve's end dragged sideways by about a tenth of the
//   diagonal (the editor's drag command, where a pointer drag ends);
// - a region edit: a new geodesic seed picked (the pick command).
// For each, the time from the edit to t = 1 reached (the page's frame whose
// steps reached it, on the page's clock, and when the test's poll saw it, after
// the final shape's draw), the steps, the main thread's
// longest task (the edit's command included: it is timed in the page, since the
// long-task observer does not see a task a test starts), the longest gap
// between drawn frames meanwhile (and, with VFSD_BROWSER_FRAMES=1, between the
// browser's own frames, which go on while the page holds its last image), on
// the CPU path
// (wasm, one thread) and the GPU path (WebGL2; SwiftShader here, a software
// renderer), and then what a drawn frame costs there (the view turned). With
// VFSD_NATIVE set to a native `vfsd`, the page's edited scene is also timed
// natively by `vfsd bench --latency --scene` (its curve edit or region edit: the
// mesh open, the region computed for a region edit, the motion built,
// integrated to t = 1; a curve edit from the rest state the last run kept, as the
// page's) on one thread and on all, and the ratios printed. VFSD_LATENCY_EDITS=N
// makes each kind of edit N times (out and back) and prints the ratios' medians;
// VFSD_LATENCY_BACKENDS=cpu (or gpu) times that path alone.
//   VFSD_WEB_SITE=build/web/site VFSD_NATIVE=$PWD/build/release/vfsd node web/tests/latency.mjs [builtin:sphere:6 ...]
// (scripts/build-web first; docs/web.md has the figures.)
import { execFileSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { openPage, openRunToEnd, recordBrowserFrames, recordFrames, stopBrowserFrames } from './harness.mjs';

// Native: the scene's curve edit and region edit in ms (medians of three), on
// `threads` threads (0: all).
function native(scene, threads) {
  const dir = mkdtempSync(join(tmpdir(), 'vfsd-latency-'));
  const file = join(dir, 'edited.json');
  writeFileSync(file, JSON.stringify(scene));
  const args = ['bench', '--latency', '--scene', file, '--no-reference', '--repeat', '3'];
  if (threads) args.push('--threads', String(threads));
  let out;
  try {
    out = execFileSync(process.env.VFSD_NATIVE, args, { encoding: 'utf8' });
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
  const line = out.split('\n').find((l) => l.startsWith('edited '));
  if (!line) throw new Error(`vfsd bench --latency printed no result:\n${out}`);
  // edited  VERTICES  REGION ms  CURVE-EDIT ms  REST-KEPT ms  REGION-EDIT ms  STEPS ...
  // The page's drag follows a run on the same region: like the editors, it starts
  // from that run's rest state, so it is compared with the curve edit that does.
  const f = line.trim().split(/\s+/);
  return { curve: Number(f[6]), region: Number(f[8]), steps: Number(f[10]) };
}

// The native figures per scene and thread count, each scene timed once.
const nativeRuns = new Map();
function nativeOf(scene, threads) {
  const key = `${threads} ${JSON.stringify(scene)}`;
  if (!nativeRuns.has(key)) nativeRuns.set(key, native(scene, threads));
  return nativeRuns.get(key);
}

function median(sorted) {
  const m = sorted.length >> 1;
  return sorted.length % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
}

const editsAsked = Math.max(1, Number(process.env.VFSD_LATENCY_EDITS || 1));

// VFSD_BROWSER_FRAMES=1: the browser's own frames recorded too. Not by default:
// a loop of animation frames makes the browser render every frame, on a
// software renderer at a cost to the run (docs/web.md, "Browser frames").
const browserFramesAsked = process.env.VFSD_BROWSER_FRAMES === '1';
const backends = (process.env.VFSD_LATENCY_BACKENDS || 'cpu,gpu').split(',');
for (const b of backends) if (b !== 'cpu' && b !== 'gpu') throw new Error(`VFSD_LATENCY_BACKENDS: ${b} is neither cpu nor gpu`);

// Runs `edit` on the page and waits until the deformation is back at t = 1.
async function timeEdit(page, edit, argument) {
  await recordFrames(page);
  if (browserFramesAsked) await recordBrowserFrames(page);
  const start = await page.evaluate(() => performance.now());
  // The edit's command runs in a task of its own (a pointer event's, in use),
  // which the long-task observer does not see when a test calls it: timed here.
  const command = await page.evaluate(edit, argument);
  await page.waitForFunction(() => {
    const st = window.vfsd.state();
    return st.stats.time === 1 && !st.moving;
  }, null, { polling: 10, timeout: 300000 });
  const done = await page.evaluate(() => performance.now());
  // The frame whose steps reached t = 1, on the page's clock: the shape computed,
  // before the draw and the test's poll.
  const reached = await page.evaluate(() => window.vfsd.reachedTargetAt());
  if (reached === null || reached < start || reached > done) throw new Error(`t = 1 reached at ${reached}, not in [${start}, ${done}]`);
  const browserFrames = browserFramesAsked ? (await stopBrowserFrames(page)).filter((t) => t >= start && t <= done) : [];
  const frames = await page.evaluate(() => window.frameTimes);
  const tasks = (await page.evaluate(() => window.longTasks)).map(([, ms]) => ms);
  const longestGap = (times) => {
    let gap = 0;
    for (let i = 1; i < times.length; ++i) gap = Math.max(gap, times[i] - times[i - 1]);
    return gap;
  };
  const gap = longestGap(frames);
  // The browser's frames from the edit to t = 1, the edit and t = 1 included as their ends.
  const browserGap = longestGap([start, ...browserFrames, done]);
  const stats = await page.evaluate(() => window.vfsd.stats());
  const scene = await page.evaluate(() => window.vfsd.exportScene());
  return { ms: done - start, computedMs: reached - start, frames: frames.length, gap, browserGap, browserFrames: browserFrames.length,
           task: Math.max(0, command, ...tasks), command, stats, scene };
}

// A drawn frame's cost: the view turned between two presets, a frame waited on, ten times.
async function drawnFrameMs(page) {
  return page.evaluate(async () => {
    const start = performance.now();
    for (let i = 0; i < 10; ++i) {
      window.vfsd.command({ cmd: 'view', name: i % 2 ? 'front' : 'right' });
      await window.vfsd.frames(1);
    }
    return (performance.now() - start) / 10;
  });
}

const meshes = process.argv.slice(2).length ? process.argv.slice(2) : ['builtin:sphere:6'];
for (const mesh of meshes) {
  for (const backend of backends) {
    const { page, close } = await openPage(`?backend=${backend}`);
    try {
      const s = await openRunToEnd(page, mesh);
      const c = s.control_points;
      const last = c.length - 1;
      const to = (await page.evaluate((p) => window.vfsd.command({ cmd: 'project', points: [p] }),
                                      [c[last][0], c[last][1] + 0.1 * s.diagonal, c[last][2]])).pixels[0];
      const back = (await page.evaluate((p) => window.vfsd.command({ cmd: 'project', points: [p] }), c[last])).pixels[0];
      // Each edit returns how long its command took. With VFSD_LATENCY_EDITS=N,
      // each kind of edit is made N times: the curve's end dragged out and back
      // in turn, the seed picked at vertex 100 and 200 in turn.
      const timed = (command) => { const t = performance.now(); window.vfsd.command(command); return performance.now() - t; };
      const edits = [];
      for (let k = 0; k < editsAsked; ++k)
        edits.push(['curve edit', await timeEdit(page, `(${timed})({ cmd: 'drag', index: ${last}, to: [${k % 2 ? back : to}] })`)]);
      for (let k = 0; k < editsAsked; ++k)
        edits.push(['region edit', await timeEdit(page, `(${timed})({ cmd: 'pick', vertex: ${k % 2 ? 200 : 100} })`)]);
      const ratios = { 'curve edit': [], 'region edit': [] };
      for (const [name, e] of edits) {
        if (e.stats.backend !== backend) throw new Error(`?backend=${backend} ran on ${e.stats.backend}`);
        let line = `${mesh} page ${backend}, ${name}: t = 1 computed in ${e.computedMs.toFixed(0)} ms, ` +
                   `seen by the test in ${e.ms.toFixed(0)} ms (${e.stats.ms_per_step.toFixed(2)} ms/step, ` +
                   `${e.frames} frames drawn, longest gap between them ${e.gap.toFixed(0)} ms, ` +
                   (browserFramesAsked ? `${e.browserFrames} browser frames, longest gap ${e.browserGap.toFixed(0)} ms, ` : '') +
                   `longest task ${e.task.toFixed(0)} ms, ` +
                   `the edit's command ${e.command.toFixed(0)} ms)`;
        if (backend === 'cpu' && process.env.VFSD_NATIVE) {
          const key = name === 'curve edit' ? 'curve' : 'region';
          const one = nativeOf(e.scene, 1), all = nativeOf(e.scene, 0);
          ratios[name].push(e.computedMs / one[key]);
          line += `; native ${one[key].toFixed(0)} ms on one thread, ${all[key].toFixed(0)} ms on all (${all.steps} steps): ` +
                  `page / native ${(e.computedMs / one[key]).toFixed(2)} (one thread), ` +
                  `${(e.computedMs / all[key]).toFixed(2)} (all); seen by the test, ${(e.ms / one[key]).toFixed(2)} (one thread)`;
        }
        console.log(line);
      }
      for (const [name, r] of Object.entries(ratios)) {
        if (r.length < 2) continue;
        r.sort((a, b) => a - b);
        console.log(`${mesh} page ${backend}, ${name}: page / native (one thread) median ${median(r).toFixed(2)} ` +
                    `of ${r.length} edits (${r[0].toFixed(2)}–${r[r.length - 1].toFixed(2)})`);
      }
      const state = await page.evaluate(() => window.vfsd.state());
      console.log(`${mesh} page ${backend}: a drawn frame ${(await drawnFrameMs(page)).toFixed(0)} ms ` +
                  `(the view turned, a frame waited on; ${state.multisampled ? '' : 'not '}multisampled)`);
    } finally {
      await close();
    }
  }
}
