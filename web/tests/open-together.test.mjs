// A scene and its mesh open together: chosen at once in the file input (multiple)
// or dropped together, paired by the mesh's file name; a scene alone whose mesh
// the page lacks says "choose NAME", and that mesh chosen next completes it. An
// opened scene plays to its target_time. After Apply the stats count since the
// mesh was opened; undo of Apply plays back to the applied pose, redo applies again.
import { openPage, check } from './harness.mjs';

const { page, errors, close } = await openPage();
try {
  const api = (fn, arg) => page.evaluate(fn, arg);
  const state = () => api(() => window.vfsd.state());
  const settled = (mesh, t) => page.waitForFunction(([m, t]) => {
    const s = window.vfsd.state();
    return s.mesh === m && s.target_time === t && s.stats.time === t && !s.moving;
  }, [mesh, t], { timeout: 60000 });

  // The default scene's box as an OBJ file, and its scene naming that mesh by a
  // folder the page does not have, with target_time 0.3.
  const obj = await api(() => window.vfsd.exportMesh('obj'));
  const scene = await api(() => window.vfsd.exportScene());
  scene.mesh = 'meshes/box.obj';
  scene.target_time = 0.3;
  // Sec. 5 as printed (no volume keeper): a volume error the panel's three decimals show.
  scene.stream_gauge = 'paper';
  scene.keep_volume = false;
  scene.fold_repair = false;
  const json = (s) => Buffer.from(JSON.stringify(s));
  check((await state()).target_time === 0, 'the default scene waits at rest');

  // Both chosen at once: the scene opens with its mesh and plays to its target.
  await page.setInputFiles('#open-scene', [
    { name: 'box-scene.json', mimeType: 'application/json', buffer: json(scene) },
    { name: 'box.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) },
  ]);
  await settled('/files/box.obj', 0.3);
  check(true, 'scene and mesh chosen together: /files/box.obj played to the scene\'s target_time 0.3');
  const pose = await api(() => window.vfsd.positionsChecksum());
  const first = await api(() => window.vfsd.stats());
  check(first.volume_error_percent >= 0.001 && !first.applied, `the deformation's volume error ${first.volume_error_percent}`);

  // Apply: at rest the stats still show the change since the mesh was opened.
  await page.click('#apply');
  await api(() => window.vfsd.frames(1));
  const applied = await state();
  check(applied.stats.applied && applied.stats.time === 0 && applied.target_time === 0, 'applied, at rest');
  check(applied.stats.volume_error_since_opened_percent === first.volume_error_percent,
        `volume error since opened ${applied.stats.volume_error_since_opened_percent} (not reset to 0)`);
  const shown = (await page.locator('#stat-volume').textContent()).trim();
  check(/^\d+\.\d+ % since opened \(this edit 0\.000 %\)$/.test(shown) && parseFloat(shown) > 0 &&
        Math.abs(parseFloat(shown) - first.volume_error_percent) < 1e-3, `the panel says so: "${shown}"`);
  check(/since opened/.test(await page.locator('#stat-flipped').textContent()), 'flipped triangles since opened');

  // Undo of Apply plays back to t = 0.3, the same pose; redo applies again.
  await page.locator('#vfsd-overlay').focus();
  await page.keyboard.press('Control+z');
  await settled('/files/box.obj', 0.3);
  check(await api(() => window.vfsd.positionsChecksum()) === pose, 'undo of Apply returns to the applied pose at t = 0.3');
  check(!(await state()).stats.applied, 'the mesh as opened again');
  await page.keyboard.press('Control+Shift+Z');
  await settled('/files/box.obj', 0);
  check((await state()).stats.applied, 'redo applies again (target 0)');

  // A scene alone whose mesh the page does not have asks for it by name.
  const lonely = { ...scene, mesh: 'other.obj' };
  await page.setInputFiles('#open-scene', { name: 'lonely.json', mimeType: 'application/json', buffer: json(lonely) });
  await page.waitForFunction(() => /choose other\.obj/.test(document.getElementById('errors').textContent), null,
                             { timeout: 20000 });
  check((await state()).missing_mesh === 'other.obj', 'the error says "choose other.obj"');
  await page.setInputFiles('#open-mesh', { name: 'other.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) });
  await settled('/files/other.obj', 0.3);
  check((await state()).missing_mesh === '', 'other.obj chosen next completes the scene, which plays to 0.3');

  // A drop of several files pairs them the same way.
  await api(() => window.vfsd.open('builtin:bar'));
  await api(([sceneText, objText]) => {
    const dt = new DataTransfer();
    dt.items.add(new File([objText], 'dropped.obj'));
    dt.items.add(new File([sceneText], 'dropped.json'));
    document.getElementById('view').dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, [JSON.stringify({ ...scene, mesh: 'dropped.obj' }), obj]);
  await settled('/files/dropped.obj', 0.3);
  check(true, 'a dropped scene and mesh open together');
  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
} finally {
  await close();
}
