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

import _thread
import os
import resource
import sys
from collections.abc import Iterator
from contextlib import contextmanager

from delkit.errors import DelkitError

__all__ = ["ResourceError", "memory_budget", "require", "fmt_bytes", "product_update_bytes",
           "sum_product_bytes", "sar_bytes", "structure_kripke_bytes", "deadline", "TimeLimit", "parse_timeout",
           "check_time", "begin_command", "remaining", "keep_alive", "time_limit", "check_outputs", "counters",
           "limit_record", "print_limit_record", "time_left"]

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
    """Peak bytes of ``delkit.models.update.product_update(model, events)``, computed from the preconditions.

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
    k = float(c.sum())
    total = k * (8.0 * 4 + len(model.props))  # pairs, valuation, labels
    for a in model.agents:
        mr, er = model.relations[a], events.relations[a]
        if mr.labels is not None and er.labels is not None:
            total += 16.0 * k
            continue
        # Relation.product enumerates, per new world (w, e), the out-degree of w times that of e candidates
        # (about 6 int64 arrays of that length); a partition's rows are materialised first (Σ class sizes²)
        out_w = np.diff(mr.rows()[0]).astype(float) if mr.labels is None else \
            np.bincount(mr.labels).astype(float)[mr.labels]
        out_e = np.diff(er.rows()[0]).astype(float) if er.labels is None else \
            np.bincount(er.labels).astype(float)[er.labels]
        cand = float(out_w @ applicable.astype(float) @ out_e)
        total += 48.0 * cand + 16.0 * (float(out_w.sum()) if mr.labels is not None else 0.0)
    return total


def structure_kripke_bytes(structure) -> float:
    """Peak bytes of the explicit Kripke model of a knowledge/belief structure (``to_kripke`` and the world
    names): about 2 KB per state (its valuation and the per-state dict the enumeration builds), plus for a
    belief structure, whose relations are not partitions, up to 16 bytes per pair of states per agent."""
    n = float(structure.count_states())
    belief = hasattr(structure, "relations") and not hasattr(structure, "observed")
    agents = len(getattr(structure, "relations", None) or getattr(structure, "observed", None) or {})
    return 2048.0 * n + (16.0 * agents * n * n if belief else 0.0)


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


# ----------------------------------------------------------------------------- time limits
#
# One discipline for every command with a time limit (``--timeout T``, see :func:`parse_timeout`):
#
# * T is wall time counted from the start of the *process* (the interpreter's start-up and the imports are
#   inside it), or, for a command run in-process after another one (tests, batch runs), from the moment
#   :func:`begin_command` was called for it;
# * ``--timeout 0`` and ``--timeout inf`` both mean *no limit*; any other positive float is a limit (no
#   overflow: beyond about 10^7 s it is no limit either); negative values and NaN are bad input (exit 2);
# * a reached limit is exit status 3 everywhere (:class:`TimeLimit`), a refusal before starting exit 2;
# * inside the body the limit is enforced in three ways: cheap explicit checks (:func:`check_time`) in the
#   loops that can run long (grounding, initial states, inside a search expansion, product update), a
#   SIGALRM at the deadline that raises :class:`TimeLimit` in whatever Python code runs (re-fired every
#   0.25 s in case something swallows it), and, when running as the console script (:data:`HARD_EXIT`), a
#   watchdog thread that ends the process 0.2 s after the deadline if the body has still not returned;
# * the console script leaves with ``os._exit`` after flushing its output (delkit.cli.run), so freeing a
#   large search space never delays the exit.

HARD_EXIT = False            # set by the console-script entry point: the process may be ended by a watchdog
_HUGE = 1e7                  # seconds (≈ 116 days): a longer limit is no limit (setitimer overflows ~1e9)
ALARM_SLACK = 0.05           # seconds after the deadline before the alarm interrupts the body
_GRACE = 0.2                 # seconds after the deadline before the watchdog ends the process
_BEGUN_PID: int | None = None


def _on_main_thread() -> bool:
    """``threading.current_thread() is threading.main_thread()``, without importing threading when no thread
    was ever started through it (≈ 1 ms of start-up): threading takes the thread that first imports it for the
    main thread, so until then the current thread is the one it would call main."""
    threading = sys.modules.get("threading")
    return threading is None or threading.current_thread() is threading.main_thread()


class _PerThread(_thread._local):  # threading.local
    """The limit state of the command running in this thread (a Dask worker runs tasks in several threads of
    one process: each task's deadline and start are its own)."""

    deadline: float | None = None   # the innermost active deadline, a time.monotonic() instant
    message: str = "time limit reached"
    t0: float | None = None         # start of the current command (time.monotonic())
    counters: dict | None = None    # the live work counters of the current command (see :func:`counters`)


_LOCAL = _PerThread()


class TimeLimit(ResourceError):
    """A ``--timeout`` was reached (exit status 3)."""

    exit_code = 3


def counters() -> dict:
    """The live work counters of the command running in this thread (e.g. ``expanded``, ``generated`` of a
    search, ``worlds`` of a counter-model search): long loops store their counts here as they go, so that a
    limit answer — also the one the watchdog prints when the body is stuck — reports how far the work got."""
    c = _LOCAL.counters
    if c is None:
        c = _LOCAL.counters = {}
    return c


#: set by the console script when the command line has ``--json``: a limit answer is then one JSON object
JSON_LIMITS = False


def limit_record(message: str, **extra) -> dict:
    """The JSON answer of a reached limit: ``status`` "limit", the reason, ``exit`` 3, the seconds since the
    command started and the live :func:`counters` (whatever the work stored so far)."""
    import time

    rec = {"status": "limit", "reason": message, "exit": 3,
           "seconds": round(time.monotonic() - command_start(), 4)}
    rec.update(dict(_LOCAL.counters or {}))
    rec.update(extra)
    return rec


_ANSWERED: list = []  # a limit answer was printed by this process (the body's, or a watchdog's): only one


def print_limit_record(message: str, stream=None, snapshot: dict | None = None, since: float | None = None) -> None:
    """Print :func:`limit_record` as one JSON line (on stdout unless ``stream``), once per process: a watchdog
    and the body reaching the same limit print one answer between them. ``snapshot``: the counters to report
    instead of this thread's (the watchdog runs in its own thread); ``since``: the start to count the
    seconds from (default: the command's)."""
    import json
    import time

    if _ANSWERED:
        return
    _ANSWERED.append(True)
    rec = limit_record(message)
    if snapshot is not None:
        rec.update(snapshot)
    if since is not None:
        rec["seconds"] = round(time.monotonic() - since, 4)
    (stream or sys.stdout).write(json.dumps(rec) + "\n")


def process_start() -> float:
    """The ``time.monotonic()`` instant at which this process started (Linux: from /proc; else now)."""
    import time

    now = time.monotonic()
    try:
        with open("/proc/self/stat", "rb") as fh:
            stat = fh.read()
        ticks = int(stat[stat.rindex(b")") + 2:].split()[19])  # field 22: start time, clock ticks since boot
        age = time.clock_gettime(time.CLOCK_BOOTTIME) - ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, AttributeError):  # pragma: no cover - not Linux
        return now
    return now - age if 0.0 <= age < 3600.0 else now


def begin_command() -> None:
    """Mark the start of a command: the process start for the first command of the ``delkit`` process itself
    (the console script, :data:`HARD_EXIT`), else now — a host program that calls ``delkit.cli.main`` (a test
    runner, a notebook) has run for its own reasons before, and that time is not the command's."""
    import time

    global _BEGUN_PID
    pid = os.getpid()
    first = _BEGUN_PID != pid and _on_main_thread()
    _LOCAL.t0 = process_start() if first and HARD_EXIT else time.monotonic()
    _ANSWERED.clear()
    if not first:
        # the same dict, emptied: a watchdog started before reads this command's counts (the process's first
        # command keeps what the early watchdog put there)
        counters().clear()
    if first:
        _BEGUN_PID = pid


def end_command() -> None:
    """Forget the command's start (:func:`begin_command`): a library call made after it (``run_check``,
    ``run_plan`` called directly) counts its limits from its own start, not from a finished command's."""
    _LOCAL.t0 = None


def command_start() -> float:
    import time

    t0 = _LOCAL.t0
    return time.monotonic() if t0 is None else t0


def parse_timeout(value: float | str | None, option: str = "--timeout") -> float | None:
    """The limit in seconds, or None for no limit (None, 0, inf, or more than ~10^7 s); bad input raises."""
    if value is None:
        return None
    try:
        seconds = float(value)
    except (TypeError, ValueError):
        raise ResourceError(f"{option} {value!r}: use a number of seconds (0 or inf: no limit)") from None
    if seconds != seconds or seconds < 0:
        raise ResourceError(f"{option} {seconds:g} is impossible: use a number of seconds >= 0 (0 or inf: no "
                            f"limit)")
    return None if seconds == 0 or seconds > _HUGE else seconds


def remaining() -> float | None:
    """Seconds left before the innermost active deadline (None: no deadline; may be negative)."""
    import time

    when = _LOCAL.deadline
    return None if when is None else when - time.monotonic()


def expired() -> bool:
    import time

    when = _LOCAL.deadline
    return when is not None and time.monotonic() > when


def check_time(slack: float = 0.0) -> None:
    """Raise :class:`TimeLimit` if the active deadline has passed by more than ``slack`` seconds (cheap: one
    clock read). A search passes a small slack inside an expansion so that its own per-expansion check,
    which reports how far it got, normally comes first."""
    when = _LOCAL.deadline
    if when is not None:
        import time

        if time.monotonic() > when + slack:
            raise TimeLimit(_LOCAL.message)


def time_left() -> float | None:
    """Seconds left before the active deadline (None: no deadline), raising :class:`TimeLimit` when none are
    left — for passing the rest of the budget on as another limit (a spent budget is a reached limit, exit 3,
    never an impossible limit)."""
    left = remaining()
    if left is not None and left <= 0:
        raise TimeLimit(_LOCAL.message)
    return left


def time_limit() -> TimeLimit:
    """The :class:`TimeLimit` of the active deadline (to raise where a library stopped at it, e.g. z3)."""
    return TimeLimit(_LOCAL.message)

_KEEP: list = []


def keep_alive(*objs) -> None:
    """In the console script, keep large structures referenced until ``os._exit`` so that a limit never waits
    for them to be freed (no-op in-process)."""
    if HARD_EXIT:
        _KEEP.extend(objs)


def _watchdog(when: float, message: str, token: list, live: dict | None = None, since: float | None = None) -> None:
    import sys
    import time

    while True:
        left = when - time.monotonic()
        if left <= 0:
            break
        time.sleep(min(left, 0.5))
        if token[0]:
            return
    if token[0]:
        return
    try:
        if JSON_LIMITS:  # the answer the body could not give: one JSON object with the counters so far
            try:
                print_limit_record(message, snapshot=dict(live or {}), since=since)
            except Exception:  # noqa: BLE001 - a closed stdout, a counter changed under us: exit anyway
                pass
        sys.stdout.flush()
        sys.stderr.write(f"delkit: error: {message}\n")
        sys.stderr.flush()
    finally:
        os._exit(3)


def early_watchdog(argv: list[str]) -> None:
    """Console script only: end the process ``_GRACE`` + 0.1 s after ``--timeout`` (``epico table``:
    ``--total-timeout``) counted from process start, whatever it is doing — a backstop started before the
    command's imports (mujoco, z3, typer: seconds on a loaded machine), which the command's own deadline
    normally beats by reporting the limit in its own words."""
    import threading

    global JSON_LIMITS

    JSON_LIMITS = "--json" in argv[:argv.index("--")] if "--" in argv else "--json" in argv
    if _batch_line(argv):
        return  # a batch's --timeout is per task: each worker holds its own (planners.batch)
    option = "--total-timeout" if argv[:2] == ["epico", "table"] else "--timeout"
    value = None
    for i, arg in enumerate(argv):
        if arg == "--":
            break
        if arg == option and i + 1 < len(argv):
            value = argv[i + 1]
        elif arg.startswith(option + "="):
            value = arg.split("=", 1)[1]
    try:
        limit = parse_timeout(value, option)
    except ResourceError:
        return  # the command reports the bad value
    if limit is None:
        return
    name = " ".join(a for a in argv[:2] if not a.startswith("-"))
    message = f"delkit {name}: no answer within {option} {limit:g} s; give it more time with {option}"
    if argv[0] == "plan":  # an answer before the search has started: it has expanded nothing yet
        counters().update(expanded=0, generated=0)
    t0 = process_start()
    threading.Thread(target=_watchdog, args=(t0 + limit + _GRACE + 0.1, message, [False], counters(), t0),
                     daemon=True).start()


def _batch_line(argv: list[str]) -> bool:
    """Whether a ``plan`` / ``check`` command line is a batch (``--jobs``, ``--scheduler``, or more files than
    one task takes), told from the words alone (before any import): its ``--timeout`` is per task."""
    if not argv or argv[0] not in ("plan", "check"):
        return False
    words = argv[1:argv.index("--")] if "--" in argv else argv[1:]
    if any(w in ("--jobs", "-j", "--scheduler") or w.startswith(("--jobs=", "--scheduler=")) for w in words):
        return True
    valued = {"--timeout", "--library", "-l", "--search", "--max-nodes", "--max-memory", "--engine", "--property",
              "-p", "--properties", "--trace-json"}
    pos, skip = 0, False
    for w in words:
        if skip:
            skip = False
        elif w in valued:
            skip = True
        elif not w.startswith("-"):
            pos += 1
    return pos > (3 if argv[0] == "check" else 2)


class _Watchdog:
    """In the console script (:data:`HARD_EXIT`), a watchdog thread that ends the process at ``when`` unless the
    body left first. It stays armed when the body left by :class:`TimeLimit`: unwinding and freeing what the
    body built must not delay the exit either. (A class, not a generator: it is entered inside the generator of
    :func:`deadline`, and must see the exception thrown into that generator as it is.)"""

    __slots__ = ("when", "message", "token")

    def __init__(self, when: float, message: str) -> None:
        self.when, self.message, self.token = when, message, [False]

    def __enter__(self) -> None:
        if HARD_EXIT:
            import threading

            threading.Thread(target=_watchdog, args=(self.when, self.message, self.token, counters(),
                                                     command_start()), daemon=True).start()

    def __exit__(self, kind, value, traceback) -> bool:
        if kind is None or not issubclass(kind, TimeLimit):
            self.token[0] = True
        return False


@contextmanager
def deadline(seconds: float | str | None, what: str, option: str = "--timeout", *,
             alarm: bool = True) -> Iterator[None]:
    """Raise :class:`TimeLimit` in the main thread once ``seconds`` (see :func:`parse_timeout`) of wall time
    have passed since the command started (:func:`begin_command`; when none was marked, since now).

    An outer, earlier deadline (a test harness's ``ITIMER_REAL`` timer, or an enclosing :func:`deadline`)
    stays in charge and is restored afterwards; off the main thread only the explicit checks apply.
    ``alarm=False``: no SIGALRM (for a body that runs a C library through ctypes, e.g. z3, whose wrappers
    turn an exception raised inside them into another one or print it as "Exception ignored"): only the
    explicit checks (:func:`check_time`, :func:`remaining`) and, in the console script, the watchdog."""
    import _signal as signal  # the C module: the signal module's enums cost ≈ 2 ms of start-up
    import time

    limit = parse_timeout(seconds, option)
    if limit is None:
        yield
        return
    when = command_start() + limit
    message = f"{what}: no answer within {option} {limit:g} s; give it more time with {option}"
    local = _LOCAL
    outer_deadline, outer_message = local.deadline, local.message
    if outer_deadline is not None and outer_deadline <= when:
        yield
        return
    local.deadline, local.message = when, message
    if not alarm or not _on_main_thread():
        try:
            with _Watchdog(when + _GRACE, message):
                yield
        finally:
            local.deadline, local.message = outer_deadline, outer_message
        return
    outer = signal.getitimer(signal.ITIMER_REAL)[0]
    left = when - time.monotonic()
    if outer and outer <= left:
        try:
            yield
        finally:
            local.deadline, local.message = outer_deadline, outer_message
        return
    previous = signal.getsignal(signal.SIGALRM)

    def expired_(signum, frame):  # noqa: ARG001 - signal handler signature
        raise TimeLimit(message)

    t0 = time.monotonic()
    signal.signal(signal.SIGALRM, expired_)
    # the timer re-fires every 0.25 s after expiry: an exception raised where Python swallows it (a C
    # extension's finaliser, e.g. a BDD node freed by CUDD's wrapper, prints "Exception ignored") must not
    # leave the body running without a limit
    # ALARM_SLACK after the deadline: a loop that checks the deadline itself (the search, per expansion)
    # normally stops first and reports how far it got; the alarm stops everything else
    signal.setitimer(signal.ITIMER_REAL, max(left + ALARM_SLACK, 1e-3), 0.25)
    try:
        with _Watchdog(when + _GRACE, message):
            yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        local.deadline, local.message = outer_deadline, outer_message
        if outer:
            signal.setitimer(signal.ITIMER_REAL, max(outer - (time.monotonic() - t0), 1e-3))


# ----------------------------------------------------------------------------- outputs

def check_outputs(outputs, inputs, *, force: bool | None = None, folder=None, option: str = "-o") -> None:
    """Refuse (exit 2, nothing written) an output that is one of the ``inputs``
    (:func:`delkit.paths.refuse_overwrite_input`; ``force`` True: the input is overwritten on purpose, False:
    the command's --force was not given, None: it has none) or that lies outside ``folder``; call it for every
    output before writing the first one."""
    from pathlib import Path

    from delkit.errors import ParseError
    from delkit.paths import refuse_overwrite_input

    base = Path(folder).resolve() if folder is not None else None
    outputs = list(outputs)
    for out in outputs:
        if base is not None and Path(out).resolve().parent != base:
            raise ParseError(f"the output {out} would be written outside the folder {folder}; give a plain file "
                             f"name (no '/' or '..')", source=str(out))
    refuse_overwrite_input(outputs, inputs, option=option, force=force)
