// The report's 3D half-edge inspector: hand-written, canvas 2D, no
// library, nothing fetched (the page opens from file://). Each case's data
// is a JSON blob written by case_data.rs (try's page: trial_page.rs). The
// student's mesh may be anything (ids out of range, non-finite positions,
// broken next loops): every id is bounds-checked and every walk bounded
// here, as on the Rust side.
//
// The files of script/ are one script, in the order page.rs lists them:
// this one opens the function scope they share (its only globals are
// window.meshlabInspect and window.meshlabInspectors), start.js closes it.
// Here: the small helpers, and a mesh as the script draws it.
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

