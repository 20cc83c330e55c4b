  // Where the panes look from: the camera, the frame each pane is fitted
  // to, turning to an element, and the projection.

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

