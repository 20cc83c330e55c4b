  // The mouse (turn, move, zoom, hover, click), the selection, "select
  // error" and Scotty3D's keys.

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

