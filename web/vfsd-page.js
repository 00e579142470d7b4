// The browser editor's page: wires the controls, the pointer, the keyboard and
// files to the engine (web/main.cpp, compiled to vfsd.js + vfsd.wasm), draws the
// overlay (control points, the handle gizmo, loops, brush) on a 2D canvas above the WebGL2 one, and
// exposes the automation API window.vfsd (docs/web.md).
'use strict';

(function () {
  const $ = (id) => document.getElementById(id);
  const params = new URLSearchParams(location.search);
  const glCanvas = $('vfsd-canvas');
  const overlayCanvas = $('vfsd-overlay');
  const overlay2d = overlayCanvas.getContext('2d');

  let readyResolve, readyReject;
  const ready = new Promise((resolve, reject) => { readyResolve = resolve; readyReject = reject; });
  let started = false;
  let frameCount = 0;  // frames drawn (web/main.cpp draws only when something changed)
  let lastState = null;
  const frameWaiters = [];  // functions called each frame until they return true

  // ---- the engine ----------------------------------------------------------------

  // One JSON command (web/main.cpp, App::command); throws on an error reply.
  function command(obj) {
    const text = Module.ccall('vfsd_command', 'string', ['string'], [JSON.stringify(obj)]);
    const out = JSON.parse(text);
    if (out && typeof out.error === 'string' && Object.keys(out).length === 1) throw new Error(out.error);
    return out;
  }

  // The UI's use: show errors instead of throwing.
  function run(obj) {
    try {
      const out = command(obj);
      if (out && out.stats) refresh(out);
      return out;
    } catch (e) {
      showError(e.message);
      return null;
    }
  }

  // An error stays in a box over the view until dismissed (its button, or Escape)
  // and is the status line; the console gets it once (`logged`: the engine logged it).
  function showError(text, logged) {
    $('errors').textContent = text || '';
    $('error-box').hidden = !text;
    if (!text) return;
    $('status').textContent = text;
    if (!logged) console.warn('vfsd: ' + text);
  }
  const dismissError = () => showError('');
  $('dismiss-error').addEventListener('click', dismissError);

  function array(which) {
    const ptr = Module.ccall('vfsd_array', 'number', ['number'], [which]);
    const n = Module.ccall('vfsd_array_size', 'number', [], []);
    return Float64Array.from(Module.HEAPF64.subarray(ptr / 8, ptr / 8 + n));
  }

  let reachedTargetAt = null;  // when a frame's steps last reached the target time (performance.now())
  const Module = window.Module = {
    canvas: glCanvas,
    vfsdOptions: { float: params.get('float') !== '0', backend: params.get('backend') || 'auto',
                   antialias: params.get('antialias') || 'auto' },
    print: (text) => console.log(text),
    printErr: (text) => console.warn(text),
    vfsdFrame: onFrame,
    vfsdProgress: () => refresh(command({ cmd: 'state' })),  // a frame that did not draw, while the run goes on
    vfsdReachedTarget: (now) => { reachedTargetAt = now; },  // a frame's steps reached the target time
    vfsdAutosaved: () => autosaveStore.write(),
    vfsdContext: (lost) => {
      $('status').textContent = lost ? 'WebGL context lost: waiting for it to come back…'
                                     : 'WebGL context restored; the deformation is recomputed';
    },
    vfsdFailed: (text) => {
      $('loading').textContent = 'The editor could not start: ' + text;
      readyReject(new Error(text));
    },
    onAbort: (what) => {
      $('loading').hidden = false;
      $('loading').textContent = 'The engine stopped: ' + what;
    },
  };

  // ---- the autosave: /autosave (IDBFS) written to IndexedDB after each autosave --

  const autosaveStore = {
    writes: 0,    // asked for by the engine
    written: 0,   // writes that reached IndexedDB
    syncing: false,
    error: '',
    write() {
      this.writes++;
      if (!this.syncing) this.sync();
    },
    sync() {
      this.syncing = true;
      const target = this.writes;
      Module.FS.syncfs(false, (err) => {
        this.syncing = false;
        this.error = err ? String(err) : '';
        if (err) console.warn('vfsd: the autosave could not be written to IndexedDB: ' + err);
        else this.written = target;
        if (this.writes > target) this.sync();
      });
    },
  };

  // ---- sizes ---------------------------------------------------------------------

  function resize() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(glCanvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(glCanvas.clientHeight * dpr));
    for (const c of [glCanvas, overlayCanvas]) {
      if (c.width !== w) c.width = w;
      if (c.height !== h) c.height = h;
    }
  }
  new ResizeObserver(() => {
    resize();
    if (started) Module.ccall('vfsd_wake', null, [], []);
  }).observe(glCanvas);
  resize();

  // ---- each frame ----------------------------------------------------------------

  // Each drawn frame; returns whether another is wanted (something waits on frames).
  function onFrame(overlayText) {
    resize();
    drawOverlay(JSON.parse(overlayText));
    frameCount++;
    if (!started) {
      started = true;
      $('loading').hidden = true;
      refresh(command({ cmd: 'state' }));
      readyResolve(api);
    }
    refresh(command({ cmd: 'state' }));
    for (let i = frameWaiters.length - 1; i >= 0; i--) {
      if (frameWaiters[i](lastState)) frameWaiters.splice(i, 1);
    }
    return frameWaiters.length > 0;
  }

  function drawOverlay(o) {
    const g = overlay2d;
    g.clearRect(0, 0, overlayCanvas.width, overlayCanvas.height);
    g.lineWidth = 1.5;
    g.strokeStyle = 'rgba(90, 90, 110, 0.8)';
    for (const [a, b] of o.polygon) {
      if (!a || !b) continue;
      g.beginPath(); g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]); g.stroke();
    }
    for (const p of o.points) {
      if (!p.at) continue;
      const r = p.hot ? 7 : 5;
      g.beginPath(); g.arc(p.at[0], p.at[1], r, 0, 2 * Math.PI);
      g.fillStyle = p.hot ? 'rgb(255, 200, 40)' : p.knot ? 'rgb(30, 30, 30)' : 'rgb(250, 250, 250)';
      g.fill(); g.strokeStyle = 'rgb(20, 20, 20)'; g.stroke();
    }
    if (o.gizmo) drawGizmo(g, o.gizmo);
    g.strokeStyle = g.fillStyle = 'rgb(250, 230, 60)';
    g.lineWidth = 2;
    for (const loop of o.loops) {
      g.beginPath();
      loop.forEach((p, i) => p && (i ? g.lineTo(p[0], p[1]) : g.moveTo(p[0], p[1])));
      g.closePath(); g.stroke();
    }
    for (const p of o.current) {
      if (p) { g.beginPath(); g.arc(p[0], p[1], 3.5, 0, 2 * Math.PI); g.fill(); }
    }
    if (o.brush) {
      g.strokeStyle = 'rgba(255, 255, 255, 0.9)';
      g.beginPath(); g.arc(o.brush[0], o.brush[1], o.brush[2], 0, 2 * Math.PI); g.stroke();
    }
  }

  // The handle gizmo (docs/web.md): rings, axes with a dot at the tip, the centre
  // disk; each stroke over a dark one, so it shows on the blue and red regions alike.
  function drawGizmo(g, z) {
    const stroke = (points, colour, closed) => {
      g.beginPath();
      points.forEach(([x, y], i) => (i ? g.lineTo(x, y) : g.moveTo(x, y)));
      if (closed) g.closePath();
      g.lineWidth = 4.5; g.strokeStyle = 'rgba(20, 20, 20, 0.6)'; g.stroke();
      g.lineWidth = 2.5; g.strokeStyle = colour; g.stroke();
    };
    for (const ring of z.rings) stroke(ring.points, ring.colour, true);
    for (const axis of z.axes) {
      stroke([axis.from, axis.to], axis.colour, false);
      g.beginPath(); g.arc(axis.to[0], axis.to[1], 5, 0, 2 * Math.PI);
      g.fillStyle = axis.colour; g.fill();
    }
    const [x, y, r] = z.centre;
    g.beginPath(); g.arc(x, y, r, 0, 2 * Math.PI);
    g.fillStyle = z.centre_colour; g.fill();
    g.lineWidth = 1.5; g.strokeStyle = 'rgb(20, 20, 20)'; g.stroke();
  }

  // ---- the panel follows the state ------------------------------------------------

  const fmt = (x, digits = 3) => Number(x).toFixed(digits);

  function setRange(id, value, max) {
    const el = $(id);
    if (max !== undefined) { el.max = String(max); el.step = String(max / 1000); }
    if (document.activeElement !== el || !el.matches(':active')) {
      if (document.activeElement !== el) el.value = String(value);
    }
    const out = $(id + '-value');
    if (out) out.textContent = fmt(value, el.step >= 1 ? 0 : 3);
  }

  const shown = { loadError: '', status: '' };

  function refresh(s) {
    lastState = s;
    const st = s.stats;
    const d = s.diagonal;
    setRange('radius', s.radius, 0.5 * d);
    setRange('g-min', s.g_min, d);
    setRange('g-max', s.g_max, d);
    setRange('band', s.band, 0.5 * d);
    setRange('s-target', s.s_target);
    setRange('strength', s.strength);
    setRange('alpha0', s.alpha[0]);
    setRange('alpha1', s.alpha[1]);
    setRange('target-time', s.target_time);
    for (const r of document.querySelectorAll('input[name=tool]')) r.checked = r.value === s.tool;
    if (document.activeElement !== $('axis')) $('axis').value = String(s.axis);
    if (document.activeElement !== $('inner-motion')) $('inner-motion').value = s.inner_motion;
    if (document.activeElement !== $('up-axis')) $('up-axis').value = s.up;
    $('force-cpu').checked = s.force_cpu;
    $('wireframe').checked = s.wireframe;
    $('time-value').textContent = s.time_text;  // "updating N %" while the last result stays on show
    $('time-progress').value = st.time;
    $('play').firstChild.textContent = s.moving ? 'Pause ' : 'Play ';
    $('stat-vertices').textContent = st.vertices;
    $('stat-triangles').textContent = st.triangles;
    $('stat-backend').textContent = st.backend + (st.backend === 'gpu' ? ' (WebGL2)' : '');
    $('stat-ms').textContent = fmt(st.ms_per_step);
    $('stat-volume').textContent = st.volume_text;
    $('stat-flipped').textContent = st.flipped_text;
    $('stat-history').textContent = s.undo + ' / ' + s.redo;
    const note = $('backend-note');
    note.hidden = st.backend === 'gpu';
    note.textContent = st.backend === 'gpu' ? '' : 'CPU path: ' + (s.backend_reason || 'GPU path not available');
    $('tool-message').textContent = (s.message || s.hint) + (s.tool === 'loops' ? ` (loops: ${s.loops[0]} closed, ${s.loops[1]} points)` : '');
    // The engine's error and status lines, each shown when it changes.
    if (s.load_error !== shown.loadError) {
      shown.loadError = s.load_error;
      if (s.load_error) showError(s.load_error, true);
    }
    if (s.status !== shown.status) {
      shown.status = s.status;
      if (s.status) $('status').textContent = s.status;
    }
    showRestoreOffer(s.autosave.offer);
    const warnings = $('warnings');
    const list = autosaveStore.error ? [...s.warnings, 'autosave: not written to IndexedDB: ' + autosaveStore.error]
                                     : s.warnings;
    const text = list.join('\n');
    if (warnings.dataset.text !== text) {
      warnings.dataset.text = text;
      warnings.replaceChildren(...list.map((w) => Object.assign(document.createElement('li'), { textContent: w })));
    }
  }

  function showRestoreOffer(offer) {
    const box = $('restore-offer');
    box.hidden = !offer;
    if (offer) $('restore-text').textContent = `Restore the autosaved session from ${offer.written} (${offer.mesh})?`;
  }

  // ---- controls ------------------------------------------------------------------

  // Every control runs a command of the editor's table (docs/commands.md).
  $('restore-autosave').addEventListener('click', () => run({ cmd: 'restore-autosave', answer: 'restore' }));
  $('discard-autosave').addEventListener('click', () => run({ cmd: 'restore-autosave', answer: 'discard' }));

  for (const r of document.querySelectorAll('input[name=tool]'))
    r.addEventListener('change', () => run({ cmd: 'tool', name: r.value }));

  // Sliders: every move sets the value; a drag of g_min/g_max or α is one undo step.
  function slider(id, make, gesture) {
    const el = $(id);
    el.addEventListener('input', () => run(Object.assign(gesture ? { gesture: true } : {}, make(Number(el.value)))));
    if (gesture) el.addEventListener('change', () => run({ cmd: 'end-gesture' }));
  }
  slider('radius', (v) => ({ cmd: 'brush', radius: v }));
  slider('s-target', (v) => ({ cmd: 'brush', target: v }));
  slider('strength', (v) => ({ cmd: 'brush', strength: v }));
  slider('g-min', (v) => ({ cmd: 'g-range', g_min: v }), true);
  slider('g-max', (v) => ({ cmd: 'g-range', g_max: v }), true);
  slider('band', (v) => ({ cmd: 'region-band', band: v }), true);
  slider('alpha0', (v) => ({ cmd: 'twist', alpha: [v, Number($('alpha1').value)] }), true);
  slider('alpha1', (v) => ({ cmd: 'twist', alpha: [Number($('alpha0').value), v] }), true);
  slider('target-time', (v) => ({ cmd: 'set-time', t: v }));
  const axisNames = ['free', 'x', 'y', 'z'];
  $('axis').addEventListener('change', () => run({ cmd: 'axis', name: axisNames[Number($('axis').value) + 1] }));
  $('inner-motion').addEventListener('change', () => run({ cmd: 'inner-motion', mode: $('inner-motion').value }));
  $('up-axis').addEventListener('change', () => run({ cmd: 'up-axis', axis: $('up-axis').value }));
  $('wireframe').addEventListener('change', () => run({ cmd: 'wireframe', on: $('wireframe').checked }));
  $('force-cpu').addEventListener('change', () => run({ cmd: 'force-cpu', on: $('force-cpu').checked }));

  const buttons = {
    'play': { cmd: 'play-pause' }, 'reset': { cmd: 'reset' }, 'apply': { cmd: 'apply' }, 'undo': { cmd: 'undo' },
    'redo': { cmd: 'redo' }, 'add-segment': { cmd: 'add-segment' }, 'remove-segment': { cmd: 'remove-segment' },
    'close-loop': { cmd: 'close-loop' }, 'clear-loops': { cmd: 'clear-loops' }, 'new-region': { cmd: 'new-region' },
    'view-frame': { cmd: 'view', name: 'frame' }, 'view-front': { cmd: 'view', name: 'front' },
    'view-back': { cmd: 'view', name: 'back' },
    'view-right': { cmd: 'view', name: 'right' }, 'view-top': { cmd: 'view', name: 'top' },
    'view-iso': { cmd: 'view', name: 'iso' },
  };
  for (const [id, c] of Object.entries(buttons)) $(id).addEventListener('click', () => run(c));

  // ---- files ---------------------------------------------------------------------

  function download(name, data, type) {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([data], { type: type || 'application/octet-stream' }));
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 60000);
  }

  function exportMesh(format) {
    const r = command({ cmd: 'export-mesh', format: format || 'ply' });
    const bytes = Module.FS.readFile(r.path);
    return { name: r.name, data: format === 'obj' || format === 'off' ? new TextDecoder().decode(bytes) : bytes };
  }

  function exportScene() {
    return command({ cmd: 'export-scene' });
  }

  for (const format of ['obj', 'ply', 'glb']) {
    $('export-' + format).addEventListener('click', () => {
      try {
        const m = exportMesh(format);
        download(m.name, m.data);
        $('status').textContent = 'exported ' + m.name;
      } catch (e) { showError(e.message); }
    });
  }
  $('export-scene').addEventListener('click', () => {
    try {
      const r = exportScene();
      download('vfsd-scene.json', JSON.stringify(r.scene, null, 2) + '\n', 'application/json');
      for (const path of r.files) download(path.split('/').pop(), Module.FS.readFile(path));
      $('status').textContent = 'exported vfsd-scene.json';
    } catch (e) { showError(e.message); }
  });

  const safeName = (name) => name.replace(/[^A-Za-z0-9._-]/g, '_');

  function readFile(file) {
    // Large files show their progress.
    const bar = $('load-progress');
    return new Promise((resolve, reject) => {
      const reader = new FileReader();
      bar.hidden = false;
      bar.value = 0;
      reader.onprogress = (e) => { if (e.lengthComputable) bar.value = e.loaded / e.total; };
      reader.onerror = () => { bar.hidden = true; reject(reader.error); };
      reader.onload = () => { bar.hidden = true; resolve(new Uint8Array(reader.result)); };
      reader.readAsArrayBuffer(file);
    });
  }

  // Writes the files into the engine's /files and opens them together: a scene with
  // the mesh it names among them (or one chosen before), else the first file. A
  // scene whose mesh is missing asks for it ("choose NAME"); that mesh opened next completes it.
  async function openFiles(files) {
    if (!files.length) return;
    showError('');
    const paths = [];
    for (const file of files) {
      paths.push('/files/' + safeName(file.name));
      Module.FS.writeFile(paths[paths.length - 1], await readFile(file));
    }
    const main = paths.find((p) => /\.json$/i.test(p)) || paths[0];
    $('status').textContent = 'opening ' + main.split('/').pop() + '…';
    await new Promise((r) => setTimeout(r, 0));  // let the page paint the message
    const r = run({ cmd: 'open', paths });
    if (!r) return;
    shown.loadError = r.load_error;
    if (r.load_error) showError(r.load_error, true);  // web/main.cpp logged it
    else refresh(command({ cmd: 'state' }));
  }

  for (const id of ['open-mesh', 'open-scene']) {
    $(id).addEventListener('change', () => {
      openFiles([...$(id).files]).catch((e) => showError(e.message));
      $(id).value = '';
    });
  }
  const view = $('view');
  view.addEventListener('dragover', (e) => { e.preventDefault(); $('drop-hint').hidden = false; });
  view.addEventListener('dragleave', () => { $('drop-hint').hidden = true; });
  view.addEventListener('drop', (e) => {
    e.preventDefault();
    $('drop-hint').hidden = true;
    openFiles([...e.dataTransfer.files]).catch((err) => showError(err.message));
  });

  // ---- pointer -------------------------------------------------------------------

  function canvasPoint(e) {
    const rect = overlayCanvas.getBoundingClientRect();
    const sx = overlayCanvas.width / rect.width, sy = overlayCanvas.height / rect.height;
    return [(e.clientX - rect.left) * sx, (e.clientY - rect.top) * sy];
  }
  const pointer = (kind, e) => {
    const [x, y] = canvasPoint(e);
    Module.ccall('vfsd_pointer', null, ['number', 'number', 'number', 'number', 'number'],
                 [kind, x, y, e.button === undefined ? 0 : e.button, e.shiftKey ? 1 : 0]);
  };
  overlayCanvas.addEventListener('pointerdown', (e) => {
    if (!started) return;
    overlayCanvas.focus();
    overlayCanvas.setPointerCapture(e.pointerId);
    pointer(0, e);
    e.preventDefault();
  });
  overlayCanvas.addEventListener('pointermove', (e) => { if (started) pointer(1, e); });
  overlayCanvas.addEventListener('pointerup', (e) => { if (started) pointer(2, e); });
  overlayCanvas.addEventListener('pointercancel', (e) => { if (started) pointer(2, e); });
  overlayCanvas.addEventListener('pointerleave', (e) => { if (started && !e.buttons) pointer(3, e); });
  overlayCanvas.addEventListener('contextmenu', (e) => e.preventDefault());
  overlayCanvas.addEventListener('wheel', (e) => {
    if (!started) return;
    e.preventDefault();
    const [x, y] = canvasPoint(e);
    const lines = e.deltaMode === 1 ? 33 : 1;
    Module.ccall('vfsd_wheel', null, ['number', 'number', 'number'], [e.deltaY * lines, x, y]);
  }, { passive: false });

  // ---- keyboard: the desktop editor's shortcuts -----------------------------------

  // The editor's key table decides what a key does (docs/commands.md). The page
  // takes keys at the document, before the focused control: Space plays / pauses
  // wherever the focus is, except in a text field, and never activates a button
  // or toggles a checkbox; Enter still activates a focused button.
  const textField = 'input:not([type]), input[type=text], input[type=number], input[type=search], ' +
                    'input[type=email], input[type=url], input[type=password], textarea, select';
  const typing = (t) => t.isContentEditable || (t.matches && t.matches(textField));
  document.addEventListener('keydown', (e) => {
    if (!started || e.altKey) return;
    const t = e.target;
    if (e.key === 'Escape' && !$('error-box').hidden) {
      dismissError();
      e.preventDefault();
      return;
    }
    if (typing(t) || (e.key === 'Enter' && t.matches && t.matches('button, a[href], input[type=file]'))) return;
    // A held key runs its command once, as in the desktop (held Space would toggle play on and off).
    if (e.repeat) {
      if (e.key === ' ') e.preventDefault();
      return;
    }
    const r = run({ cmd: 'key', key: e.key, ctrl: e.ctrlKey || e.metaKey, shift: e.shiftKey });
    if ((r && r.handled) || e.key === ' ') e.preventDefault();
  }, true);
  // A button or checkbox activates on Space's keyup: that is the editor's too.
  document.addEventListener('keyup', (e) => {
    if (started && e.key === ' ' && !typing(e.target)) e.preventDefault();
  }, true);
  // A clicked button gives the focus back to the page, so keys go to the editor.
  document.addEventListener('click', (e) => {
    const button = e.target.closest && e.target.closest('button');
    if (button && e.detail > 0) button.blur();
  });

  // ---- the automation API (docs/web.md) -------------------------------------------

  // Resolves on the first frame whose state satisfies `done` (rejects after `frames`).
  function waitFor(done, frames = 100000) {
    Module.ccall('vfsd_wake', null, [], []);
    return new Promise((resolve, reject) => {
      let n = 0;
      frameWaiters.push((s) => {
        try {
          if (done(s)) { resolve(s); return true; }
        } catch (e) { reject(e); return true; }
        if (++n > frames) { reject(new Error('vfsd: gave up waiting')); return true; }
        return false;
      });
    });
  }

  // Canvas pixels to page (CSS) coordinates.
  function toPage([x, y]) {
    const rect = overlayCanvas.getBoundingClientRect();
    return [rect.left + x * rect.width / overlayCanvas.width, rect.top + y * rect.height / overlayCanvas.height];
  }

  const api = {
    ready,
    command,
    loadScene: async (scene) => {
      await ready;
      const s = command({ cmd: 'load-scene', scene });
      refresh(s);
      await waitFor(() => true);  // drawn once
      return api.stats();
    },
    open: async (path) => {
      await ready;
      const r = command(Array.isArray(path) ? { cmd: 'open', paths: path } : { cmd: 'open', path });
      if (r.load_error) throw new Error(r.load_error);
    },
    runTo: async (t) => {
      await ready;
      command({ cmd: 'set-time', t });
      const target = command({ cmd: 'state' }).target_time;
      await waitFor((s) => {
        if (s.target_time !== target) throw new Error('vfsd.runTo: the target time changed');
        return s.stats.time === target && !s.moving;
      });
      return api.stats();
    },
    stats: () => command({ cmd: 'state' }).stats,
    // When the steps of a frame last reached the target time, on performance.now()'s
    // clock (null before): the shape is computed then, and drawn after.
    reachedTargetAt: () => reachedTargetAt,
    state: () => command({ cmd: 'state' }),
    positions: () => array(0),
    regionS: () => array(1),
    positionsChecksum: () => command({ cmd: 'checksum' }).checksum,
    // Page (CSS) coordinates of points in mesh space, for aiming the pointer.
    project: (points) => {
      const r = command({ cmd: 'project', points });
      return { eye: r.eye, pixels: r.pixels.map(toPage) };
    },
    // Page coordinates of a point on each part of the handle gizmo ('centre', 'x',
    // 'y', 'z', 'ring-x', 'ring-y', 'ring-z') and of its centre; null without a handle.
    gizmo: () => {
      const r = command({ cmd: 'gizmo-parts' });
      if (!r.parts) return null;
      const parts = {};
      for (const [name, p] of Object.entries(r.parts)) parts[name] = toPage(p);
      return { parts, centre: toPage(r.centre) };
    },
    exportMesh: (format) => exportMesh(format).data,
    exportScene: () => exportScene().scene,
    script: async (actions) => {
      await ready;
      command({ cmd: 'script', actions });
      const s = await waitFor((st) => st.script && st.script.done);
      if (s.script.error) throw new Error(s.script.error);
    },
    frames: (n) => waitFor(() => --n <= 0),
    // Frames drawn since the page loaded (none while nothing changes).
    framesDrawn: () => frameCount,
    // The autosave: `behind` while the session has changes it does not hold yet,
    // `stored` once every autosave reached IndexedDB.
    autosave: () => {
      const s = command({ cmd: 'state' }).autosave;
      return { offer: s.offer, behind: s.behind, stored: autosaveStore.written === autosaveStore.writes && !autosaveStore.syncing,
               writes: autosaveStore.writes, error: autosaveStore.error };
    },
  };
  window.vfsd = api;
})();
