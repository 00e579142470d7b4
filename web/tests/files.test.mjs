// Files and fallbacks: a mesh opened through the file input replaces the scene;
// a malformed file shows an error and keeps the previous mesh; loadScene without
// "mesh" applies to the current mesh; without EXT_color_buffer_float (?float=0)
// the CPU path runs and the page says so; a lost WebGL context comes back.
import { openPage, check } from './harness.mjs';

{
  const { page, errors, close } = await openPage('?backend=gpu');  // the GPU path even on SwiftShader
  try {
    const api = (fn, arg) => page.evaluate(fn, arg);
    // A good OBJ (a tetrahedron) through the file picker.
    const tetra = 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n';
    await page.setInputFiles('#open-mesh', { name: 'tetra.obj', mimeType: 'text/plain', buffer: Buffer.from(tetra) });
    await page.waitForFunction(() => window.vfsd.stats().vertices === 4, null, { timeout: 20000 });
    check((await api(() => window.vfsd.state())).mesh === '/files/tetra.obj', 'opened tetra.obj from the file input');
    const checksum = await api(() => window.vfsd.positionsChecksum());

    // A malformed file: an error, and the tetrahedron stays.
    await page.setInputFiles('#open-mesh', { name: 'broken.obj', mimeType: 'text/plain',
                                             buffer: Buffer.from('v 0 0 0\nv 1 zero 0\nf 1 2 7\n') });
    await page.waitForFunction(() => document.getElementById('errors').textContent.length > 0, null, { timeout: 20000 });
    const message = await page.locator('#errors').textContent();
    check(/broken\.obj/.test(message), `the error is shown: "${message.trim()}"`);
    check(await page.locator('#errors').isVisible(), 'the error area is visible');
    check((await api(() => window.vfsd.stats())).vertices === 4, 'the previous mesh stays');
    check(await api(() => window.vfsd.positionsChecksum()) === checksum, 'its positions are unchanged');

    // A scene without "mesh" applies to the current mesh.
    await api(() => window.vfsd.open('builtin:bar'));
    const bar = await api(() => window.vfsd.state());
    const d = bar.diagonal, c = bar.control_points;
    await api((scene) => window.vfsd.loadScene(scene), {
      region: { kind: 'geodesic', seed: c[0], g_min: 0.1 * d, g_max: 0.4 * d },
      curve: { bezier: [c[0], c[1], c[2], c[3].map((x, k) => x + (k === 1 ? 0.1 * d : 0))] },
    });
    const same = await api(() => window.vfsd.state());
    check(same.mesh === 'builtin:bar' && same.stats.vertices === bar.stats.vertices, 'loadScene without mesh keeps builtin:bar');
    const stats = await api(() => window.vfsd.runTo(1));
    check(stats.time === 1 && stats.backend === 'gpu', `runTo(1) on the GPU path (${stats.ms_per_step.toFixed(3)} ms/step)`);

    // Context loss: the page survives and recomputes from the CPU state.
    const before = await api(() => window.vfsd.positionsChecksum());
    await api(() => {
      const ext = document.getElementById('vfsd-canvas').getContext('webgl2').getExtension('WEBGL_lose_context');
      ext.loseContext();
      return new Promise((r) => setTimeout(() => { ext.restoreContext(); r(); }, 300));
    });
    await page.waitForFunction(() => !window.vfsd.state().context_lost, null, { timeout: 20000 });
    await api(() => window.vfsd.runTo(1));
    const after = await api(() => window.vfsd.positionsChecksum());
    check(Math.abs(after - before) <= 1e-6 * Math.abs(before), 'after a context loss the shape is recomputed to t = 1');
    check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
  } finally {
    await close();
  }
}

{
  // No float render targets: the CPU path, and the page says why.
  const { page, errors, close } = await openPage('?float=0');
  try {
    const stats = await page.evaluate(() => window.vfsd.runTo(0.5));
    check(stats.backend === 'cpu' && stats.time === 0.5, 'without EXT_color_buffer_float the CPU path runs');
    const note = await page.locator('#backend-note').textContent();
    check(await page.locator('#backend-note').isVisible() && /EXT_color_buffer_float/.test(note), `the page says so: "${note}"`);
    check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' | ') : ''));
  } finally {
    await close();
  }
}
