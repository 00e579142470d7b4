// The first minutes of a new user, with real mouse and keyboard events. At
// 1280x720 and 1400x900 Play, the time slider, the stats and a load error are
// on screen without scrolling. A garbage .obj shows its error in a box over the
// view until dismissed (Escape or its button), as the status line, and once in
// the console. Keys go to the editor whatever has the focus: Space after a click
// on Export OBJ plays and downloads nothing more, Space on a clicked checkbox
// plays and leaves it as it is; in a text or number field Space is the field's;
// a held key runs its command once, as in the desktop.
// New region and the band slider each make one undo step.
import path from 'node:path';
import { openPage, outDir, check } from './harness.mjs';

const out = outDir();
const { page, errors, log, close } = await openPage('', { width: 1280, height: 720 });
const api = (fn, arg) => page.evaluate(fn, arg);
const state = () => api(() => window.vfsd.state());

// The element's box lies inside the viewport, and the page itself does not scroll.
async function onScreen(selector, size) {
  const box = await page.locator(selector).boundingBox();
  const inside = box && box.x >= 0 && box.y >= 0 && box.x + box.width <= size.width && box.y + box.height <= size.height;
  check(inside, `${selector} within ${size.width}x${size.height} (${box ? [box.x, box.y, box.width, box.height].map(Math.round) : 'hidden'})`);
}
const pinned = ['#play', '#target-time', '#time-progress', '#stats', '#stat-backend', '#stat-ms', '#stat-volume',
                '#stat-flipped', '#backend-note'];

try {
  // ---- the controls in view ----
  for (const size of [{ width: 1400, height: 900 }, { width: 1280, height: 720 }]) {
    await page.setViewportSize(size);
    await api(() => window.vfsd.frames(2));
    for (const selector of pinned) await onScreen(selector, size);
    const scroll = await api(() => [document.scrollingElement.scrollHeight, window.innerHeight]);
    check(scroll[0] <= scroll[1], `the page does not scroll (${scroll[0]} <= ${scroll[1]})`);
  }

  // ---- a failed load: a box over the view until dismissed, the status, the console once ----
  const garbage = Buffer.from('\u0000\u0001 not a mesh \u00ff\nf 1 2 9\nv x y\n');
  const upload = () => page.setInputFiles('#open-mesh', { name: 'notes.obj', mimeType: 'text/plain', buffer: garbage });
  const mentions = () => log.filter((line) => /notes\.obj/.test(line) && !/opening/.test(line)).length;
  const vertices = (await state()).stats.vertices;
  await upload();
  await page.locator('#error-box').waitFor({ state: 'visible', timeout: 20000 });
  const message = (await page.locator('#errors').textContent()).trim();
  check(/^notes\.obj: /.test(message), `the error is shown over the view: "${message}"`);
  await onScreen('#error-box', { width: 1280, height: 720 });
  await page.screenshot({ path: path.join(out, 'web-1280x720-load-error.png') });
  check((await page.locator('#status').textContent()).trim() === message, 'the status line is the error');
  await page.waitForTimeout(1000);  // frames go by
  check(await page.locator('#error-box').isVisible(), 'the error stays until dismissed');
  check(mentions() === 1, `the console has the error once (${mentions()}: ${log.filter((l) => /notes\.obj/.test(l)).join(' | ')})`);
  check((await state()).stats.vertices === vertices, 'the mesh stays');
  await page.keyboard.press('Escape');
  check(await page.locator('#error-box').isHidden(), 'Escape dismisses the error');
  await upload();
  await page.locator('#error-box').waitFor({ state: 'visible', timeout: 20000 });
  check(mentions() === 2, 'the same file failing again shows and logs its error again, once');
  await page.getByRole('button', { name: 'Dismiss the error' }).click();
  check(await page.locator('#error-box').isHidden(), 'the close button dismisses the error');
  await page.waitForTimeout(500);
  check(await page.locator('#error-box').isHidden() && mentions() === 2, 'a dismissed error stays dismissed, logged no more');

  // ---- Space after Export OBJ: play, and no second download ----
  let downloads = 0;
  page.on('download', () => downloads++);
  const [download] = await Promise.all([page.waitForEvent('download'), page.locator('#export-obj').click()]);
  check(/\.obj$/.test(download.suggestedFilename()) && downloads === 1, `Export OBJ downloaded ${download.suggestedFilename()}`);
  const before = await state();
  check(before.target_time === 0 && !before.moving, 'at rest at t = 0');
  await page.keyboard.press('Space');
  const played = await state();
  check(played.target_time === 1, `Space after the click plays (target time ${played.target_time})`);
  await page.waitForTimeout(1000);
  check(downloads === 1, `no second download (${downloads})`);
  await page.keyboard.press('Space');  // pauses, or plays again from the end: either way a toggle ran
  await page.keyboard.press('r');
  check((await state()).target_time === 0, 'R resets to t = 0 with the focus on the page');

  // ---- Space on a clicked checkbox: play; the checkbox keeps its state ----
  await page.getByLabel('Wireframe').click();
  check((await state()).wireframe === true, 'a click turns the wireframe on');
  await page.keyboard.press('Space');
  const afterBox = await state();
  check(afterBox.wireframe === true && afterBox.target_time === 1, 'Space on the checkbox plays and leaves it checked');
  await page.keyboard.press('r');
  await page.getByLabel('Wireframe').click();

  // ---- a held key runs its command once (the key's repeats do not toggle play on and off) ----
  await page.keyboard.down(' ');
  for (let k = 0; k < 5; k++) await page.keyboard.down(' ');  // the browser's repeats: repeat = true
  const held = await api(() => window.vfsd.state());
  await page.keyboard.up(' ');
  check(held.target_time === 1, `held Space plays once, its 5 repeats ignored (target time ${held.target_time})`);
  await page.keyboard.press('r');

  // ---- Space in a text or number field is the field's ----
  await api(() => {
    const panel = document.getElementById('panel');
    for (const type of ['text', 'number']) {
      const field = Object.assign(document.createElement('input'), { type, id: 'test-' + type });
      field.setAttribute('aria-label', 'test ' + type);
      panel.prepend(field);
    }
  });
  for (const type of ['text', 'number']) {
    await page.locator('#test-' + type).click();
    await page.keyboard.type(type === 'text' ? 'i o' : '1 2');
    const s = await state();
    check(s.target_time === 0 && !s.moving && s.tool === 'navigate',
          `Space and letters typed in a ${type} field do not reach the editor (target time ${s.target_time}, tool ${s.tool})`);
  }
  check(await page.locator('#test-text').inputValue() === 'i o', 'the text field has the space');

  // ---- the region controls: New region and the band, each one undo step ----
  const undoBefore = (await state()).undo;
  await page.getByRole('button', { name: 'New region' }).click();
  const cleaned = await state();
  check(cleaned.undo === undoBefore + 1, `New region is one undo step (${undoBefore} -> ${cleaned.undo})`);
  const band = cleaned.band;
  check(band > 0, `a painted region starts with a band (${band})`);
  const slider = page.locator('#band');
  await slider.scrollIntoViewIfNeeded();
  const at = await slider.boundingBox();
  await page.mouse.click(at.x + 0.9 * at.width, at.y + at.height / 2);
  const widened = await state();
  check(widened.band > band && widened.undo === cleaned.undo + 1,
        `a click on the band slider widens the band (${band} -> ${widened.band}), one undo step`);

  // ---- the up axis: Y up from the View section, saved in the state ----
  await page.selectOption('#up-axis', 'y');
  check((await state()).up === 'y', 'the Up axis select makes the scene Y-up');
  await page.selectOption('#up-axis', 'z');
  check((await state()).up === 'z', 'and Z-up again');
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
