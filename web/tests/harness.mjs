// Shared set-up of the browser tests: the site (VFSD_WEB_SITE) served on
// 127.0.0.1 by a small static server, Debian's Chromium in headless mode with
// SwiftShader's WebGL2 (docs/web.md), and the page's console collected.
import http from 'node:http';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

const types = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm',
                '.json': 'application/json', '.png': 'image/png' };

export function serve(dir) {
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    const file = path.join(dir, path.normalize(decodeURIComponent(url.pathname)).replace(/^(\.\.[/\\])+/, ''));
    const target = file.endsWith(path.sep) ? path.join(file, 'index.html') : file;
    fs.readFile(target, (err, data) => {
      if (err) { res.writeHead(404); res.end('not found'); return; }
      res.writeHead(200, { 'Content-Type': types[path.extname(target)] || 'application/octet-stream' });
      res.end(data);
    });
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

export const chromiumArgs = () => [
  '--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-gpu-sandbox', '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--no-first-run', '--disable-dev-shm-usage',
];

// Opens the page (query: e.g. '?float=0'); returns what a test needs.
export async function openPage(query = '', viewport = { width: 1200, height: 800 }) {
  const site = process.env.VFSD_WEB_SITE;
  if (!site || !fs.existsSync(path.join(site, 'index.html'))) throw new Error('VFSD_WEB_SITE: no built site');
  const server = await serve(site);
  const userData = fs.mkdtempSync(path.join(os.tmpdir(), 'vfsd-chromium-'));
  const browser = await chromium.launchPersistentContext(userData, {
    executablePath: process.env.VFSD_CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: chromiumArgs(),
    viewport,
    acceptDownloads: true,
  });
  const page = browser.pages()[0] || await browser.newPage();
  const errors = [], log = [];
  page.on('console', (m) => {
    log.push(`${m.type()}: ${m.text()}`);
    if (m.type() === 'error') errors.push(m.text());
  });
  page.on('pageerror', (e) => errors.push(String(e)));
  const url = `http://127.0.0.1:${server.address().port}/index.html${query}`;
  await page.goto(url);
  await page.evaluate(() => window.vfsd.ready.then(() => true));
  const close = async () => {
    await browser.close();
    server.close();
    fs.rmSync(userData, { recursive: true, force: true });
  };
  return { page, errors, log, url, close, userData };
}

// Opens `mesh` (a file or builtin name) with a geodesic region about its
// starting curve's first knot and that curve, and runs it to t = 1: where the
// edit tests and benches start. Returns the page's state at rest (the curve's
// control points, the diagonal).
export async function openRunToEnd(page, mesh) {
  await page.evaluate((m) => window.vfsd.open(m), mesh);
  const s = await page.evaluate(() => window.vfsd.state());
  const c = s.control_points;
  const region = { kind: 'geodesic', seed: c[0], g_min: 0.1 * s.diagonal, g_max: 0.45 * s.diagonal };
  await page.evaluate((scene) => window.vfsd.loadScene(scene), { region, curve: { bezier: c }, target_time: 1 });
  await page.evaluate(() => window.vfsd.runTo(1));
  return s;
}

// Where tests write screenshots and downloads.
export function outDir() {
  const dir = process.env.VFSD_WEB_OUT || fs.mkdtempSync(path.join(os.tmpdir(), 'vfsd-web-'));
  fs.mkdirSync(dir, { recursive: true });
  return dir;
}

export function check(condition, message) {
  if (!condition) throw new Error('check failed: ' + message);
  console.log('  ok: ' + message);
}

// CPU seconds so far of the browser started with `userData` and all its descendants.
export function cpuSeconds(userData) {
  const procs = fs.readdirSync('/proc').filter((d) => /^\d+$/.test(d)).map((pid) => {
    try {
      const stat = fs.readFileSync(`/proc/${pid}/stat`, 'utf8');
      const f = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
      const cmd = fs.readFileSync(`/proc/${pid}/cmdline`, 'utf8');
      return { pid, ppid: f[1], cpu: (Number(f[11]) + Number(f[12])) / 100 /* USER_HZ */, root: cmd.includes(userData) };
    } catch { return null; }
  }).filter(Boolean);
  const mine = new Set(procs.filter((p) => p.root).map((p) => p.pid));
  for (let grew = true; grew;) {
    grew = false;
    for (const p of procs) if (!mine.has(p.pid) && mine.has(p.ppid)) { mine.add(p.pid); grew = true; }
  }
  return procs.filter((p) => mine.has(p.pid)).reduce((sum, p) => sum + p.cpu, 0);
}

// Records the times of the browser's own frames (requestAnimationFrame
// callbacks, window.browserFrames) until stopBrowserFrames: whether the page
// keeps rendering while a run holds its last image. Not left running: a loop
// of animation frames keeps an idle page rendering.
export async function recordBrowserFrames(page) {
  await page.evaluate(() => {
    window.browserFrames = [];
    window.browserFramesOn = true;
    const tick = (t) => {
      window.browserFrames.push(t);
      if (window.browserFramesOn) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}

export async function stopBrowserFrames(page) {
  return page.evaluate(() => {
    window.browserFramesOn = false;
    return window.browserFrames;
  });
}

// From now on, records in the page the times of the drawn frames (window.frameTimes)
// and the main thread's long tasks, [start, duration] each (window.longTasks;
// over 50 ms: a frame the page could not answer in). Called again, it starts
// both lists afresh (the page's frame hook wrapped and the observer made once).
export async function recordFrames(page) {
  await page.evaluate(() => {
    window.frameTimes = [];
    window.longTasks = [];
    if (window.recordingFrames) return;
    window.recordingFrames = true;
    const frame = window.Module.vfsdFrame;
    window.Module.vfsdFrame = (overlay) => { window.frameTimes.push(performance.now()); return frame(overlay); };
    new PerformanceObserver((list) => {
      for (const e of list.getEntries()) window.longTasks.push([e.startTime, e.duration]);
    }).observe({ type: 'longtask' });
  });
}
