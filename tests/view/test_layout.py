"""Static pictures that read well: no two edge labels on top of each other (nor on a world), symmetric models
drawn symmetric, and SVG whose labels survive conversion with cairosvg (which ignores ``paint-order``)."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit import KripkeModel, product_update, sensing
from delkit.drawing.draw import _overlap, picture

ROOT = Path(__file__).resolve().parents[2]
COIN = ROOT / "specs" / "coin_in_the_box"


def readme_models() -> dict[str, object]:
    coin = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]], "c": [[0, 1]]}, designated=[0])
    peek = sensing("p", ["a", "b", "c"], full=["a"], partial=["b"])
    return {"coin": coin, "peek": peek, "after": product_update(coin, peek)}


def muddy(n: int) -> KripkeModel:
    """n muddy children: child i sees every forehead but its own (props m1..mn, agents c1..cn)."""
    worlds = [{f"m{i + 1}" for i in range(n) if bits >> (n - 1 - i) & 1} for bits in range(2 ** n)]
    rel = {}
    for i in range(n):
        bit = 1 << (n - 1 - i)
        rel[f"c{i + 1}"] = [[w, w | bit] for w in range(2 ** n) if not w & bit]
    return KripkeModel.build(worlds, rel, designated=[2 ** n - 1])


def task_states() -> list[object]:
    from delkit.view.document import load_document

    doc = load_document([COIN / "domain.epddl", COIN / "problem.epddl", COIN / "problem.plan"])
    return [p.model for f in doc.frames for p in f.panels]


def assert_readable(pic) -> None:
    boxes = pic.label_boxes()
    for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2):
        assert _overlap(a, b) == 0.0, f"labels {pic.edges[i].label!r} and {pic.edges[j].label!r} overlap"
    for i, (x0, y0, x1, y1) in enumerate(boxes):
        for nd in pic.nodes:
            r = nd.r + (4 if nd.designated else 0)
            cx, cy = min(max(nd.x, x0), x1), min(max(nd.y, y0), y1)  # the box's point nearest the centre
            assert math.hypot(cx - nd.x, cy - nd.y) >= r - 0.5, f"label {pic.edges[i].label!r} on world {nd.name}"
    for a, b in itertools.combinations(pic.nodes, 2):
        assert math.hypot(a.x - b.x, a.y - b.y) > a.r + b.r, f"worlds {a.name} and {b.name} overlap"


@pytest.mark.parametrize("name", ["coin", "peek", "after"])
def test_readme_pictures_have_no_overlapping_labels(name):
    assert_readable(picture(readme_models()[name]))


def test_plan_states_have_no_overlapping_labels():
    for m in task_states():
        assert_readable(picture(m))


def test_muddy_structure_is_readable_and_symmetric():
    from delkit.view.document import load_document

    m = load_document([ROOT / "specs" / "smcdel" / "muddy3.smcdel.txt"]).frames[0].panels[0].model
    pic = picture(m)
    assert_readable(pic)
    # every amy edge joins worlds that differ in variable 1 only, and no edge passes the centre under one label
    xs = sorted({round(n.x, 6) for n in pic.nodes})
    assert len(xs) == 3 and xs[0] == -xs[2]


@pytest.mark.parametrize("n", [2, 3, 4])
def test_symmetric_models_are_drawn_symmetric(n):
    """Renaming child i as child n+1-i is an automorphism of the muddy model: the picture's mirror image."""
    m = muddy(n)
    pic = picture(m)
    assert_readable(pic)
    pos = {frozenset(m.true_props(w)): (pic.nodes[w].x, pic.nodes[w].y) for w in range(m.n_worlds)}
    swap = {f"m{i}": f"m{n + 1 - i}" for i in range(1, n + 1)}
    scale = max(abs(x) for x, _ in pos.values()) or 1.0
    for props, (x, y) in pos.items():
        sx, sy = pos[frozenset(swap.get(p, p) for p in props)]
        assert abs(sx + x) <= 1e-6 * scale and abs(sy - y) <= 1e-6 * scale, sorted(props)


@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=2, max_value=7), st.integers(min_value=0, max_value=2 ** 32 - 1))
def test_random_models_have_no_overlapping_labels(n, seed):
    rng = np.random.default_rng(seed)
    worlds = [{p for p in "pq" if rng.random() < 0.5} for _ in range(n)]
    rel = {a: {"pairs": [[int(x), int(y)] for x in range(n) for y in range(n) if rng.random() < 0.3]} for a in "ab"}
    assert_readable(picture(KripkeModel.build(worlds, rel, designated=[0])))


def test_svg_labels_survive_cairosvg():
    cairosvg = pytest.importorskip("cairosvg", reason="cairosvg is not installed (pip install 'delkit[view-test]')")
    import io

    from PIL import Image

    pic = picture(readme_models()["after"])
    svg = pic.svg()
    assert "paint-order" not in svg
    x0, y0, _, _ = pic._extent()
    head = 16 * len(pic.header) + 6
    img = np.asarray(Image.open(io.BytesIO(cairosvg.svg2png(bytestring=svg.encode()))).convert("RGB")).astype(int)
    for e, (bx0, by0, bx1, by1) in zip(pic.edges, pic.label_boxes(), strict=True):
        # the label's box in the PNG: its glyphs are drawn in the edge's colour (not hidden under white)
        px0, px1 = int(bx0 - x0), int(bx1 - x0)
        py0, py1 = int(by0 - y0 + head), int(by1 - y0 + head)
        region = img[py0:py1, px0:px1]
        want = np.array([int(e.color[i:i + 2], 16) for i in (1, 3, 5)])
        close = (np.abs(region - want).sum(-1) < 120).sum()
        assert close >= 4, f"label {e.label!r} not visible after cairosvg ({close} pixels of its colour)"
