  // What is under the pointer, and where an element was drawn.

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

