  // A pane's picture, painted far to near on a canvas: faces shaded by
  // their normal, sides, halfedges' arrows, vertices, the marks (what is
  // wrong), the selection; and the labels each element's drawing wants.

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

  // Draws one pane: its faces far to near, what no face holds, the marks
  // again faded, the selection, then the labels; what was drawn where is
  // kept in `panes[pane].items`, for picking.
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
    // What the steps share: the pane, its positions on screen, its marks
    // and layers, what they drew (`items`) and the labels they want.
    // Labels are gathered while drawing and placed at the end, so none
    // covers another (see placeLabels).
    var d = { I: I, pane: pane, m: m, ctx: ctx, S: S, marks: I.marksOf(pane), L: I.layers, items: [], labels: [], small: m.nv < 150 };
    drawFaces(d, faceOrder(d));
    drawLoose(d);
    // How many marks show (for the tests); drawn again, faded, so that
    // those behind the surface still show.
    var L = d.L, marks = d.marks;
    P.marksShown = L.marks ? Object.keys(marks.v).length + Object.keys(marks.e).length + Object.keys(marks.named).length : 0;
    if (L.marks) { drawMarks(d); }
    drawSelection(d);
    P.items = d.items;
    I.placeLabels(pane, ctx, d.labels, W, H, S);
  };

  // The faces to paint, far to near: those whose corners are all on
  // screen, front faces only unless the back faces are shown.
  function faceOrder(d) {
    var m = d.m, S = d.S, L = d.L;
    var light = [0.35, 0.55, 0.8];
    var order = [];
    m.polys.forEach(function (f, k) {
      var ss = f.vs.map(function (v) { return S[v]; });
      if (ss.some(function (s) { return !s; })) { return; }
      var n = d.I.rotated(newell(f.vs.map(function (v) { return m.pos[v]; })));
      var l = len(n);
      if (!(l > 0)) { return; }
      n = scale(n, m.outward / l);
      var front = n[2] > 0;
      if (!front && !L.back) { return; }
      var depth = ss.reduce(function (a, s) { return a + s[2]; }, 0) / ss.length;
      order.push({ k: k, ss: ss, front: front, shade: Math.abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]), depth: depth });
    });
    order.sort(function (a, b) { return a.depth - b.depth; });
    return order;
  }

  function pairKey(a, b) { return Math.min(a, b) + ',' + Math.max(a, b); }

  // A halfedge's arrow from a to b; returns the segment drawn.
  function arrow(ctx, a, b, cx, cy, color, width) {
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
  }
  function dot(ctx, s, color, r) { ctx.fillStyle = color; ctx.beginPath(); ctx.arc(s[0], s[1], r, 0, 2 * Math.PI); ctx.fill(); }
  // A label the pane wants, placed later by rank.
  function want(d, kind, id, at, color, rank) {
    d.labels.push({ kind: kind, id: id, at: at, t: d.I.label(d.pane, kind, id), color: color, rank: rank, n: d.labels.length });
  }

  // Each face in `order`: filled, its sides (red or orange where marked),
  // its halfedges' arrows, its corners, and the labels it wants.
  function drawFaces(d, order) {
    var I = d.I, pane = d.pane, m = d.m, ctx = d.ctx, marks = d.marks, L = d.L, items = d.items;
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
          var seg = arrow(ctx, ss[j], ss[(j + 1) % ss.length], cx, cy, named ? '#8e24aa' : 'rgba(29,39,51,.7)', named ? 2.4 : 1.1);
          items.push({ kind: 'h', id: h, seg: seg, w: 4 });
          // Only the halfedges that have a name: all of them would be unreadable.
          var hname = L.names ? I.names[pane]['h' + h] : null;
          if (L.labels && (hname || named)) { want(d, 'h', h, [(seg[0] + seg[2]) / 2, (seg[1] + seg[3]) / 2], '#6a4c93', 2); }
        }
      }
      var fname = L.names ? I.names[pane]['f' + f.face] : null;
      if (L.labels && f.hs && o.front && (fname || (L.marks && marks.named['f' + f.face]))) {
        want(d, 'f', f.face, [cx, cy], '#2e5d2e', 2);
      }
      f.vs.forEach(function (v, i) {
        var wrong = L.marks && marks.v[v];
        if (L.dots || wrong) { dot(ctx, ss[i], wrong ? '#e00000' : '#1d2733', wrong ? 4 : d.small ? 2.4 : 1.5); }
        items.push({ kind: 'v', id: v, at: ss[i], r: 6 });
        if (L.labels && (o.front || wrong)) { want(d, 'v', v, ss[i], wrong ? '#c00000' : '#1d2733', wrong || (L.names && I.names[pane]['v' + v]) ? 2 : 4); }
      });
    });
  }

  // What no drawn face holds: halfedges of holes or broken loops along
  // their edge, loose edges, lone vertices; on top.
  function drawLoose(d) {
    var m = d.m, ctx = d.ctx, S = d.S, marks = d.marks, L = d.L, items = d.items;
    var inPoly = {};
    m.polys.forEach(function (f) { f.vs.forEach(function (v) { inPoly[v] = 1; }); });
    m.looseH.forEach(function (h) {
      var ends = m.hEnds(h);
      if (!ends || !S[ends[0]] || !S[ends[1]]) { return; }
      var a = S[ends[0]], b = S[ends[1]], dx = b[0] - a[0], dy = b[1] - a[1], l = Math.sqrt(dx * dx + dy * dy) || 1;
      // Offset to the halfedge's left in the picture.
      var ox = dy / l * 5, oy = -dx / l * 5;
      var named = L.marks && marks.named['h' + h];
      var seg = arrow(ctx, [a[0] + ox, a[1] + oy], [b[0] + ox, b[1] + oy], (a[0] + b[0]) / 2 + ox, (a[1] + b[1]) / 2 + oy, named ? '#8e24aa' : 'rgba(150,80,0,.8)', named ? 2.4 : 1.1);
      if (L.arrows || named) { items.push({ kind: 'h', id: h, seg: seg, w: 4 }); }
      if (L.labels && (named || m.looseH.length < 40)) { want(d, 'h', h, [(seg[0] + seg[2]) / 2, (seg[1] + seg[3]) / 2], '#6a4c93', named ? 2 : 4); }
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
      dot(ctx, s, wrong ? '#e00000' : '#1d2733', wrong ? 4 : 2.4);
      items.push({ kind: 'v', id: v, at: s, r: 6 });
      if (L.labels) { want(d, 'v', v, s, wrong ? '#c00000' : '#1d2733', wrong ? 2 : 4); }
    });
  }

  // The marks drawn again, faded, over everything (those behind the
  // surface too), the named elements outlined, the case's vertices ringed.
  function drawMarks(d) {
    var m = d.m, ctx = d.ctx, S = d.S, marks = d.marks;
    ctx.globalAlpha = 0.35;
    Object.keys(marks.v).forEach(function (v) { if (S[v]) { dot(ctx, S[v], '#e00000', 4); } });
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
  function drawSelection(d) {
    var m = d.m, ctx = d.ctx, S = d.S, items = d.items;
    var sel = d.I.sel;
    if (!sel || sel.pane !== d.pane) { return; }
    ctx.strokeStyle = '#00b8d4'; ctx.fillStyle = '#00b8d4'; ctx.lineWidth = 3.5;
    ctx.shadowColor = '#fff'; ctx.shadowBlur = 4;
    var vs = m.verticesOf(sel.kind, sel.id), ss = vs.map(function (v) { return S[v]; });
    if (sel.kind === 'v' && ss[0]) { ctx.beginPath(); ctx.arc(ss[0][0], ss[0][1], 7, 0, 2 * Math.PI); ctx.stroke(); }
    if (sel.kind === 'e' && ss[0] && ss[1]) { ctx.beginPath(); ctx.moveTo(ss[0][0], ss[0][1]); ctx.lineTo(ss[1][0], ss[1][1]); ctx.stroke(); }
    if (sel.kind === 'h') {
      var it = items.filter(function (x) { return x.kind === 'h' && x.id === sel.id; }).pop();
      if (it) { arrow(ctx, [it.seg[0], it.seg[1]], [it.seg[2], it.seg[3]], (it.seg[0] + it.seg[2]) / 2, (it.seg[1] + it.seg[3]) / 2, '#00b8d4', 3.5); } else if (ss[0] && ss[1]) {
        arrow(ctx, ss[0], ss[1], (ss[0][0] + ss[1][0]) / 2, (ss[0][1] + ss[1][1]) / 2, '#00b8d4', 3.5);
      }
    }
    if (sel.kind === 'f' && ss.length >= 2 && ss.every(function (s) { return s; })) {
      ctx.beginPath(); ss.forEach(function (s, i) { if (i) { ctx.lineTo(s[0], s[1]); } else { ctx.moveTo(s[0], s[1]); } });
      ctx.closePath(); ctx.stroke();
    }
    ctx.shadowBlur = 0;
  }
