"""On a 2 agents × 4 rooms × 4 boxes Collaboration-and-Communication task whose single expansion is
slow, a time limit is held within 0.5 s of wall time (plus the shared machine's margin, as in
tests/fuzz/test_limits.py). The numpy engine (``--engine del``) takes several seconds of CPU for the initial
state's expansion there (bench/RESULTS-planner.md §11), so a limit shorter than one expansion is met only if the
deadline is checked inside the expansion (per successor, inside the product update)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DELKIT = Path(sys.executable).parent / "delkit"
MARGIN = float(os.environ.get("DELKIT_LIMIT_MARGIN", "1.5"))  # loaded machine; 0 on an idle one
HARD = sorted((REPO / "specs").glob("cc_2_4_4*/*.txt"))


def test_cc_2_4_4_limit_is_exit_3() -> None:
    """The exit status at any load (the task cannot be solved in 2 s); the time it takes: the slow test below."""
    p = subprocess.run([str(DELKIT), "plan", str(HARD[-1]), "--search", "astar", "--engine", "del", "--timeout", "2"],
                       capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(REPO)}, timeout=120)
    assert p.returncode == 3, (p.returncode, (p.stdout + p.stderr)[-300:])


@pytest.mark.slow
def test_cc_2_4_4_limit_held_within_half_a_second() -> None:
    limit, engine = 2.0, "del"
    task = HARD[-1]
    t0 = time.monotonic()
    p = subprocess.run([str(DELKIT), "plan", str(task), "--search", "astar", "--engine", engine, "--timeout",
                        str(limit)], capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(REPO)},
                       timeout=120)
    wall = time.monotonic() - t0
    out = p.stdout + p.stderr
    # stopped inside the first expansion: nothing was expanded — reported by the search itself, or, where a
    # loaded machine delays that report past the grace period, by the console watchdog (the limit named)
    assert p.returncode == 3, (p.returncode, out[-300:])
    assert ("--timeout 2 s reached" in out and "0 expanded" in out) or (
        not p.stdout and "no answer within --timeout 2 s" in p.stderr), out[-300:]
    assert wall < limit + 0.5 + MARGIN, wall
