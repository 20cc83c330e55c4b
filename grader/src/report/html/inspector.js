// The report's 3D half-edge inspector: hand-written, canvas 2D, no
// library, nothing fetched (the page opens from file://). Each case's data
// is a JSON blob written by inspector.rs. The student's mesh may be
// anything (ids out of range, non-finite positions, broken next loops): every id
// is bounds-checked and every walk bounded here, as on the Rust side.
(function () {
  'use strict';
  var KINDS = { v: 'vertex', e: 'edge', f: 'face', h: 'halfedge' };
  var MAX_DEGREE = 64;

  function isId(x, n) { return typeof x === 'number' && x >= 0 && x < n && Math.floor(x) === x; }
  function fmt(x) {
    if (typeof x !== 'number' || !isFinite(x)) { return 'not a number'; }
    return Math.abs(x) < 1e7 ? String(Math.round(x * 1e6) / 1e6) : x.toExponential(3);
  }
  function fmtP(p) { return p ? '(' + fmt(p[0]) + ', ' + fmt(p[1]) + ', ' + fmt(p[2]) + ')' : '(not a finite position)'; }
  function triple(a, i) {
    var x = a[3 * i], y = a[3 * i + 1], z = a[3 * i + 2];
    var ok = typeof x === 'number' && typeof y === 'number' && typeof z === 'number' &&
      isFinite(x) && isFinite(y) && isFinite(z);
    return ok ? [x, y, z] : null;
  }
  // A list of the ids that have a flag, as a lookup.
  function flagSet(list) {
    var set = {};
    (Array.isArray(list) ? list : []).forEach(function (i) { set[i] = 1; });
    return set;
  }
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
  function scale(a, k) { return [a[0] * k, a[1] * k, a[2] * k]; }
  function len(a) { return Math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function newell(ps) {
    var n = [0, 0, 0];
    for (var i = 0; i < ps.length; i++) { n = add(n, cross(ps[i], ps[(i + 1) % ps.length])); }
    return n;
  }

  // A mesh as the script draws it. `full`: the student's records (every
  // pointer); otherwise positions and faces only (the expected result).
  function Model(data, full) {
    var m = this;
    m.full = full;
    var p = data.p || [];
    m.nv = Math.floor(p.length / 3);
    m.pos = [];
    for (var i = 0; i < m.nv; i++) { m.pos.push(triple(p, i)); }
    m.polys = [];
    m.looseH = [];
    m.looseE = [];
    if (full) {
      m.vh = data.vh || []; m.vn = flagSet(data.vn); m.vq = data.vq || null;
      m.eh = data.eh || []; m.en = flagSet(data.en); m.eq = data.eq || null;
      m.fh = data.fh || []; m.fb = flagSet(data.fb);
      m.hr = data.h || [];
      m.ne = m.eh.length; m.nf = m.fh.length; m.nh = Math.floor(m.hr.length / 5);
      m.polyOf = new Int32Array(m.nh).fill(-1);
      // Faces as drawn are the next-cycles of halfedges: what the
      // student's links make, whatever the face ids say.
      var seen = new Uint8Array(m.nh);
      for (var s = 0; s < m.nh; s++) {
        if (seen[s]) { continue; }
        var cyc = [], x = s;
        while (isId(x, m.nh) && !seen[x] && cyc.length <= MAX_DEGREE) { seen[x] = 1; cyc.push(x); x = m.link(x, 1); }
        var vs = cyc.map(function (h) { return m.link(h, 2); });
        var ok = x === s && cyc.length >= 3 && vs.every(function (v) { return isId(v, m.nv) && m.pos[v]; });
        var face = cyc.length ? m.link(cyc[0], 4) : -1;
        var boundary = isId(face, m.nf) && m.fb[face] === 1;
        if (ok && !boundary) {
          var k = m.polys.length;
          m.polys.push({ hs: cyc, vs: vs, face: face });
          cyc.forEach(function (h) { m.polyOf[h] = k; });
        } else {
          Array.prototype.push.apply(m.looseH, cyc);
        }
      }
    } else {
      var fv = data.fv || [], j = 0;
      while (j < fv.length) {
        var n = fv[j], corners = fv.slice(j + 1, j + 1 + n);
        j += 1 + n;
        if (n >= 3 && corners.every(function (v) { return isId(v, m.nv) && m.pos[v]; })) {
          m.polys.push({ hs: null, vs: corners, face: m.polys.length });
        }
      }
      var le = data.le || [];
      for (var q = 0; q + 1 < le.length; q += 2) { m.looseE.push([le[q], le[q + 1]]); }
      m.sid = data.sid || [];
      m.iid = data.iid || [];
      m.nf = m.polys.length;
    }
    // Which way the faces wind: outward normals for shading and culling.
    var c = m.center(), vol = 0;
    m.polys.forEach(function (f) {
      var ps = f.vs.map(function (v) { return m.pos[v]; });
      var nn = newell(ps), mid = scale(ps.reduce(add, [0, 0, 0]), 1 / ps.length);
      vol += (mid[0] - c[0]) * nn[0] + (mid[1] - c[1]) * nn[1] + (mid[2] - c[2]) * nn[2];
    });
    m.outward = vol < 0 ? -1 : 1;
    // Closed: every side used once each way; its back faces never show.
    var dir = {};
    m.polys.forEach(function (f) {
      for (var i = 0; i < f.vs.length; i++) { var k = f.vs[i] + ',' + f.vs[(i + 1) % f.vs.length]; dir[k] = (dir[k] || 0) + 1; }
    });
    m.closed = m.polys.length > 0 && Object.keys(dir).every(function (k) {
      var ab = k.split(','); return dir[k] === 1 && dir[ab[1] + ',' + ab[0]] === 1;
    });
  }
  Model.prototype.link = function (h, k) {
    var x = isId(h, this.nh) ? this.hr[5 * h + k] : -1;
    return typeof x === 'number' ? x : -1;
  };
  Model.prototype.bounds = function () {
    var lo = null, hi = null;
    this.pos.forEach(function (p) {
      if (!p || len(p) > 1e6) { return; }
      if (!lo) { lo = p.slice(); hi = p.slice(); return; }
      for (var k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], p[k]); hi[k] = Math.max(hi[k], p[k]); }
    });
    return lo ? [lo, hi] : [[-1, -1, -1], [1, 1, 1]];
  };
  Model.prototype.center = function () { var b = this.bounds(); return scale(add(b[0], b[1]), 0.5); };
  // A halfedge's two ends (its vertex, its twin's), if both exist.
  Model.prototype.hEnds = function (h) {
    var a = this.link(h, 2), t = this.link(h, 0), b = this.link(t, 2);
    if (!isId(t, this.nh)) { b = this.link(this.link(h, 1), 2); }
    return isId(a, this.nv) && isId(b, this.nv) ? [a, b] : null;
  };
  Model.prototype.eEnds = function (e) {
    return isId(e, this.ne) ? this.hEnds(this.eh[e]) : null;
  };
  // Where an element is, for turning the view to it.
  Model.prototype.place = function (kind, id) {
    var m = this, ps = [];
    if (kind === 'v' && isId(id, m.nv)) { ps = [m.pos[id]]; }
    if (kind === 'e' && m.full) { ps = (m.eEnds(id) || []).map(function (v) { return m.pos[v]; }); }
    if (kind === 'h' && m.full) { ps = (m.hEnds(id) || []).map(function (v) { return m.pos[v]; }); }
    if (kind === 'f') {
      var poly = m.polyOfFace(id);
      if (poly) { ps = poly.vs.map(function (v) { return m.pos[v]; }); }
    }
    ps = ps.filter(function (p) { return p; });
    return ps.length ? scale(ps.reduce(add, [0, 0, 0]), 1 / ps.length) : null;
  };
  Model.prototype.polyOfFace = function (f) {
    var m = this;
    if (m.full) {
      var k = isId(m.fh[f], m.nh) ? m.polyOf[m.fh[f]] : -1;
      return k >= 0 ? m.polys[k] : null;
    }
    return m.polys[f] || null;
  };
  // The outward normal at `vs`: of the faces that have all of them as
  // corners (an edge's two faces), else of those that have any.
  Model.prototype.normalNear = function (vs) {
    var m = this;
    var sum = function (all) {
      var n = [0, 0, 0];
      m.polys.forEach(function (f) {
        var has = all ? vs.every(function (v) { return f.vs.indexOf(v) >= 0; }) : vs.some(function (v) { return f.vs.indexOf(v) >= 0; });
        if (!has) { return; }
        var nn = newell(f.vs.map(function (v) { return m.pos[v]; })), l = len(nn);
        if (l > 0) { n = add(n, scale(nn, m.outward / l)); }
      });
      return len(n) > 1e-12 ? n : null;
    };
    return sum(true) || sum(false);
  };
  Model.prototype.verticesOf = function (kind, id) {
    var m = this;
    if (kind === 'v') { return isId(id, m.nv) ? [id] : []; }
    if (kind === 'e') { return m.full ? (m.eEnds(id) || []) : []; }
    if (kind === 'h') { return m.full ? (m.hEnds(id) || []) : []; }
    var poly = m.polyOfFace(id);
    return poly ? poly.vs.slice() : [];
  };

  // --- one inspector per case -------------------------------------------

  function el(tag, attrs, text) {
    var e = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) { e.setAttribute(k, attrs[k]); });
    if (text !== undefined) { e.textContent = text; }
    return e;
  }

  function Inspector(root, data) {
    var I = this;
    I.root = root; I.data = data;
    I.models = {};
    if (data.input) { I.models.input = new Model(data.input, true); }
    if (data.expected) { I.models.expected = new Model(data.expected, false); }
    if (data.yours) { I.models.yours = new Model(data.yours, true); }
    I.frames = data.frames && data.frames.list && data.frames.list.length ? data.frames : null;
    if (I.frames) {
      // The first frame is whole, each later one what changed since the
      // one before (new length, then index, value pairs, per array).
      var prev = {};
      I.frameModels = I.frames.list.map(function (fr) {
        var mesh = fr.mesh || {};
        if (!fr.mesh && fr.delta) {
          mesh = {};
          Object.keys(prev).forEach(function (k) { mesh[k] = prev[k]; });
          Object.keys(fr.delta).forEach(function (k) {
            var d = fr.delta[k];
            if (!Array.isArray(d) || !d.length) { delete mesh[k]; return; }
            var arr = (prev[k] || []).slice(0, d[0]);
            for (var i = 1; i + 1 < d.length; i += 2) { if (isId(d[i], d[0])) { arr[d[i]] = d[i + 1]; } }
            for (var j = 0; j < d[0]; j++) { if (arr[j] === undefined) { arr[j] = null; } }
            mesh[k] = arr;
          });
        }
        prev = mesh;
        return new Model(mesh, true);
      });
      I.frame = I.frameModels.length - 1;
      I.models.yours = I.frameModels[I.frame];
    }
    I.layers = { input: true, expected: true, yours: true, back: true, labels: true, arrows: true, dots: true, marks: true, names: true, only: false };
    var big = I.models.yours || I.models.expected || I.models.input;
    if (big && big.nv >= 60) { I.layers.labels = false; }
    // Back faces of a closed surface only clutter the picture.
    if (['input', 'expected', 'yours'].every(function (k) { return !I.models[k] || I.models[k].closed; })) { I.layers.back = false; }
    if (big && big.full && big.nh > 300) { I.layers.arrows = false; }
    if (big && big.nv > 400) { I.layers.dots = false; }
    I.names = {};
    ['input', 'yours', 'expected'].forEach(function (pane) {
      var map = {};
      ((data.names || {})[pane] || []).forEach(function (n) { map[n[0][0] + n[0][1]] = n[1]; });
      I.names[pane] = map;
    });
    I.sel = null;
    I.build();
    I.resetView();
    // `try`'s page opens on what validate() found.
    if (data.select && data.error) { I.selectError(); }
  }

  Inspector.prototype.build = function () {
    var I = this, root = I.root;
    root.removeAttribute('hidden');
    root.classList.remove('pending');
    root.setAttribute('tabindex', '0');
    var bar = el('div', { 'class': 'bar' });
    var errBtn = el('button', { type: 'button', 'class': 'select-error' }, 'select error');
    if (!I.data.error) { errBtn.disabled = true; }
    errBtn.onclick = function () { I.selectError(); };
    var resetBtn = el('button', { type: 'button', 'class': 'reset' }, 'reset view');
    resetBtn.onclick = function () { I.resetView(); };
    var staticBtn = el('button', { type: 'button', 'class': 'static-pictures' }, 'static pictures');
    staticBtn.onclick = function () { showStatic(root); staticBtn.disabled = true; };
    bar.appendChild(errBtn); bar.appendChild(resetBtn); bar.appendChild(staticBtn);
    var toggles = [['input', 'input'], ['expected', 'expected'], ['yours', 'yours'], ['back', 'back faces'],
      ['labels', 'ids'], ['names', 'handout names'], ['arrows', 'halfedges'], ['dots', 'vertices'], ['marks', 'marks'], ['only', 'first problem only']];
    toggles.forEach(function (t) {
      if (['input', 'expected', 'yours'].indexOf(t[0]) >= 0 && !I.models[t[0]]) { return; }
      if (t[0] === 'names' && !I.data.names) { return; }
      var lab = el('label', { 'class': 'toggle' });
      var box = el('input', { type: 'checkbox', 'data-layer': t[0] });
      box.checked = I.layers[t[0]];
      box.onchange = function () { I.layers[t[0]] = box.checked; I.layout(); I.draw(); };
      lab.appendChild(box); lab.appendChild(document.createTextNode(' ' + t[1]));
      bar.appendChild(lab);
    });
    root.appendChild(bar);
    if (I.frames) {
      var fb = el('div', { 'class': 'frames' });
      var slider = el('input', { type: 'range', min: '0', max: String(I.frameModels.length - 1), value: String(I.frame), 'class': 'frame-slider' });
      slider.oninput = function () { I.setFrame(+slider.value); };
      I.frameText = el('span', { 'class': 'frame-text' });
      I.frameBroken = el('span', { 'class': 'frame-broken' });
      fb.appendChild(el('span', {}, 'step through your run: '));
      fb.appendChild(slider); fb.appendChild(I.frameText); fb.appendChild(I.frameBroken);
      if (I.frames.firstBroken !== null && I.frames.firstBroken !== undefined) {
        fb.appendChild(el('span', { 'class': 'frame-note' }, 'the first broken frame is ' + (I.frames.firstBroken + 1)));
      }
      if (I.frames.cut) { fb.appendChild(el('span', { 'class': 'frame-cut' }, I.frames.cut)); }
      I.slider = slider;
      root.appendChild(fb);
    }
    var row = el('div', { 'class': 'row' });
    I.panes = {};
    [['input', 'input (as sent)'], ['expected', 'expected'], ['yours', 'yours']].forEach(function (p) {
      if (!I.models[p[0]]) { return; }
      var box = el('div', { 'class': 'pane', 'data-pane': p[0] });
      box.appendChild(el('div', { 'class': 'pane-title' }, p[1]));
      var cv = el('canvas', { width: '360', height: '320' });
      box.appendChild(cv);
      row.appendChild(box);
      I.panes[p[0]] = { box: box, canvas: cv, items: [] };
      I.mouse(p[0], cv);
    });
    var side = el('div', { 'class': 'side' });
    I.panel = el('div', { 'class': 'panel' }, 'click a vertex, edge, face or halfedge');
    I.status = el('div', { 'class': 'status' });
    side.appendChild(I.panel); side.appendChild(I.status);
    side.appendChild(el('div', { 'class': 'help' },
      'drag: turn · shift-drag or right-drag: move · wheel: zoom · keys: n next, t twin, h halfedge, v vertex, e edge, f face, Esc clear'));
    row.appendChild(side);
    root.appendChild(row);
    root.addEventListener('keydown', function (ev) {
      if (ev.ctrlKey || ev.metaKey || ev.altKey) { return; }
      if (I.key(ev.key)) { ev.preventDefault(); }
    });
    I.setFrameText();
    I.layout();
  };

  Inspector.prototype.layout = function () {
    var I = this;
    Object.keys(I.panes).forEach(function (k) { I.panes[k].box.style.display = I.layers[k] ? '' : 'none'; });
  };

  Inspector.prototype.setFrame = function (k) {
    var I = this;
    if (!I.frames || !isId(k, I.frameModels.length)) { return; }
    I.frame = k;
    I.models.yours = I.frameModels[k];
    if (I.slider && +I.slider.value !== k) { I.slider.value = String(k); }
    if (I.sel && I.sel.pane === 'yours') { I.select('yours', I.sel.kind, I.sel.id); }
    I.setFrameText();
    I.draw();
  };
  Inspector.prototype.setFrameText = function () {
    var I = this;
    if (!I.frames) { return; }
    var n = I.frameModels.length, fr = I.frames.list[I.frame] || {};
    I.frameText.textContent = 'frame ' + (I.frame + 1) + ' of ' + n + ': ' + (fr.label || '');
    var broken = I.frames.firstBroken === I.frame;
    I.frameBroken.textContent = broken ? 'first broken frame' : '';
    I.frameBroken.style.display = broken ? '' : 'none';
  };

  // The frame to view in: the expected result's box, else the input's.
  Inspector.prototype.resetView = function () {
    var I = this;
    var ref = I.models.expected || I.models.input || I.models.yours;
    var b = ref.bounds();
    I.cam = { yaw: 0.6, pitch: 0.45, zoom: 1, pan: [0, 0], center: scale(add(b[0], b[1]), 0.5), radius: Math.max(len(sub(b[1], b[0])) / 2, 1e-9) };
    var e = I.data.error;
    if (e) { I.turnTo(e.pane, e.el[0], +e.el.slice(1)); } else {
      var fe = ((I.data.marks || {}).input || {}).fe || [];
      if (fe.length >= 2 && I.models.input) { I.turnToVertices('input', [fe[0], fe[1]]); }
    }
    I.draw();
  };
  // What a pane is framed on: the input on its own box, the expected
  // result and yours on the expected one's (so that they compare).
  Inspector.prototype.frameOf = function (pane) {
    var ref = pane === 'input' ? this.models.input : (this.models.expected || this.models.input || this.models.yours);
    if (!ref) { return this.cam; }
    if (ref.frame) { return ref.frame; }
    // The bounding sphere about the box's centre: whole from any side.
    var b = ref.bounds(), c = scale(add(b[0], b[1]), 0.5), r = 0;
    ref.pos.forEach(function (p) { if (p && len(p) <= 1e6) { r = Math.max(r, len(sub(p, c))); } });
    ref.frame = { center: c, radius: Math.max(r * 1.05, 1e-9) };
    return ref.frame;
  };
  Inspector.prototype.turnTo = function (pane, kind, id) {
    var m = this.models[pane];
    if (m) { this.turnToVertices(pane, m.verticesOf(kind, id)); }
  };
  Inspector.prototype.turnToVertices = function (pane, vs) {
    var I = this, m = I.models[pane];
    var ps = vs.map(function (v) { return m.pos[v]; }).filter(function (p) { return p; });
    if (!ps.length) { return; }
    var at = scale(ps.reduce(add, [0, 0, 0]), 1 / ps.length);
    var d = m.normalNear(vs) || sub(at, I.cam.center);
    if (len(d) < 1e-12) { return; }
    d = scale(d, 1 / len(d));
    // A little from above, so that the view is not edge-on.
    d = add(d, [0.08, 0.2, 0.05]);
    I.cam.yaw = Math.atan2(-d[0], d[2]);
    I.cam.pitch = Math.atan2(d[1], Math.sqrt(d[0] * d[0] + d[2] * d[2]));
    I.cam.pan = [0, 0];
  };

  // World to view: yaw about y, then pitch about x; z toward the eye.
  Inspector.prototype.project = function (p, W, H, frame) {
    var c = this.cam, f = frame || c, q = sub(p, f.center);
    var cy = Math.cos(c.yaw), sy = Math.sin(c.yaw), cp = Math.cos(c.pitch), sp = Math.sin(c.pitch);
    var x = cy * q[0] + sy * q[2], z1 = -sy * q[0] + cy * q[2];
    var y = cp * q[1] - sp * z1, z = sp * q[1] + cp * z1;
    var k = Math.min(W, H) * 0.45 / f.radius * c.zoom;
    return [W / 2 + x * k + c.pan[0], H / 2 - y * k + c.pan[1], z * k];
  };
  Inspector.prototype.rotated = function (n) {
    var c = this.cam;
    var cy = Math.cos(c.yaw), sy = Math.sin(c.yaw), cp = Math.cos(c.pitch), sp = Math.sin(c.pitch);
    var x = cy * n[0] + sy * n[2], z1 = -sy * n[0] + cy * n[2];
    return [x, cp * n[1] - sp * z1, sp * n[1] + cp * z1];
  };

  // The marks of one pane, as sets; "first problem only" keeps those
  // near the selection (or the error).
  Inspector.prototype.marksOf = function (pane) {
    var I = this, mk = ((I.data.marks || {})[pane]) || {}, m = I.models[pane];
    // The marks are about the end state: no frame before it has them.
    if (pane === 'yours' && I.frames && I.frame !== I.frameModels.length - 1) { mk = {}; }
    var out = { v: {}, e: {}, named: {}, fe: {}, fv: {} };
    var near = null;
    if (I.layers.only) {
      var s = I.sel || (I.data.error ? { pane: I.data.error.pane, kind: I.data.error.el[0], id: +I.data.error.el.slice(1) } : null);
      near = {};
      if (s && s.pane === pane) {
        var vs = m.verticesOf(s.kind, s.id);
        m.polys.forEach(function (f) {
          if (f.vs.some(function (v) { return vs.indexOf(v) >= 0; })) { f.vs.forEach(function (v) { near[v] = 1; }); }
        });
        vs.forEach(function (v) { near[v] = 1; });
      }
    }
    var keep = function (vs) { return !near || vs.some(function (v) { return near[v]; }); };
    (mk.v || []).forEach(function (v) { if (keep([v])) { out.v[v] = 1; } });
    var e = mk.e || [];
    for (var i = 0; i + 1 < e.length; i += 2) {
      if (keep([e[i], e[i + 1]])) { out.e[Math.min(e[i], e[i + 1]) + ',' + Math.max(e[i], e[i + 1])] = 1; }
    }
    (mk.named || []).forEach(function (n) {
      if (!near || keep(m.verticesOf(n[0], n[1]))) { out.named[n[0] + n[1]] = 1; }
    });
    var fe = mk.fe || [];
    for (var j = 0; j + 1 < fe.length; j += 2) { out.fe[Math.min(fe[j], fe[j + 1]) + ',' + Math.max(fe[j], fe[j + 1])] = 1; }
    (mk.fv || []).forEach(function (v) { out.fv[v] = 1; });
    return out;
  };

  Inspector.prototype.draw = function () {
    var I = this;
    Object.keys(I.panes).forEach(function (k) { if (I.layers[k]) { I.drawPane(k); } });
    I.showPanel();
  };

  Inspector.prototype.label = function (pane, kind, id) {
    var name = this.layers.names ? this.names[pane][kind + id] : null;
    if (name === kind + id) { name = null; }
    if (pane === 'expected' && kind === 'v') {
      // Your id where the judge matched one of yours to it, else the
      // input's (an old vertex keeps its id), else unknown.
      var s = this.models.expected.sid[id], n = this.models.expected.iid[id];
      var shown = typeof s === 'number' && s >= 0 ? 'v' + s : typeof n === 'number' && n >= 0 ? 'v' + n : '?';
      return shown + (name ? ' (' + name + ')' : '');
    }
    return kind + id + (name ? ' (' + name + ')' : '');
  };

  Inspector.prototype.drawPane = function (pane) {
    var I = this, P = I.panes[pane], m = I.models[pane], cv = P.canvas;
    var dpr = window.devicePixelRatio || 1, W = 360, H = 320;
    if (cv.width !== W * dpr) { cv.width = W * dpr; cv.height = H * dpr; cv.style.width = W + 'px'; cv.style.height = H + 'px'; }
    var ctx = cv.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, W, H);
    ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, W, H);
    var S = m.pos.map(function (p) {
      if (!p) { return null; }
      var s = I.project(p, W, H, I.frameOf(pane));
      return isFinite(s[0]) && isFinite(s[1]) && Math.abs(s[0]) < 1e6 && Math.abs(s[1]) < 1e6 ? s : null;
    });
    var marks = I.marksOf(pane), L = I.layers, items = [];
    var light = [0.35, 0.55, 0.8];
    var order = [];
    m.polys.forEach(function (f, k) {
      var ss = f.vs.map(function (v) { return S[v]; });
      if (ss.some(function (s) { return !s; })) { return; }
      var n = I.rotated(newell(f.vs.map(function (v) { return m.pos[v]; })));
      var l = len(n);
      if (!(l > 0)) { return; }
      n = scale(n, m.outward / l);
      var front = n[2] > 0;
      if (!front && !L.back) { return; }
      var depth = ss.reduce(function (a, s) { return a + s[2]; }, 0) / ss.length;
      order.push({ k: k, ss: ss, front: front, shade: Math.abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]), depth: depth });
    });
    order.sort(function (a, b) { return a.depth - b.depth; });
    var pairKey = function (a, b) { return Math.min(a, b) + ',' + Math.max(a, b); };
    var small = m.nv < 150;
    var arrow = function (a, b, cx, cy, color, width) {
      // Inside the face: ends pulled toward its centre and shortened.
      var ax = a[0] + (cx - a[0]) * 0.22, ay = a[1] + (cy - a[1]) * 0.22;
      var bx = b[0] + (cx - b[0]) * 0.22, by = b[1] + (cy - b[1]) * 0.22;
      var dx = bx - ax, dy = by - ay;
      ax += dx * 0.12; ay += dy * 0.12; bx -= dx * 0.12; by -= dy * 0.12;
      ctx.strokeStyle = color; ctx.fillStyle = color; ctx.lineWidth = width;
      ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(bx, by); ctx.stroke();
      var l = Math.sqrt(dx * dx + dy * dy) || 1, ux = dx / l, uy = dy / l, hl = Math.min(7, l * 0.3);
      ctx.beginPath(); ctx.moveTo(bx, by);
      ctx.lineTo(bx - ux * hl - uy * hl * 0.5, by - uy * hl + ux * hl * 0.5);
      ctx.lineTo(bx - ux * hl + uy * hl * 0.5, by - uy * hl - ux * hl * 0.5);
      ctx.closePath(); ctx.fill();
      return [ax, ay, bx, by];
    };
    var dot = function (s, color, r) { ctx.fillStyle = color; ctx.beginPath(); ctx.arc(s[0], s[1], r, 0, 2 * Math.PI); ctx.fill(); };
    // Labels are gathered while drawing and placed at the end, so none
    // covers another (see placeLabels).
    var labels = [];
    var want = function (kind, id, at, color, rank) {
      labels.push({ kind: kind, id: id, at: at, t: I.label(pane, kind, id), color: color, rank: rank, n: labels.length });
    };
    order.forEach(function (o) {
      var f = m.polys[o.k], ss = o.ss;
      var k = Math.round(o.shade * 15) / 15;
      ctx.fillStyle = o.front ? 'rgb(' + Math.round(150 * (0.5 + 0.55 * k)) + ',' + Math.round(182 * (0.5 + 0.55 * k)) + ',' + Math.min(255, Math.round(226 * (0.5 + 0.55 * k))) + ')'
        : 'rgb(' + Math.min(255, Math.round(240 * (0.82 + 0.2 * k))) + ',' + Math.round(222 * (0.82 + 0.2 * k)) + ',' + Math.round(190 * (0.82 + 0.2 * k)) + ')';
      ctx.beginPath();
      ss.forEach(function (s, i) { if (i) { ctx.lineTo(s[0], s[1]); } else { ctx.moveTo(s[0], s[1]); } });
      ctx.closePath(); ctx.fill();
      items.push({ kind: 'f', id: f.face, poly: ss });
      var cx = 0, cy = 0;
      ss.forEach(function (s) { cx += s[0]; cy += s[1]; });
      cx /= ss.length; cy /= ss.length;
      for (var i = 0; i < ss.length; i++) {
        var a = f.vs[i], b = f.vs[(i + 1) % ss.length], key = pairKey(a, b);
        var red = L.marks && marks.e[key], orange = L.marks && marks.fe[key];
        ctx.strokeStyle = red ? '#e00000' : orange ? '#ef6c00' : 'rgba(42,58,79,.6)';
        ctx.lineWidth = red || orange ? 3 : 0.8;
        ctx.beginPath(); ctx.moveTo(ss[i][0], ss[i][1]); ctx.lineTo(ss[(i + 1) % ss.length][0], ss[(i + 1) % ss.length][1]); ctx.stroke();
        var eid = f.hs ? m.link(f.hs[i], 3) : -1;
        items.push({ kind: 'e', id: eid, pair: [a, b], seg: [ss[i][0], ss[i][1], ss[(i + 1) % ss.length][0], ss[(i + 1) % ss.length][1]], w: 3 });
      }
      if (f.hs && L.arrows && o.front) {
        for (var j = 0; j < ss.length; j++) {
          var h = f.hs[j];
          var named = L.marks && marks.named['h' + h];
          var seg = arrow(ss[j], ss[(j + 1) % ss.length], cx, cy, named ? '#8e24aa' : 'rgba(29,39,51,.7)', named ? 2.4 : 1.1);
          items.push({ kind: 'h', id: h, seg: seg, w: 4 });
          // Only the halfedges that have a name: all of them would be unreadable.
          var hname = L.names ? I.names[pane]['h' + h] : null;
          if (L.labels && (hname || named)) { want('h', h, [(seg[0] + seg[2]) / 2, (seg[1] + seg[3]) / 2], '#6a4c93', 2); }
        }
      }
      var fname = L.names ? I.names[pane]['f' + f.face] : null;
      if (L.labels && f.hs && o.front && (fname || (L.marks && marks.named['f' + f.face]))) {
        want('f', f.face, [cx, cy], '#2e5d2e', 2);
      }
      f.vs.forEach(function (v, i) {
        var wrong = L.marks && marks.v[v];
        if (L.dots || wrong) { dot(ss[i], wrong ? '#e00000' : '#1d2733', wrong ? 4 : small ? 2.4 : 1.5); }
        items.push({ kind: 'v', id: v, at: ss[i], r: 6 });
        if (L.labels && (o.front || wrong)) { want('v', v, ss[i], wrong ? '#c00000' : '#1d2733', wrong || (L.names && I.names[pane]['v' + v]) ? 2 : 4); }
      });
    });
    // What no drawn face holds: halfedges of holes or broken loops along
    // their edge, loose edges, lone vertices; on top.
    var inPoly = {};
    m.polys.forEach(function (f) { f.vs.forEach(function (v) { inPoly[v] = 1; }); });
    m.looseH.forEach(function (h) {
      var ends = m.hEnds(h);
      if (!ends || !S[ends[0]] || !S[ends[1]]) { return; }
      var a = S[ends[0]], b = S[ends[1]], dx = b[0] - a[0], dy = b[1] - a[1], l = Math.sqrt(dx * dx + dy * dy) || 1;
      // Offset to the halfedge's left in the picture.
      var ox = dy / l * 5, oy = -dx / l * 5;
      var named = L.marks && marks.named['h' + h];
      var seg = arrow([a[0] + ox, a[1] + oy], [b[0] + ox, b[1] + oy], (a[0] + b[0]) / 2 + ox, (a[1] + b[1]) / 2 + oy, named ? '#8e24aa' : 'rgba(150,80,0,.8)', named ? 2.4 : 1.1);
      if (L.arrows || named) { items.push({ kind: 'h', id: h, seg: seg, w: 4 }); }
      if (L.labels && (named || m.looseH.length < 40)) { want('h', h, [(seg[0] + seg[2]) / 2, (seg[1] + seg[3]) / 2], '#6a4c93', named ? 2 : 4); }
    });
    m.looseE.forEach(function (e) {
      if (!S[e[0]] || !S[e[1]]) { return; }
      ctx.strokeStyle = L.marks && marks.e[pairKey(e[0], e[1])] ? '#e00000' : '#41536b'; ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(S[e[0]][0], S[e[0]][1]); ctx.lineTo(S[e[1]][0], S[e[1]][1]); ctx.stroke();
      inPoly[e[0]] = inPoly[e[1]] = 0;
    });
    S.forEach(function (s, v) {
      if (!s || inPoly[v]) { return; }
      var wrong = L.marks && marks.v[v];
      dot(s, wrong ? '#e00000' : '#1d2733', wrong ? 4 : 2.4);
      items.push({ kind: 'v', id: v, at: s, r: 6 });
      if (L.labels) { want('v', v, s, wrong ? '#c00000' : '#1d2733', wrong ? 2 : 4); }
    });
    // Marks again, faded, so those behind the surface still show.
    P.marksShown = L.marks ? Object.keys(marks.v).length + Object.keys(marks.e).length + Object.keys(marks.named).length : 0;
    if (L.marks) {
      ctx.globalAlpha = 0.35;
      Object.keys(marks.v).forEach(function (v) { if (S[v]) { dot(S[v], '#e00000', 4); } });
      Object.keys(marks.e).forEach(function (k) {
        var ab = k.split(','), a = S[+ab[0]], b = S[+ab[1]];
        if (a && b) { ctx.strokeStyle = '#e00000'; ctx.lineWidth = 2.5; ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke(); }
      });
      ctx.globalAlpha = 1;
      Object.keys(marks.named).forEach(function (k) {
        var vs = m.verticesOf(k[0], +k.slice(1)), ss = vs.map(function (v) { return S[v]; }).filter(function (s) { return s; });
        if (!ss.length) { return; }
        ctx.strokeStyle = 'rgba(142,36,170,.75)'; ctx.lineWidth = 3; ctx.beginPath();
        if (ss.length === 1) { ctx.arc(ss[0][0], ss[0][1], 7, 0, 2 * Math.PI); } else {
          ss.forEach(function (s, i) { if (i) { ctx.lineTo(s[0], s[1]); } else { ctx.moveTo(s[0], s[1]); } });
          if (ss.length > 2) { ctx.closePath(); }
        }
        ctx.stroke();
      });
      Object.keys(marks.fv).forEach(function (v) {
        if (S[v]) { ctx.strokeStyle = '#ef6c00'; ctx.lineWidth = 2.2; ctx.beginPath(); ctx.arc(S[v][0], S[v][1], 6, 0, 2 * Math.PI); ctx.stroke(); }
      });
    }
    // The selection, always on top.
    var sel = I.sel;
    if (sel && sel.pane === pane) {
      ctx.strokeStyle = '#00b8d4'; ctx.fillStyle = '#00b8d4'; ctx.lineWidth = 3.5;
      ctx.shadowColor = '#fff'; ctx.shadowBlur = 4;
      var vs = m.verticesOf(sel.kind, sel.id), ss = vs.map(function (v) { return S[v]; });
      if (sel.kind === 'v' && ss[0]) { ctx.beginPath(); ctx.arc(ss[0][0], ss[0][1], 7, 0, 2 * Math.PI); ctx.stroke(); }
      if (sel.kind === 'e' && ss[0] && ss[1]) { ctx.beginPath(); ctx.moveTo(ss[0][0], ss[0][1]); ctx.lineTo(ss[1][0], ss[1][1]); ctx.stroke(); }
      if (sel.kind === 'h') {
        var it = items.filter(function (x) { return x.kind === 'h' && x.id === sel.id; }).pop();
        if (it) { arrow([it.seg[0], it.seg[1]], [it.seg[2], it.seg[3]], (it.seg[0] + it.seg[2]) / 2, (it.seg[1] + it.seg[3]) / 2, '#00b8d4', 3.5); } else if (ss[0] && ss[1]) {
          arrow(ss[0], ss[1], (ss[0][0] + ss[1][0]) / 2, (ss[0][1] + ss[1][1]) / 2, '#00b8d4', 3.5);
        }
      }
      if (sel.kind === 'f' && ss.length >= 2 && ss.every(function (s) { return s; })) {
        ctx.beginPath(); ss.forEach(function (s, i) { if (i) { ctx.lineTo(s[0], s[1]); } else { ctx.moveTo(s[0], s[1]); } });
        ctx.closePath(); ctx.stroke();
      }
      ctx.shadowBlur = 0;
    }
    P.items = items;
    I.placeLabels(pane, ctx, labels, W, H, S);
  };

  // Where an element's label hangs: a vertex's at its dot, a halfedge's or
  // edge's at the middle of what is drawn, a face's at its centre.
  function anchorOf(it) {
    if (it.at) { return it.at; }
    if (it.seg) { return [(it.seg[0] + it.seg[2]) / 2, (it.seg[1] + it.seg[3]) / 2]; }
    var c = [0, 0];
    it.poly.forEach(function (s) { c[0] += s[0] / it.poly.length; c[1] += s[1] / it.poly.length; });
    return c;
  }

  // Places the pane's labels so that no two overlap: greedily by rank (the
  // selection, then what is hovered, then the selection's neighbours, then
  // marked or named elements, then the rest, front-most first within a
  // rank), each tried at a few spots around its anchor and skipped where
  // every spot is taken. The selection's and the hovered element's labels
  // are shown even with the labels layer off: placed first, they always
  // fit. What was placed stays in `panes[pane].labels` (for tests).
  Inspector.prototype.placeLabels = function (pane, ctx, labels, W, H, S) {
    var I = this, P = I.panes[pane], m = I.models[pane], items = P.items;
    var near = null, sel = I.sel && I.sel.pane === pane ? I.sel : null;
    var hov = I.hover && I.hover.pane === pane ? I.hover : null;
    if (sel) {
      near = {};
      m.verticesOf(sel.kind, sel.id).forEach(function (v) { near[v] = 1; });
    }
    var touches = function (c) {
      if (!near) { return false; }
      if (c.kind === 'v') { return !!near[c.id]; }
      return m.verticesOf(c.kind, c.id).some(function (v) { return near[v]; });
    };
    labels.forEach(function (c) { if (c.rank > 1 && touches(c)) { c.rank = 1; } });
    [[sel, 0], [hov, 0.5]].forEach(function (x) {
      var s = x[0];
      if (!s) { return; }
      var c = labels.filter(function (l) { return l.kind === s.kind && l.id === s.id; }).pop();
      if (!c) {
        // Where it is drawn, else (hidden: a back face, a vertex behind)
        // the middle of its projected corners.
        var it = items.filter(function (y) { return y.kind === s.kind && y.id === s.id; }).pop();
        var at = it ? anchorOf(it) : null;
        if (!at) {
          var ss = m.verticesOf(s.kind, s.id).map(function (v) { return S[v]; }).filter(function (p) { return p; });
          if (!ss.length) { return; }
          at = anchorOf({ poly: ss });
        }
        c = { kind: s.kind, id: s.id, at: at, t: I.label(pane, s.kind, s.id), color: '#1d2733', n: labels.length };
        labels.push(c);
      }
      c.rank = Math.min(c.rank === undefined ? 9 : c.rank, x[1]);
      if (x[1] === 0) { c.color = '#00687a'; }
    });
    labels.sort(function (a, b) { return a.rank - b.rank || b.n - a.n; });
    ctx.font = '10px ui-monospace,Menlo,Consolas,monospace';
    var widths = I.labelWidths || (I.labelWidths = {});
    // A grid of 32 px cells, each listing the placed rectangles over it.
    var grid = {}, placed = [], skipped = 0, CELL = 32;
    var cells = function (r, f) {
      for (var gx = Math.floor(r[0] / CELL); gx <= Math.floor((r[0] + r[2]) / CELL); gx++) {
        for (var gy = Math.floor(r[1] / CELL); gy <= Math.floor((r[1] + r[3]) / CELL); gy++) {
          if (f(gx + ',' + gy) === false) { return false; }
        }
      }
      return true;
    };
    var free = function (r) {
      return cells(r, function (k) {
        return !(grid[k] || []).some(function (q) { return r[0] < q[0] + q[2] && q[0] < r[0] + r[2] && r[1] < q[1] + q[3] && q[1] < r[1] + r[3]; });
      });
    };
    // A vertex is offered once per face around it: the best offer stands.
    var done = {};
    labels.forEach(function (c) {
      if (done[c.kind + c.id]) { return; }
      done[c.kind + c.id] = 1;
      var w = widths[c.t];
      if (w === undefined) { w = widths[c.t] = Math.ceil(ctx.measureText(c.t).width) + 2; }
      var x = c.at[0], y = c.at[1], h = 12;
      // Top-left corners: a vertex's label beside its dot, the others
      // centred on their anchor first.
      var spots = c.kind === 'v'
        ? [[x + 3, y - 14], [x + 3, y + 2], [x - 3 - w, y - 14], [x - 3 - w, y + 2], [x - w / 2, y - 18], [x - w / 2, y + 6], [x + 8, y - 6], [x - 8 - w, y - 6]]
        : [[x - w / 2, y - 6], [x - w / 2, y - 18], [x - w / 2, y + 6], [x + 4, y - 6], [x - 4 - w, y - 6], [x - w / 2, y - 30], [x - w / 2, y + 18]];
      var r = null;
      for (var i = 0; i < spots.length && !r; i++) {
        var q = [spots[i][0], spots[i][1], w, h];
        var inside = q[0] >= 0 && q[1] >= 0 && q[0] + w <= W && q[1] + h <= H;
        if ((inside || c.rank === 0) && free(q)) { r = q; }
      }
      if (!r) { skipped++; return; }
      cells(r, function (k) { (grid[k] || (grid[k] = [])).push(r); });
      placed.push({ kind: c.kind, id: c.id, text: c.t, x: r[0], y: r[1], w: w, h: h, rank: c.rank });
      ctx.lineWidth = 3; ctx.strokeStyle = '#fff'; ctx.strokeText(c.t, r[0] + 1, r[1] + 9.5);
      ctx.fillStyle = c.color; ctx.fillText(c.t, r[0] + 1, r[1] + 9.5);
    });
    P.labels = placed;
    P.labelsSkipped = skipped;
  };

  function segDist(x, y, s) {
    var dx = s[2] - s[0], dy = s[3] - s[1], l2 = dx * dx + dy * dy;
    var t = l2 > 0 ? Math.max(0, Math.min(1, ((x - s[0]) * dx + (y - s[1]) * dy) / l2)) : 0;
    var px = s[0] + t * dx - x, py = s[1] + t * dy - y;
    return Math.sqrt(px * px + py * py);
  }
  function inside(x, y, poly) {
    var c = false;
    for (var i = 0, j = poly.length - 1; i < poly.length; j = i++) {
      var a = poly[i], b = poly[j];
      if ((a[1] > y) !== (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) { c = !c; }
    }
    return c;
  }
  // What is under (x, y): the front-most face there hides everything drawn
  // before it; of what is drawn after it (its own sides, arrows, corners,
  // and what lies in front), a vertex beats a halfedge beats an edge, the
  // nearest first; else the face itself.
  Inspector.prototype.pick = function (pane, x, y) {
    var items = this.panes[pane].items || [], front = -1, k;
    for (k = 0; k < items.length; k++) { if (items[k].poly && inside(x, y, items[k].poly)) { front = k; } }
    var best = null, rank = { v: 0, h: 1, e: 2 };
    for (k = front + 1; k < items.length; k++) {
      var it = items[k], d = it.kind === 'v' ? Math.hypot(it.at[0] - x, it.at[1] - y) : it.seg ? segDist(x, y, it.seg) : Infinity;
      if (d > (it.r || it.w || 0)) { continue; }
      if (!best || rank[it.kind] < rank[best.it.kind] || (rank[it.kind] === rank[best.it.kind] && d <= best.d)) { best = { it: it, d: d }; }
    }
    return best ? best.it : front >= 0 ? items[front] : null;
  };
  // Where an element is drawn, in the page's client coordinates (for
  // tests and for turning to it): its last drawn place.
  Inspector.prototype.screenOf = function (pane, kind, id) {
    var P = this.panes[pane];
    if (!P) { return null; }
    var it = (P.items || []).filter(function (x) { return x.kind === kind && x.id === id; }).pop();
    if (!it) { return null; }
    var at = it.at || (it.seg ? [(it.seg[0] + it.seg[2]) / 2, (it.seg[1] + it.seg[3]) / 2] : null);
    if (!at && it.poly) {
      at = [0, 0];
      it.poly.forEach(function (s) { at[0] += s[0] / it.poly.length; at[1] += s[1] / it.poly.length; });
    }
    var r = P.canvas.getBoundingClientRect();
    return { x: r.left + at[0], y: r.top + at[1] };
  };

  Inspector.prototype.mouse = function (pane, cv) {
    var I = this, drag = null;
    cv.addEventListener('contextmenu', function (ev) { ev.preventDefault(); });
    cv.addEventListener('mousedown', function (ev) {
      drag = { x: ev.clientX, y: ev.clientY, pan: ev.shiftKey || ev.button !== 0, moved: false };
      I.root.focus({ preventScroll: true });
    });
    window.addEventListener('mousemove', function (ev) {
      if (!drag) { return; }
      var dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 2) { drag.moved = true; }
      drag.x = ev.clientX; drag.y = ev.clientY;
      if (drag.pan) { I.cam.pan[0] += dx; I.cam.pan[1] += dy; } else {
        I.cam.yaw += dx * 0.01;
        I.cam.pitch = Math.max(-1.55, Math.min(1.55, I.cam.pitch + dy * 0.01));
      }
      I.draw();
    });
    window.addEventListener('mouseup', function () { if (drag) { I.dragged = drag.moved; } drag = null; });
    // Hovering shows the label of what is under the pointer (a label the
    // placement skipped included), one redraw per animation frame.
    var hover = function (h) {
      var old = I.hover;
      if (old === h || (old && h && old.pane === h.pane && old.kind === h.kind && old.id === h.id)) { return; }
      I.hover = h;
      if (I.hoverQueued) { return; }
      I.hoverQueued = true;
      requestAnimationFrame(function () {
        I.hoverQueued = false;
        Object.keys(I.panes).forEach(function (k) { if (I.layers[k]) { I.drawPane(k); } });
      });
    };
    cv.addEventListener('mousemove', function (ev) {
      if (drag) { return; }
      var r = cv.getBoundingClientRect();
      var hit = I.pick(pane, ev.clientX - r.left, ev.clientY - r.top);
      hover(hit ? { pane: pane, kind: hit.kind, id: hit.id } : null);
    });
    cv.addEventListener('mouseleave', function () { hover(null); });
    cv.addEventListener('click', function (ev) {
      if (I.dragged) { I.dragged = false; return; }
      var r = cv.getBoundingClientRect();
      var hit = I.pick(pane, ev.clientX - r.left, ev.clientY - r.top);
      I.root.focus({ preventScroll: true });
      if (hit) { I.select(pane, hit.kind, hit.id); } else { I.sel = null; I.draw(); }
    });
    cv.addEventListener('wheel', function (ev) {
      ev.preventDefault();
      I.cam.zoom = Math.max(0.05, Math.min(200, I.cam.zoom * Math.exp(-ev.deltaY * 0.0015)));
      I.draw();
    }, { passive: false });
  };

  Inspector.prototype.select = function (pane, kind, id) {
    this.sel = { pane: pane, kind: kind, id: id };
    this.status.textContent = '';
    this.draw();
  };
  Inspector.prototype.selectError = function () {
    var e = this.data.error;
    if (!e) { return; }
    var kind = e.el[0], id = +e.el.slice(1);
    this.turnTo(e.pane, kind, id);
    this.select(e.pane, kind, id);
  };

  // Scotty3D's keys: n next, t twin, h the selection's halfedge, v/e/f the
  // halfedge's vertex, edge, face.
  Inspector.prototype.key = function (k) {
    var I = this, s = I.sel;
    if (k === 'Escape') { I.sel = null; I.draw(); return true; }
    if ('nthvef'.indexOf(k) < 0 || k.length !== 1) { return false; }
    if (!s) { I.status.textContent = 'select something first'; return true; }
    var m = I.models[s.pane];
    if (!m.full) { I.status.textContent = 'the expected result is known by positions and faces only'; return true; }
    var go = null, what = '';
    if (s.kind === 'h') {
      var field = { n: 1, t: 0, v: 2, e: 3, f: 4 }[k];
      if (field === undefined) { I.status.textContent = 'h: already a halfedge'; return true; }
      go = { kind: { 1: 'h', 0: 'h', 2: 'v', 3: 'e', 4: 'f' }[field], id: m.link(s.id, field) };
      what = { n: 'next', t: 'twin', v: 'vertex', e: 'edge', f: 'face' }[k];
    } else if (k === 'h') {
      var arr = { v: m.vh, e: m.eh, f: m.fh }[s.kind];
      go = { kind: 'h', id: isId(s.id, arr.length) ? arr[s.id] : -1 };
      what = 'halfedge';
    } else {
      I.status.textContent = k + ': select a halfedge first (h goes to the ' + KINDS[s.kind] + "'s halfedge)";
      return true;
    }
    var n = { v: m.nv, e: m.ne, f: m.nf, h: m.nh }[go.kind];
    if (!isId(go.id, n)) {
      I.status.textContent = s.kind + s.id + "'s " + what + ' is ' + go.kind + go.id + ', which does not exist (the mesh has ' + n + ' ' + KINDS[go.kind] + 's)';
      return true;
    }
    I.select(s.pane, go.kind, go.id);
    I.status.textContent = k + ': ' + what + ' of ' + s.kind + s.id + ' is ' + go.kind + go.id;
    return true;
  };

  // The panel: the selection's id (both numberings where the input was
  // relabelled), its position or pointers, its handout name.
  Inspector.prototype.showPanel = function () {
    var I = this, s = I.sel, P = I.panel;
    P.textContent = '';
    if (!s) { P.appendChild(el('div', { 'class': 'hint' }, 'click a vertex, edge, face or halfedge')); return; }
    var m = I.models[s.pane];
    var line = function (k, v, cls) {
      var d = el('div', { 'class': 'line' + (cls ? ' ' + cls : '') });
      d.appendChild(el('span', { 'class': 'k' }, k + ' '));
      d.appendChild(el('span', { 'class': 'v' }, v));
      P.appendChild(d);
    };
    var ref = function (kind, id, n) { return kind + id + (isId(id, n) ? '' : ' (does not exist)'); };
    var title = KINDS[s.kind] + ' ' + s.kind + s.id;
    if (s.pane === 'expected' && s.kind === 'v') { title = 'expected vertex ' + s.id; }
    if (s.pane === 'expected' && s.kind === 'f') { title = 'expected face'; }
    P.appendChild(el('div', { 'class': 'title' }, title + ' · ' + s.pane));
    var name = I.names[s.pane][s.kind + s.id];
    if (name) { line('handout name', name, 'name'); }
    var ids = I.data.caseIds;
    if (ids && s.pane !== 'expected' && ids[s.kind] && isId(s.id, ids[s.kind].length)) {
      var c = ids[s.kind][s.id];
      line("in the case's numbering", c >= 0 ? s.kind + c : 'none (made by your code)', 'case-id');
    } else if (ids && s.pane !== 'expected') {
      line("in the case's numbering", 'none (made by your code)', 'case-id');
    }
    if (s.pane === 'expected') {
      if (s.kind === 'v') {
        line('position', fmtP(m.pos[s.id]));
        var sid = m.sid[s.id];
        var iid = m.iid[s.id];
        line('yours', typeof sid === 'number' && sid >= 0 ? 'v' + sid + ' stands for it' : 'none of yours stands for it');
        if (typeof iid === 'number' && iid >= 0) { line('in the input', 'v' + iid + ' (an old vertex keeps its id)'); }
      } else if (s.kind === 'f') {
        var poly = m.polys[s.id];
        line('corners', poly ? poly.vs.map(function (v) { return I.label('expected', 'v', v); }).join(', ') : '?');
      }
      return;
    }
    if (s.kind === 'v') {
      if (!isId(s.id, m.nv)) { line('', 'does not exist'); return; }
      line('position', fmtP(m.pos[s.id]));
      line('halfedge', ref('h', m.vh[s.id], m.nh));
      line('is_new', m.vn[s.id] === 1 ? 'true' : 'false');
      line('new_pos', m.vq ? fmtP(triple(m.vq, s.id)) : '(0, 0, 0)');
    } else if (s.kind === 'e') {
      if (!isId(s.id, m.ne)) { line('', 'does not exist'); return; }
      line('halfedge', ref('h', m.eh[s.id], m.nh));
      var ends = m.eEnds(s.id);
      line('between', ends ? 'v' + ends[0] + ' and v' + ends[1] : '?');
      line('is_new', m.en[s.id] === 1 ? 'true' : 'false');
      line('new_pos', m.eq ? fmtP(triple(m.eq, s.id)) : '(0, 0, 0)');
    } else if (s.kind === 'f') {
      if (!isId(s.id, m.nf)) { line('', 'does not exist'); return; }
      line('halfedge', ref('h', m.fh[s.id], m.nh));
      line('is_boundary', m.fb[s.id] === 1 ? 'true' : 'false');
      var walk = [], x = m.fh[s.id];
      while (isId(x, m.nh) && walk.length < MAX_DEGREE) { walk.push('h' + x); x = m.link(x, 1); if (x === m.fh[s.id]) { break; } }
      line('next walk', walk.join(' ') + (x === m.fh[s.id] ? ' (closes)' : ' (does not close)'));
    } else {
      if (!isId(s.id, m.nh)) { line('', 'does not exist'); return; }
      line('twin', ref('h', m.link(s.id, 0), m.nh));
      line('next', ref('h', m.link(s.id, 1), m.nh));
      line('vertex', ref('v', m.link(s.id, 2), m.nv));
      line('edge', ref('e', m.link(s.id, 3), m.ne));
      line('face', ref('f', m.link(s.id, 4), m.nf));
      var f = m.link(s.id, 4);
      line('is_boundary', isId(f, m.nf) ? (m.fb[f] === 1 ? 'true (its face is a hole)' : 'false') : '?');
      var he = m.hEnds(s.id);
      line('runs', he ? 'v' + he[0] + ' -> v' + he[1] : '?');
    }
  };

  // The static pictures sit in a <noscript> (a page with script parses
  // none of their thousands of paths): shown on demand from its text.
  function showStatic(root) {
    var section = root.closest('section'), ns = section && section.querySelector('noscript');
    if (!ns || ns.meshlabShown) { return; }
    ns.meshlabShown = true;
    var div = document.createElement('div');
    div.innerHTML = ns.textContent;
    ns.parentNode.insertBefore(div, ns.nextSibling);
  }

  // Each inspector is built when its case comes near the screen (a page
  // of every case would take seconds to build at once); tests and links
  // build one at once with window.meshlabInspect(name).
  function start() {
    var all = {}, roots = {};
    var canvas = document.createElement('canvas');
    if (!canvas.getContext || !canvas.getContext('2d')) { return; }
    var build = function (root) {
      if (root.meshlabBuilt) { return all[root.meshlabName]; }
      root.meshlabBuilt = true;
      var blob = root.querySelector('script.inspector-data');
      try {
        var data = JSON.parse(blob.textContent);
        var insp = new Inspector(root, data);
        all[data.name] = insp;
        return insp;
      } catch (e) {
        root.setAttribute('hidden', '');
        var p = document.createElement('p');
        p.className = 'inspector-failed';
        p.textContent = 'the inspector could not show this case (' + e + '); the static pictures below still do';
        root.parentNode.insertBefore(p, root);
        showStatic(root);
        if (window.console) { console.error(e); }
        return null;
      }
    };
    var observer = window.IntersectionObserver ? new IntersectionObserver(function (entries) {
      entries.forEach(function (en) { if (en.isIntersecting) { observer.unobserve(en.target); build(en.target); } });
    }, { rootMargin: '300px' }) : null;
    Array.prototype.forEach.call(document.querySelectorAll('div.inspector'), function (root) {
      var section = root.closest('section');
      var name = section ? section.getAttribute('data-case') : null;
      root.meshlabName = name;
      roots[name] = root;
      // Until it is built, the inspector holds its place.
      root.removeAttribute('hidden');
      root.classList.add('pending');
      if (observer) { observer.observe(root); } else { build(root); }
    });
    window.meshlabInspectors = all;
    window.meshlabInspect = function (name) { return roots[name] ? build(roots[name]) : null; };
    // When the page was ready to use, for the tests' measurement.
    document.documentElement.setAttribute('data-inspector-ready', String(Math.round(performance.now())));
  }
  if (document.readyState === 'loading') { document.addEventListener('DOMContentLoaded', start); } else { start(); }
})();
