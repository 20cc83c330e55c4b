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

