// Apply right after an edit, timed in the page: on the 41k sphere (CPU path) with
// a geodesic region and the starting curve run to t = 1, the curve's end dragged
// by a tenth of the diagonal and Apply clicked in the same task, RUNS times (the
// first a drag of the starting curve, the others of the short curve an apply
// leaves; back to t = 1 after each). Prints the drag's and the click's time, the
// time from the drag to the bake, and the long tasks (over 50 ms, the browser's
// observer) meanwhile. docs/web.md, "Apply while an edit updates", has figures.
//   VFSD_WEB_SITE=build/web/site RUNS=4 node web/tests/apply-tasks.mjs
import { openPage, openRunToEnd } from './harness.mjs';

const runs = Number(process.env.RUNS || 4);
const { page, close } = await openPage('?backend=cpu');
const api = (fn, arg) => page.evaluate(fn, arg);
try {
  const s = await openRunToEnd(page, 'builtin:sphere:6');
  const c = s.control_points;
  await api(() => {
    window.tasks = [];
    new PerformanceObserver((l) => { for (const e of l.getEntries()) window.tasks.push([e.startTime, e.duration]); })
      .observe({ type: 'longtask' });
  });
  const last = c.length - 1;
  for (let k = 0; k < runs; ++k) {
    const p = (await api(() => window.vfsd.state())).control_points[last];
    const aim = [p[0], p[1] + (k % 2 ? -1 : 1) * 0.1 * s.diagonal, p[2]];
    const to = (await api((q) => window.vfsd.command({ cmd: 'project', points: [q] }), aim)).pixels[0];
    const r = await api((a) => {
      const t0 = performance.now();
      window.vfsd.command({ cmd: 'drag', index: a.last, to: a.to });
      const t1 = performance.now();
      document.getElementById('apply').click();
      return { t0, drag: t1 - t0, click: performance.now() - t1 };
    }, { last, to });
    await page.waitForFunction(() => {
      const st = window.vfsd.state();
      return !st.apply_due && !st.moving && st.target_time === 0;
    }, null, { polling: 10, timeout: 300000 });
    const baked = await api(() => performance.now());
    await new Promise((done) => setTimeout(done, 300));  // the observer reports a little later
    const tasks = await api((t0) => window.tasks.filter(([at]) => at >= t0 - 5).map(([, ms]) => ms), r.t0);
    console.log(`apply ${k}: drag ${r.drag.toFixed(1)} ms, click ${r.click.toFixed(1)} ms, drag to baked ` +
                `${(baked - r.t0).toFixed(0)} ms, long tasks: ${tasks.map((ms) => ms.toFixed(0)).join(' ') || 'none'}`);
    await api(() => window.vfsd.runTo(1));
  }
} finally {
  await close();
}
