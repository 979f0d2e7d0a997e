"""``delkit convert``: mA* / E-PDDL (2021) tasks written as EPDDL (2026) and as mA*, read back (by content) and
planned: the optimal length is the one of the original on every shared mA* instance, and along the expected
plan the converted task's states stay bisimilar to the original's."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from delkit.cli import main
from delkit.errors import PlanningError
from delkit.models.bisimulation import bisimilar
from planners.demo import specs_dir
from planners.epistemic import Limits, plan
from planners.lang import load_task, shared_benchmarks
from planners.lang.detect import detect
from planners.lang.writer import to_epddl, to_mastar
from planners.task import apply_action
from planners.validate import parse_plan_text

BENCH = shared_benchmarks()
if BENCH is None:
    pytest.skip("../shared/benchmarks is not available", allow_module_level=True)
MASTAR = BENCH / "mastar"
ROWS = list(csv.DictReader((MASTAR / "expected.csv").open()))


def _convert(capsys, files: list[Path], out: Path, to: str) -> dict:
    rc = main(["convert", *map(str, files), "--to", to, "--out", str(out), "--json"])
    assert rc == 0
    return json.loads(capsys.readouterr().out)


def _round_trip(capsys, tmp_path, row: dict) -> None:
    src = MASTAR / row["file"]
    original = load_task(src)
    expected = int(row["expected_length"])
    ep = _convert(capsys, [src], tmp_path / "epddl", "epddl")
    assert {detect(ep[k]) for k in ("domain", "problem", "library")} == {"epddl2026"}
    converted = load_task(ep["domain"], ep["problem"])          # the library is found next to the domain
    ma = _convert(capsys, [src], tmp_path / "mastar", "mastar")
    again = load_task(ma["mastar"])
    for task in (converted, again):
        res = plan(task, limits=Limits(timeout=60))
        assert res.solved and res.length == expected, (task.source, res.status, res.length)
    # differential: along EFP's plan the three tasks' states are bisimilar and agree on which actions apply
    m0, m1, m2 = original.initial, converted.initial, again.initial
    for name in parse_plan_text(row["efp_plan"]):
        for act in original.actions:
            ok = [apply_action(t, t.action(act.name), m) is not None
                  for t, m in ((original, m0), (converted, m1), (again, m2))]
            assert ok[0] == ok[1] == ok[2], (act.name, ok)
        m0 = apply_action(original, original.action(name), m0)
        m1 = apply_action(converted, converted.action(name), m1)
        m2 = apply_action(again, again.action(name), m2)
        assert m0 is not None and m1 is not None and m2 is not None
        assert bisimilar(m0, m1) and bisimilar(m0, m2), name


FAST = ["CB_simple__pl_4", "CC_2_2_3__pl_3"]


@pytest.mark.parametrize("stem", FAST)
def test_round_trip_fast(capsys, tmp_path, stem: str) -> None:
    _round_trip(capsys, tmp_path, next(r for r in ROWS if stem in r["file"]))


@pytest.mark.slow
@pytest.mark.parametrize("row", ROWS, ids=[Path(r["file"]).stem for r in ROWS])
def test_round_trip_every_shared_mastar_instance(capsys, tmp_path, row: dict) -> None:
    _round_trip(capsys, tmp_path, row)


def test_epddl2021_to_epddl2026(capsys, tmp_path) -> None:
    d = specs_dir() / "coin_in_the_box"
    ep = _convert(capsys, [d / "domain.epddl", d / "problem.epddl"], tmp_path, "epddl")
    res = plan(load_task(ep["domain"], ep["problem"], [ep["library"]]), limits=Limits(timeout=60))
    ref = plan(load_task(d / "domain.epddl", d / "problem.epddl"), limits=Limits(timeout=60))
    assert res.solved and res.length == ref.length == 3


def test_what_does_not_fit_is_refused_clearly() -> None:
    root = BENCH / "epddl2026" / "plank"
    cn = load_task(root / "domains/Consecutive-Numbers/cn.epddl",
                   root / "domains/Consecutive-Numbers/instances/cn5.epddl")
    with pytest.raises(PlanningError, match="general event model|2 designated worlds"):
        to_mastar(cn)
    with pytest.raises(PlanningError, match="not an mA\\*-shaped action"):
        to_epddl(cn)
