"""Pictures (``delkit.drawing.draw``, ``delkit model draw``): SVG parses and shows every world and edge, TikZ is a
balanced tikzpicture, PNG files are PNGs; Jupyter reprs; knowledge/belief structures."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from hypothesis import given, settings

from delkit import KripkeModel, public_announcement
from delkit.backends.symbolic import KnowledgeStructure
from delkit.backends.symbolic_belief import BeliefStructure
from delkit.cli import main
from delkit.drawing.draw import picture
from delkit.io.formats import dumps
from delkit.logic.formula import Prop
from delkit.testing import kripke_models

SVG = "{http://www.w3.org/2000/svg}"
SPECS = Path(__file__).resolve().parents[2] / "specs" / "smcdel"


def _model() -> KripkeModel:
    # a: S5 (loops left out), b: a K relation with a loop at w, a one-way edge w→u and a two-way edge v–u
    return KripkeModel.build({"w": {"p"}, "v": set(), "u": {"q"}},
                             {"a": [["w", "v"], ["u"]],
                              "b": {"pairs": [("w", "w"), ("w", "u"), ("u", "v"), ("v", "u")]}},
                             designated=["w"])


def _svg_parts(svg: str):
    root = ET.fromstring(svg)
    worlds = {g.get("id"): g for g in root.iter(f"{SVG}g") if g.get("class") == "world"}
    edges = [g for g in root.iter(f"{SVG}g") if g.get("class") == "edge"]
    return root, worlds, edges


def test_svg_has_every_world_edge_and_label():
    svg = picture(_model()).svg()
    root, worlds, edges = _svg_parts(svg)
    assert set(worlds) == {"w-w", "w-v", "w-u"}
    # designated w: two circles; the others one
    assert len(list(worlds["w-w"].iter(f"{SVG}circle"))) == 2
    assert len(list(worlds["w-v"].iter(f"{SVG}circle"))) == 1
    texts = {"".join(t.itertext()) for t in root.iter(f"{SVG}text")}
    assert {"w", "v", "u", "p", "q", "∅"} <= texts
    labels = sorted("".join(t.itertext()) for e in edges for t in e.iter(f"{SVG}text"))
    assert labels == ["a", "b", "b", "b"]  # a: w–v; b: loop at w, w→u, v–u merged
    arrows = [e for e in edges if any(p.get("marker-end") for p in e.iter(f"{SVG}path"))]
    assert len(arrows) == 2  # the loop and the one-way edge; the two-way edges have no arrow heads


def test_shared_edges_merge_agents():
    m = KripkeModel.build({"x": {"p"}, "y": set()}, {"a": [["x", "y"]], "b": [["x", "y"]]}, designated=["x"])
    _, _, edges = _svg_parts(picture(m).svg())
    assert ["".join(t.itertext()) for e in edges for t in e.iter(f"{SVG}text")] == ["a,b"]


def test_tikz_is_balanced_and_complete():
    tex = picture(_model()).tikz(standalone=True)
    assert tex.count("{") == tex.count("}") and r"\begin{tikzpicture}" in tex and r"\end{tikzpicture}" in tex
    depth = 0
    for ch in tex:
        depth += {"{": 1, "}": -1}.get(ch, 0)
        assert depth >= 0
    assert tex.count(r"\node[world") == 3 and "designated" in tex and "loop above" in tex
    assert r"\documentclass" in tex and r"\end{document}" in tex


def test_event_model_and_repr():
    e = public_announcement("p", ["a", "b"])
    svg = e._repr_svg_()
    root, worlds, _ = _svg_parts(svg)
    assert len(worlds) == 1 and any("pre: p" in "".join(t.itertext()) for t in root.iter(f"{SVG}text"))
    assert _model()._repr_svg_().startswith("<svg")


def test_structures_show_law_observations_and_kripke_model():
    ks = KnowledgeStructure.create(["1", "2"], Prop("1") | Prop("2"), {"amy": ["1"], "ben": ["2"]})
    html = ks._repr_html_()
    root, worlds, _ = _svg_parts(html)
    texts = ["".join(t.itertext()) for t in root.iter(f"{SVG}text")]
    assert "O_amy = {1}" in texts and any(t.startswith("θ = ") for t in texts)
    assert set(worlds) == {"w-_1_", "w-_2_", "w-_1_2_"}  # three states of the law
    big = KnowledgeStructure.create([str(i) for i in range(8)], "T", {"a": ["0"]})
    assert "not drawn" in picture(big, max_worlds=16).svg()
    bs = BeliefStructure.create(["p"], "T", {"a": Prop("p'")})
    texts = ["".join(t.itertext()) for t in ET.fromstring(bs._repr_html_()).iter(f"{SVG}text")]
    assert any(t.startswith("Ω_a = ") for t in texts) and "belief structure" in texts


@pytest.mark.parametrize("suffix", [".svg", ".png", ".tex"])
def test_cli_draw_formats(tmp_path, suffix):
    src = tmp_path / "m.json"
    src.write_text(dumps(_model()))
    out = tmp_path / f"m{suffix}"
    assert main(["model", "draw", str(src), "-o", str(out)]) == 0
    data = out.read_bytes()
    if suffix == ".png":
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 1000
    elif suffix == ".svg":
        assert len(_svg_parts(data.decode())[1]) == 3
    else:
        assert b"\\begin{tikzpicture}" in data


def test_cli_draw_smcdel_and_errors(tmp_path, capsys):
    out = tmp_path / "muddy.svg"
    assert main(["model", "draw", str(SPECS / "muddy3.smcdel.txt"), "-o", str(out)]) == 0
    assert len(_svg_parts(out.read_text())[1]) == 8
    assert main(["model", "draw", str(SPECS / "muddy3.smcdel.txt"), "-o", str(tmp_path / "x.pdf")]) == 2
    assert "*.svg, *.png or *.tex" in capsys.readouterr().err


def test_large_models_fall_back_to_text_in_jupyter():
    import numpy as np

    from delkit.models.relation import Relation

    n = 201
    m = KripkeModel(("p",), ("a",), np.zeros((n, 1), dtype=bool), {"a": Relation.identity(n)}, (0,))
    assert m._repr_svg_() is None


# --------------------------------------------------------------- readable laws (form_of)
@settings(max_examples=25, deadline=None)
@given(kripke_models(("p", "q"), ("a", "b"), max_worlds=4, frame="K"))
def test_structure_pictures_show_laws_as_formulas(m) -> None:
    """A belief structure's picture writes θ and every Ω_a as a formula (form_of, not dd's ite(...) text)
    that denotes exactly that BDD: parsed back and rebuilt, it is the same node."""
    from delkit.backends.symbolic_belief import _propositional, belief_from_kripke
    from delkit.drawing.draw import picture
    from delkit.logic.formula import parse

    bs, _ = belief_from_kripke(m)
    header = picture(bs, max_worlds=0).header
    shown = {line.split(" = ", 1)[0]: line.split(" = ", 1)[1] for line in header if " = " in line}
    for label, node in [("θ", bs.law)] + [(f"Ω_{a}", r) for a, r in bs.relations.items()]:
        text = shown[label]
        assert "ite(" not in text
        if not text.endswith("…"):
            assert _propositional(bs.bdd, parse(text)) == node, (label, text)


def test_viewer_notes_show_a_belief_structures_law_as_a_formula() -> None:
    """``delkit view`` on a belief structure file: θ and Ω_a in the notes as form_of formulas."""
    from delkit.backends.symbolic_belief import _propositional
    from delkit.io.smcdel import parse_smcdel, structure
    from delkit.logic.formula import parse
    from delkit.view.document import load_document

    path = Path(__file__).resolve().parents[2] / "specs" / "smcdel" / "muddy3-belief.smcdel.txt"
    doc = load_document([path])
    line = next(n for n in doc.notes if "θ = " in n)
    assert "ite(" not in line and "belief structure" in line
    bs = structure(parse_smcdel(path.read_text(encoding="utf-8")))
    theta = next(part for part in line.split("; ") if part.startswith("θ = "))[4:]
    assert _propositional(bs.bdd, parse(theta)) == bs.law
