"""Whole-process timing shared by the benchmarks: one child process, its wall seconds (around
``subprocess.run``) and its CPU seconds (user + system of the child, the ``RUSAGE_CHILDREN`` difference).

    from _timing import timed_run          # bench/ is the script's directory, so it is on sys.path
    r = timed_run([sys.executable, "-c", "pass"])
    r.wall, r.cpu, r.returncode, r.stdout, r.stderr, r.timed_out

With ``timeout`` a child still running then is killed and ``timed_out`` is set (its CPU until then is
counted; ``returncode`` is None). Concurrent callers in threads share ``RUSAGE_CHILDREN``: time children
one at a time when the CPU figure matters.
"""

from __future__ import annotations

import resource
import subprocess
import time
from dataclasses import dataclass
from typing import Any

__all__ = ["Timed", "timed_run"]


@dataclass(frozen=True)
class Timed:
    wall: float
    cpu: float
    returncode: int | None
    stdout: str
    stderr: str
    timed_out: bool = False


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed_run(cmd: list[str], *, timeout: float | None = None, clock=time.perf_counter, **kw: Any) -> Timed:
    """Run ``cmd`` (``subprocess.run`` keywords in ``kw``; output captured as text) and time it."""
    kw.setdefault("errors", "replace")
    c0, t0 = _children_cpu(), clock()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False, **kw)
        out, err, code, late = p.stdout, p.stderr, p.returncode, False
    except subprocess.TimeoutExpired as e:
        def text(x: Any) -> str:
            return x.decode(errors="replace") if isinstance(x, bytes) else (x or "")

        out, err, code, late = text(e.stdout), text(e.stderr), None, True
    return Timed(clock() - t0, _children_cpu() - c0, code, out, err, late)
