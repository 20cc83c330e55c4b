  // The step-through of the student's own subdivision: the mesh before
  // each split or flip their loop_subdivide made, and the end state; the
  // slider shows one of them in the "yours" pane.

  // The frames of the case's data, the last (the end state) shown.
  Inspector.prototype.loadFrames = function () {
    var I = this, data = I.data;
    I.frames = data.frames && data.frames.list && data.frames.list.length ? data.frames : null;
    if (!I.frames) { return; }
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
  };

  // The slider's bar, above the panes.
  Inspector.prototype.buildFrames = function (root) {
    var I = this;
    if (!I.frames) { return; }
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

