"""The fuzz suite: generated bad and unusual input for every command, each outcome classified.

Quick slice (fast suite): a fixed-seed sample of every command family. Slow run (``make test-slow``):
at least 5,000 inputs. Both demand 0 crashes (tracebacks), 0 hangs, 0 memory overruns and 0 answers that
the oracle rejects; see :mod:`fuzzkit` for the classes and oracles, :mod:`fuzzgen` for the generators and
``bench/fuzz.py`` for the table of counts per command.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
import fuzzgen  # noqa: E402
from fuzzkit import Case, Runner  # noqa: E402


def _assert_clean(tally) -> None:
    assert tally.total > 0
    assert not tally.bad, f"{len(tally.bad)} bad outcome(s):\n{tally.report_bad()}\n{tally.table()}"


def test_quick_slice_every_family():
    """About 6 inputs per command family (seeded): every outcome a clean error or an accepted answer."""
    with Runner() as runner:
        for i, family in enumerate(sorted(fuzzgen.FAMILIES)):
            if family in ("batches", "limit-answers"):
                continue  # processes of a few seconds each: tests/fuzz/test_safety.py (slow sweep, fast cases)
            n = 3 if family in ("arms", "explore", "consistency") else 6
            tally = fuzzgen.run_fuzz(n, seed=100 + i, families=[family], runner=runner)
            _assert_clean(tally)


def test_runner_classifies_hang_and_memory_overrun(monkeypatch):
    """The harness can fail: a command that runs too long is a hang, one that allocates past the worker's
    address-space limit (here: with the budget check switched off by a huge budget) is 'limit'."""
    monkeypatch.setenv("DELKIT_MEMORY_BUDGET", str(10**9))  # inherited by the forked worker
    with Runner(mem_mb=1024, grace=5) as runner:
        # a long z3 search in little memory (symbolic muddy 1000 could also reach the 1 GB limit within the second
        # on a loaded machine and count as a crash); first, while the worker is fresh: after the overrun below its
        # address space can be too full under the 1 GB cap to load libz3 ("libz3.so not found", a crash)
        hang = runner.run(Case("x", ("prove", "C{a,b} p -> K_a K_b K_a p", "--worlds", "12"), budget=1.0))
        assert hang.kind == "hang", hang
        over = runner.run(Case("x", ("puzzle", "sum-product", "--limit", "30000"), budget=20.0))
        assert over.kind == "limit", over
        ok = runner.run(Case("x", ("puzzle", "muddy", "--json"), oracle="json"))
        assert ok.kind == "ok", ok.detail


def test_an_answer_after_the_budget_is_a_hang():
    """The alarm can be lost (its handler runs only between bytecodes; raised inside a ctypes callback such as
    z3's it is printed and swallowed): an answer that comes after the budget is still a hang. Here no alarm is
    armed at all (run_case in this process) and the puzzle takes longer than its 10 ms budget."""
    from fuzzkit import run_case

    out = run_case(Case("x", ("puzzle", "russian-cards", "--json"), budget=0.01))
    assert out.kind == "hang", out


@pytest.mark.slow
def test_five_thousand_inputs():
    tally = fuzzgen.run_fuzz(5000, seed=2026)
    print(tally.table())
    assert tally.total >= 5000
    _assert_clean(tally)


def test_the_harness_alarm_inside_a_ctypes_call_is_a_hang():
    """z3's wrappers call into ctypes: the harness's alarm raised while ctypes converts an argument comes back
    as ``ctypes.ArgumentError("argument 1: _Hang: ")`` — that is a hang of the command, not its crash."""
    import ctypes

    import fuzzkit

    class Arg:
        @classmethod
        def from_param(cls, obj):
            raise fuzzkit._Hang()

    fn = ctypes.CDLL(None).abs
    fn.argtypes = [Arg]
    with pytest.raises(ctypes.ArgumentError) as info:
        fn(1)
    assert fuzzkit._from_hang(info.value)
    assert not fuzzkit._from_hang(ctypes.ArgumentError("argument 1: TypeError: wrong type"))
    assert not fuzzkit._from_hang(ValueError("_Hang"))
