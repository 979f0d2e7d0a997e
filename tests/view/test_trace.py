"""``delkit check --trace`` / ``--trace-json``, ``delkit model draw TASK --plan --step K`` and the notebook
stepper, on the Coin-in-the-Box and Selective-Communication specs."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from delkit.io.formats import model_from_dict
from delkit.models.bisimulation import bisimilar
from planners.cli.plan_cmd import fast_args, run_check
from planners.lang import load_task
from planners.task import apply_steps
from planners.trace import state_json, trace_plan
from planners.validate import check_plan, read_plan

ROOT = Path(__file__).resolve().parents[2]
SPECS = {name: [ROOT / "specs" / name / "domain.epddl", ROOT / "specs" / name / "problem.epddl",
                ROOT / "specs" / name / "problem.plan"] for name in ("coin_in_the_box", "selective_communication")}


@pytest.mark.parametrize("name", sorted(SPECS))
def test_check_trace_prints_every_step(name, capsys):
    files = SPECS[name]
    plan = read_plan(files[2])
    assert run_check(files, trace=True) == 0
    out = capsys.readouterr().out
    assert "step 0 (initial state)" in out and out.rstrip().endswith("goal reached")
    for i, act in enumerate(plan, 1):
        assert f"step {i}: {act}" in out
    assert out.count("  goal ") == len(plan) + 1 and "goal K" in out


@pytest.mark.parametrize("name", sorted(SPECS))
def test_trace_json_states_are_the_replayed_states(name, tmp_path, capsys):
    files = SPECS[name]
    out = tmp_path / "trace.json"
    assert run_check(files, trace_json=out) == 0
    trace = json.loads(out.read_text())
    task = load_task(files[0], files[1])
    plan = read_plan(files[2])
    assert trace["verdict"] == check_plan(task, plan).to_json()
    # independently: the reference transitions (planners.task.apply_steps, no contraction)
    ems, states = apply_steps(task, [task.action(a) for a in plan], task.initial)
    assert len(trace["steps"]) == len(states)
    for k, (step, ref) in enumerate(zip(trace["steps"], states, strict=True)):
        if step["carried"] in ("initial", "product"):
            assert step["state"] == state_json(ref), f"step {k}"
        else:
            assert bisimilar(_model(step["state"], ref), ref), f"step {k}"
        assert step["goal"] == ref.holds(task.goal)
    assert trace["steps"][-1]["goal"] is True
    assert "b now knows whether tail" in trace["steps"][-1]["changed"]["learned"] if name == "coin_in_the_box" else True


def _model(st: dict, like):
    return model_from_dict({"delkit": "kripke-model", "version": 1, "props": list(like.props),
                            "agents": list(like.agents),
                            "worlds": [{"name": w["name"], "true": w["true"]} for w in st["worlds"]],
                            "relations": {a: {"pairs": [[st["worlds"][u]["name"], st["worlds"][v]["name"]]
                                                        for u, v in ps]} for a, ps in st["relations"].items()},
                            "designated": [w["name"] for w in st["worlds"] if w["designated"]]})


def test_trace_stops_where_check_fails(tmp_path):
    files = SPECS["coin_in_the_box"]
    task = load_task(files[0], files[1])
    bad = ["peek_b"]  # the box is closed and b is not looking
    tr = trace_plan(task, bad)
    assert tr.verdict["valid"] is False and tr.verdict["step"] == 1
    assert len(tr.steps) == 2 and tr.steps[1].failed == tr.verdict["reason"]


def test_fast_path_takes_the_trace_options():
    call = fast_args(["check", "a.epddl", "b.epddl", "p.plan", "--trace", "--trace-json", "t.json"])
    assert call is not None


@pytest.mark.parametrize("step", [0, 3])
def test_model_draw_plan_step(step, tmp_path, capsys):
    from delkit.cli.model_tools import run_draw
    from delkit.view.document import load_document

    files = SPECS["coin_in_the_box"]
    out = tmp_path / f"s{step}.svg"
    run_draw([str(files[0]), str(files[1])], out, 64, "auto", 0, plan=files[2], step=step)
    svg = out.read_text()
    doc = load_document(files)
    fr = doc.frames[step]
    m = next(p.model for p in fr.panels if p.key == fr.data["carried"])
    assert svg.count('class="world"') == m.n_worlds
    assert ("initial state" if step == 0 else "state after step 3: peek_b") in svg


def test_model_draw_step_past_the_plan_is_refused(tmp_path):
    from delkit.cli.model_tools import run_draw
    from delkit.errors import DelkitError

    files = SPECS["coin_in_the_box"]
    with pytest.raises(DelkitError, match="the plan has 3 step"):
        run_draw([str(files[0]), str(files[1])], tmp_path / "x.png", 64, "auto", 0, plan=files[2], step=4)


def test_notebook_stepper_is_self_contained():
    from planners.view import stepper

    files = SPECS["selective_communication"]
    task = load_task(files[0], files[1])
    plan = read_plan(files[2])
    html = stepper(task, plan)._repr_html_()
    assert html.count('type="radio"') == len(plan) + 1
    assert "<script" not in html and "http" not in html.replace('xmlns="http://www.w3.org/2000/svg"', "")
    assert html.count("<svg") >= 1 + 3 * len(plan)  # initial state; before, event model, product per step
