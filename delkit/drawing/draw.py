"""Pictures of Kripke models, event models and symbolic structures — SVG, PNG and LaTeX/TikZ, no Graphviz.

:func:`picture` turns a :class:`~delkit.models.kripke.KripkeModel`, an :class:`~delkit.models.events.EventModel`, a
:class:`~delkit.backends.symbolic.KnowledgeStructure` or a :class:`~delkit.backends.symbolic_belief.BeliefStructure`
into a
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

Layout (``auto``): a Kripke model with at most 48 worlds that differ in at most 8 propositions is drawn in
rows by its valuations (:func:`_layered`: symmetric models come out mirror-symmetric); otherwise networkx —
a circle up to 6 nodes, Kamada–Kawai for connected graphs up to 40, spring above (seeded; a numpy
Fruchterman–Reingold above 300 nodes) — scaled so that nodes do not overlap. Then every edge label is placed
where it covers no node and no other label, loops turn to the node's freest side and straight edges that
would cross a node are bent (:func:`_place_labels`). Propositions true in every world are listed once in the
caption. Label boxes are SVG ``<rect>`` s, not ``paint-order`` halos (cairosvg and rsvg ignore
``paint-order``). The drawing code is written here (SVG/TikZ are text formats; matplotlib only renders the
PNG); the explorer (:mod:`delkit.view`) uses the same positions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from html import escape
from pathlib import Path
from typing import Any

__all__ = ["Picture", "picture", "LAYOUTS", "label_size", "agent_color", "structure_header"]

#: the layouts :func:`picture` takes (``auto``: layered by valuation when small, else by size)
LAYOUTS = ("auto", "layered", "circle", "spring", "kamada-kawai")

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
    loop: tuple[float, float] = (0.0, -1.0)   # a loop's direction (unit vector, y down): the freest side
    lx: float | None = None   # label centre (set by the layout: no two labels, no label and node overlap)
    ly: float | None = None


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
        for x0, y0, x1, y1 in self.label_boxes():
            xs0.append(x0 - 4)
            ys0.append(y0 - 4)
            xs1.append(x1 + 4)
            ys1.append(y1 + 4)
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
        lx, ly = self.label_xy(e)
        # the label's white box is a <rect> behind the text, not a stroke halo: cairosvg and rsvg ignore
        # ``paint-order`` and would paint the halo over the glyphs (the label vanished in their PNGs)
        w, h = label_size(e.label)
        label = (f'<rect class="label-box" x="{lx - w / 2:.1f}" y="{ly - h / 2:.1f}" width="{w:.1f}" '
                 f'height="{h:.1f}" fill="white" fill-opacity="0.9"/><text x="{lx:.1f}" y="{ly + 4:.1f}" '
                 f'text-anchor="middle" fill="{e.color}">{escape(e.label)}</text>')
        if e.u == e.v:  # reflexive loop on the node's freest side
            (ax_, ay_), (bx_, by_), (cx_, cy_), (dx_, dy_) = self.loop_points(e)
            path = f'M {ax_:.1f} {ay_:.1f} C {bx_:.1f} {by_:.1f} {cx_:.1f} {cy_:.1f} {dx_:.1f} {dy_:.1f}'
            return (f'<g class="edge"><path d="{path}" fill="none" stroke="{e.color}" marker-end="url(#arrow)"/>'
                    f'{label}</g>')
        (sx, sy), (cx, cy), (tx, ty) = self._edge_points(e)
        marker = "" if e.both else ' marker-end="url(#arrow)"'
        return (f'<g class="edge"><path d="M {sx:.1f} {sy:.1f} Q {cx:.1f} {cy:.1f} {tx:.1f} {ty:.1f}" fill="none" '
                f'stroke="{e.color}"{marker}/>{label}</g>')

    def loop_points(self, e: Edge) -> list[tuple[float, float]]:
        """The cubic curve of a loop: start, two control points, end (in the loop's direction)."""
        n = self.nodes[e.u]
        r = n.r + (4 if n.designated else 0)
        dx, dy = e.loop
        px, py = -dy, dx

        def at(u: float, v: float) -> tuple[float, float]:
            return n.x + u * px + v * dx, n.y + u * py + v * dy

        return [at(-8, r - 1), at(-26, r + 34), at(26, r + 34), at(8, r - 1)]

    def label_xy(self, e: Edge) -> tuple[float, float]:
        """Centre of the edge's label: where the layout placed it, else the curve's midpoint (above a loop)."""
        if e.lx is not None and e.ly is not None:
            return e.lx, e.ly
        if e.u == e.v:
            n = self.nodes[e.u]
            d = n.r + (4 if n.designated else 0) + 32
            return n.x + e.loop[0] * d, n.y + e.loop[1] * d
        (sx, sy), (cx, cy), (tx, ty) = self._edge_points(e)
        return (sx + 2 * cx + tx) / 4, (sy + 2 * cy + ty) / 4

    def label_boxes(self) -> list[tuple[float, float, float, float]]:
        """(x0, y0, x1, y1) of every edge label, in the order of :attr:`edges` (for layout tests)."""
        out = []
        for e in self.edges:
            x, y = self.label_xy(e)
            w, h = label_size(e.label)
            out.append((x - w / 2, y - h / 2, x + w / 2, y + h / 2))
        return out

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
                from matplotlib.path import Path as MPath

                curve = MPath(self.loop_points(e), [MPath.MOVETO, MPath.CURVE4, MPath.CURVE4, MPath.CURVE4])
                ax.add_patch(FancyArrowPatch(path=curve, arrowstyle="-|>", mutation_scale=10, color=e.color))
                lx, ly = self.label_xy(e)
                ax.text(lx, ly, e.label, ha="center", va="center", color=e.color, fontsize=9,
                        bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.5})
                continue
            (sx, sy), (cx, cy), (tx, ty) = self._edge_points(e)
            from matplotlib.path import Path as MPath

            curve = MPath([(sx, sy), (cx, cy), (tx, ty)], [MPath.MOVETO, MPath.CURVE3, MPath.CURVE3])
            ax.add_patch(FancyArrowPatch(path=curve, arrowstyle="-" if e.both else "-|>", mutation_scale=10,
                                         color=e.color))
            mx, my = self.label_xy(e)
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
    """The picture of a Kripke model, an event model, or a knowledge/belief structure.

    The kind is told by what the object offers (a Kripke model its worlds' names and valuation, an event
    model its events with pre- and postconditions, a structure its vocabulary and Kripke model), so this
    module imports none of the model classes: they import it, for their ``_repr_svg_``."""
    from delkit.errors import DelkitError

    if layout not in LAYOUTS:
        raise DelkitError(f"layout {layout!r}: use {', '.join(LAYOUTS)}")
    if hasattr(obj, "world_name") and hasattr(obj, "valuation"):
        return _kripke(obj, [obj.world_name(w) for w in range(obj.n_worlds)], layout, seed)
    if hasattr(obj, "events") and hasattr(obj, "pre") and hasattr(obj, "post"):
        from delkit.logic.formula import show

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


def _kripke(m: Any, names: list[str], layout: str, seed: int) -> Picture:
    """A Kripke model's picture, its worlds called ``names``."""
    _refuse_huge(m.n_worlds, m.relations, layout)
    # propositions true in every world are said once, in the caption, not in every node (planning states carry
    # many fluents that no world disagrees on)
    common = set(m.props) if m.n_worlds > 1 and len(m.props) > 2 else set()
    for w in range(m.n_worlds):
        common &= m.true_props(w)
    labels = [[names[w], ", ".join(sorted(m.true_props(w) - common)) or ("∅" if not common else "·")]
              for w in range(m.n_worlds)]
    vals = [tuple(bool(b) for b in m.valuation[w]) for w in range(m.n_worlds)]
    pic = _graph(labels, names, set(m.designated), m.relations, m.agents, layout, seed, vals)
    if common:
        pic.caption.insert(0, "true in every world (not repeated in the worlds): " + ", ".join(sorted(common)))
    pic.summary = f"{m.n_worlds} world(s), agents {', '.join(m.agents)}"
    return pic


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



def structure_header(obj: Any, limit: int = 90) -> list[str]:
    """The lines describing a knowledge or belief structure: its kind, V, the state law θ and the observed
    variables O_a or relations Ω_a, laws and relations as readable formulas (``form_of``)."""
    belief = hasattr(obj, "relations") and not hasattr(obj, "observed")
    header = [f"{'belief' if belief else 'knowledge'} structure", "V = {" + ", ".join(obj.vocabulary) + "}",
              "θ = " + _bdd_text(obj, obj.law, limit)]
    if belief:
        header += [f"Ω_{a} = " + _bdd_text(obj, r, limit) for a, r in obj.relations.items()]
    else:
        header += [f"O_{a} = {{" + ", ".join(vs) + "}" for a, vs in obj.observed.items()]
    return header


def _structure(obj: Any, max_worlds: int, layout: str, seed: int) -> Picture:
    header = structure_header(obj)
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
    pic = _kripke(m, names, layout, seed)
    for node in pic.nodes:  # the name already lists the true variables
        node.lines = node.lines[:1]
        node.r = max(22.0, len(node.name) * 3.3 + 6)
    _layout(pic.nodes, pic.edges, layout, seed, [tuple(bool(b) for b in m.valuation[w]) for w in range(m.n_worlds)])
    pic.header = header
    pic.caption = [f"{n} state(s); each world is named by its true variables"] + pic.caption
    pic.summary = f"structure with {n} state(s), Kripke model drawn"
    return pic


def _bdd_text(obj: Any, u: Any, limit: int = 90) -> str:
    """A BDD as a readable formula (the structure's ``form_of``: :func:`delkit.backends.symbolic.form_of`, SMCDEL's
    ``formOf``; this module imports no structure class), shortened to ``limit`` characters."""
    from delkit.logic.formula import show

    text = show(obj.form_of(u))
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _graph(labels: list[list[str]], names: list[str], designated: set[int], relations: Any, agents: Any,
           layout: str, seed: int, valuations: list[tuple[bool, ...]] | None = None) -> Picture:
    n = len(labels)
    nodes = [Node(names[i], _wrap(labels[i]), i in designated) for i in range(n)]
    for node in nodes:
        width = max(len(t) for t in node.lines) * 6.6
        node.r = max(22.0, math.hypot(width / 2, 7 * len(node.lines)) + 4)
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
    color = {a: agent_color(i) for i, a in enumerate(agents)}
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
    _layout(nodes, edges, layout, seed, valuations)
    caption = []
    if s5:
        caption.append(f"reflexive loops of {', '.join(s5)} not drawn (equivalence relations)")
    if designated:
        caption.append("double circle: designated")
    return Picture(nodes, edges, caption)


def _wrap(lines: list[str], width: int = 18) -> list[str]:
    """A node's lines with long comma lists broken after a comma (so that nodes stay round and small)."""
    out = []
    for line in lines:
        if len(line) <= width or ", " not in line:
            out.append(line)
            continue
        cur = ""
        for part in line.split(", "):
            if cur and len(cur) + 2 + len(part) > width:
                out.append(cur + ",")
                cur = part
            else:
                cur = f"{cur}, {part}" if cur else part
        out.append(cur)
    return out


def agent_color(i: int) -> str:
    """The colour of the ``i``-th agent's edges (the explorer uses the same)."""
    return _PALETTE[i % len(_PALETTE)]


def _color(ags: list[str], color: dict[str, str]) -> str:
    return color[ags[0]] if len(ags) == 1 else "#333333"


def label_size(text: str) -> tuple[float, float]:
    """Width and height (px) of an edge label's box at the pictures' 12 px font."""
    return 7.0 * max(len(text), 1) + 6.0, 15.0


def _layout(nodes: list[Node], edges: list[Edge], layout: str, seed: int,
            valuations: list[tuple[bool, ...]] | None = None) -> None:
    """Place the nodes (``auto``: by valuation in rows when that is small and readable, else a circle up to 6
    nodes, Kamada–Kawai for connected graphs up to 40, spring otherwise), then the edge labels."""
    import networkx as nx

    n = len(nodes)
    if n == 0:
        return
    if n == 1:
        nodes[0].x, nodes[0].y = 0.0, 0.0
        _place_labels(nodes, edges)
        return
    rmax = max(nd.r for nd in nodes)
    pitch = 2 * rmax + 70
    if layout in ("auto", "layered") and valuations is not None:
        rows = _layered(valuations)
        if rows is not None:
            for nd, (x, y) in zip(nodes, rows, strict=True):
                nd.x, nd.y = x * pitch, y * (pitch * 0.9)
            _place_labels(nodes, edges)
            return
    g = nx.Graph()
    g.add_nodes_from(range(n))
    g.add_edges_from((e.u, e.v) for e in edges if e.u != e.v)
    kind = layout
    if kind in ("auto", "layered"):
        kind = "circle" if n <= 6 else ("kamada-kawai" if n <= 40 and nx.is_connected(g) else "spring")
    if kind == "circle":
        pos = nx.circular_layout(g)
    elif kind == "kamada-kawai":
        pos = nx.kamada_kawai_layout(g)
    else:
        import numpy as np

        # any seed 0..2^63-1 (the CLI's range for every seed), mapped to the 32 bits numpy's RandomState takes
        s32 = int(np.random.SeedSequence(seed).generate_state(1)[0])
        if n > 300:  # networkx's spring layout takes 5-20 s on 1,000 nodes; a vectorised one, < 1 s
            pos = _force_layout(n, [(e.u, e.v) for e in edges if e.u != e.v], s32)
        else:
            pos = nx.spring_layout(g, seed=s32)
    pts = [(float(pos[i][0]), float(pos[i][1])) for i in range(n)]
    dmin = _min_distance(pts)
    scale = pitch / max(dmin, 1e-6)
    scale = min(scale, 400.0 * math.sqrt(n))
    for nd, (x, y) in zip(nodes, pts, strict=True):
        nd.x, nd.y = x * scale, -y * scale
    _place_labels(nodes, edges)


def _force_layout(n: int, pairs: list[tuple[int, int]], seed: int, iterations: int = 40) -> Any:
    """Fruchterman–Reingold with numpy (all-pairs repulsion as n×n float32 arrays, attraction along edges,
    linear cooling), for the viewer's large models (in blocks of rows above 1,500 nodes)."""
    import numpy as np

    rng = np.random.default_rng(seed)
    pos = rng.random((n, 2)).astype(np.float32)
    k2 = np.float32(1.0 / n)
    u = np.array([a for a, _ in pairs], dtype=np.int64)
    v = np.array([b for _, b in pairs], dtype=np.int64)
    t = 0.1
    block = n if n <= 1500 else 512  # rows at a time: at most ~1500 × n float32 per array
    for _ in range(iterations):
        x, y = pos[:, 0], pos[:, 1]
        disp = np.empty_like(pos)
        for lo in range(0, n, block):
            dx = x[lo:lo + block, None] - x[None, :]
            dy = y[lo:lo + block, None] - y[None, :]
            inv = dx * dx
            inv += dy * dy
            np.maximum(inv, 1e-6, out=inv)
            np.divide(k2, inv, out=inv)
            disp[lo:lo + block, 0] = (dx * inv).sum(1)
            disp[lo:lo + block, 1] = (dy * inv).sum(1)
        if len(u):
            d = pos[u] - pos[v]
            dist = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-6)
            f = d * (dist / math.sqrt(k2))[:, None]
            np.add.at(disp, u, -f)
            np.add.at(disp, v, f)
        length = np.maximum(np.hypot(disp[:, 0], disp[:, 1]), 1e-9)
        pos += disp / length[:, None] * np.minimum(length, t)[:, None]
        t -= 0.1 / (iterations + 1)
    pos -= pos.mean(0)
    return pos.astype(float)


def _min_distance(pts: list[tuple[float, float]]) -> float:
    if len(pts) > 400:  # nearest pairs through a k-d tree (scipy) instead of all pairs
        import numpy as np
        from scipy.spatial import cKDTree

        d, _ = cKDTree(np.asarray(pts)).query(np.asarray(pts), k=2)
        return float(d[:, 1].min()) if len(d) else 1.0
    return min((math.hypot(a[0] - b[0], a[1] - b[1]) for i, a in enumerate(pts) for b in pts[i + 1:]), default=1.0)


#: the layered layout is used up to this many worlds / varying propositions / worlds per valuation row
_LAYERED_MAX = (48, 8, 8)


def _layered(valuations: list[tuple[bool, ...]]) -> list[tuple[float, float]] | None:
    """Rows by the number of true propositions (of those that vary), x by a symmetric weight per proposition
    (the i-th of k varying propositions weighs i - (k-1)/2): the picture of the Boolean cube that books
    draw, and one whose mirror image swaps the first and the last proposition — so a model symmetric under
    such a swap (muddy children) is drawn mirror-symmetric. Worlds with the same place (same valuation)
    sit side by side. None when the model is too big or too uniform for it."""
    n = len(valuations)
    if not valuations or n > _LAYERED_MAX[0]:
        return None
    k_all = len(valuations[0])
    vary = [i for i in range(k_all) if len({v[i] for v in valuations}) > 1]
    if not vary or len(vary) > _LAYERED_MAX[1]:
        return None
    k = len(vary)
    weight = {i: j - (k - 1) / 2 for j, i in enumerate(vary)}
    places: dict[tuple[int, float], dict[tuple[bool, ...], list[int]]] = {}
    for w, val in enumerate(valuations):
        key = tuple(val[i] for i in vary)
        row = sum(key)
        x = sum(weight[i] for i in vary if val[i])
        places.setdefault((row, x), {}).setdefault(key, []).append(w)
    # in a place: distinct valuations ordered by a second weight that the mirror also reverses (cubes);
    # on the axis (x = 0) the mirror maps each valuation to itself, so they are stacked, not spread
    slots, stack = 1, 1
    for (_, x), groups in places.items():
        if x == 0 and len(groups) > 1:
            slots = max(slots, max(len(ws) for ws in groups.values()))
            stack = max(stack, len(groups))
        else:
            slots = max(slots, sum(len(ws) for ws in groups.values()))
    rows: dict[int, int] = {}
    for (row, _), groups in places.items():
        rows[row] = rows.get(row, 0) + sum(len(ws) for ws in groups.values())
    if max(rows.values()) > _LAYERED_MAX[2]:
        return None
    gap = 1.0 + 0.55 * (stack - 1)
    out: list[tuple[float, float]] = [(0.0, 0.0)] * n
    for (row, x), groups in places.items():
        order = sorted(groups, key=lambda key: (sum(weight[i] ** 3 for i, b in zip(vary, key, strict=True) if b),
                                                key))
        if x == 0 and len(groups) > 1:
            for s_, key in enumerate(order):
                ws = groups[key]
                for j, w in enumerate(ws):
                    out[w] = (j - (len(ws) - 1) / 2, -row * gap + (s_ - (len(order) - 1) / 2) * 0.55)
            continue
        ws = [w for key in order for w in groups[key]]
        for j, w in enumerate(ws):
            out[w] = (x * slots + (j - (len(ws) - 1) / 2), -row * gap)
    return out


def _bezier(e: Edge, nodes: list[Node], t: float) -> tuple[float, float, float, float]:
    """Point of the edge's curve at ``t`` and the unit normal there."""
    a, b = nodes[e.u], nodes[e.v]
    dx, dy = b.x - a.x, b.y - a.y
    d = math.hypot(dx, dy) or 1.0
    nx_, ny_ = -dy / d, dx / d
    cx, cy = (a.x + b.x) / 2 + e.bend * nx_ * d * 0.25, (a.y + b.y) / 2 + e.bend * ny_ * d * 0.25
    x = (1 - t) ** 2 * a.x + 2 * t * (1 - t) * cx + t * t * b.x
    y = (1 - t) ** 2 * a.y + 2 * t * (1 - t) * cy + t * t * b.y
    return x, y, nx_, ny_


def _overlap(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> float:
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return w * h if w > 0 and h > 0 else 0.0


#: labels are placed (no two on top of each other) for pictures with at most this many edges
_PLACE_MAX_EDGES = 600


def _place_labels(nodes: list[Node], edges: list[Edge]) -> None:
    """Give every edge label a place on (or beside) its edge where it covers no node and no other label:
    candidates along the curve from the middle outwards, then beside it; the first free one is taken (the
    least covered one when none is free). Loops' labels go above the loop, else beside it."""
    _loop_directions(nodes, edges)
    if len(edges) > _PLACE_MAX_EDGES:
        return
    _avoid_nodes(nodes, edges)
    taken: list[tuple[float, float, float, float]] = []
    for nd in nodes:
        rr = nd.r + (4 if nd.designated else 0) + 1
        taken.append((nd.x - rr, nd.y - rr, nd.x + rr, nd.y + rr))
    order = sorted(range(len(edges)), key=lambda i: (edges[i].u != edges[i].v, _length(edges[i], nodes)))
    for i in order:
        e = edges[i]
        w, h = label_size(e.label)
        cands: list[tuple[float, float]] = []
        if e.u == e.v:
            nd = nodes[e.u]
            dx, dy = e.loop
            d = nd.r + (4 if nd.designated else 0) + 32
            cx, cy = nd.x + dx * d, nd.y + dy * d
            cands = [(cx, cy), (cx + dx * h, cy + dy * h), (cx - dy * (w / 2 + 20), cy + dx * (w / 2 + 20)),
                     (cx + dy * (w / 2 + 20), cy - dx * (w / 2 + 20))]
        else:
            for off in (0.0, h * 0.8, -h * 0.8, h * 1.6, -h * 1.6):
                for t in (0.5, 0.4, 0.6, 0.32, 0.68, 0.25, 0.75, 0.18, 0.82):
                    x, y, nx_, ny_ = _bezier(e, nodes, t)
                    cands.append((x + nx_ * off, y + ny_ * off))
        x, y = cands[0]
        for ring in range(1, 9):  # then around the first place, ring by ring
            for q in range(8 * ring):
                a = 2 * math.pi * q / (8 * ring)
                cands.append((x + math.cos(a) * ring * h * 0.9, y + math.sin(a) * ring * h * 0.9))
        best, best_cost = cands[0], float("inf")
        for x, y in cands:
            box = (x - w / 2, y - h / 2, x + w / 2, y + h / 2)
            cost = sum(_overlap(box, o) for o in taken)
            if cost < best_cost:
                best, best_cost = (x, y), cost
                if cost == 0.0:
                    break
        e.lx, e.ly = best
        taken.append((best[0] - w / 2, best[1] - h / 2, best[0] + w / 2, best[1] + h / 2))


def _crossed(nodes: list[Node], e: Edge, bend: float) -> int:
    """How many other nodes the edge's curve (with ``bend``) passes through."""
    hits = 0
    saved, e.bend = e.bend, bend
    pts = [_bezier(e, nodes, t / 16)[:2] for t in range(1, 16)]
    e.bend = saved
    for k, nd in enumerate(nodes):
        if k in (e.u, e.v):
            continue
        rr = nd.r + (4 if nd.designated else 0) + 3
        if any(math.hypot(x - nd.x, y - nd.y) < rr for x, y in pts):
            hits += 1
    return hits


def _avoid_nodes(nodes: list[Node], edges: list[Edge]) -> None:
    """Bend a straight edge that would pass through another node (the layered layout's long edges)."""
    for e in edges:
        if e.u == e.v or e.bend or not _crossed(nodes, e, 0.0):
            continue
        best = min((0.5, -0.5, 0.9, -0.9), key=lambda b: (_crossed(nodes, e, b), abs(b)))
        if _crossed(nodes, e, best) < _crossed(nodes, e, 0.0):
            e.bend = best


def _loop_directions(nodes: list[Node], edges: list[Edge]) -> None:
    """Point each loop into the widest angular gap between the node's other edges (up when that is free)."""
    angles: dict[int, list[float]] = {}
    for e in edges:
        if e.u != e.v:
            a, b = nodes[e.u], nodes[e.v]
            angles.setdefault(e.u, []).append(math.atan2(b.y - a.y, b.x - a.x))
            angles.setdefault(e.v, []).append(math.atan2(a.y - b.y, a.x - b.x))
    up = -math.pi / 2
    for e in edges:
        if e.u != e.v:
            continue
        angs = sorted(angles.get(e.u, []))
        if not angs:
            e.loop = (0.0, -1.0)
            continue
        gaps = [((angs[(i + 1) % len(angs)] - a) % (2 * math.pi) or 2 * math.pi, a) for i, a in enumerate(angs)]
        clearance = min(abs((up - a + math.pi) % (2 * math.pi) - math.pi) for a in angs)
        if clearance >= math.radians(50):
            best = up
        else:
            size, start = max(gaps)
            best = start + size / 2
        e.loop = (math.cos(best), math.sin(best))


def _length(e: Edge, nodes: list[Node]) -> float:
    a, b = nodes[e.u], nodes[e.v]
    return math.hypot(a.x - b.x, a.y - b.y)
