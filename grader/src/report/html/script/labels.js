  // The labels, placed once a pane is drawn so that none covers another.

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

