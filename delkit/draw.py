"""Pictures of Kripke models, event models and symbolic structures — SVG, PNG and LaTeX/TikZ, no Graphviz.

:func:`picture` turns a :class:`~delkit.kripke.KripkeModel`, an :class:`~delkit.events.EventModel`, a
:class:`~delkit.symbolic.KnowledgeStructure` or a :class:`~delkit.symbolic_belief.BeliefStructure` into a
:class:`Picture`: positioned nodes and edges. Then

* :meth:`Picture.svg` writes SVG text directly (it is what Jupyter shows: the models have ``_repr_svg_``,
  the structures ``_repr_html_``),
* :meth:`Picture.png` draws the same picture with matplotlib (Agg canvas, no pyplot state touched),
* :meth:`Picture.tikz` writes a ``tikzpicture`` (``standalone=True``: a whole LaTeX document).

Conventions: a node shows the world's (event's) name and its true propositions (its precondition and
postconditions); designated worlds/events are double-circled; edges carry the agents' names; an edge
used in both directions is drawn once without arrow heads (several agents on one edge share it, "a,b");
one-way edges have arrows; reflexive loops are drawn, except for agents whose relation is an equivalence
(S5: every world sees itself; the caption says so). Knowledge structures list their vocabulary, state law
and observed variables, and draw their Kripke model when it has at most ``max_worlds`` states; belief
structures list their relations Ω_a over V and V'.

Layout: networkx (circle for up to 6 nodes, Kamada–Kawai for connected graphs up to 40, spring otherwise,
seeded), scaled so that nodes do not overlap. The drawing code is written here (SVG/TikZ are text formats;
matplotlib only renders the PNG).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from html import escape
from pathlib import Path
from typing import Any

__all__ = ["Picture", "picture"]

_PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")


@dataclass
class Node:
    name: str
    lines: list[str]
    designated: bool
    x: float = 0.0
    y: float = 0.0
    r: float = 24.0


@dataclass
class Edge:
    u: int
    v: int
    label: str
    both: bool          # used in both directions: no arrow heads
    bend: float = 0.0   # curvature (for a one-way edge beside another edge between the same nodes)
    color: str = "#333333"


@dataclass
class Picture:
    """Positioned nodes and edges plus caption lines; render with :meth:`svg`, :meth:`png`, :meth:`tikz`."""

    nodes: list[Node]
    edges: list[Edge]
    caption: list[str] = field(default_factory=list)
    header: list[str] = field(default_factory=list)
    summary: str = ""

    # ------------------------------------------------------------------ geometry
    def _extent(self) -> tuple[float, float, float, float]:
        if not self.nodes:
            return 0.0, 0.0, 200.0, 40.0
        xs0 = [n.x - n.r - 30 for n in self.nodes]
        xs1 = [n.x + n.r + 30 for n in self.nodes]
        ys0 = [n.y - n.r - 40 for n in self.nodes]
        ys1 = [n.y + n.r + 20 for n in self.nodes]
        return min(xs0), min(ys0), max(xs1), max(ys1)

    def _edge_points(self, e: Edge) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
        """Start, control and end point of an edge (quadratic curve), cut at the node circles."""
        a, b = self.nodes[e.u], self.nodes[e.v]
        dx, dy = b.x - a.x, b.y - a.y
        d = math.hypot(dx, dy) or 1.0
        nx_, ny_ = -dy / d, dx / d
        cx, cy = (a.x + b.x) / 2 + e.bend * nx_ * d * 0.25, (a.y + b.y) / 2 + e.bend * ny_ * d * 0.25

        def cut(p: Node, qx: float, qy: float) -> tuple[float, float]:
            ux, uy = qx - p.x, qy - p.y
            du = math.hypot(ux, uy) or 1.0
            rr = p.r + (4 if p.designated else 0) + 1
            return p.x + ux / du * rr, p.y + uy / du * rr

        return cut(a, cx, cy), (cx, cy), cut(b, cx, cy)

    # ------------------------------------------------------------------ SVG
    def svg(self) -> str:
        """The picture as an SVG document (text)."""
        x0, y0, x1, y1 = self._extent()
        head_h = 16 * len(self.header)
        cap_h = 16 * len(self.caption)
        width = max(x1 - x0, 12 + 7 * max((len(s) for s in self.header + self.caption), default=0))
        height = (y1 - y0) + head_h + cap_h + 10
        ox, oy = -x0, -y0 + head_h + 6
        out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
               f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="sans-serif" font-size="12">',
               '<defs><marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" '
               'orient="auto-start-reverse"><path d="M 0 0 L 10 5 L 0 10 z" fill="#333"/></marker></defs>',
               f'<rect width="{width:.0f}" height="{height:.0f}" fill="white"/>']
        for i, line in enumerate(self.header):
            out.append(f'<text x="6" y="{16 * i + 14}" font-family="monospace">{escape(line)}</text>')
        out.append(f'<g transform="translate({ox:.1f},{oy:.1f})">')
        for e in self.edges:
            out.append(self._svg_edge(e))
        for n in self.nodes:
            out.append(f'<g class="world" id="{escape(_ident(n.name))}">')
            if n.designated:
                out.append(f'<circle cx="{n.x:.1f}" cy="{n.y:.1f}" r="{n.r + 4:.1f}" fill="none" stroke="black"/>')
            out.append(f'<circle cx="{n.x:.1f}" cy="{n.y:.1f}" r="{n.r:.1f}" fill="#f8f8f8" stroke="black"/>')
            k = len(n.lines)
            for j, line in enumerate(n.lines):
                dy = (j - (k - 1) / 2) * 14 + 4
                weight = ' font-weight="bold"' if j == 0 else ' font-size="11"'
                out.append(f'<text x="{n.x:.1f}" y="{n.y + dy:.1f}" text-anchor="middle"{weight}>'
                           f'{escape(line)}</text>')
            out.append("</g>")
        out.append("</g>")
        for i, line in enumerate(self.caption):
            out.append(f'<text x="6" y="{height - cap_h + 16 * i + 2:.0f}" font-size="11" fill="#555">'
                       f'{escape(line)}</text>')
        out.append("</svg>")
        return "\n".join(out) + "\n"

    def _svg_edge(self, e: Edge) -> str:
        if e.u == e.v:  # reflexive loop above the node
            n = self.nodes[e.u]
            top = n.y - n.r - (4 if n.designated else 0)
            path = (f'M {n.x - 8:.1f} {top + 1:.1f} C {n.x - 26:.1f} {top - 34:.1f} {n.x + 26:.1f} {top - 34:.1f} '
                    f'{n.x + 8:.1f} {top + 1:.1f}')
            return (f'<g class="edge"><path d="{path}" fill="none" stroke="{e.color}" marker-end="url(#arrow)"/>'
                    f'<text x="{n.x:.1f}" y="{top - 28:.1f}" text-anchor="middle" fill="{e.color}">'
                    f'{escape(e.label)}</text></g>')
        (sx, sy), (cx, cy), (tx, ty) = self._edge_points(e)
        marker = "" if e.both else ' marker-end="url(#arrow)"'
        mx, my = (sx + 2 * cx + tx) / 4, (sy + 2 * cy + ty) / 4
        return (f'<g class="edge"><path d="M {sx:.1f} {sy:.1f} Q {cx:.1f} {cy:.1f} {tx:.1f} {ty:.1f}" fill="none" '
                f'stroke="{e.color}"{marker}/><text x="{mx:.1f}" y="{my - 3:.1f}" text-anchor="middle" '
                f'fill="{e.color}" stroke="white" stroke-width="3" paint-order="stroke">{escape(e.label)}</text></g>')

    def html(self) -> str:
        """HTML for Jupyter: the header lines as preformatted text above the SVG."""
        return self.svg()

    # ------------------------------------------------------------------ TikZ
    def tikz(self, *, standalone: bool = False) -> str:
        """A ``tikzpicture`` (needs ``\\usetikzlibrary{arrows.meta}``); ``standalone``: a whole document."""
        s = 1 / 60  # px → cm
        lines = [r"\begin{tikzpicture}[>=Stealth, every node/.style={font=\small},",
                 r"  world/.style={circle, draw, fill=black!3, align=center, inner sep=1pt},",
                 r"  designated/.style={double, double distance=1.5pt}]"]
        for i, n in enumerate(self.nodes):
            style = "world, designated" if n.designated else "world"
            text = r"\\ ".join([r"\textbf{" + _tex(n.lines[0]) + "}"] + [_tex(t) for t in n.lines[1:]])
            lines.append(f"  \\node[{style}, minimum size={2 * n.r * s:.2f}cm] (n{i}) at "
                         f"({n.x * s:.2f},{-n.y * s:.2f}) {{{text}}};")
        for e in self.edges:
            label = f"node[midway, fill=white, inner sep=1pt, font=\\scriptsize] {{{_tex(e.label)}}}"
            if e.u == e.v:
                lines.append(f"  \\path[->] (n{e.u}) edge[loop above] {label} (n{e.u});")
            else:
                arrow = "-" if e.both else "->"
                bend = "" if not e.bend else f", bend {'left' if e.bend > 0 else 'right'}=20"
                lines.append(f"  \\path[{arrow}] (n{e.u}) edge[draw{bend}] {label} (n{e.v});")
        if self.header or self.caption:
            x0, y0, x1, y1 = self._extent()
            text = r"\\ ".join(_tex(t) for t in self.header + self.caption)
            lines.append(f"  \\node[anchor=north west, align=left, font=\\footnotesize\\ttfamily] at "
                         f"({x0 * s:.2f},{-(y1 + 10) * s:.2f}) {{{text}}};")
        lines.append(r"\end{tikzpicture}")
        body = "\n".join(lines) + "\n"
        if not standalone:
            return body
        return ("\\documentclass[tikz]{standalone}\n\\usetikzlibrary{arrows.meta}\n\\begin{document}\n"
                + body + "\\end{document}\n")

    # ------------------------------------------------------------------ PNG
    def png(self, path: str | Path, *, dpi: int = 150) -> None:
        """Render with matplotlib (Agg canvas) to a PNG file."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.patches import Circle, FancyArrowPatch

        x0, y0, x1, y1 = self._extent()
        extra = 16 * (len(self.header) + len(self.caption))
        longest = max((len(t) for t in self.header + self.caption), default=0)
        w, h = max(x1 - x0, 200, 7 * longest + 12), (y1 - y0) + extra
        fig = Figure(figsize=(w / 72, h / 72))
        FigureCanvasAgg(fig)
        ax = fig.add_axes((0, 0, 1, 1))
        ax.set_xlim(x0, x0 + w)
        ax.set_ylim(y1 + 16 * len(self.caption), y0 - 16 * len(self.header))  # y grows downwards as in SVG
        ax.set_aspect("equal")
        ax.axis("off")
        for e in self.edges:
            if e.u == e.v:
                n = self.nodes[e.u]
                top = n.y - n.r - (4 if n.designated else 0)
                ax.add_patch(FancyArrowPatch((n.x - 8, top), (n.x + 8, top), connectionstyle="arc3,rad=-2.2",
                                             arrowstyle="-|>", mutation_scale=10, color=e.color))
                ax.text(n.x, top - 28, e.label, ha="center", va="center", color=e.color, fontsize=9)
                continue
            (sx, sy), (cx, cy), (tx, ty) = self._edge_points(e)
            ax.add_patch(FancyArrowPatch((sx, sy), (tx, ty), connectionstyle=f"arc3,rad={-e.bend * 0.5}",
                                         arrowstyle="-" if e.both else "-|>", mutation_scale=10, color=e.color))
            mx, my = (sx + 2 * cx + tx) / 4, (sy + 2 * cy + ty) / 4
            ax.text(mx, my, e.label, ha="center", va="center", color=e.color, fontsize=9,
                    bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.5})
        for n in self.nodes:
            if n.designated:
                ax.add_patch(Circle((n.x, n.y), n.r + 4, fill=False, color="black"))
            ax.add_patch(Circle((n.x, n.y), n.r, facecolor="#f8f8f8", edgecolor="black"))
            k = len(n.lines)
            for j, line in enumerate(n.lines):
                ax.text(n.x, n.y + (j - (k - 1) / 2) * 14, line, ha="center", va="center",
                        fontsize=9 if j == 0 else 8, fontweight="bold" if j == 0 else "normal")
        for i, line in enumerate(self.header):
            ax.text(x0 + 6, y0 - 16 * len(self.header) + 16 * i + 8, line, family="monospace", fontsize=9,
                    va="center")
        for i, line in enumerate(self.caption):
            ax.text(x0 + 6, y1 + 16 * i + 8, line, fontsize=8, color="#555", va="center")
        fig.savefig(str(path), dpi=dpi, format="png")


def _ident(name: str) -> str:
    return "w-" + "".join(c if c.isalnum() or c in "-_" else "_" for c in name)


_TEX = {"\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#", "^": r"\^{}",
        "_": r"\_", "%": r"\%", "~": r"\textasciitilde{}", "<": r"\textless{}", ">": r"\textgreater{}",
        "|": r"\textbar{}", "∅": r"$\emptyset$", "Ω": r"$\Omega$", "θ": r"$\theta$", "′": "'"}


def _tex(s: str) -> str:
    return "".join(_TEX.get(c, c) for c in s)


# ============================================================================ building pictures


def picture(obj: Any, *, max_worlds: int = 64, layout: str = "auto", seed: int = 0) -> Picture:
    """The picture of a Kripke model, an event model, or a knowledge/belief structure."""
    from delkit.errors import DelkitError
    from delkit.events import EventModel
    from delkit.kripke import KripkeModel

    if layout not in ("auto", "circle", "spring", "kamada-kawai"):
        raise DelkitError(f"layout {layout!r}: use auto, circle, spring or kamada-kawai")
    if isinstance(obj, KripkeModel):
        _refuse_huge(obj.n_worlds, obj.relations, layout)
        names = [obj.world_name(w) for w in range(obj.n_worlds)]
        labels = [[names[w], ", ".join(sorted(obj.true_props(w))) or "∅"] for w in range(obj.n_worlds)]
        pic = _graph(labels, names, set(obj.designated), obj.relations, obj.agents, layout, seed)
        pic.summary = f"{obj.n_worlds} world(s), agents {', '.join(obj.agents)}"
        return pic
    if isinstance(obj, EventModel):
        from delkit.formula import show

        labels = []
        for i, name in enumerate(obj.events):
            lines = [name, "pre: " + show(obj.pre[i])]
            lines += [f"{p} := {show(v)}" for p, v in sorted(obj.post[i].items())]
            labels.append(lines)
        pic = _graph(labels, list(obj.events), set(obj.designated), obj.relations, obj.agents, layout, seed)
        pic.summary = f"{obj.n_events} event(s), agents {', '.join(obj.agents)}"
        return pic
    if hasattr(obj, "vocabulary") and hasattr(obj, "to_kripke"):
        return _structure(obj, max_worlds, layout, seed)
    raise DelkitError(f"cannot draw a {type(obj).__name__}: give a Kripke model, an event model or a structure")


#: above these a drawing is refused before it is built: kamada-kawai is O(n²) memory and ~O(n³) time
#: (3.8 s CPU for 300 worlds), and every drawn element costs ~1 KB in the picture
KAMADA_KAWAI_MAX = 300


def drawn_edges(relations) -> float:
    """Upper bound of the edges a picture draws: per agent the pairs of its relation (Σ class² for a
    partition), before merging the two directions."""
    import numpy as np

    total = 0.0
    for r in relations.values():
        if r.labels is not None:
            sizes = np.bincount(r.labels).astype(float)
            total += float(sizes @ sizes)
        else:
            total += float(r.rows()[1].size)
    return total


def _refuse_huge(n: int, relations, layout: str) -> None:
    from delkit.errors import DelkitError
    from delkit.resources import require

    if layout == "kamada-kawai" and n > KAMADA_KAWAI_MAX:
        raise DelkitError(f"--layout kamada-kawai: {n} worlds is more than the {KAMADA_KAWAI_MAX} it lays out in "
                          f"reasonable time (O(n³)); use --layout spring or circle, or contract the model first "
                          f"(delkit model contract)")
    require(1024.0 * (n + drawn_edges(relations)), f"drawing {n} world(s)",
            "draw a smaller or contracted model (delkit model contract), or a lower --max-worlds")


def _structure(obj: Any, max_worlds: int, layout: str, seed: int) -> Picture:
    from delkit.kripke import KripkeModel

    belief = hasattr(obj, "relations") and not hasattr(obj, "observed")
    header = [f"{'belief' if belief else 'knowledge'} structure", "V = {" + ", ".join(obj.vocabulary) + "}",
              "θ = " + _bdd_text(obj, obj.law)]
    if belief:
        header += [f"Ω_{a} = " + _bdd_text(obj, r) for a, r in obj.relations.items()]
    else:
        header += [f"O_{a} = {{" + ", ".join(vs) + "}" for a, vs in obj.observed.items()]
    n = obj.count_states()
    if n > max_worlds:
        pic = Picture([], [], header=header, caption=[f"{n} states: the Kripke model is not drawn (more than "
                                                      f"{max_worlds}; raise max_worlds)"])
        pic.summary = f"structure with {n} states, Kripke model not drawn"
        return pic
    from delkit.resources import require, structure_kripke_bytes

    require(structure_kripke_bytes(obj), f"the explicit model of a structure with {n} states",
            "use a lower --max-worlds")
    m = obj.to_kripke()
    states = obj.states()
    names = ["{" + ",".join(v for v in obj.vocabulary if s[v]) + "}" for s in states]
    named = KripkeModel(m.props, m.agents, m.valuation, m.relations, m.designated, tuple(names))
    pic = picture(named, layout=layout, seed=seed)
    for node in pic.nodes:  # the name already lists the true variables
        node.lines = node.lines[:1]
        node.r = max(22.0, len(node.name) * 3.3 + 6)
    _layout(pic.nodes, pic.edges, layout, seed)
    pic.header = header
    pic.caption = [f"{n} state(s); each world is named by its true variables"] + pic.caption
    pic.summary = f"structure with {n} state(s), Kripke model drawn"
    return pic


def _bdd_text(obj: Any, u: Any, limit: int = 90) -> str:
    """A BDD as a formula text (dd's if-then-else expression), shortened to ``limit`` characters."""
    b = obj.bdd
    if u == b.true:
        return "⊤"
    if u == b.false:
        return "⊥"
    text = b.to_expr(u)
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _graph(labels: list[list[str]], names: list[str], designated: set[int], relations: Any, agents: Any,
           layout: str, seed: int) -> Picture:
    n = len(labels)
    nodes = [Node(names[i], labels[i], i in designated) for i in range(n)]
    for node in nodes:
        width = max(len(t) for t in node.lines) * 6.6
        node.r = max(22.0, width / 2 + 6, 7.5 * len(node.lines) + 6)
    # agents per directed pair; S5 agents' loops are left out (said in the caption)
    directed: dict[tuple[int, int], list[str]] = {}
    s5 = []
    for a in agents:
        rel = relations[a]
        equivalence = rel.labels is not None or (rel.is_reflexive() and rel.is_symmetric() and rel.is_transitive())
        if equivalence:
            s5.append(a)
        for x, y in rel.pairs():
            x, y = int(x), int(y)
            if x == y and equivalence:
                continue
            directed.setdefault((x, y), []).append(a)
    edges: list[Edge] = []
    color = {a: _PALETTE[i % len(_PALETTE)] for i, a in enumerate(agents)}
    done = set()
    for (x, y), ags in sorted(directed.items()):
        if (x, y) in done:
            continue
        if x == y:
            edges.append(Edge(x, x, ",".join(ags), False, color=_color(ags, color)))
            continue
        back = directed.get((y, x), [])
        done |= {(x, y), (y, x)}
        both = [a for a in ags if a in back]
        only_xy = [a for a in ags if a not in back]
        only_yx = [a for a in back if a not in ags]
        groups = [(x, y, both, True), (x, y, only_xy, False), (y, x, only_yx, False)]
        present = [g for g in groups if g[2]]
        for k, (u, v, ag, two) in enumerate(present):
            bend = 0.0 if len(present) == 1 else (0.0 if two else (0.8 if k % 2 else -0.8))
            edges.append(Edge(u, v, ",".join(ag), two, bend, _color(ag, color)))
    _layout(nodes, edges, layout, seed)
    caption = []
    if s5:
        caption.append(f"reflexive loops of {', '.join(s5)} not drawn (equivalence relations)")
    if designated:
        caption.append("double circle: designated")
    return Picture(nodes, edges, caption)


def _color(ags: list[str], color: dict[str, str]) -> str:
    return color[ags[0]] if len(ags) == 1 else "#333333"


def _layout(nodes: list[Node], edges: list[Edge], layout: str, seed: int) -> None:
    import networkx as nx

    n = len(nodes)
    if n == 0:
        return
    if n == 1:
        nodes[0].x, nodes[0].y = 0.0, 0.0
        return
    g = nx.Graph()
    g.add_nodes_from(range(n))
    g.add_edges_from((e.u, e.v) for e in edges if e.u != e.v)
    kind = layout
    if kind == "auto":
        kind = "circle" if n <= 6 else ("kamada-kawai" if n <= 40 and nx.is_connected(g) else "spring")
    if kind == "circle":
        pos = nx.circular_layout(g)
    elif kind == "kamada-kawai":
        pos = nx.kamada_kawai_layout(g)
    else:
        import numpy as np

        # any seed 0..2^63-1 (the CLI's range for every seed), mapped to the 32 bits numpy's RandomState takes
        pos = nx.spring_layout(g, seed=int(np.random.SeedSequence(seed).generate_state(1)[0]))
    pts = [(float(pos[i][0]), float(pos[i][1])) for i in range(n)]
    rmax = max(nd.r for nd in nodes)
    dmin = min((math.hypot(a[0] - b[0], a[1] - b[1]) for i, a in enumerate(pts) for b in pts[i + 1:]), default=1.0)
    scale = (2 * rmax + 70) / max(dmin, 1e-6)
    scale = min(scale, 400.0 * math.sqrt(n))
    for nd, (x, y) in zip(nodes, pts, strict=True):
        nd.x, nd.y = x * scale, -y * scale
