"""Batch mode of ``delkit plan`` / ``delkit check``: a whole suite in one command, across cores.

``delkit plan FILE... [--jobs N] [--timeout T] [--scheduler ADDRESS] [--json]`` plans every task of the
files: an mA* file is a task; an E-PDDL / EPDDL domain file is paired with each problem file that follows it
(``D P1 P2 D2 P3``; ``--library`` applies to all). ``delkit check`` takes groups ``SPEC [PROBLEM] PLAN_FILE``
the same way (a file that is not a spec is the plan file closing a group).

* Runs go through :func:`delkit.executors.executor`: ``N`` local worker processes (default: one per core),
  each reused for many tasks, or the Dask cluster at ``--scheduler``. Each task runs the command's own body
  (:func:`planners.commands.run_plan` with ``--json``), so its answer, its limits (``--timeout``,
  ``--max-nodes``, ``--max-memory`` hold per task) and its exit status are those of a single run.
* One task's crash, hang past its limit or memory blow-up is reported as that task's result (status
  ``crash``) and the others go on: the worker is replaced (see :class:`delkit.executors.IsolatedPool`).
* Results: with ``--json`` one JSON object per task on stdout as soon as it is done (``file``, ``problem``,
  ``exit``, ``cpu`` — the worker's CPU seconds for the task —, ``wall`` and the fields of the single
  command's JSON), then one ``{"summary": ...}`` object; otherwise a table in input order and a totals line.
  A progress bar (rich) is drawn on stderr when it is a terminal and ``--json`` is not given.
* Exit status: 0 every task solved (check: every plan valid); otherwise that of the worst task, from best
  to worst 1 (no plan exists / plan invalid), 3 (a limit, a crash, or killed), 2 (bad input).
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from delkit._lazy import lazy_module

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    import json
    from typing import Any
else:
    json = lazy_module("json")  # a single small task never needs it (start-up)

__all__ = ["plan_files", "check_files", "is_batch", "plan_units", "check_units", "run_plan_batch",
           "run_check_batch", "plan_one", "check_one"]


def plan_files(files: Sequence[Path], *, jobs: int | None = None, scheduler: str | None = None,
               **options: Any) -> int:
    """``delkit plan FILE...``: one task (the single command, :func:`run_plan`), or a batch (more tasks than
    one, or ``--scheduler``); returns the exit status."""
    from planners.commands import run_plan

    files = [Path(f) for f in files]
    jobs = _check_jobs(jobs, "delkit plan", scheduler)
    if is_batch(files, {"jobs": jobs, "scheduler": scheduler}):
        if options.get("plan_out") is not None:
            from delkit.errors import ParseError

            raise ParseError("--plan-out writes the plan of one task, planned in this process: leave out "
                             "--jobs / --scheduler and give one SPEC or DOMAIN PROBLEM", source="delkit plan")
        units = plan_units(files)
        parallel = jobs is not None and jobs > 1
        # one task with --scheduler and no --jobs N: the batch runner (the task on one Dask worker); with
        # --jobs N: one parallel search whose N parts are Dask actors
        if len(units) != 1 or (scheduler and not parallel):
            return run_plan_batch(files, jobs=jobs, scheduler=scheduler, **options)
        files = [units[0][0]] + ([units[0][1]] if units[0][1] is not None else [])
        if parallel:
            from planners.parallel import run_plan_parallel

            return run_plan_parallel(files[0], files[1] if len(files) == 2 else None, jobs=jobs,
                                     scheduler=scheduler, **options)
    return run_plan(files[0], files[1] if len(files) == 2 else None, **options)


def check_files(files: Sequence[Path], *, jobs: int | None = None, scheduler: str | None = None,
                **options: Any) -> int:
    """``delkit check``: one SPEC [PROBLEM] PLAN_FILE group (:func:`run_check`), or a batch of groups."""
    from planners.commands import run_check

    files = [Path(f) for f in files]
    jobs = _check_jobs(jobs, "delkit check", scheduler)
    if is_batch(files, {"jobs": jobs, "scheduler": scheduler}, "check") and (
            len(check_units(files)) != 1 or scheduler):
        return run_check_batch(files, jobs=jobs, scheduler=scheduler, **options)
    return run_check(files, **options)


#: the most worker processes (or parallel parts) ``--jobs`` takes
MAX_JOBS = 256


def _check_jobs(jobs: int | str | None, command: str, scheduler: str | None = None) -> int | None:
    """``--jobs`` as a number 1..MAX_JOBS written in plain digits (``+2``, ``0x4``, ``1e3`` are refused), and a
    well-formed ``--scheduler`` address (:func:`delkit.executors.parse_scheduler`); bad input raises."""
    from delkit.errors import ParseError

    if scheduler is not None:
        from delkit.executors import parse_scheduler

        parse_scheduler(scheduler)
    if jobs is None:
        return None
    text = str(jobs).strip()
    if not re.fullmatch(r"[0-9]{1,20}", text) or not 1 <= int(text) <= MAX_JOBS:
        raise ParseError(f"--jobs {jobs}: use a number of worker processes 1..{MAX_JOBS} in plain digits, e.g. "
                         f"--jobs 2 (this machine has {os.cpu_count() or 1} cores)", source=command)
    return int(text)

_PROBLEM = r"(?i)\(\s*define\s*\(\s*problem\b"  # compiled on first use (re's cache): start-up


def is_batch(pos: Sequence[Path], kw: dict[str, Any], command: str = "plan") -> bool:
    """Whether a command line is a batch: ``--jobs`` or ``--scheduler`` given, or more files than one task
    takes (plan: more than DOMAIN PROBLEM, or two mA* files; check: more than SPEC PROBLEM PLAN)."""
    if kw.get("jobs") is not None or kw.get("scheduler"):
        return True
    if command == "check":
        return len(pos) > 3
    if len(pos) > 2:
        return True
    return len(pos) == 2 and _role(pos[0]) == "mastar" and _role(pos[1]) == "mastar"


def _role(path: Path) -> str:
    """``mastar``, ``domain`` (E-PDDL / EPDDL domain or a one-file E-PDDL task), ``problem``, or ``other``
    (not a spec: a plan file, or unreadable — the task's own run reports that)."""
    from delkit.errors import ParseError
    from planners.lang.detect import detect_text

    try:
        from delkit.paths import read_input

        text = read_input(path)
        dialect = detect_text(text, str(path))[0]
    except (OSError, UnicodeDecodeError, ParseError):
        return "other"
    if dialect == "mastar":
        return "mastar"
    lisp = "\n".join(ln.split(";", 1)[0] for ln in text.splitlines())
    return "problem" if re.search(_PROBLEM, lisp) and "(domain" not in lisp.replace(" ", "")[:200] else "domain"


def plan_units(files: Sequence[Path]) -> list[tuple[Path, Path | None]]:
    """(spec, problem) of every task of a batch's files (module docstring)."""
    units: list[tuple[Path, Path | None]] = []
    domain: Path | None = None
    pending = False  # a domain not yet paired with a problem
    for f in files:
        role = _role(f)
        if role == "problem" and domain is not None:
            units.append((domain, f))
            pending = False
            continue
        if pending and domain is not None:
            units.append((domain, None))  # a one-file E-PDDL task (or a domain without problem: reported)
        if role == "domain":
            domain, pending = f, True
        else:
            domain, pending = None, False
            units.append((f, None))       # mA*, or a file the run will report (unreadable, a lone problem...)
    if pending and domain is not None:
        units.append((domain, None))
    return units


def check_units(files: Sequence[Path]) -> list[list[Path]]:
    """The ``SPEC [PROBLEM] PLAN_FILE`` groups of a check batch."""
    units: list[list[Path]] = []
    cur: list[Path] = []
    for f in files:
        cur.append(f)
        if _role(f) == "other":
            units.append(cur)
            cur = []
    if cur:
        units.append(cur)
    return units


class _ThreadStdout:
    """``sys.stdout`` for a process whose threads run tasks at once (a Dask worker with several threads): a
    thread capturing its task's output writes to its own buffer, every other write goes to the real stream.
    (``contextlib.redirect_stdout`` swaps the one ``sys.stdout`` of the process: two tasks in two threads
    then write into each other's capture, and one task's JSON result was lost.)"""

    def __init__(self, base) -> None:
        import threading

        self._base, self._local = base, threading.local()

    def _target(self):
        buf = getattr(self._local, "buf", None)
        return self._base if buf is None else buf

    def write(self, text: str) -> int:
        return self._target().write(text)

    def flush(self) -> None:
        self._target().flush()

    def __getattr__(self, name: str):
        return getattr(self._target(), name)


@contextlib.contextmanager
def _thread_stdout(out: io.StringIO):
    """Send this thread's writes to ``sys.stdout`` to ``out`` (other threads' writes are not captured)."""
    proxy = sys.stdout
    if not isinstance(proxy, _ThreadStdout):
        proxy = sys.stdout = _ThreadStdout(sys.stdout)
    proxy._local.buf = out
    try:
        yield
    finally:
        proxy._local.buf = None


def _cpu_clock() -> Callable[[], float]:
    """This task's CPU clock: the process's in a worker process's main thread (what a single run measures),
    the thread's own where several threads of one process run tasks (a Dask worker's threads)."""
    import threading

    return time.process_time if threading.current_thread() is threading.main_thread() else time.thread_time


def _capture(fn: Callable[[], int]) -> tuple[int, str, str]:
    """(exit status, stdout, one-line error) of a command body run in this process."""
    import threading

    out = io.StringIO()
    err = ""
    main = threading.current_thread() is threading.main_thread()
    with contextlib.redirect_stdout(out) if main else _thread_stdout(out):
        try:
            code = fn()
        except BaseException as exc:  # noqa: BLE001 - mapped like the CLI maps it
            from delkit.errors import DelkitError

            if isinstance(exc, DelkitError):
                code, err = int(getattr(exc, "exit_code", 2)), str(exc)  # 3: a limit (TimeLimit)
            elif isinstance(exc, MemoryError):
                code, err = 3, "out of memory (the worker's address-space limit)"
            elif isinstance(exc, RecursionError):
                code, err = 2, "the input is nested too deeply"
            elif isinstance(exc, OSError):
                code, err = 2, f"{exc.filename or ''}: {exc.strerror or exc}".lstrip(": ")
            else:
                raise
    return code, out.getvalue(), err


def _begin_task(timeout: Any = None) -> Callable[[], None]:
    """A task's limits count from now (not from the worker's start), and its counters start at zero. In a pool
    worker with a ``timeout``, a watchdog answers for the task if it is still running 0.3 s after its limit
    (stuck in native code, where the alarm cannot stop it): the limit record with the counters so far, and the
    worker ends (the pool starts another). Returns the function that disarms the watchdog."""
    import threading

    import delkit.resources as resources
    from delkit.resources import begin_command, parse_timeout

    begin_command()  # a worker's first command would count from the process start: mark a fresh start below
    resources._LOCAL.t0 = t0 = time.monotonic()
    try:
        limit = parse_timeout(timeout)
    except Exception:  # noqa: BLE001 - the task's own run reports a bad value
        limit = None
    done = threading.Event()
    if limit is None or threading.current_thread() is not threading.main_thread():
        return done.set
    live = resources.counters()
    c0 = time.process_time()

    def watch() -> None:
        if done.wait(limit + 0.3):
            return
        from delkit.executors import answer_and_exit

        rec = resources.limit_record(f"no answer within --timeout {limit:g} s (counted from the task's start); give "
                                     f"it more time with --timeout")
        rec.update(dict(live), seconds=round(time.monotonic() - t0, 4))
        rec.update(exit=3, cpu=round(time.process_time() - c0, 4), wall=rec["seconds"],
                   stopped_by="watchdog")
        answer_and_exit(rec, time.process_time() - c0)

    threading.Thread(target=watch, daemon=True).start()
    return done.set



def _result(code: int, text: str, err: str, t0: float, c0: float, cpu: Callable[[], float]) -> dict[str, Any]:
    lines = [ln for ln in text.splitlines() if ln.startswith("{")]
    res: dict[str, Any] = json.loads(lines[-1]) if lines else {}
    if err and code == 3:  # a limit outside the search (reading, replaying): the counters so far
        from delkit.resources import limit_record

        res = {**limit_record(err), **res}
    elif err:
        res.update(status="error", reason=err)
    res.update(exit=code, cpu=round(cpu() - c0, 4), wall=round(time.monotonic() - t0, 4))
    return res


def plan_one(spec: str, problem: str | None, options: dict[str, Any]) -> dict[str, Any]:
    """One task of a plan batch, in a worker: :func:`run_plan` with ``--json``; its JSON object plus ``exit``,
    ``cpu`` and ``wall`` (the task's CPU and wall-clock seconds in this worker, reading included)."""
    from planners.commands import run_plan

    disarm = _begin_task(options.get("timeout"))
    cpu = _cpu_clock()
    t0, c0 = time.monotonic(), cpu()
    try:
        code, text, err = _capture(lambda: run_plan(Path(spec), Path(problem) if problem else None,
                                                    as_json=True, **options))
    finally:
        disarm()
    return _result(code, text, err, t0, c0, cpu)


def check_one(files: list[str], options: dict[str, Any]) -> dict[str, Any]:
    """One group of a check batch, in a worker: :func:`run_check` with ``--json``."""
    from planners.commands import run_check

    disarm = _begin_task(options.get("timeout"))
    cpu = _cpu_clock()
    t0, c0 = time.monotonic(), cpu()
    try:
        code, text, err = _capture(lambda: run_check([Path(f) for f in files], as_json=True, **options))
    finally:
        disarm()
    return _result(code, text, err, t0, c0, cpu)


_SEVERITY = {0: 0, 1: 1, 3: 2, 2: 3}


class _Interrupted(BaseException):
    """SIGTERM (or SIGINT) reached the batch's main process, or its stdout went away: end the batch."""

    def __init__(self, why: str, code: int) -> None:
        super().__init__(why)
        self.why, self.code = why, code


def _emit(line: str) -> None:
    """One JSON line on stdout, at once; a closed or full stdout ends the batch (no traceback)."""
    try:
        print(line, flush=True)
    except (OSError, ValueError) as exc:
        raise _Interrupted(f"standard output failed ({getattr(exc, 'strerror', None) or exc})", 2) from None


def _say(text: str) -> None:
    try:
        print(text, file=sys.stderr, flush=True)
    except (OSError, ValueError):  # pragma: no cover - stderr closed: nowhere to say it
        pass


def _drive(jobs: list[tuple[Callable, tuple, dict[str, Any]]], workers: int | None, scheduler: str | None,
           hard_timeout: float | None, memory_mb: float | None, as_json: bool) -> tuple[list[dict[str, Any]], Any]:
    """Run every job; each result dict gets ``exit`` (a crash: 3) — JSON lines printed as they finish. Returns
    (one result per job, in input order, and the interruption or None). SIGTERM, SIGINT (to the main process
    alone, or Ctrl-C to the group: the workers leave it to the main process) and a failing stdout end the
    batch: the running tasks' workers are killed, every task not finished gets a record ``interrupted``."""
    import signal
    from concurrent.futures import as_completed

    from delkit.executors import executor

    results: list[dict[str, Any] | None] = [None] * len(jobs)
    bar = _progress(len(jobs)) if not as_json and sys.stderr.isatty() else None
    stop: _Interrupted | None = None

    def on_signal(signum, frame):  # noqa: ARG001 - signal handler signature
        raise _Interrupted(signal.Signals(signum).name, 128 + signum)

    import threading

    main = threading.current_thread() is threading.main_thread()
    previous = {s: signal.signal(s, on_signal) for s in (signal.SIGTERM, signal.SIGINT)} if main else {}
    def interrupted(exc: BaseException) -> _Interrupted:
        for s in previous:  # a second signal while the workers are being ended changes nothing
            signal.signal(s, signal.SIG_IGN)
        return exc if isinstance(exc, _Interrupted) else _Interrupted("SIGINT", 130)

    try:
        with executor(workers, scheduler, hard_timeout=hard_timeout, memory_mb=memory_mb) as ex:
            futures = {}
            try:
                futures = {ex.submit(fn, *args): (i, ident) for i, (fn, args, ident) in enumerate(jobs)}
                for fut in as_completed(futures):
                    i, ident = futures[fut]
                    try:
                        res = dict(fut.result())
                    except Exception as exc:  # noqa: BLE001 - a crash, a kill, a lost Dask worker: this task only
                        res = {"status": "crash", "reason": f"{type(exc).__name__}: {exc}", "exit": 3,
                               "cpu": getattr(fut, "cpu", None), "wall": None}
                    res = {**ident, **res}
                    results[i] = res
                    if res.get("status") in ("error", "crash") and res.get("reason"):  # bad input: stderr too
                        _say(f"delkit: error: {_name(res)}: {res['reason']}")
                    if as_json:
                        _emit(json.dumps(res))
                    if bar is not None:
                        bar(res)
            except (_Interrupted, KeyboardInterrupt) as exc:
                stop = interrupted(exc)
                if hasattr(ex, "terminate"):
                    ex.terminate(f"the batch was interrupted ({stop.why})")
                else:  # a Dask executor: what has not started is cancelled
                    for fut in futures:
                        fut.cancel()
    except (_Interrupted, KeyboardInterrupt) as exc:  # while the pool was being started or shut down
        stop = stop or interrupted(exc)
    finally:
        for s, h in previous.items():
            signal.signal(s, h)
        if bar is not None:
            bar(None)
    if stop is not None:
        for i, (_fn, _args, ident) in enumerate(jobs):
            if results[i] is None:
                results[i] = {**ident, "status": "interrupted", "reason": f"not finished: the batch was interrupted "
                                                                          f"({stop.why})", "exit": stop.code,
                              "cpu": None, "wall": None}
                if as_json and stop.code != 2:
                    try:
                        _emit(json.dumps(results[i]))
                    except _Interrupted:
                        stop = _Interrupted(stop.why, 2)
    return [r for r in results if r is not None], stop


def _progress(total: int) -> Callable[[dict | None], None]:
    """A rich progress bar on stderr; call it with each result, then with None to close it."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    prog = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                    TextColumn("{task.fields[last]}"), console=Console(stderr=True), transient=True)
    prog.start()
    tid = prog.add_task("tasks", total=total, last="")
    counts = {"solved": 0}

    def step(res: dict | None) -> None:
        if res is None:
            prog.stop()
            return
        counts["solved"] += res.get("exit") == 0
        prog.update(tid, advance=1, description=f"{counts['solved']} ok",
                    last=f"{Path(str(res.get('problem') or res.get('file'))).name}: {res.get('status')}")
    return step


def _worst(results: list[dict[str, Any]], stop: Any = None) -> int:
    if stop is not None:  # interrupted: 128 + the signal (130 SIGINT, 143 SIGTERM), 2 a failing stdout
        return int(stop.code)
    codes = [int(r.get("exit", 3)) for r in results] or [0]
    return max(codes, key=lambda c: _SEVERITY.get(c, 2))


def _stopped(stop: Any) -> str:
    return "" if stop is None else f" (interrupted: {stop.why})"


def _text(line: str) -> bool:
    """Print a line of the text report; False if stdout failed."""
    try:
        print(line, flush=True)
    except (OSError, ValueError):
        return False
    return True


def _report_summary(summ: dict[str, Any], stop: Any, as_json: bool) -> bool:
    """Print the JSON summary (with ``--json``); say on stderr that the batch was interrupted. False: stdout
    is gone (nothing more to print)."""
    if stop is not None:
        _say(f"delkit: batch interrupted ({stop.why}): {summ['by_status'].get('interrupted', 0)} of {summ['tasks']} "
             f"task(s) not finished, the workers were ended")
        if stop.code == 2:
            return False
    if as_json:
        return _text(json.dumps(summ))
    return True


def _summary(results: list[dict[str, Any]], wall: float, workers: str, stop: Any = None) -> dict[str, Any]:
    solved = [r for r in results if r.get("exit") == 0]
    by: dict[str, int] = {}
    for r in results:
        status = str(r.get("status") or ("valid" if r.get("valid") else "invalid" if "valid" in r else None))
        by[status] = by.get(status, 0) + 1
    cpu = sum(float(r.get("cpu") or 0.0) for r in results)
    return {"summary": True, "tasks": len(results), "ok": len(solved), "by_status": by,
            "task_cpu_s": round(cpu, 3), "wall_s": round(wall, 3), "workers": workers,
            "interrupted": None if stop is None else stop.why}


def _workers_label(jobs: int | None, scheduler: str | None) -> str:
    n = jobs or os.cpu_count() or 1
    return f"dask {scheduler}" if scheduler else f"{n} local process{'es' if n != 1 else ''}"


def _hard(timeout: float | None) -> float | None:
    """The pool's backstop: the task's own limit plus a grace (its run stops itself well before)."""
    if timeout is None or timeout <= 0:
        return None
    return timeout + max(5.0, 0.25 * timeout)


def _table(rows: list[list[str]], head: list[str]) -> None:
    w = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(head)]
    print("  ".join(h.ljust(w[i]) for i, h in enumerate(head)))
    for r in rows:
        print("  ".join(c.rjust(w[i]) if i else c.ljust(w[i]) for i, c in enumerate(r)))


def run_plan_batch(files: Sequence[Path], *, jobs: int | None = None, scheduler: str | None = None,
                   as_json: bool = False, timeout: float = 60.0, max_memory: float = 8192.0,
                   **options: Any) -> int:
    """``delkit plan FILE...`` (module docstring); returns the exit status."""
    t0 = time.monotonic()
    opts = {"timeout": timeout, "max_memory": max_memory, **options}
    units = plan_units(files)
    jobs_l = [(plan_one, (str(s), str(p) if p else None, opts), {"file": str(s), "problem": str(p) if p else None})
              for s, p in units]
    results, stop = _drive(jobs_l, jobs, scheduler, _hard(timeout), max_memory * 1.5 + 1024, as_json)
    summ = _summary(results, time.monotonic() - t0, _workers_label(jobs, scheduler), stop)
    summ["solved"] = sum(1 for r in results if r.get("status") == "solved")
    if not _report_summary(summ, stop, as_json):
        pass
    elif not as_json:
        rows = [[_name(r), str(r.get("status")), "" if r.get("length") is None else str(r["length"]),
                 str(r.get("expanded", "")), _num(r.get("cpu")), _num(r.get("wall"))] for r in results]
        _table(rows, ["task", "status", "length", "expanded", "cpu s", "wall s"])
        _text(f"{summ['solved']}/{summ['tasks']} solved; task CPU {summ['task_cpu_s']:.3f} s, wall "
              f"{summ['wall_s']:.3f} s on {summ['workers']}" + _stopped(stop))
    return _worst(results, stop)


def run_check_batch(files: Sequence[Path], *, jobs: int | None = None, scheduler: str | None = None,
                    as_json: bool = False, timeout: float = 60.0, **options: Any) -> int:
    """``delkit check`` over many ``SPEC [PROBLEM] PLAN_FILE`` groups; returns the exit status."""
    t0 = time.monotonic()
    opts = {"timeout": timeout, **options}
    jobs_l = [(check_one, ([str(f) for f in u], opts), {"files": [str(f) for f in u]}) for u in check_units(files)]
    results, stop = _drive(jobs_l, jobs, scheduler, _hard(timeout), None, as_json)
    summ = _summary(results, time.monotonic() - t0, _workers_label(jobs, scheduler), stop)
    summ["valid"] = sum(1 for r in results if r.get("valid") is True)
    if not _report_summary(summ, stop, as_json):
        pass
    elif not as_json:
        rows = [[" ".join(Path(f).name for f in r["files"]),
                 "valid" if r.get("valid") else str(r.get("status") or "invalid"),
                 str(r.get("reason") or "")[:60], _num(r.get("cpu"))] for r in results]
        _table(rows, ["files", "result", "reason", "cpu s"])
        _text(f"{summ['valid']}/{summ['tasks']} valid; task CPU {summ['task_cpu_s']:.3f} s, wall "
              f"{summ['wall_s']:.3f} s on {summ['workers']}" + _stopped(stop))
    return _worst(results, stop)


def _name(r: dict[str, Any]) -> str:
    """The task's name: its problem or spec file (a check group: its files)."""
    if r.get("files"):
        return " ".join(Path(str(f)).name for f in r["files"])
    return Path(str(r.get("problem") or r.get("file"))).name


def _num(x: Any) -> str:
    return "" if x is None else f"{float(x):.3f}"
