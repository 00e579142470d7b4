// Nothing lost in the browser: an edited session is autosaved to IndexedDB; the
// reloaded page offers to restore it (a Restore / Discard box), and restored, the
// exported mesh equals the one exported before the reload. Discarded, the next
// reload offers nothing.
import path from 'node:path';
import { openPage, outDir, check } from './harness.mjs';

const out = outDir();
const { page, errors, close } = await openPage();

const api = (fn, arg) => page.evaluate(fn, arg);
const state = () => api(() => window.vfsd.state());
const reload = async () => {
  await page.reload();
  await page.evaluate(() => window.vfsd.ready.then(() => true));
};
const waitTime = (t) => page.waitForFunction((t) => {
  const s = window.vfsd.state();
  return s.stats.time === t && !s.moving;
}, t, { polling: 100, timeout: 300000 });
// Every change autosaved and written to IndexedDB.
const waitStored = () => page.waitForFunction(() => {
  const a = window.vfsd.autosave();
  return !a.behind && a.stored;
}, null, { polling: 100, timeout: 60000 });

function readObj(text) {
  const v = [];
  for (const line of text.split('\n'))
    if (line.startsWith('v ')) v.push(line.trim().split(/\s+/).slice(1, 4).map(Number));
  return v;
}

try {
  check(await page.locator('#restore-offer').isHidden(), 'a fresh browser offers no restore');

  // Edit as a person would: drag the curve's last control point, twist, scrub to 0.7.
  await page.getByLabel('Curve drag').check();
  const curveBefore = (await state()).control_points;
  const last = curveBefore.length - 1;
  const [[px, py]] = await api((p) => window.vfsd.project(p).pixels, [curveBefore[last]]);
  await page.mouse.move(px, py);
  await page.mouse.down();
  await page.mouse.move(px + 40, py + 20, { steps: 8 });
  await page.mouse.up();
  await page.getByLabel('α1 (twist at t = 1)').fill('60');
  await page.getByLabel('Target time').fill('0.7');
  await waitTime(0.7);
  const edited = await state();
  check(JSON.stringify(edited.control_points) !== JSON.stringify(curveBefore), 'the control point was dragged');
  check(edited.undo >= 1 && edited.alpha[1] === 60, `edited: ${edited.undo} undo steps, α1 = ${edited.alpha[1]}`);
  const before = await api(() => window.vfsd.exportMesh('obj'));
  await waitStored();
  const { writes } = await api(() => window.vfsd.autosave());
  check(writes > 0, `autosaved to IndexedDB (${writes} writes)`);

  // Reload: the page offers the autosave; Restore brings the session back.
  await reload();
  await page.locator('#restore-offer').waitFor({ state: 'visible', timeout: 20000 });
  const text = (await page.locator('#restore-text').textContent()).trim();
  check(/^Restore the autosaved session from \d{4}-\d\d-\d\d \d\d:\d\d \(builtin:box\)\?$/.test(text),
        `the reloaded page offers: "${text}"`);
  await page.screenshot({ path: path.join(out, 'web-restore-offer.png') });
  check((await state()).stats.time === 0 && (await state()).undo === 0, 'until answered, the default scene is shown');
  await page.getByRole('button', { name: 'Restore', exact: true }).click();
  await waitTime(0.7);
  check(await page.locator('#restore-offer').isHidden(), 'the offer is gone once answered');
  const restored = await state();
  check(JSON.stringify(restored.control_points) === JSON.stringify(edited.control_points) &&
        restored.alpha[1] === 60 && restored.target_time === 0.7, 'the restored curve, twist and target time');
  const after = await api(() => window.vfsd.exportMesh('obj'));
  const a = readObj(before), b = readObj(after);
  const worst = Math.max(...a.map((p, v) => Math.hypot(p[0] - b[v][0], p[1] - b[v][1], p[2] - b[v][2])));
  check(a.length === b.length && a.length > 0, `same vertex count (${a.length})`);
  check(after === before, `the exported mesh equals the one before the reload (max difference ${worst})`);

  // Reload again and discard: the next reload offers nothing.
  await reload();
  await page.locator('#restore-offer').waitFor({ state: 'visible', timeout: 20000 });
  await page.getByRole('button', { name: 'Discard' }).click();
  check(await page.locator('#restore-offer').isHidden(), 'Discard closes the offer');
  await waitStored();
  await reload();
  await api(() => window.vfsd.frames(3));
  check(await page.locator('#restore-offer').isHidden(), 'after Discard a reload offers nothing');
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
