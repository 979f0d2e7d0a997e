"""The viewer in a real browser (headless Chromium, one session for the module): the page for a Kripke model,
a ``.smcdel.txt`` structure, an EPDDL task with a plan and an e-PICO result. What the page highlights must be
what delkit computes (``KripkeModel.holds`` per world); each step's drawn state must be what ``delkit check
--trace-json`` writes. Screenshots go to out/view/."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from delkit import KripkeModel, product_update, sensing
from delkit.io.formats import dumps
from delkit.logic.formula import parse
from delkit.view.browser import open_page
from delkit.view.document import load_document

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "out" / "view"

COIN = ROOT / "specs" / "coin_in_the_box"


def js(drv, script: str, *args):
    """Run an async snippet (``done`` is the callback) in the page."""
    return drv.execute_async_script("const done = arguments[arguments.length - 1];" + script, *args)


def screenshot(drv, name: str) -> Path:
    OUT.mkdir(parents=True, exist_ok=True)
    drv.save_screenshot(str(OUT / name))
    return OUT / name


def readme_after() -> KripkeModel:
    """The README's tour: a coin lies heads, a peeks, b watches, c looks away."""
    coin = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]], "c": [[0, 1]]}, designated=[0])
    return product_update(coin, sensing("p", ["a", "b", "c"], full=["a"], partial=["b"]))


def holds_per_world(m: KripkeModel, f) -> set[str]:
    return {m.world_name(w) for w in range(m.n_worlds) if m.with_designated([w]).holds(f)}


def type_formula(drv, text: str) -> dict:
    """Type into the formula box like a user, press Enter, wait for the server's answer."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    drv.execute_script("window.delkitView.lastEval = null")
    box = drv.find_element(By.ID, "formula")
    box.clear()
    box.send_keys(text, Keys.ENTER)
    end = time.monotonic() + 10
    while time.monotonic() < end:
        out = drv.execute_script("return window.delkitView.lastEval")
        if out is not None:
            return out
        time.sleep(0.02)
    raise AssertionError(f"no answer for {text!r}")


def test_kripke_model_formulas_and_agent_view(browser, serve, tmp_path):
    m = readme_after()
    path = tmp_path / "after.json"
    path.write_text(dumps(m))
    open_page(browser, serve(load_document([path])))
    for text in ["K_a p", "~Kw_b p & K_b Kw_a p", "K_c ~Kw_a p", "C{a,b} Kw_a p", "p & ~K_b p"]:
        answer = type_formula(browser, text)
        assert answer["ok"], answer
        shown = set(browser.execute_script("return window.delkitView.highlighted('state')"))
        assert shown == holds_per_world(m, parse(text)), text
        assert answer["holds"] == m.holds(text)
    # a parse error is shown with its column, nothing highlighted
    answer = type_formula(browser, "K_a (p &")
    assert not answer["ok"] and answer["column"] == 9
    err = browser.find_element("id", "formula-error")
    assert err.is_displayed() and "^" in err.text
    assert browser.execute_script("return window.delkitView.highlighted('state')") == []
    # "what does b consider possible from the actual world": b's successors, computed by delkit
    browser.find_element("id", "agent").send_keys("b")
    got = js(browser, "delkitView.possible('state', 0).then(d => done(d.worlds))")
    assert got == m.successors("b", 0)
    type_formula(browser, "K_b Kw_a p")
    screenshot(browser, "kripke-readme-after-peek.png")


def test_smcdel_structure(browser, serve):
    path = ROOT / "specs" / "smcdel" / "muddy3.smcdel.txt"
    doc = load_document([path])
    m = doc.frames[0].panels[0].model
    open_page(browser, serve(doc))
    answer = type_formula(browser, "amy knows that (2 & 3)")   # SMCDEL's own syntax
    assert answer["ok"]
    shown = set(browser.execute_script("return window.delkitView.highlighted('state')"))
    assert shown == holds_per_world(m, doc.parse("amy knows that (2 & 3)")) == {"{2,3}", "{1,2,3}"}
    answer = type_formula(browser, "Kw_amy 1 | Kw_ben 2")       # delkit's syntax on the same structure
    assert not answer["ok"]  # variables are numbers: delkit's syntax has no proposition "1"
    screenshot(browser, "smcdel-muddy3.png")


def _pairs_drawn(drawn: dict) -> dict[str, set[tuple[str, str]]]:
    """Each agent's pairs, read back from the drawn graph (S5 loops are hidden: added back)."""
    names = {w["idx"]: w["name"] for w in drawn["worlds"]}
    out: dict[str, set] = {a: set() for a in drawn["agents"]}
    for e in drawn["edges"]:
        for a in e["agents"]:
            out.setdefault(a, set()).add((names[e["u"]], names[e["v"]]))
            if e["both"]:
                out[a].add((names[e["v"]], names[e["u"]]))
    for a in drawn["s5"]:
        out.setdefault(a, set()).update((n, n) for n in names.values())
    return out


LAMP = ROOT / "specs" / "epddl2026" / "lamp"


@pytest.mark.parametrize("name", ["coin_in_the_box (E-PDDL 2021)", "lamp (EPDDL 2026)"])
def test_plan_stepper_matches_check_trace_json(name, browser, serve, tmp_path):
    if name.startswith("lamp"):
        plan = tmp_path / "lamp.plan"
        plan.write_text("look_robot\nsay-on_robot\n")  # the plan delkit plan finds
        files = [LAMP / "domain.epddl", LAMP / "problem.epddl", plan]
    else:
        files = [COIN / "domain.epddl", COIN / "problem.epddl", COIN / "problem.plan"]
    trace_file = tmp_path / "trace.json"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    subprocess.run([str(Path(sys.executable).parent / "delkit"), "check", *map(str, files), "--trace-json",
                    str(trace_file)], check=True, capture_output=True, cwd=ROOT, env=env)
    trace = json.loads(trace_file.read_text())
    open_page(browser, serve(load_document(files)))
    n = len(trace["steps"])
    assert browser.execute_script("return window.delkitView.doc.frames.length") == n
    for k, step in enumerate(trace["steps"]):
        if k:
            browser.find_element("id", "next").click()
            end = time.monotonic() + 10
            while browser.execute_script("return window.delkitView.frame") != k and time.monotonic() < end:
                time.sleep(0.02)
        carried = browser.execute_script("return window.delkitView.doc.frames[window.delkitView.frame].data.carried")
        drawn = browser.execute_script(f"return window.delkitView.drawn('{carried}')")
        st = step["state"]
        worlds = sorted(drawn["worlds"], key=lambda w: w["idx"])
        assert [(w["name"], sorted(w["props"]), w["designated"]) for w in worlds] == \
            [(w["name"], w["true"], w["designated"]) for w in st["worlds"]], f"step {k}"
        names = [w["name"] for w in st["worlds"]]
        want = {a: {(names[u], names[v]) for u, v in pairs} for a, pairs in st["relations"].items()}
        assert _pairs_drawn(drawn) == want, f"step {k}"
        if k == 3 or k == len(trace["steps"]) - 1:
            screenshot(browser, f"plan-{name.split()[0]}-step{k}.png")
    # the goal at the end, evaluated by the server on the final state
    answer = type_formula(browser, trace["goal"])
    assert answer["holds"] == trace["steps"][-1]["goal"] is True


def _cells(drv) -> list[dict[str, list[str]]]:
    """The beliefs table the page shows, per frame: {column: {robot: formulas (one a line)}}."""
    out = []
    for k in range(drv.execute_script("return window.delkitView.doc.frames.length")):
        drv.execute_script(f"window.delkitView.show({k})")
        rows = drv.execute_script("return [...document.querySelectorAll('#frame-table tr')]"
                                  ".map(r => [...r.cells].map(c => c.innerText))")
        head, body = rows[0], rows[1:]
        out.append({col: {r[0]: [x for x in r[i].split("\n") if x not in ("", "—", "nothing yet", "nothing")]
                          for r in body} for i, col in enumerate(head) if i})
    return out


def shown_in_order(frames) -> list[tuple[str, str]]:
    return [(r, f) for fr in frames for r, fs in fr["learnt at this step"].items() for f in fs]


def test_epico_run_beliefs_shown_are_the_belief_log(browser, serve, epico_result):
    """A run made now: the formulas the page lists as learnt, frame after frame, are the belief log's
    ``learnt`` formulas, each once, in the log's order, each under the robot it is about (K_robot2 … under
    robot2) and on the frame of the step of its own task; "known so far" accumulates them; the last frame
    also lists the result's final beliefs."""
    data = json.loads(epico_result.read_text())
    open_page(browser, serve(load_document([epico_result])))
    frames = _cells(browser)
    assert len(frames) == len(data["steps"]) + 1
    shown = [(r, f) for fr in frames for r, fs in sorted(fr["learnt at this step"].items()) for f in fs]
    logged = [(f.split(" ", 1)[0][2:], f) for e in data["belief_log"] for f in e["learnt"]
              if not f.startswith("no longer")]
    assert sorted(shown) == sorted(logged) and len(shown) == len(logged) > 0
    for robot in {r for r, _ in logged}:  # per robot, the log's order
        assert [f for r, f in shown_in_order(frames) if r == robot] == [f for r, f in logged if r == robot]
    known: dict[str, list[str]] = {}
    for fr in frames:
        for r, fs in fr["learnt at this step"].items():
            known.setdefault(r, []).extend(f for f in fs if f not in known.get(r, []))
        assert {r: v for r, v in fr["known so far (belief log)"].items() if v} == {r: v for r, v in known.items() if v}
    where = []  # the frame of each entry that learnt something
    for e in data["belief_log"]:
        fs = [f for f in e["learnt"] if not f.startswith("no longer")]
        if fs:
            k = next(k for k, fr in enumerate(frames) if fs[0] in sum(fr["learnt at this step"].values(), []))
            where.append(k)
            if k and e["task"] in {s["task"] for s in data["steps"]}:
                assert data["steps"][k - 1]["task"] == e["task"], (k, e)
    assert where == sorted(where)
    final = {r: v for r, v in frames[-1]["at the end (result)"].items() if v}
    assert final == {r: v for r, v in data["beliefs"].items() if v}
    end = time.monotonic() + 15
    while time.monotonic() < end and not browser.execute_script(
            "const i = document.getElementById('frame-image'); return i.complete && i.naturalWidth > 0"):
        time.sleep(0.05)
    width = browser.execute_script("return document.getElementById('frame-image').naturalWidth")
    assert width > 0 or not data["files"].get("png")  # the run's own picture is served
    used = browser.execute_script("""const m = document.querySelector('main').getBoundingClientRect();
        const b = [...document.querySelectorAll('#side > .box')].filter(x => !x.hidden)
          .map(x => x.getBoundingClientRect());
        return Math.max(...b.map(r => r.right)) - Math.min(...b.map(r => r.left)) > 0.8 * m.width""")
    assert used  # the page's width is used (no empty two thirds)
    screenshot(browser, "epico-run-last-step.png")


def test_formula_box_shows_underscores(browser, serve):
    """``K_b Kw_a p`` typed into the formula box: its two underscores are drawn (the box's own pixels differ
    from those of ``K b Kw a p``, in two places), i.e. not clipped by the line height or the font."""
    import io

    from PIL import Image, ImageChops
    from selenium.webdriver.common.by import By

    path = ROOT / "specs" / "smcdel" / "muddy3.smcdel.txt"
    open_page(browser, serve(load_document([path])))
    box = browser.find_element(By.ID, "formula")
    shots = []
    for text in ("K_b Kw_a p", "K b Kw a p"):  # the same glyph positions in a monospace font
        browser.execute_script("arguments[0].value = arguments[1]; arguments[0].blur()", box, text)
        time.sleep(0.1)
        shots.append(Image.open(io.BytesIO(box.screenshot_as_png)).convert("L"))
    diff = np.asarray(ImageChops.difference(*shots)) > 60
    cols = np.flatnonzero(diff.any(axis=0))
    assert cols.size > 0, "the underscores are not drawn inside the formula box"
    runs = 1 + int((np.diff(cols) > 1).sum())
    assert runs == 2, f"expected two underscores, found {runs} runs of changed pixels"
    rows = np.flatnonzero(diff.any(axis=1))
    assert rows.max() < diff.shape[0] - 1  # below the baseline and inside the box, not on its border
    OUT.mkdir(parents=True, exist_ok=True)
    shots[0].save(OUT / "formula-box-underscores.png")


def test_thousand_world_model(browser, serve, tmp_path):
    """A 1,000-world model loads and a formula's highlight is delkit's (the time is bench/view_page.py's)."""
    from delkit.view.samples import random_s5

    m = random_s5(1000)
    path = tmp_path / "big.json"
    path.write_text(dumps(m))
    open_page(browser, serve(load_document([path])), timeout=60)
    answer = type_formula(browser, "K_a p0 & ~K_b p1")
    truth = np.asarray(answer["truth"])
    assert truth.shape == (1000,) and (truth == m.check(parse("K_a p0 & ~K_b p1"))).all()
    shown = browser.execute_script("return window.delkitView.highlighted('state').length")
    assert shown == int(truth.sum())
    screenshot(browser, "kripke-1000-worlds.png")
