// What the page costs while nothing changes: after the deformation ran to
// t = 0.1 and stopped, the frames it draws and the CPU time of Chromium's
// processes over an idle interval (docs/web.md, "Idle"):
//   VFSD_WEB_SITE=build/web/site node web/tests/idle.mjs [SECONDS]
// Frames are counted by wrapping the engine's per-frame call to the page
// (Module.vfsdFrame), so the figure means the same for any version of the page.
import { openPage, cpuSeconds } from './harness.mjs';

const seconds = Number(process.argv[2] || 5);
const { page, close, userData } = await openPage('', { width: 1400, height: 900 });
try {
  await page.evaluate(() => {
    window.idleFrames = 0;
    const frame = window.Module.vfsdFrame;
    window.Module.vfsdFrame = (overlay) => { window.idleFrames++; return frame(overlay); };
  });
  await page.evaluate(() => window.vfsd.runTo(0.1));
  await page.waitForTimeout(1000);  // the last frames and any autosave settle
  const f0 = await page.evaluate(() => window.idleFrames), c0 = cpuSeconds(userData);
  await page.waitForTimeout(seconds * 1000);
  const f1 = await page.evaluate(() => window.idleFrames), c1 = cpuSeconds(userData);
  console.log(`idle for ${seconds} s: ${f1 - f0} frames drawn, Chromium CPU ${(100 * (c1 - c0) / seconds).toFixed(0)} % ` +
              `of one core (${(c1 - c0).toFixed(2)} s)`);
} finally {
  await close();
}
