  // One inspector per case: its meshes, its layers (what is drawn), the
  // bar of buttons and toggles, the panes and the panel beside them.

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
    I.loadFrames();
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
    I.buildFrames(root);
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

