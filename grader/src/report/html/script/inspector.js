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

