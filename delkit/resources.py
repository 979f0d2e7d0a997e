"""Resources known before they are spent: a memory budget and size estimates for the big structures.

Commands that build something whose size follows from the input (a product update, the Sum-and-Product
model, a search-and-rescue grid) first estimate the bytes it needs and call :func:`require`, which refuses
anything beyond the budget with one line that gives the estimate, the budget and what to change —
instead of letting numpy try to allocate 900 GiB.

The budget is half of the machine's physical memory, lowered to 80 % of the process's address-space limit
(``ulimit -v``) if one is set; the environment variable ``DELKIT_MEMORY_BUDGET`` (MiB) overrides it.
The estimates are upper bounds of the peak of the named structure, not of the whole process.
"""

from __future__ import annotations

import os
import resource
from collections.abc import Iterator
from contextlib import contextmanager

from delkit.errors import DelkitError

__all__ = ["ResourceError", "memory_budget", "require", "fmt_bytes", "product_update_bytes",
           "sum_product_bytes", "sar_bytes", "deadline"]

ENV = "DELKIT_MEMORY_BUDGET"


class ResourceError(DelkitError):
    """The input asks for more memory than the budget allows (raised before anything is allocated)."""


def _physical() -> int:
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return 8 << 30


def memory_budget() -> tuple[int, str]:
    """(bytes, how it was chosen)."""
    env = os.environ.get(ENV, "").strip()
    if env:
        try:
            mib = float(env)
        except ValueError:
            raise ResourceError(f"{ENV}={env!r} is not a number of MiB; e.g. {ENV}=4096") from None
        if not mib > 0 or mib != mib or mib == float("inf"):
            raise ResourceError(f"{ENV}={env!r} must be a positive number of MiB")
        return int(mib * 2**20), f"{ENV}={env}"
    phys = _physical()
    budget, why = phys // 2, f"half of this machine's {fmt_bytes(phys)} of memory"
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    if soft != resource.RLIM_INFINITY and soft > 0 and int(0.8 * soft) < budget:
        budget, why = int(0.8 * soft), f"80 % of the process's address-space limit {fmt_bytes(soft)}"
    return budget, why


def fmt_bytes(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n:.1f} PiB"  # pragma: no cover


def require(nbytes: float, what: str, change: str) -> None:
    """Refuse (``ResourceError``) if ``what`` would need more than the budget; ``change`` says which option
    makes it smaller, e.g. ``"use a smaller --limit"``."""
    budget, why = memory_budget()
    if nbytes > budget:
        raise ResourceError(f"{what} would need about {fmt_bytes(nbytes)} of memory, more than the budget of "
                            f"{fmt_bytes(budget)} ({why}); {change}, or set {ENV} (MiB) to raise the budget")


# ----------------------------------------------------------------------------- estimates

def product_update_bytes(model, events) -> float:
    """Peak bytes of ``delkit.update.product_update(model, events)``, computed from the preconditions.

    With c_e the number of worlds where event e's precondition holds and d_w the number of events
    applicable at world w, the product has k = Σ c_e worlds; a partition × partition relation costs O(k),
    any other relation materialises two sparse matrices with Σ_{(e,f)∈R_E} c_e·c_f and
    Σ_{(w,v)∈R_a} d_w·d_v entries (≈ 16 bytes each)."""
    import numpy as np  # here, not at the top: `delkit plan` of a small task never loads numpy (start-up)

    n = model.n_worlds
    if n == 0 or not len(events.events):
        return 0.0
    applicable = np.stack([np.asarray(model.check(p), dtype=bool) for p in events.pre], axis=1)  # n × |E|
    c = applicable.sum(axis=0).astype(float)  # per event
    d = applicable.sum(axis=1).astype(float)  # per world
    k = float(c.sum())
    total = k * (8.0 * 4 + len(model.props))  # pairs, valuation, labels
    for a in model.agents:
        mr, er = model.relations[a], events.relations[a]
        if mr.labels is not None and er.labels is not None:
            total += 16.0 * k
            continue
        emat = er.to_matrix().tocoo()
        nnz_b = float(np.dot(c[emat.row], c[emat.col]))
        if mr.labels is not None:  # the partition is first materialised as an n × n matrix
            sizes = np.bincount(mr.labels).astype(float)
            sums = np.bincount(mr.labels, weights=d)
            nnz_a = float(np.dot(sums, sums) + np.dot(sizes, sizes))
        else:
            mmat = mr.to_matrix().tocoo()
            nnz_a = float(np.dot(d[mmat.row], d[mmat.col]))
        total += 16.0 * (nnz_a + nnz_b)
    return total


def sum_product_bytes(limit: int) -> float:
    """Peak bytes of the Sum-and-Product model for x + y ≤ limit (``numpy.triu_indices(limit)`` and friends:
    about 12 bytes per pair x < y < limit, plus the model on the ≈ limit²/4 worlds)."""
    pairs = float(limit) * float(limit) / 2.0
    return 12.0 * 2 * pairs + 64.0 * pairs / 2


def sar_bytes(width: int, height: int, robots: int, epochs: int) -> float:
    """Peak bytes of one search-and-rescue episode: per-cell priors, beliefs and targets, and the per-step
    observation log (robots × epochs entries, each known to every robot)."""
    cells = float(width) * float(height)
    log = float(robots) * float(epochs)
    return cells * (64.0 + 16.0 * robots) + log * (40.0 + robots) + 8.0 * (epochs + 1) * robots


@contextmanager
def deadline(seconds: float | None, what: str, option: str = "--timeout") -> Iterator[None]:
    """Raise :class:`ResourceError` in the main thread if the body runs longer than ``seconds`` of wall time.

    ``None``/0 means no limit. An outer, shorter ``ITIMER_REAL`` timer (e.g. a test harness's) stays in
    charge and is restored afterwards; off the main thread the limit is not enforced (signals need it)."""
    import signal
    import threading
    import time

    if not seconds or threading.current_thread() is not threading.main_thread():
        yield
        return
    if not seconds > 0 or seconds != seconds:
        raise ResourceError(f"{option} must be a positive number of seconds, got {seconds}")
    outer = signal.getitimer(signal.ITIMER_REAL)[0]
    if outer and outer <= seconds:
        yield
        return
    previous = signal.getsignal(signal.SIGALRM)

    def expired(signum, frame):  # noqa: ARG001 - signal handler signature
        raise ResourceError(f"{what}: no answer within {option} {seconds:g} s; give it more time with {option}")

    t0 = time.monotonic()
    signal.signal(signal.SIGALRM, expired)
    # the timer re-fires every 0.25 s after expiry: an exception raised where Python swallows it (a C
    # extension's finaliser, e.g. a BDD node freed by CUDD's wrapper, prints "Exception ignored") must not
    # leave the body running without a limit
    signal.setitimer(signal.ITIMER_REAL, seconds, 0.25)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if outer:
            signal.setitimer(signal.ITIMER_REAL, max(outer - (time.monotonic() - t0), 1e-3))
