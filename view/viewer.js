/* viewer.js - the script of a `pomlab view` page (docs/view.md). Reads the
 * scene (JSON in #pom-scene, written by cli/cli_view.c: every length in
 * metres, fixed frame, z up) and draws it with three.js r111: only APIs
 * that release has (BufferGeometry.setAttribute, THREE.VertexColors, no
 * THREE.MathUtils). Reports in #status, after the first render, the bodies
 * drawn (data-bodies), the script errors (data-errors), whether WebGL ran
 * (data-webgl), the frames and the frame shown. URL fragment: #frame=N shows
 * frame N; #play starts the animation; #tiles=START,COUNT,COLS,W,H draws
 * frames START.. as a grid of W x H tiles (pomlab view --mp4). */
(function () {
  'use strict';
  var statusEl = document.getElementById('status');
  var errors = [];
  function noteError(msg) {
    errors.push(String(msg));
    statusEl.setAttribute('data-errors', String(errors.length));
    var box = document.getElementById('errors');
    if (box) {
      box.textContent = errors.join('\n');
      box.style.display = 'block';
    }
  }
  window.addEventListener('error', function (e) {
    noteError(e.message || 'script error');
  });

  var S = JSON.parse(document.getElementById('pom-scene').textContent);
  var hash = {};
  location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
    var p = kv.split('=');
    if (p[0]) hash[p[0]] = p.length > 1 ? decodeURIComponent(p[1]) : '1';
  });
  var tiles = null;
  if (hash.tiles) {
    var tv = hash.tiles.split(',').map(Number);
    tiles = {start: tv[0] | 0, count: tv[1] | 0, cols: tv[2] | 0, w: tv[3] | 0, h: tv[4] | 0};
  }

  /* ---- page layout --------------------------------------------------------- */
  var app = document.createElement('div');
  app.id = 'app';
  document.body.appendChild(app);
  var stage = document.createElement('div');
  stage.id = 'stage';
  app.appendChild(stage);
  var canvas = document.createElement('canvas');
  canvas.id = 'view';
  stage.appendChild(canvas);
  var labels = document.createElement('div');
  labels.id = 'labels';
  stage.appendChild(labels);
  var bar = document.createElement('div');
  bar.id = 'toolbar';
  stage.appendChild(bar);
  var errBox = document.createElement('pre');
  errBox.id = 'errors';
  stage.appendChild(errBox);
  var side = null;
  if ((S.trace || S.workspace) && !tiles) {
    side = document.createElement('div');
    side.id = 'side';
    app.appendChild(side);
  }
  if (tiles) document.body.className = 'tiles';

  function el(tag, parent, text, cls) {
    var e = document.createElement(tag);
    if (text) e.textContent = text;
    if (cls) e.className = cls;
    parent.appendChild(e);
    return e;
  }

  el('div', bar, S.title, 'title');
  var resetBtn = el('button', bar, 'reset view');
  resetBtn.id = 'reset';
  var info = el('span', bar, '', 'info');
  if (!S.trace) {
    var e = S.euler_deg;
    info.textContent = 'platform at ZYX Euler (' + e.map(function (x) {
      return (+x).toFixed(2);
    }).join(', ') + ') deg';
  }
  el('span', bar, 'drag: orbit, right-drag: pan, wheel: zoom', 'hint');

  /* ---- three.js scene -------------------------------------------------------- */
  var renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true,
                                          preserveDrawingBuffer: true});
  renderer.setPixelRatio(1);
  statusEl.setAttribute('data-webgl', '1');
  var scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  var camera = new THREE.PerspectiveCamera(30, 1, 1e-4, 100);
  camera.up.set(0, 0, 1);
  scene.add(camera);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  var sun = new THREE.DirectionalLight(0xffffff, 0.65);
  sun.position.set(0.4, 0.6, 1.0);
  camera.add(sun);
  var fill = new THREE.DirectionalLight(0xffffff, 0.25);
  fill.position.set(-1, -0.5, 0.3);
  scene.add(fill);

  function v3(a) { return new THREE.Vector3(a[0], a[1], a[2]); }
  var Y = new THREE.Vector3(0, 1, 0);

  /* a rod from a to b (Vector3), radius r */
  function rod(a, b, r, mat) {
    var d = b.clone().sub(a), len = d.length();
    var m = new THREE.Mesh(new THREE.CylinderBufferGeometry(r, r, Math.max(len, 1e-9), 20), mat);
    m.position.copy(a).add(b).multiplyScalar(0.5);
    if (len > 0) m.quaternion.setFromUnitVectors(Y, d.normalize());
    return m;
  }

  /* the platform blue; per limb, its first body orange and its second teal */
  function bodyMaterial(M, b) {
    var c = b === M.platform ? 0x4477aa : b === 0 ? 0x9e9e9e : (b % 2 ? 0x44aa99 : 0xee7733);
    return new THREE.MeshPhongMaterial({color: c, shininess: 40});
  }

  function makeShape(s, mat) {
    var m;
    if (s.kind === 'segment') return rod(v3(s.from), v3(s.to), s.radius, mat);
    if (s.kind === 'box') {
      m = new THREE.Mesh(new THREE.BoxBufferGeometry(s.size[0], s.size[1], s.size[2]), mat);
      var a = v3(s.axis).normalize(), b = v3(s.axis2).normalize();
      var c = new THREE.Vector3().crossVectors(a, b);
      m.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(a, b, c));
      m.position.copy(v3(s.center));
      return m;
    }
    if (s.kind === 'arc') {
      var o = v3(s.center), f = v3(s.from).sub(o), t = v3(s.to).sub(o);
      var R = f.length(), e1 = f.clone().normalize(), tn = t.clone().normalize();
      var ang = Math.acos(Math.max(-1, Math.min(1, e1.dot(tn))));
      var e2 = tn.clone().sub(e1.clone().multiplyScalar(e1.dot(tn)));
      if (e2.length() < 1e-9) e2 = new THREE.Vector3(0, 0, 1).cross(e1);
      e2.normalize();
      var e3 = new THREE.Vector3().crossVectors(e1, e2);
      m = new THREE.Mesh(new THREE.TorusBufferGeometry(R, s.radius, 10, 48, Math.max(ang, 1e-3)),
                         mat);
      m.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(e1, e2, e3));
      m.position.copy(o);
      return m;
    }
    if (s.kind === 'disc') {
      m = new THREE.Mesh(new THREE.CylinderBufferGeometry(s.radius, s.radius,
                                                          Math.max(s.thickness, 1e-9), 48), mat);
      m.quaternion.setFromUnitVectors(Y, v3(s.axis).normalize());
      m.position.copy(v3(s.center));
      return m;
    }
    throw new Error('unknown shape kind ' + s.kind);
  }

  var jointColors = {spherical: 0x333333, revolute: 0x2255cc, prismatic: 0xd9a400,
                     universal: 0x8844aa};
  function jointMarker(j, size) {
    var g = new THREE.Group();
    var col = j.actuator >= 0 ? 0xcc2222 : jointColors[j.type];
    var mat = new THREE.MeshPhongMaterial({color: col, shininess: 60});
    var p = v3(j.point), a = v3(j.axis), r = size;
    if (j.type === 'spherical') {
      var s = new THREE.Mesh(new THREE.SphereBufferGeometry(1.1 * r, 16, 12), mat);
      s.position.copy(p);
      g.add(s);
    } else if (j.type === 'revolute') {
      g.add(rod(p.clone().addScaledVector(a, -1.6 * r), p.clone().addScaledVector(a, 1.6 * r),
                0.7 * r, mat));
    } else if (j.type === 'prismatic') {
      var sleeve = new THREE.MeshPhongMaterial({color: col, transparent: true, opacity: 0.45});
      g.add(rod(p.clone().addScaledVector(a, -5 * r), p.clone().addScaledVector(a, -0.5 * r),
                1.5 * r, sleeve));
    } else if (j.type === 'universal') {
      var b = v3(j.axis2);
      g.add(rod(p.clone().addScaledVector(a, -1.5 * r), p.clone().addScaledVector(a, 1.5 * r),
                0.5 * r, mat));
      g.add(rod(p.clone().addScaledVector(b, -1.5 * r), p.clone().addScaledVector(b, 1.5 * r),
                0.5 * r, mat));
    }
    return g;
  }

  /* ---- the mechanisms -------------------------------------------------------- */
  var mechs = [], bodiesDrawn = 0, nFrames = 1;
  var slotX = 0;
  S.mechs.forEach(function (M) {
    var root = new THREE.Group();
    scene.add(root);
    var sc = M.scale, groups = [], drawn = {};
    for (var b = 0; b < M.bodies.length; ++b) {
      var g = new THREE.Group();
      g.matrixAutoUpdate = false;
      root.add(g);
      groups.push(g);
    }
    M.shapes.forEach(function (s) {
      groups[s.body].add(makeShape(s, bodyMaterial(M, s.body)));
      if (s.body !== 0) drawn[s.body] = 1;
    });
    M.joints.forEach(function (j) {
      groups[j.bodies[0]].add(jointMarker(j, 0.055 * sc));
      if (j.actuator >= 0) {
        var a = v3(j.axis).normalize(), len = 1.2 * sc;
        var o = v3(j.point).addScaledVector(a, j.type === 'prismatic' ? -0.5 * len : 0);
        groups[j.bodies[0]].add(new THREE.ArrowHelper(a, o, len, 0xcc2222, 0.18 * len,
                                                      0.08 * len));
      }
    });
    /* the base frame and O */
    root.add(new THREE.AxesHelper(0.9 * sc));
    var O = new THREE.Mesh(new THREE.SphereBufferGeometry(0.07 * sc, 16, 12),
                           new THREE.MeshPhongMaterial({color: 0x000000}));
    root.add(O);
    bodiesDrawn += Object.keys(drawn).length;
    nFrames = Math.max(nFrames, M.frames.length);
    /* its size, for the layout below */
    scene.updateMatrixWorld(true);
    setPose(groups, M.frames[0]);
    root.updateMatrixWorld(true);
    var box = new THREE.Box3().setFromObject(root);
    var half = Math.max(Math.abs(box.min.x), Math.abs(box.max.x), 0.5 * sc);
    var lab = el('div', labels, M.arch_label + ' \u00b7 ' + M.label, 'label');
    mechs.push({M: M, root: root, groups: groups, label: lab, top: box.max.z, half: half,
                bottom: Math.min(box.min.z, -0.5 * sc), sc: sc});
  });
  /* side by side: each at the right of the previous, spaced by their size;
   * more than four in a regular grid of ceil(sqrt(n)) columns, the cells as
   * large as the largest mechanism, the next row below */
  (function () {
    var n = mechs.length;
    if (n <= 4) {
      mechs.forEach(function (m, i) {
        if (i > 0) slotX += m.half;
        m.root.position.x = slotX;
        slotX += m.half + 0.6 * m.sc;
      });
      return;
    }
    var cols = Math.ceil(Math.sqrt(n)), w = 0, h = 0, sc = 0;
    mechs.forEach(function (m) {
      w = Math.max(w, 2 * m.half);
      h = Math.max(h, m.top - m.bottom);
      sc = Math.max(sc, m.sc);
    });
    var cw = w + 0.6 * sc, ch = h + 0.8 * sc;
    mechs.forEach(function (m, i) {
      m.root.position.x = (i % cols) * cw;
      m.root.position.z = -Math.floor(i / cols) * ch;
    });
    slotX = (cols - 1) * cw + 0.5 * w + 0.6 * sc;
  })();

  function setPose(groups, pose) {
    for (var b = 0; b < groups.length; ++b) {
      var p = pose.slice(12 * b, 12 * b + 12);
      groups[b].matrix.set(p[0], p[1], p[2], p[9], p[3], p[4], p[5], p[10], p[6], p[7], p[8],
                           p[11], 0, 0, 0, 1);
      groups[b].matrixWorldNeedsUpdate = true;
    }
  }

  /* ---- the workspace sphere ---------------------------------------------------- */
  var viridis = [[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551],
                 [0.369, 0.789, 0.383], [0.993, 0.906, 0.144]];
  function cmap(x) {
    x = Math.max(0, Math.min(1, x)) * 4;
    var i = Math.min(3, Math.floor(x)), f = x - i, a = viridis[i], b = viridis[i + 1];
    return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
  }
  var pointer = null, wsRadius = 0;
  /* --capability: a figure per sampled direction, the nearest sample colours
   * each vertex; pale grey where not evaluated (a limit, a failure) */
  var CAP = S.workspace && S.workspace.capability ? S.workspace.capability : null;
  function capValue(it, ia) {
    var jt = Math.min(CAP.n_tilt - 1, Math.round(it / CAP.stride_tilt));
    var ja = Math.min(CAP.n_azimuth - 1, Math.round(ia / CAP.stride_azimuth));
    return CAP.value[jt * CAP.n_azimuth + ja];
  }
  function capColor(it, ia) {
    var v = capValue(it, ia);
    if (v === null || !isFinite(v)) return [0.93, 0.93, 0.93];
    return cmap(CAP.hi > CAP.lo ? (v - CAP.lo) / (CAP.hi - CAP.lo) : 0.5);
  }
  if (S.workspace) {
    var W = S.workspace, sc0 = S.mechs[0].scale;
    wsRadius = 1.1 * sc0;
    var wroot = new THREE.Group();
    scene.add(wroot);
    slotX += wsRadius + 0.3 * sc0;
    wroot.position.x = slotX;
    slotX += wsRadius;
    var nt = W.n_tilt, na = W.n_azimuth, pos = [], col = [], idx = [];
    for (var it = 0; it < nt; ++it)
      for (var ia = 0; ia < na; ++ia) {
        var th = it * W.tilt_step, az = 2 * Math.PI * ia / (na - 1), k = it * na + ia;
        pos.push(wsRadius * Math.sin(th) * Math.cos(az), wsRadius * Math.sin(th) * Math.sin(az),
                 wsRadius * Math.cos(th));
        var c = W.state[k] === 2 ? [0.86, 0.86, 0.86] : cmap(W.dexterity[k]);
        if (CAP && W.state[k] !== 2) c = capColor(it, ia);
        if (W.state[k] === 1) c = [0.55 + 0.45 * c[0] * 0.5, 0.55 + 0.45 * c[1] * 0.5,
                                   0.55 + 0.45 * c[2] * 0.5];
        col.push(c[0], c[1], c[2]);
      }
    for (it = 0; it + 1 < nt; ++it)
      for (ia = 0; ia + 1 < na; ++ia) {
        var q = it * na + ia;
        idx.push(q, q + na, q + 1, q + 1, q + na, q + na + 1);
      }
    var geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    geo.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
    geo.setIndex(idx);
    geo.computeVertexNormals();
    wroot.add(new THREE.Mesh(geo, new THREE.MeshLambertMaterial({
      vertexColors: THREE.VertexColors, side: THREE.DoubleSide})));
    if (W.outline.length >= 6) {
      var op = [];
      for (var i = 0; i < W.outline.length; ++i) op.push(1.012 * wsRadius * W.outline[i]);
      var lg = new THREE.BufferGeometry();
      lg.setAttribute('position', new THREE.Float32BufferAttribute(op, 3));
      wroot.add(new THREE.LineLoop(lg, new THREE.LineBasicMaterial({color: 0xd62728})));
    }
    wroot.add(new THREE.AxesHelper(1.25 * wsRadius));
    pointer = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(0, 0, 0),
                                    1.3 * wsRadius, 0x000000, 0.12 * wsRadius, 0.06 * wsRadius);
    wroot.add(pointer);
    var wl = el('div', labels, 'pointing directions, ' +
                (CAP ? CAP.name + ' (' + CAP.unit + ')' : '1/kappa'), 'label');
    mechs.push({M: null, root: wroot, groups: [], label: wl, top: 1.3 * wsRadius});
  }

  /* ---- frames ----------------------------------------------------------------- */
  var frame = 0;
  function clampFrame(k) { return Math.max(0, Math.min(nFrames - 1, k | 0)); }
  function showFrame(k) {
    frame = clampFrame(k);
    mechs.forEach(function (m) {
      if (!m.M) return;
      var F = m.M.frames;
      setPose(m.groups, F[Math.min(frame, F.length - 1)]);
    });
    if (pointer) {
      var P = S.mechs[0].frames[Math.min(frame, S.mechs[0].frames.length - 1)];
      var p0 = 12 * S.mechs[0].platform;
      pointer.setDirection(new THREE.Vector3(P[p0 + 2], P[p0 + 5], P[p0 + 8]).normalize());
    }
    statusEl.setAttribute('data-frame', String(frame));
    if (S.trace) {
      var t = S.trace.t[frame] * 1e3;
      info.textContent = 't = ' + t.toFixed(3) + ' ms (frame ' + frame + ' of ' + nFrames + ')';
      if (slider) slider.value = String(frame);
      drawPlots();
    }
  }

  /* ---- camera: orbit, pan, zoom, reset ---------------------------------------- */
  scene.updateMatrixWorld(true);
  var all = new THREE.Box3();
  mechs.forEach(function (m) { all.expandByObject(m.root); });
  var center0 = all.getCenter(new THREE.Vector3());
  var radius0 = Math.max(all.getSize(new THREE.Vector3()).length() * 0.5, 1e-3);
  var cam = {};
  function resetView() {
    cam.az = -Math.PI / 2 + 0.55;
    cam.el = 0.42;
    cam.dist = radius0 / Math.sin(15 * Math.PI / 180) * 1.05;
    cam.target = center0.clone();
  }
  resetView();
  function placeCamera() {
    var ce = Math.cos(cam.el);
    camera.position.set(cam.target.x + cam.dist * ce * Math.cos(cam.az),
                        cam.target.y + cam.dist * ce * Math.sin(cam.az),
                        cam.target.z + cam.dist * Math.sin(cam.el));
    camera.near = cam.dist / 100;
    camera.far = cam.dist * 100;
    camera.lookAt(cam.target);
    camera.updateProjectionMatrix();
  }
  var drag = null;
  canvas.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  canvas.addEventListener('pointerdown', function (e) {
    drag = {x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey};
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointerup', function () { drag = null; });
  canvas.addEventListener('pointermove', function (e) {
    if (!drag) return;
    var dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) {
      var s = cam.dist * 0.0015;
      var right = new THREE.Vector3(), up = new THREE.Vector3();
      camera.matrixWorld.extractBasis(right, up, new THREE.Vector3());
      cam.target.addScaledVector(right, -dx * s).addScaledVector(up, dy * s);
    } else {
      cam.az -= dx * 0.008;
      cam.el = Math.max(-1.55, Math.min(1.55, cam.el + dy * 0.008));
    }
    requestRender();
  });
  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    cam.dist *= Math.exp(0.001 * e.deltaY);
    requestRender();
  }, {passive: false});
  resetBtn.addEventListener('click', function () { resetView(); requestRender(); });
  window.addEventListener('keydown', function (e) {
    if (e.key === 'r') { resetView(); requestRender(); }
    if (e.key === ' ' && playBtn) { e.preventDefault(); togglePlay(); }
  });

  /* ---- trace: slider, play, plots ----------------------------------------------- */
  var slider = null, playBtn = null, plot = null, playing = false, lastTick = 0;
  if (S.trace && side) {
    var T = S.trace;
    el('div', side, 'maneuver ' + T.source, 'ptitle');
    var row = el('div', side, '', 'controls');
    playBtn = el('button', row, 'play');
    playBtn.id = 'play';
    slider = el('input', row);
    slider.id = 'slider';
    slider.type = 'range';
    slider.min = '0';
    slider.max = String(nFrames - 1);
    slider.value = '0';
    slider.addEventListener('input', function () { showFrame(+slider.value); requestRender(); });
    playBtn.addEventListener('click', togglePlay);
    plot = el('canvas', side);
    plot.id = 'plots';
    plot.width = 380;
    plot.height = 480;
    plot.addEventListener('click', function (e) {
      var r = plot.getBoundingClientRect(), x = e.clientX - r.left;
      var u = (x - 52) / (plot.width - 62), t0 = T.t[0], t1 = T.t[T.t.length - 1];
      var tt = t0 + u * (t1 - t0), best = 0;
      for (var i = 0; i < T.t.length; ++i)
        if (Math.abs(T.t[i] - tt) < Math.abs(T.t[best] - tt)) best = i;
      showFrame(best);
      requestRender();
    });
  }
  if (S.workspace && side) {
    var W2 = S.workspace;
    el('div', side, 'workspace of ' + S.mechs[0].label, 'ptitle');
    el('div', side, 'sphere: platform normal R e_z for tilts 0-' +
       ((W2.n_tilt - 1) * W2.tilt_step * 180 / Math.PI).toFixed(0) +
       ' deg, torsion 0; colour: ' + (CAP ? CAP.name + ', ' + CAP.description + ' (' + CAP.unit +
       '), sampled every ' + (CAP.stride_tilt * W2.tilt_step * 180 / Math.PI).toFixed(0) +
       ' deg of tilt and ' + (360 * CAP.stride_azimuth / (W2.n_azimuth - 1)).toFixed(0) +
       ' deg of azimuth' + (CAP.joints ? ', ' + CAP.joints + ' joints' : '') + ' (grey: not assemblable, pale: not evaluated)'
         : 'dexterity 1/kappa (grey: not assemblable, pale: a limit violated)'), 'note');
    var cb = el('div', side, '', 'colorbar');
    cb.style.background = 'linear-gradient(to right,' + [0, 0.25, 0.5, 0.75, 1].map(function (x) {
      var c = cmap(x);
      return 'rgb(' + c.map(function (v) { return Math.round(255 * v); }).join(',') + ')';
    }).join(',') + ')';
    var cbl = el('div', side, '', 'cbl');
    function capNum(v) { return v === null ? 'none' : (+v).toPrecision(4); }
    el('span', cbl, CAP ? capNum(CAP.lo) : '0');
    el('span', cbl, CAP ? CAP.name + ' (' + CAP.unit + ')' : 'dexterity 1/kappa');
    el('span', cbl, CAP ? capNum(CAP.hi) : '1');
    el('div', side, W2.rdw_half_width >= 0
      ? 'red outline: regular dexterous workspace, Euler cube +-' +
        (W2.rdw_half_width * 180 / Math.PI).toFixed(1) + ' deg at 1/kappa >= ' +
        W2.dexterity_min + ' (pointing directions of its poses at psi = 0)'
      : 'no regular dexterous workspace: the home pose fails', 'note');
  }

  function togglePlay() {
    playing = !playing;
    playBtn.textContent = playing ? 'pause' : 'play';
    if (playing && frame >= nFrames - 1) showFrame(0);
    lastTick = 0;
    requestRender();
  }

  var plotColors = ['#cc3311', '#0077bb', '#009988'];
  function drawPlots() {
    if (!plot) return;
    var T = S.trace, ctx = plot.getContext('2d'), W = plot.width, H = plot.height;
    ctx.clearRect(0, 0, W, H);
    ctx.font = '11px sans-serif';
    var n = T.t.length, t0 = T.t[0], t1 = T.t[n - 1] > t0 ? T.t[n - 1] : t0 + 1;
    var panels = [
      {name: 'actuator q (' + T.unit + ')', get: function (i, a) { return T.q[3 * i + a] * T.to_display; },
       lines: 3, target: T.target.map(function (v) { return v * T.to_display; })},
      {name: 'voltage u (V)', get: function (i, a) { return T.u[3 * i + a]; }, lines: 3},
      {name: 'pointing error (deg)', get: function (i) { return T.err[i] * 180 / Math.PI; },
       lines: 1}];
    var ph = H / panels.length, x0 = 52, x1 = W - 10;
    function X(t) { return x0 + (t - t0) / (t1 - t0) * (x1 - x0); }
    panels.forEach(function (P, p) {
      var top = p * ph + 16, bot = (p + 1) * ph - 18, lo = Infinity, hi = -Infinity, i, a;
      for (i = 0; i < n; ++i)
        for (a = 0; a < P.lines; ++a) {
          var v = P.get(i, a);
          if (v === null || !isFinite(v)) continue;
          lo = Math.min(lo, v);
          hi = Math.max(hi, v);
        }
      if (P.target) P.target.forEach(function (v) { lo = Math.min(lo, v); hi = Math.max(hi, v); });
      if (!(hi > lo)) { hi = (isFinite(hi) ? hi : 0) + 1; lo = hi - 2; }
      var pad = 0.05 * (hi - lo);
      lo -= pad;
      hi += pad;
      function Yv(v) { return bot - (v - lo) / (hi - lo) * (bot - top); }
      ctx.strokeStyle = '#999';
      ctx.strokeRect(x0, top, x1 - x0, bot - top);
      ctx.fillStyle = '#222';
      ctx.fillText(P.name, x0, top - 4);
      ctx.fillText(hi.toPrecision(3), 2, top + 9);
      ctx.fillText(lo.toPrecision(3), 2, bot);
      if (lo < 0 && hi > 0) {
        ctx.strokeStyle = '#ddd';
        ctx.beginPath();
        ctx.moveTo(x0, Yv(0));
        ctx.lineTo(x1, Yv(0));
        ctx.stroke();
      }
      for (a = 0; a < P.lines; ++a) {
        ctx.strokeStyle = P.lines > 1 ? plotColors[a] : '#333';
        ctx.beginPath();
        for (i = 0; i < n; ++i) {
          var y = P.get(i, a);
          if (y === null) continue;
          if (i) ctx.lineTo(X(T.t[i]), Yv(y)); else ctx.moveTo(X(T.t[i]), Yv(y));
        }
        ctx.stroke();
        if (P.target) {
          ctx.setLineDash([4, 3]);
          ctx.beginPath();
          ctx.moveTo(x0, Yv(P.target[a]));
          ctx.lineTo(x1, Yv(P.target[a]));
          ctx.stroke();
          ctx.setLineDash([]);
        }
      }
      ctx.fillStyle = '#222';
      if (p === panels.length - 1) {
        ctx.fillText('0', x0, bot + 13);
        ctx.fillText((t1 * 1e3).toFixed(1) + ' ms', x1 - 40, bot + 13);
      }
    });
    /* the cursor at the frame shown */
    var xc = X(T.t[frame]);
    ctx.strokeStyle = '#000';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(xc, 0);
    ctx.lineTo(xc, H);
    ctx.stroke();
    ctx.lineWidth = 1;
  }

  /* ---- rendering ---------------------------------------------------------------- */
  var pending = false;
  function requestRender() {
    if (!pending) {
      pending = true;
      requestAnimationFrame(tick);
    }
  }
  function resize() {
    var w = stage.clientWidth || window.innerWidth, h = stage.clientHeight || window.innerHeight;
    if (tiles) {
      w = tiles.w * tiles.cols;
      h = tiles.h * Math.ceil(tiles.count / tiles.cols);
    }
    renderer.setSize(w, h, false);
    canvas.style.width = w + 'px';
    canvas.style.height = h + 'px';
    camera.aspect = tiles ? tiles.w / tiles.h : w / h;
    camera.updateProjectionMatrix();
  }
  function placeLabels() {
    var w = canvas.clientWidth, h = canvas.clientHeight;
    mechs.forEach(function (m) {
      var p = new THREE.Vector3(0, 0, m.top).applyMatrix4(m.root.matrixWorld).project(camera);
      m.label.style.left = ((p.x + 1) / 2 * w) + 'px';
      m.label.style.top = ((1 - p.y) / 2 * h - 18) + 'px';
    });
  }
  function render() {
    placeCamera();
    if (tiles) {
      renderer.setScissorTest(true);
      for (var i = 0; i < tiles.count; ++i) {
        var cx = i % tiles.cols, cy = Math.floor(i / tiles.cols);
        var rows = Math.ceil(tiles.count / tiles.cols);
        showFrame(tiles.start + i);
        var y = (rows - 1 - cy) * tiles.h;
        renderer.setViewport(cx * tiles.w, y, tiles.w, tiles.h);
        renderer.setScissor(cx * tiles.w, y, tiles.w, tiles.h);
        renderer.render(scene, camera);
      }
    } else {
      renderer.render(scene, camera);
      placeLabels();
    }
  }
  function tick(now) {
    pending = false;
    if (playing) {
      if (lastTick) {
        /* real time slowed 50 times: a 100 ms maneuver lasts 5 s */
        var T = S.trace, dt = (now - lastTick) / 1000 / 50, t = T.t[frame] + dt, k = frame;
        while (k + 1 < nFrames && T.t[k + 1] <= t) ++k;
        if (k === frame && k + 1 < nFrames) ++k;
        showFrame(k);
        if (frame >= nFrames - 1) togglePlay();
      }
      lastTick = now;
    }
    render();
    if (playing) requestRender();
  }
  window.addEventListener('resize', function () { resize(); requestRender(); });

  /* the first render, then the status the browser test reads */
  resize();
  var f0 = hash.frame === 'last' ? nFrames - 1 : hash.frame !== undefined ? +hash.frame : S.frame;
  showFrame(f0 || 0);
  render();
  statusEl.setAttribute('data-bodies', String(bodiesDrawn));
  statusEl.setAttribute('data-frames', String(nFrames));
  statusEl.setAttribute('data-failed-frames', String(S.failed_frames || 0));
  statusEl.setAttribute('data-errors', String(errors.length));
  statusEl.setAttribute('data-capability', CAP ? CAP.name : '');
  statusEl.setAttribute('data-ready', '1');
  if (hash.play && playBtn) togglePlay(); /* #play: start the animation at once */
})();
