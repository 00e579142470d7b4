// Apply right after an edit, on the CPU path with a mesh whose run spans many
// frames (the 41k sphere): the curve's end dragged after a run to t = 1, and
// Apply pressed at once. The apply waits for the new run: the click returns with
// the run still going, the page renders frames meanwhile, and the frame that
// reaches t = 1 bakes it. Undo plays back to t = 1 and gives the baked shape.
// The checks count what happened, not how long it took.
import { openPage, openRunToEnd, check } from './harness.mjs';

const { page, errors, close } = await openPage('?backend=cpu');
const api = (fn, arg) => page.evaluate(fn, arg);
try {
  const s = await openRunToEnd(page, 'builtin:sphere:6');
  const c = s.control_points;
  const before = await api(() => window.vfsd.positionsChecksum());
  const undoBefore = (await api(() => window.vfsd.state())).undo;

  // Count, from inside the page, the frames it renders while the apply waits.
  await api(() => {
    window.applying = { frames: 0, running: true };
    const frame = () => {
      if (!window.applying.running) return;
      if (window.vfsd.state().apply_due) window.applying.frames++;
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
  });
  const last = c.length - 1;
  const to = (await api((p) => window.vfsd.command({ cmd: 'project', points: [p] }),
                        [c[last][0], c[last][1] + 0.15 * s.diagonal, c[last][2]])).pixels[0];
  const clicked = await api((a) => {
    window.vfsd.command({ cmd: 'drag', index: a.last, to: a.to });
    document.getElementById('apply').click();
    return window.vfsd.state();
  }, { last, to });
  check(clicked.apply_due && clicked.moving && clicked.holding,
        `the click returned with the apply waiting for the run (apply_due ${clicked.apply_due}, moving ${clicked.moving})`);
  check(clicked.undo === undoBefore + 1, `the drag is one undo step, the apply not yet (${clicked.undo} after ${undoBefore})`);
  check(/applying/.test(clicked.status), `the status line says so: "${clicked.status}"`);

  await page.waitForFunction(() => {
    const st = window.vfsd.state();
    return !st.apply_due && !st.moving;
  }, null, { polling: 10, timeout: 300000 });
  const frames = await api(() => { window.applying.running = false; return window.applying.frames; });
  const applied = await api(() => window.vfsd.state());
  const baked = await api(() => window.vfsd.positionsChecksum());
  check(frames >= 1, `the page rendered ${frames} frames while the apply waited`);
  check(applied.stats.applied && applied.stats.time === 0 && applied.target_time === 0, 'applied, at rest');
  check(applied.undo === undoBefore + 2, `the apply is the next undo step (${applied.undo})`);
  check(baked !== before, 'the baked shape is the edit\'s result, not the one on show before it');

  // Undo plays back to the time the apply was of: the same shape, bit for bit.
  await api(() => window.vfsd.command({ cmd: 'undo' }));
  await page.waitForFunction(() => {
    const st = window.vfsd.state();
    return st.stats.time === 1 && !st.moving;
  }, null, { polling: 10, timeout: 300000 });
  const replayed = await api(() => window.vfsd.positionsChecksum());
  check(replayed === baked, `undo of the apply plays back to t = 1, the baked shape (${replayed}, ${baked})`);
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
