#!/usr/bin/env python3
"""Draws the handout's figures: `python3 docs/figures/make_figures.py`
(English, into this folder) and `... --lang zh` (Chinese, into `zh/`);
`--out DIR` writes them elsewhere (the docs test compares the two).

Plain Python 3, no dependencies. Each figure is computed from the same
vertex positions the text uses, so halfedge arrows sit exactly inside their
faces and point the way the mesh's links run. The SVG it writes is meant to
be inlined by rustdoc (`#[doc = include_str!(...)]`) as well as shown as an
image by Markdown viewers, hence:
- no blank lines (a blank line would end rustdoc's HTML block),
- no ids, no <defs>, no markers (several figures share one page's ids),
- arrowheads drawn as polygons, an opaque white background (dark themes),
- generic font families only, nothing fetched.

Coordinates below are mathematical (y up) in pixels; `Fig` flips them.
Faces are listed counter-clockwise in the picture, as the lab's meshes are
seen from the side their faces wind counter-clockwise.
"""

import argparse
import math
import os

OUT = os.path.dirname(os.path.abspath(__file__))
LANG = "en"

INK = "#222222"
OLD = "#222222"
NEW = "#0a6ebd"  # new elements: blue
HOT = "#c2410c"  # the edge being operated on: orange
GREY = "#8a8a8a"
FAINT = "#c8c8c8"
HOLE = "#ececec"
SANS = "DejaVu Sans, Helvetica, Arial, sans-serif"
MONO = "DejaVu Sans Mono, Menlo, Consolas, monospace"
# Chinese figures name CJK fonts before the generic family.
CJK = "Noto Sans CJK SC, Source Han Sans SC, PingFang SC, Microsoft YaHei"
SANS_ZH = "DejaVu Sans, " + CJK + ", sans-serif"
MONO_ZH = "DejaVu Sans Mono, Menlo, Consolas, " + CJK + ", monospace"

# Every caption in words, in Chinese (code, names and formulas stay).
ZH = {
    "A halfedge h and its five links: twin, next, vertex, edge, face":
        "半边 h 及其五个链接：twin、next、vertex、edge、face",
    "mesh[a].halfedge: any halfedge": "mesh[a].halfedge：任意一条",
    "  that starts at a (h, ...)": "  从 a 出发的半边（h, ...）",
    "mesh[e].halfedge: h or t": "mesh[e].halfedge：h 或 t",
    "mesh[f0].halfedge: h, h1 or h2": "mesh[f0].halfedge：h、h1 或 h2",
    "vertex_halfedges(v) turns by twin then next: clockwise when faces are counter-clockwise":
        "vertex_halfedges(v) 先走 twin 再走 next：面为逆时针时，绕顶点顺时针转",
    "faces counter-clockwise in the": "图中各面为逆时针，",
    "picture: the walk turns clockwise": "绕顶点的行走为顺时针",
    "one step back:": "退回一步：",
    "flip_edge(mesh, e): before and after, six halfedges named":
        "flip_edge(mesh, e)：翻转前后，标出六条半边",
    "flip": "翻转",
    "split_edge(mesh, e) on an edge between two triangles: before and after":
        "split_edge(mesh, e) 作用于两个三角形之间的边：分裂前后",
    "split": "分裂",
    "edges: e = a-m (old id)": "边：e = a-m（原来的 id）",
    "eb = m-b, ec = m-c, ed = m-d (new)": "eb = m-b, ec = m-c, ed = m-d（新建）",
    "mesh[m].halfedge == hb: along the old edge": "mesh[m].halfedge == hb：沿着旧边",
    "split_edge(mesh, e) on a boundary edge: only the real triangle is divided":
        "split_edge(mesh, e) 作用于边界边：只分割真实的三角形",
    "f1: is_boundary (the hole)": "f1：is_boundary（洞）",
    "One old triangle through subdivision: three splits, then one flip":
        "一个旧三角形的细分过程：三次分裂，再一次翻转",
    "input": "输入",
    "1. split AB": "1. 分裂 AB",
    "2. split BC": "2. 分裂 BC",
    "3. split CA": "3. 分裂 CA",
    "4. flip m1-C": "4. 翻转 m1-C",
    "old vertex": "旧顶点",
    "new vertex": "新顶点",
    "old edge (or half of one)": "旧边（或其一半）",
    "new edge": "新边",
    "new, joins old and new: flip": "新边，连接旧顶点和新顶点：翻转",
    "flipped": "已翻转",
    "The lab's Loop weights: vertex mask and edge mask": "实验采用的 Loop 权重：顶点模板与边模板",
    "old vertex v with n neighbours": "有 n 个邻居的旧顶点 v",
    "u = 3/16 if n = 3, else 3/(8n)": "n = 3 时 u = 3/16，否则 u = 3/(8n)",
    "n = 3: u = 3/16, v keeps 7/16": "n = 3：u = 3/16，v 保留 7/16",
    "n = 6: u = 1/16, v keeps 5/8": "n = 6：u = 1/16，v 保留 5/8",
    "new vertex m on edge ab": "边 ab 上的新顶点 m",
    "Boundary rules: edge 1/2, 1/2; vertex 3/4, 1/8, 1/8": "边界规则：边 1/2、1/2；顶点 3/4、1/8、1/8",
    "hole": "洞",
    "new vertex on a boundary edge": "边界边上的新顶点",
    "old vertex on the boundary": "边界上的旧顶点",
}


def tr(s):
    """A caption in the figures' language."""
    return ZH.get(s, s) if LANG == "zh" else s


def add(p, q):
    return (p[0] + q[0], p[1] + q[1])


def sub(p, q):
    return (p[0] - q[0], p[1] - q[1])


def mul(p, s):
    return (p[0] * s, p[1] * s)


def lerp(p, q, t):
    return (p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t)


def norm(p):
    n = math.hypot(p[0], p[1])
    return (p[0] / n, p[1] / n)


def left(d):
    """The left normal of direction d (math coordinates)."""
    return (-d[1], d[0])


def centroid(pts):
    return (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))


def esc(s):
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


class Fig:
    def __init__(self, name, width, height, title):
        self.name = name
        self.w = width
        self.h = height
        self.title = tr(title)
        self.items = []

    def xy(self, p):
        return (round(p[0], 1), round(self.h - p[1], 1))

    def line(self, p, q, color=INK, width=2.0, dash=None, cap="round"):
        (x1, y1), (x2, y2) = self.xy(p), self.xy(q)
        d = f' stroke-dasharray="{dash}"' if dash else ""
        self.items.append(
            f'<line x1="{x1}" y1="{y1}" x2="{x2}" y2="{y2}" stroke="{color}" '
            f'stroke-width="{width}" stroke-linecap="{cap}"{d}/>'
        )

    def polygon(self, pts, fill, stroke="none", width=0):
        s = " ".join("%s,%s" % self.xy(p) for p in pts)
        self.items.append(
            f'<polygon points="{s}" fill="{fill}" stroke="{stroke}" stroke-width="{width}"/>'
        )

    def polyline(self, pts, color=INK, width=2.0, dash=None):
        s = " ".join("%s,%s" % self.xy(p) for p in pts)
        d = f' stroke-dasharray="{dash}"' if dash else ""
        self.items.append(
            f'<polyline points="{s}" fill="none" stroke="{color}" stroke-width="{width}" '
            f'stroke-linejoin="round" stroke-linecap="round"{d}/>'
        )

    def arrow(self, p, q, color=INK, width=2.0, head=9.0, dash=None):
        """A straight arrow from p to q whose head ends exactly at q."""
        d = norm(sub(q, p))
        base = sub(q, mul(d, head))
        self.line(p, base, color, width, dash, cap="butt")
        n = left(d)
        self.polygon(
            [q, add(base, mul(n, head * 0.42)), sub(base, mul(n, head * 0.42))], color
        )

    def curved_arrow(self, p, q, bend, color=INK, width=1.6, head=8.0):
        """A quadratic arc from p to q bulging `bend` px to the left."""
        mid = lerp(p, q, 0.5)
        ctrl = add(mid, mul(left(norm(sub(q, p))), bend))
        (x1, y1), (cx, cy), (x2, y2) = self.xy(p), self.xy(ctrl), self.xy(q)
        d = norm(sub(q, ctrl))
        base = sub(q, mul(d, head))
        (bx, by) = self.xy(base)
        self.items.append(
            f'<path d="M{x1},{y1} Q{cx},{cy} {bx},{by}" fill="none" stroke="{color}" '
            f'stroke-width="{width}"/>'
        )
        n = left(d)
        self.polygon(
            [q, add(base, mul(n, head * 0.42)), sub(base, mul(n, head * 0.42))], color
        )

    def dot(self, p, color=INK, r=5.5, hollow=False):
        x, y = self.xy(p)
        if hollow:
            self.items.append(
                f'<circle cx="{x}" cy="{y}" r="{r}" fill="#ffffff" stroke="{color}" stroke-width="2.2"/>'
            )
        else:
            self.items.append(f'<circle cx="{x}" cy="{y}" r="{r}" fill="{color}"/>')

    def text(self, p, s, size=16, color=INK, anchor="middle", font=SANS,
             weight="normal", style="normal", halo=True):
        s = tr(s)
        if LANG == "zh":
            font = {SANS: SANS_ZH, MONO: MONO_ZH}.get(font, font)
        x, y = self.xy(p)
        # dominant-baseline is not honoured everywhere: shift by hand so
        # that p is the text's visual centre.
        y = round(y + size * 0.35, 1)
        h = (' stroke="#ffffff" stroke-width="4" stroke-linejoin="round" '
             'paint-order="stroke"') if halo else ""
        w = f' font-weight="{weight}"' if weight != "normal" else ""
        st = f' font-style="{style}"' if style != "normal" else ""
        self.items.append(
            f'<text x="{x}" y="{y}" font-family="{font}" font-size="{size}" '
            f'fill="{color}" text-anchor="{anchor}" xml:space="preserve"{w}{st}{h}>{esc(s)}</text>'
        )

    def write(self):
        head = (
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{self.w}" height="{self.h}" '
            f'viewBox="0 0 {self.w} {self.h}" role="img" aria-label="{esc(self.title)}" '
            f'style="max-width:100%;height:auto;background:#ffffff">'
        )
        body = [
            head,
            f"<title>{esc(self.title)}</title>",
            f'<rect x="0" y="0" width="{self.w}" height="{self.h}" fill="#ffffff"/>',
        ] + self.items + ["</svg>"]
        text = "\n".join(body) + "\n"
        # What rustdoc's inlining needs (see the module docstring).
        assert "\n\n" not in text and " id=" not in text, self.name
        folder = os.path.join(OUT, "zh") if LANG == "zh" else OUT
        os.makedirs(folder, exist_ok=True)
        path = os.path.join(folder, self.name + ".svg")
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        print("wrote", path)


# ---- halfedges drawn inside their faces ---------------------------------------


def inset_polygon(pts, d):
    """The polygon whose sides run d px inside those of the counter-clockwise
    polygon pts (each side moved along its left normal)."""
    n = len(pts)
    lines = []
    for i in range(n):
        p, q = pts[i], pts[(i + 1) % n]
        dirv = norm(sub(q, p))
        off = mul(left(dirv), d)
        lines.append((add(p, off), dirv))
    out = []
    for i in range(n):
        (p1, d1), (p2, d2) = lines[i - 1], lines[i]
        # p1 + s d1 = p2 + r d2
        den = d1[0] * d2[1] - d1[1] * d2[0]
        s = ((p2[0] - p1[0]) * d2[1] - (p2[1] - p1[1]) * d2[0]) / den
        out.append(add(p1, mul(d1, s)))
    return out


def draw_face_halfedges(fig, pts, names, colors=None, inset=11, trim=0.16,
                        label_inset=27, size=15, label_shift=None):
    """Draws the halfedges of the counter-clockwise face pts (pts[i] to
    pts[i+1] is names[i]) as arrows inside it, each labelled."""
    n = len(pts)
    arrows = inset_polygon(pts, inset)
    labels = inset_polygon(pts, label_inset)
    for i in range(n):
        if names[i] is None:
            continue
        c = colors[i] if colors else INK
        p, q = arrows[i], arrows[(i + 1) % n]
        fig.arrow(lerp(p, q, trim), lerp(p, q, 1 - trim), c, 2.0, head=10)
        lp, lq = labels[i], labels[(i + 1) % n]
        at = lerp(lp, lq, 0.5)
        if label_shift and names[i] in label_shift:
            at = add(at, label_shift[names[i]])
        fig.text(at, names[i], size, c, font=MONO)


def draw_edges(fig, edges, color=OLD, width=2.0, dash=None):
    for p, q in edges:
        fig.line(p, q, color, width, dash)


def label_vertex(fig, p, name, offset, color=INK, size=19):
    fig.text(add(p, offset), name, size, color, style="italic")


# ---- the figures -----------------------------------------------------------------


def halfedge_figure():
    f = Fig("halfedge", 720, 420, "A halfedge h and its five links: twin, next, vertex, edge, face")
    o = (40, 210)
    a, b = add(o, (0, 0)), add(o, (300, 0))
    c, d = add(o, (150, 175)), add(o, (150, -175))
    draw_edges(f, [(a, c), (b, c), (a, d), (b, d)])
    f.line(a, b, HOT, 3.0)
    f0 = [a, b, c]
    f1 = [b, a, d]
    draw_face_halfedges(f, f0, ["h", "h1", "h2"], [HOT, NEW, GREY])
    draw_face_halfedges(f, f1, ["t", None, None], [HOT, None, None])
    for p in (a, b, c, d):
        f.dot(p)
    label_vertex(f, a, "a", (-16, 0))
    label_vertex(f, b, "b", (16, 0))
    label_vertex(f, c, "c", (0, 18))
    label_vertex(f, d, "d", (0, -18))
    f.text(add(centroid(f0), (0, 12)), "f0", 18, GREY)
    f.text(add(centroid(f1), (0, -12)), "f1", 18, GREY)
    f.text(add(lerp(a, b, 0.5), (0, 0)), "e", 16, HOT, style="italic")
    # The listing on the right.
    x, y = 380, 360
    rows = [
        ("mesh[h].twin   == t", HOT),
        ("mesh[h].next   == h1", NEW),
        ("mesh[h].vertex == a", INK),
        ("mesh[h].edge   == e", INK),
        ("mesh[h].face   == f0", INK),
        ("mesh.prev(h)   == h2", GREY),
        ("", INK),
        ("mesh[a].halfedge: any halfedge", INK),
        ("  that starts at a (h, ...)", INK),
        ("mesh[e].halfedge: h or t", INK),
        ("mesh[f0].halfedge: h, h1 or h2", INK),
        ("mesh.halfedge_dst(h) == b", INK),
    ]
    for i, (s, col) in enumerate(rows):
        f.text((x, y - i * 25), s, 15, col, anchor="start", font=MONO, halo=False)
    f.write()


def vertex_walk_figure():
    f = Fig("vertex-walk", 760, 440,
            "vertex_halfedges(v) turns by twin then next: clockwise when faces are counter-clockwise")
    v = (215, 220)
    R = 190
    # The ring clockwise from east: spoke k at -60k degrees.
    units = [(math.cos(math.radians(-60 * k)), math.sin(math.radians(-60 * k))) for k in range(6)]
    ring = [add(v, mul(u, R)) for u in units]
    for k in range(6):
        f.line(v, ring[k], OLD, 2.0)
        f.line(ring[k], ring[(k + 1) % 6], FAINT, 2.0)
    # g_k = v -> ring[k] has its face on its left (the counter-clockwise
    # side); twin(g_k) runs back on the right, in the face that also holds
    # g_(k+1), the next halfedge out of v.
    for k in range(3):
        u = units[k]
        n = left(u)
        g0, g1 = add(v, add(mul(u, 38), mul(n, 9))), add(v, add(mul(u, 165), mul(n, 9)))
        f.arrow(g0, g1, NEW, 2.2, head=11)
        f.text(add(v, add(mul(u, 150), mul(n, 28))), f"g{k}", 15, NEW, font=MONO)
        t0, t1 = add(v, add(mul(u, 165), mul(n, -9))), add(v, add(mul(u, 38), mul(n, -9)))
        f.arrow(t0, t1, HOT, 2.2, head=11)
        lab = add(v, add(mul(u, 92), mul(n, -44)))
        f.text(lab, f"twin(g{k})", 14, HOT, font=MONO)
    # The turning direction, from spoke 0 towards spoke 2.
    r = 62
    arc = [add(v, (r * math.cos(math.radians(-t)), r * math.sin(math.radians(-t))))
           for t in range(14, 112, 3)]
    f.polyline(arc[:-1], GREY, 1.8)
    f.arrow(arc[-3], arc[-1], GREY, 1.8, head=9)
    f.dot(v)
    for p in ring:
        f.dot(p)
    label_vertex(f, v, "v", (-22, 14))
    x, y = 440, 360
    rows = [
        ("vertex_halfedges(v):", INK),
        ("  g0, g1, g2, ...", NEW),
        ("g(k+1) == mesh[mesh[g(k)].twin].next", INK),
        ("", INK),
        ("faces counter-clockwise in the", GREY),
        ("picture: the walk turns clockwise", GREY),
        ("", INK),
        ("one step back:", INK),
        ("g(k) == mesh[mesh.prev(g(k+1))].twin", INK),
    ]
    for i, (s, col) in enumerate(rows):
        f.text((x, y - i * 25), s, 14, col, anchor="start", font=MONO, halo=False)
    f.write()


def pair(o, w=300, hgt=175):
    a, b = add(o, (0, 0)), add(o, (w, 0))
    c, d = add(o, (w / 2, hgt)), add(o, (w / 2, -hgt))
    return a, b, c, d


def flip_figure():
    f = Fig("flip", 820, 430, "flip_edge(mesh, e): before and after, six halfedges named")
    for panel, o in enumerate([(40, 215), (480, 215)]):
        a, b, c, d = pair(o)
        draw_edges(f, [(a, c), (b, c), (a, d), (b, d)])
        if panel == 0:
            f.line(a, b, HOT, 3.0)
            draw_face_halfedges(f, [a, b, c], ["h", "h1", "h2"], [HOT, INK, INK])
            draw_face_halfedges(f, [b, a, d], ["t", "t1", "t2"], [HOT, INK, INK])
            f.text(add(centroid([a, b, c]), (0, 14)), "f0", 18, GREY)
            f.text(add(centroid([b, a, d]), (0, -14)), "f1", 18, GREY)
            f.text(lerp(a, b, 0.5), "e", 16, HOT, style="italic")
        else:
            f.line(d, c, HOT, 3.0)
            # f0 = (d, c, a), f1 = (c, d, b): as in the doc comment.
            draw_face_halfedges(f, [d, c, a], ["h", "h2", "t1"], [HOT, INK, INK])
            draw_face_halfedges(f, [c, d, b], ["t", "t2", "h1"], [HOT, INK, INK])
            f.text(add(centroid([d, c, a]), (-16, 0)), "f0", 18, GREY)
            f.text(add(centroid([c, d, b]), (16, 0)), "f1", 18, GREY)
            f.text(add(lerp(c, d, 0.5), (0, 0)), "e", 16, HOT, style="italic")
        for p in (a, b, c, d):
            f.dot(p)
        label_vertex(f, a, "a", (-16, 0))
        label_vertex(f, b, "b", (16, 0))
        label_vertex(f, c, "c", (0, 18))
        label_vertex(f, d, "d", (0, -18))
    f.arrow((382, 215), (448, 215), INK, 2.5, head=13)
    f.text((415, 240), "flip", 15, INK, font=MONO, halo=False)
    f.write()


def split_figure():
    f = Fig("split", 900, 560, "split_edge(mesh, e) on an edge between two triangles: before and after")
    w, hgt = 340, 200
    o1, o2 = (40, 325), (520, 325)
    a, b, c, d = pair(o1, w, hgt)
    draw_edges(f, [(a, c), (b, c), (a, d), (b, d)])
    f.line(a, b, HOT, 3.0)
    draw_face_halfedges(f, [a, b, c], ["h", "h1", "h2"], [HOT, INK, INK])
    draw_face_halfedges(f, [b, a, d], ["t", "t1", "t2"], [HOT, INK, INK])
    f.text(add(centroid([a, b, c]), (0, 18)), "f0", 18, GREY)
    f.text(add(centroid([b, a, d]), (0, -18)), "f1", 18, GREY)
    f.text(lerp(a, b, 0.5), "e", 16, HOT, style="italic")
    for p, n, off in ((a, "a", (-16, 0)), (b, "b", (16, 0)), (c, "c", (0, 18)), (d, "d", (0, -18))):
        f.dot(p)
        label_vertex(f, p, n, off)

    a, b, c, d = pair(o2, w, hgt)
    m = lerp(a, b, 0.5)
    draw_edges(f, [(a, c), (b, c), (a, d), (b, d)])
    f.line(a, m, HOT, 3.0)
    f.line(m, b, NEW, 3.0)
    f.line(m, c, NEW, 2.0)
    f.line(m, d, NEW, 2.0)
    k = dict(inset=10, label_inset=25, size=14, trim=0.17)
    draw_face_halfedges(f, [a, m, c], ["h", "hc", "h2"], [HOT, NEW, INK], **k)
    draw_face_halfedges(f, [m, b, c], ["hb", "h1", "tc"], [NEW, INK, NEW], **k)
    draw_face_halfedges(f, [m, a, d], ["t", "t1", "td"], [HOT, INK, NEW], **k)
    draw_face_halfedges(f, [b, m, d], ["tb", "hd", "t2"], [NEW, NEW, INK], **k)
    # Face names nearer the corner at m than the centroid, clear of labels.
    for face, name, col in (([a, m, c], "f0", GREY), ([m, b, c], "f2", NEW),
                            ([m, a, d], "f1", GREY), ([b, m, d], "f3", NEW)):
        f.text(lerp(centroid(face), m, 0.3), name, 17, col)
    for p, n, off in ((a, "a", (-16, 0)), (b, "b", (16, 0)), (c, "c", (0, 18)), (d, "d", (0, -18))):
        f.dot(p)
        label_vertex(f, p, n, off)
    f.dot(m, NEW, hollow=True)
    label_vertex(f, m, "m", (-15, -17), NEW)
    f.arrow((410, 325), (480, 325), INK, 2.5, head=13)
    f.text((445, 350), "split", 15, INK, font=MONO, halo=False)
    rows = [("edges: e = a-m (old id)", HOT), ("eb = m-b, ec = m-c, ed = m-d (new)", NEW),
            ("mesh[m].halfedge == hb: along the old edge", NEW)]
    for i, (s, col) in enumerate(rows):
        f.text((500, 64 - i * 22), s, 15, col, anchor="start", font=MONO, halo=False)
    f.write()


def hole(f, left_x, right_x, y, depth):
    """The hole below the boundary line at height y, as a grey band."""
    f.polygon([(left_x, y), (right_x, y), (right_x, y - depth), (left_x, y - depth)], HOLE)


def split_boundary_figure():
    f = Fig("split-boundary", 940, 420,
            "split_edge(mesh, e) on a boundary edge: only the real triangle is divided")
    w, hgt = 300, 180
    y = 200
    for panel, o in enumerate([(70, y), (560, y)]):
        a, b, c, _ = pair(o, w, hgt)
        p, q = add(a, (-52, 0)), add(b, (52, 0))
        hole(f, p[0] - 8, q[0] + 8, y, 105)
        f.text(((p[0] + q[0]) / 2, y - 88), "f1: is_boundary (the hole)", 14, GREY,
               font=MONO, halo=False)
        draw_edges(f, [(a, c), (b, c), (p, a), (b, q)])
        f.line(p, c, FAINT, 2.0)
        f.line(q, c, FAINT, 2.0)
        yy = y - 12
        # The hole's loop runs right to left, just below the line.
        f.arrow((q[0] - 6, yy), (b[0] + 10, yy), GREY, 2.0, head=10)
        f.arrow((a[0] - 10, yy), (p[0] + 6, yy), GREY, 2.0, head=10)
        f.text(((q[0] + b[0]) / 2, yy - 22), "prev_t", 13, GREY, font=MONO)
        f.text(((a[0] + p[0]) / 2, yy - 22), "next_t", 13, GREY, font=MONO)
        if panel == 0:
            f.line(a, b, HOT, 3.0)
            draw_face_halfedges(f, [a, b, c], ["h", "h1", "h2"], [HOT, INK, INK])
            f.text(add(centroid([a, b, c]), (0, 14)), "f0", 18, GREY)
            f.text(lerp(a, b, 0.5), "e", 16, HOT, style="italic")
            f.arrow((b[0] - 30, yy), (a[0] + 30, yy), HOT, 2.0, head=10)
            f.text(((a[0] + b[0]) / 2, yy - 22), "t", 15, HOT, font=MONO)
            rows = [("prev_t == mesh.prev(t)", GREY), ("next_t == mesh[t].next", GREY)]
        else:
            m = lerp(a, b, 0.5)
            f.line(a, m, HOT, 3.0)
            f.line(m, b, NEW, 3.0)
            f.line(m, c, NEW, 2.0)
            k = dict(inset=10, label_inset=25, size=14, trim=0.17)
            draw_face_halfedges(f, [a, m, c], ["h", "hc", "h2"], [HOT, NEW, INK], **k)
            draw_face_halfedges(f, [m, b, c], ["hb", "h1", "tc"], [NEW, INK, NEW], **k)
            f.text(lerp(centroid([a, m, c]), m, 0.3), "f0", 17, GREY)
            f.text(lerp(centroid([m, b, c]), m, 0.3), "f2", 17, NEW)
            f.arrow((b[0] - 12, yy), (m[0] + 12, yy), NEW, 2.0, head=10)
            f.arrow((m[0] - 12, yy), (a[0] + 12, yy), HOT, 2.0, head=10)
            f.text(((m[0] + b[0]) / 2, yy - 22), "tb", 15, NEW, font=MONO)
            f.text(((a[0] + m[0]) / 2, yy - 22), "t", 15, HOT, font=MONO)
            f.dot(m, NEW, hollow=True)
            label_vertex(f, m, "m", (-15, 17), NEW)
            rows = [("mesh[prev_t].next == tb", NEW), ("mesh[tb].next == t", NEW),
                    ("e = a-m, eb = m-b, ec = m-c", NEW)]
        for v, n, off in ((a, "a", (-6, 18)), (b, "b", (6, 18)), (c, "c", (0, 18))):
            f.dot(v)
            label_vertex(f, v, n, off)
        f.dot(p, GREY)
        f.dot(q, GREY)
        for i, (s, col) in enumerate(rows):
            f.text((o[0] - 52, 66 - i * 22), s, 14, col, anchor="start", font=MONO, halo=False)
    f.arrow((452, 260), (496, 260), INK, 2.5, head=13)
    f.text((474, 285), "split", 15, INK, font=MONO, halo=False)
    f.write()


def steps_figure():
    f = Fig("split-flip-steps", 960, 330,
            "One old triangle through subdivision: three splits, then one flip")
    side = 146
    hgt = side * math.sqrt(3) / 2
    titles = ["input", "split AB", "split BC", "split CA", "flip m1-C"]
    for k in range(5):
        o = (30 + k * 190, 95)
        A, B = o, add(o, (side, 0))
        C = add(o, (side / 2, hgt))
        m1, m2, m3 = lerp(A, B, 0.5), lerp(B, C, 0.5), lerp(C, A, 0.5)
        old = [(A, B), (B, C), (C, A)]
        draw_edges(f, old, OLD, 2.2)
        new_edges = []
        if k >= 1:
            new_edges.append((m1, C))
        if k >= 2:
            new_edges.append((m2, m1))
        if k >= 3:
            new_edges.append((m3, m1))
        for p, q in new_edges:
            if (p, q) == (m1, C) and k == 3:
                f.line(p, q, HOT, 2.6, dash="7 5")
            elif (p, q) == (m1, C) and k == 4:
                pass  # flipped away
            else:
                f.line(p, q, NEW, 2.2)
        if k == 4:
            f.line(m2, m3, HOT, 2.6)
        for p in (A, B, C):
            f.dot(p)
        label_vertex(f, A, "A", (-4, -19), size=16)
        label_vertex(f, B, "B", (4, -19), size=16)
        label_vertex(f, C, "C", (0, 16), size=16)
        shown = [m1] * (k >= 1) + [m2] * (k >= 2) + [m3] * (k >= 3)
        names = {m1: ("m1", (0, -16)), m2: ("m2", (16, 8)), m3: ("m3", (-16, 8))}
        for p in shown:
            f.dot(p, NEW, r=5, hollow=True)
            n, off = names[p]
            label_vertex(f, p, n, off, NEW, size=14)
        f.text((o[0] + side / 2, 295), f"{k}. {titles[k]}" if k else titles[k], 15, INK,
               font=MONO, halo=False)
        if k < 4:
            f.arrow((o[0] + side + 10, 150), (o[0] + side + 36, 150), GREY, 2.0, head=9)
    # Legend.
    y = 30
    f.dot((40, y), INK)
    f.text((52, y), "old vertex", 13, INK, anchor="start", halo=False)
    f.dot((150, y), NEW, r=5, hollow=True)
    f.text((162, y), "new vertex", 13, INK, anchor="start", halo=False)
    f.line((262, y), (292, y), OLD, 2.2)
    f.text((300, y), "old edge (or half of one)", 13, INK, anchor="start", halo=False)
    f.line((490, y), (520, y), NEW, 2.2)
    f.text((528, y), "new edge", 13, INK, anchor="start", halo=False)
    f.line((612, y), (642, y), HOT, 2.6, dash="7 5")
    f.text((650, y), "new, joins old and new: flip", 13, INK, anchor="start", halo=False)
    f.line((842, y), (872, y), HOT, 2.6)
    f.text((880, y), "flipped", 13, INK, anchor="start", halo=False)
    f.write()


def weight(f, p, s, color=INK, offset=(0, 0), size=16):
    f.text(add(p, offset), s, size, color, weight="bold")


def masks_figure():
    f = Fig("loop-masks", 820, 470, "The lab's Loop weights: vertex mask and edge mask")
    # Vertex mask, drawn for n = 6.
    v = (200, 190)
    r = 130
    ring = [add(v, (r * math.cos(math.radians(60 * k + 30)), r * math.sin(math.radians(60 * k + 30))))
            for k in range(6)]
    for k in range(6):
        f.line(v, ring[k], OLD, 2.0)
        f.line(ring[k], ring[(k + 1) % 6], FAINT, 2.0)
    for k, p in enumerate(ring):
        f.dot(p)
        out = norm(sub(p, v))
        weight(f, p, "u", NEW, mul(out, 22))
    f.dot(v, HOT, r=7)
    f.text(add(v, (14, 0)), "1 - n\u00b7u", 16, HOT, anchor="start", weight="bold")
    f.text((200, 452), "old vertex v with n neighbours", 14, INK, halo=False)
    f.text((200, 430), "u = 3/16 if n = 3, else 3/(8n)", 14, INK, font=MONO, halo=False)
    f.text((200, 406), "n = 3: u = 3/16, v keeps 7/16", 13, GREY, font=MONO, halo=False)
    f.text((200, 388), "n = 6: u = 1/16, v keeps 5/8", 13, GREY, font=MONO, halo=False)
    # Edge mask.
    o = (470, 190)
    a, b = o, add(o, (280, 0))
    c, d = add(o, (140, 140)), add(o, (140, -140))
    draw_edges(f, [(a, c), (b, c), (a, d), (b, d)], OLD, 2.0)
    f.line(a, b, HOT, 3.0)
    m = lerp(a, b, 0.5)
    for p in (a, b, c, d):
        f.dot(p)
    f.dot(m, NEW, r=7, hollow=True)
    weight(f, a, "3/8", NEW, (-28, 0))
    weight(f, b, "3/8", NEW, (28, 0))
    weight(f, c, "1/8", NEW, (0, 20))
    weight(f, d, "1/8", NEW, (0, -20))
    label_vertex(f, a, "a", (-12, -18), size=16)
    label_vertex(f, b, "b", (12, -18), size=16)
    label_vertex(f, c, "c", (24, 4), size=16)
    label_vertex(f, d, "d", (24, -4), size=16)
    f.text(add(m, (0, 20)), "m", 16, NEW, style="italic")
    f.text((610, 452), "new vertex m on edge ab", 14, INK, halo=False)
    f.text((610, 430), "3/8 (a + b) + 1/8 (c + d)", 14, INK, font=MONO, halo=False)
    f.write()


def boundary_masks_figure():
    f = Fig("boundary-masks", 820, 400, "Boundary rules: edge 1/2, 1/2; vertex 3/4, 1/8, 1/8")
    y0 = 130
    # Edge rule.
    a, b = (90, y0), (330, y0)
    c = (210, y0 + 150)
    hole(f, 40, 380, y0, 80)
    f.text((210, y0 - 55), "hole", 14, GREY, halo=False)
    f.line(a, c, OLD, 2.0)
    f.line(b, c, OLD, 2.0)
    f.line((40, y0), a, OLD, 2.0)
    f.line(b, (380, y0), OLD, 2.0)
    f.line(a, b, HOT, 3.0)
    m = lerp(a, b, 0.5)
    for p in (a, b, c):
        f.dot(p)
    f.dot(m, NEW, r=7, hollow=True)
    weight(f, a, "1/2", NEW, (0, -24))
    weight(f, b, "1/2", NEW, (0, -24))
    weight(f, c, "0", GREY, (0, 20))
    f.text((210, 380), "new vertex on a boundary edge", 14, INK, halo=False)
    f.text((210, 358), "1/2 (a + b)", 14, INK, font=MONO, halo=False)
    # Vertex rule.
    v = (610, y0)
    p, q = (470, y0), (750, y0)
    inner = [(540, y0 + 130), (680, y0 + 130)]
    hole(f, 430, 790, y0, 80)
    f.text((610, y0 - 55), "hole", 14, GREY, halo=False)
    f.line(p, v, HOT, 3.0)
    f.line(v, q, HOT, 3.0)
    for w in inner:
        f.line(v, w, OLD, 2.0)
    f.line(p, inner[0], FAINT, 2.0)
    f.line(inner[0], inner[1], FAINT, 2.0)
    f.line(inner[1], q, FAINT, 2.0)
    for w in inner:
        f.dot(w)
        weight(f, w, "0", GREY, (0, 20))
    f.dot(p)
    f.dot(q)
    f.dot(v, HOT, r=7)
    weight(f, v, "3/4", HOT, (0, -24))
    weight(f, p, "1/8", NEW, (0, -24))
    weight(f, q, "1/8", NEW, (0, -24))
    f.text((610, 380), "old vertex on the boundary", 14, INK, halo=False)
    f.text((610, 358), "3/4 v + 1/8 (p + q)", 14, INK, font=MONO, halo=False)
    label_vertex(f, v, "v", (0, 24), size=16)
    label_vertex(f, p, "p", (-14, 14), size=16)
    label_vertex(f, q, "q", (14, 14), size=16)
    label_vertex(f, a, "a", (-14, 14), size=16)
    label_vertex(f, b, "b", (14, 14), size=16)
    label_vertex(f, c, "c", (18, 6), size=16)
    f.write()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="Draws the handout's figures.")
    parser.add_argument("--lang", choices=["en", "zh"], default="en",
                        help="the captions' language (zh: into zh/)")
    parser.add_argument("--out", help="the folder to write into (default: this one)")
    args = parser.parse_args()
    LANG = args.lang
    if args.out:
        OUT = os.path.abspath(args.out)
    halfedge_figure()
    vertex_walk_figure()
    flip_figure()
    split_figure()
    split_boundary_figure()
    steps_figure()
    masks_figure()
    boundary_masks_figure()
