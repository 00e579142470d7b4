// Where the page's CPU path spends an edit's time: Chromium's sampling profiler
// (over the DevTools protocol) around four curve drags of the 41k sphere (or the
// mesh given), each run to t = 1, and the functions' shares of the samples,
// largest first. Function names need a site linked with --profiling-funcs:
//   NODE_PATH=/usr/share/nodejs cmake -S . -B build/web-prof -G Ninja \
//     -DCMAKE_TOOLCHAIN_FILE=/usr/share/emscripten/cmake/Modules/Platform/Emscripten.cmake \
//     -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=-fwasm-exceptions -msimd128" \
//     "-DCMAKE_EXE_LINKER_FLAGS=-fwasm-exceptions --profiling-funcs" -DVFSD_BUILD_CLI=OFF -DVFSD_BUILD_TESTS=OFF
//   cmake --build build/web-prof --target vfsd-web
//   VFSD_WEB_SITE=build/web-prof/site node web/tests/profile.mjs [MESH] [ROWS]
// (docs/web.md, "Where the page's time goes", has the figures.)
import { openPage, openRunToEnd } from './harness.mjs';

const mesh = process.argv[2] || 'builtin:sphere:6';
const rows = Number(process.argv[3] || 30);
const { page, close } = await openPage('?backend=cpu');
try {
  const s = await openRunToEnd(page, mesh);
  const c = s.control_points;
  const last = c.length - 1;
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Profiler.enable');
  await cdp.send('Profiler.setSamplingInterval', { interval: 100 });  // microseconds
  await cdp.send('Profiler.start');
  for (let k = 0; k < 4; ++k) {
    const to = (await page.evaluate((p) => window.vfsd.command({ cmd: 'project', points: [p] }),
                                    [c[last][0], c[last][1] + (0.05 + 0.02 * k) * s.diagonal, c[last][2]])).pixels[0];
    await page.evaluate(([index, at]) => window.vfsd.command({ cmd: 'drag', index, to: at }), [last, to]);
    await page.waitForFunction(() => { const st = window.vfsd.state(); return st.stats.time === 1 && !st.moving; },
                               null, { polling: 10, timeout: 300000 });
  }
  const { profile } = await cdp.send('Profiler.stop');
  const nodes = new Map(profile.nodes.map((n) => [n.id, n]));
  const shares = new Map();
  for (const id of profile.samples) {
    const frame = nodes.get(id).callFrame;
    const name = frame.functionName || `(${frame.url.split('/').pop()}:${frame.lineNumber})`;
    shares.set(name, (shares.get(name) || 0) + 1);
  }
  const total = profile.samples.length;
  console.log(`${mesh}: four curve drags to t = 1, ${total} samples; share of the samples, function`);
  for (const [name, n] of [...shares.entries()].sort((a, b) => b[1] - a[1]).slice(0, rows))
    console.log(`${(100 * n / total).toFixed(1).padStart(5)} %  ${name.slice(0, 150)}`);
} finally {
  await close();
}
