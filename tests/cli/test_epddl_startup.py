"""Start-up of ``delkit plan`` / ``delkit check`` on EPDDL (2026) files: the fast argument path is taken and
nothing heavy (typer, click, rich, pydantic, scipy, lark, z3, dd, ...) is imported on the way."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from planners.cli.plan_cmd import fast_args
from planners.lang import shared_benchmarks

ROOT = Path(__file__).resolve().parents[2]
BENCH = shared_benchmarks()
E26 = BENCH / "epddl2026" / "plank" if BENCH else None
HEAVY = {"typer", "click", "rich", "pydantic", "scipy", "z3", "dd", "matplotlib", "mujoco", "lark", "networkx"}


def _run(argv: list[str]) -> tuple[int, set[str]]:
    code = ("import sys; from delkit.cli import main; rc = main(sys.argv[1:]); "
            "print('MODULES', ' '.join(sorted(sys.modules)), file=sys.stderr); sys.exit(rc)")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, env=env, check=False)
    line = [ln for ln in proc.stderr.splitlines() if ln.startswith("MODULES ")]
    assert line, proc.stderr
    return proc.returncode, {m.split(".")[0] for m in line[0].split()[1:]} | {
        m for m in line[0].split()[1:] if m.startswith("numpy.ma")}


def _files(domain: str, problem: str, library: str | None) -> list[str]:
    out = [str(E26 / "domains" / domain), str(E26 / "domains" / problem)]
    return out + (["--library", str(E26 / "libraries" / library)] if library else [])


CASES = [  # (domain, problem, library): event models with oblivious agents, explicit and finitary-S5 states
    ("Coin-in-the-Box/cb.epddl", "Coin-in-the-Box/instances/problem_2.epddl", "intermediate.epddl"),
    ("Active-Muddy-Child/amc.epddl", "Active-Muddy-Child/instances/problem_1.epddl", "intermediate.epddl"),
    ("Blocks-World/bw.epddl", "Blocks-World/instances/problem_1.epddl", "basic.epddl"),
    ("Consecutive-Numbers/cn.epddl", "Consecutive-Numbers/instances/cn5.epddl", None),
    ("N-Consecutive-Numbers/ncn.epddl", "N-Consecutive-Numbers/instances/ncn-1.epddl", None),
]


@pytest.mark.skipif(E26 is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("case", CASES, ids=lambda c: c[0].split("/")[0])
def test_epddl_plan_and_check_import_nothing_heavy(tmp_path, case) -> None:
    files = _files(*case)
    argv = ["plan", *files, "--json"]
    assert fast_args(argv) is not None   # no typer
    rc, mods = _run(argv)
    assert rc == 0 and not mods & HEAVY, mods & HEAVY
    assert "numpy.ma" not in mods
    plan = tmp_path / "empty.plan"
    plan.write_text("")
    rc, mods = _run(["check", *files, str(plan)])
    assert rc == 1 and not mods & HEAVY, mods & HEAVY   # the empty plan does not reach these goals


@pytest.mark.parametrize("preset", [None, "2"])
def test_cli_runs_blas_on_one_thread_unless_the_user_chose(preset) -> None:
    """numpy's OpenBLAS pool (a thread per core, ~70 ms of CPU at import) is not started by the CLI; a value the
    user set is kept."""
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if preset is not None:
        env["OPENBLAS_NUM_THREADS"] = preset
    env["PYTHONPATH"] = str(ROOT)
    code = "import os, delkit.cli, numpy; print(os.environ.get('OPENBLAS_NUM_THREADS'))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    assert out.stdout.strip() == (preset or "1")
