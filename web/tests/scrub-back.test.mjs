// Scrubbing back shows the way out's shapes, on the CPU path and the GPU path:
// on a box twisted half a turn, which folds without the fold repair and which
// the repair acts on, the shape at t = 0.5 scrubbed back from t = 1 is the one
// the run showed there on its way out (the same checksum), and at t = 0 the
// mesh as it was (on the GPU, as its float textures hold it). The volume keeper
// is off: the GPU path's deformation pass then left its sampler of the keeper's
// sums on a texture it wrote, which WebGL refused as a feedback loop, and the
// page's run stopped at its first steps.
import { readFileSync } from 'node:fs';
import { openPage, check } from './harness.mjs';

const scene = JSON.parse(readFileSync(new URL('../../assets/scenes/fig05-box-bend-twist.json', import.meta.url)));
scene.twist_degrees = [scene.twist_degrees?.[0] ?? 0, 180];
Object.assign(scene, { keep_volume: false, fold_repair: true, steps: 40, tolerance: 0, target_time: 0 });

for (const backend of ['cpu', 'gpu']) {
  const { page, errors, close } = await openPage(`?backend=${backend}`);
  const api = (fn, arg) => page.evaluate(fn, arg);
  try {
    await api((s) => window.vfsd.loadScene(s), scene);
    const rest = await api(() => window.vfsd.positionsChecksum());
    const half = await api(() => window.vfsd.runTo(0.5));
    check(half.backend === backend, `?backend=${backend} runs the ${backend} path (${half.backend})`);
    const wayOut = await api(() => window.vfsd.positionsChecksum());
    const end = await api(() => window.vfsd.runTo(1));
    check(end.time === 1, `${backend}: the run reached t = 1`);
    await api(() => window.vfsd.runTo(0.5));
    const back = await api(() => window.vfsd.positionsChecksum());
    check(back === wayOut, `${backend}: back at t = 0.5 the way out's shape (checksum ${back}, out ${wayOut})`);
    await api(() => window.vfsd.runTo(0));
    const zero = await api(() => window.vfsd.positionsChecksum());
    const apart = Math.abs(zero - rest) / Math.abs(rest);
    check(backend === 'cpu' ? zero === rest : apart < 1e-6, `${backend}: back at t = 0 the mesh as it was (${zero}, ${rest})`);
    const { warnings } = await api(() => window.vfsd.state());
    check(!(warnings || []).some((w) => /stopped/.test(w)), `${backend}: the run did not stop: ${warnings}`);
    check(errors.length === 0, `${backend}: no console errors` + (errors.length ? ': ' + errors.join(' | ') : ''));
  } finally {
    await close();
  }
}
