"""delkit.executors.actors: stateful workers in their own processes, called by method name."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from delkit.executors import WorkerDied, actors


@pytest.fixture(autouse=True)
def _importable_in_the_workers(monkeypatch) -> None:
    """The actors' spawned processes unpickle :class:`Counter` by its module, ``tests.delkit.test_actors``:
    the repository root must be on the path they inherit (pytest's importlib mode does not put it there, and
    the core-only run, ``make test-core``, starts pytest from another directory)."""
    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[2]))


class Counter:
    """Keeps a total across calls (state lives in the worker)."""

    def __init__(self, start: int) -> None:
        self.total = start

    def add(self, x: int) -> tuple[int, int]:
        self.total += x
        return self.total, os.getpid()

    def fail(self) -> None:
        raise ValueError("asked to fail")

    def die(self) -> None:
        os._exit(7)


def test_actors_keep_state_in_their_own_processes_and_report_failures() -> None:
    with actors(Counter, [(10,), (100,)]) as (a, b):
        pa, pb = a.call("add", 1), b.call("add", 2)  # both start before either is read
        (ta, ida), (tb, idb) = pa.result(), pb.result()
        assert (ta, tb) == (11, 102) and len({ida, idb, os.getpid()}) == 3
        assert a.call("add", 5).result()[0] == 16  # the state persisted between calls
        with pytest.raises(ValueError, match="asked to fail"):
            a.call("fail").result()
        assert a.call("add", 0).result()[0] == 16  # a failed call leaves the actor usable
        with pytest.raises(WorkerDied, match="status 7"):
            b.call("die").result()
