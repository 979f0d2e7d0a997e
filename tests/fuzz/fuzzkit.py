"""The fuzz harness: run any ``delkit`` command on generated input and classify what happened.

Every input is a :class:`Case` — a command line (``{d}`` stands for a scratch directory) and the files it
names. A long-lived *worker process* (forked, with an address-space limit so that a runaway allocation
fails instead of swapping the machine) runs ``delkit.cli.main(argv)`` in-process under a per-input
alarm and sends back an :class:`Outcome`:

* ``error``   — exit 2 and exactly one ``delkit: error:`` line on stderr, no traceback (the promised answer
  to bad input);
* ``ok``      — an answer (exit 0, or the command's documented negative status 1/3) that its oracle accepts;
* ``crash``   — an exception escaped ``main`` (a traceback), or exit 2 without the one-line error;
* ``limit``   — MemoryError under the address-space limit: something was allocated beyond any budget;
* ``hang``    — the per-input time budget ran out (alarm in the worker, or an answer after the budget when the
  alarm was lost in native code; the worker is killed and replaced
  if even the alarm does not come back);
* ``wrong``   — an answer the oracle rejects (a plan that ``delkit check`` refuses, a model round trip
  that is not bisimilar to the input, a truth value that the contracted model contradicts, ...).

The generators (hypothesis strategies) live in :mod:`fuzzgen`; this module knows nothing about them.
"""

from __future__ import annotations

import contextlib
import io
import json
import multiprocessing as mp
import os
import resource
import shutil
import signal
import tempfile
import time
import traceback
from collections import Counter, defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: ``late``: a limit answer that is right but came more than 0.5 s after T (a timing figure of the machine's
#: load as much as of the code: counted and reported, not a bad outcome)
KINDS = ("error", "ok", "late", "crash", "limit", "hang", "wrong")
#: exit statuses that are answers (not bad input) per command: everything else must be exit 2 + one line
ANSWER_STATUS = {0, 1, 3}


@dataclass(frozen=True)
class Case:
    """One fuzz input: ``command`` is the label counts are kept under (e.g. ``plan``, ``model check``)."""

    command: str
    argv: tuple[str, ...]
    files: tuple[tuple[str, bytes], ...] = ()
    oracle: str | None = None
    budget: float = 20.0
    note: str = ""
    #: made after ``files``: (name, kind, target) with kind symlink / hardlink (to ``target``, relative to the
    #: scratch directory), fifo or dir
    links: tuple[tuple[str, str, str], ...] = ()
    #: environment variables set while the case runs
    env: tuple[tuple[str, str], ...] = ()
    #: "inprocess" (``main(argv)`` in the worker) or "process" (the console script, run by
    #: :func:`fuzzsafety.run_process_case`); "call": ``argv[0]`` is ``module:function``, called with the case
    #: and the scratch directory, returning an :class:`Outcome` (families from other modules, e.g. HTTP)
    mode: str = "inprocess"

    def describe(self) -> str:
        return f"{self.command}: delkit {' '.join(self.argv)}" + (f"  [{self.note}]" if self.note else "")


@dataclass
class Outcome:
    kind: str
    status: int | None = None
    detail: str = ""
    seconds: float = 0.0
    case: Case | None = field(default=None, repr=False)


class _Hang(BaseException):
    """Raised by the alarm inside the worker (a BaseException so that no ``except Exception`` swallows it)."""


def _on_alarm(signum, frame):  # noqa: ARG001 - signal handler signature
    raise _Hang()


def _materialise(case: Case, d: str) -> list[str]:
    for name, data in case.files:
        p = Path(d) / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(data)
    for name, kind, target in case.links:
        p = Path(d) / name
        if kind == "symlink":
            p.symlink_to(target)
        elif kind == "hardlink":
            os.link(Path(d) / target, p)
        elif kind == "fifo":
            os.mkfifo(p)
        elif kind == "dir":
            p.mkdir(parents=True, exist_ok=True)
    return [a.replace("{d}", d) for a in case.argv]


def _call(argv: list[str]) -> tuple[int | None, str, str, BaseException | None, str]:
    """Run ``main(argv)`` capturing stdout/stderr; returns (status, out, err, escaped exception, traceback)."""
    from delkit.cli import main

    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            rc = main(argv)
    except _Hang:
        raise
    except SystemExit as exc:  # main must return a status, never exit
        return None, out.getvalue(), err.getvalue(), exc, "SystemExit escaped main"
    except BaseException as exc:  # noqa: BLE001 - this is what the harness looks for
        if _from_hang(exc):
            raise _Hang() from exc
        return None, out.getvalue(), err.getvalue(), exc, traceback.format_exc()
    return rc, out.getvalue(), err.getvalue(), None, ""


def _from_hang(exc: BaseException) -> bool:
    """Whether ``exc`` is the harness's own alarm in disguise: raised inside a ctypes call (z3's wrappers),
    :class:`_Hang` comes back as ``ctypes.ArgumentError("argument 1: _Hang: ")``, or another exception was
    raised while handling it."""
    seen = 0
    while exc is not None and seen < 20:
        if isinstance(exc, _Hang) or (type(exc).__name__ == "ArgumentError" and ": _Hang:" in f": {exc}"):
            return True
        exc, seen = exc.__cause__ or exc.__context__, seen + 1
    return False


def classify_error_text(err: str, batch: bool = False) -> str | None:
    """None if stderr is a clean one-line error (``batch``: one line per bad task, at least one), else what is
    wrong with it."""
    if "Traceback (most recent call last)" in err:
        return "traceback on stderr"
    lines = [ln for ln in err.splitlines() if ln.startswith("delkit: error:")]
    if batch and lines:
        return None
    if len(lines) != 1:
        return f"{len(lines)} 'delkit: error:' lines on stderr: {err.strip()[:200]!r}"
    return None


def run_case(case: Case) -> Outcome:
    """Run one case in the current process (the worker), with the alarm already armed by the caller."""
    d = tempfile.mkdtemp(prefix="delkit-fuzz-")
    saved = {k: os.environ.get(k) for k, _ in case.env}
    try:
        argv = _materialise(case, d)
        if case.mode != "inprocess":
            try:
                if case.mode == "process":
                    from fuzzsafety import run_process_case

                    return run_process_case(case, d)
                import importlib

                module, _, fn = case.argv[0].partition(":")
                return getattr(importlib.import_module(module), fn)(case, d)
            except _Hang:
                return Outcome("hang", None, f"no answer within {case.budget:g} s")
        os.environ.update(dict(case.env))
        t0 = time.perf_counter()
        try:
            rc, out, err, exc, tb = _call(argv)
        except _Hang:
            return Outcome("hang", None, f"no answer within {case.budget:g} s", time.perf_counter() - t0)
        secs = time.perf_counter() - t0
        if secs > case.budget:
            # the budget ran out but the alarm was lost: its handler runs only between bytecodes, so it fires after
            # a long native call returns, and raised inside a ctypes callback (z3's) it is printed and swallowed
            return Outcome("hang", rc, f"no answer within {case.budget:g} s (answered after {secs:.1f} s; the "
                           "alarm was lost in native code)", secs)
        if exc is not None:
            if isinstance(exc, MemoryError):
                return Outcome("limit", None, f"MemoryError: {str(exc)[:200]}", secs)
            last = tb.strip().splitlines()[-1] if tb.strip() else repr(exc)
            where = [ln.strip() for ln in tb.splitlines() if ln.strip().startswith("File ")][-1:]
            return Outcome("crash", None, f"{last[:240]} @ {where[0][:200] if where else '?'}", secs)
        if rc == 2:
            from delkit.resources import _batch_line

            bad = classify_error_text(err, batch=_batch_line(argv))
            return Outcome("crash" if bad else "error", rc, bad or err.strip()[:240], secs)
        if rc not in ANSWER_STATUS:
            return Outcome("crash", rc, f"unexpected exit status {rc}; stderr {err.strip()[:200]!r}", secs)
        if "Traceback (most recent call last)" in err:
            return Outcome("crash", rc, "traceback on stderr of an answer", secs)
        lost = _inputs_changed(case, d)
        if lost:
            return Outcome("wrong", rc, lost, secs)
        if rc == 3 and not out.strip():  # a limit reached (exit 3, every command): one clean line on stderr
            bad = classify_error_text(err)
            return Outcome("crash" if bad else "ok", rc, bad or err.strip()[:240], secs)
        if case.oracle:
            try:
                why = ORACLES[case.oracle](case, argv, rc, out, d)
            except _Hang:
                return Outcome("hang", rc, f"the oracle of {case.oracle} ran out of time", secs)
            except Exception as exc:  # noqa: BLE001 - an oracle that cannot even read the answer rejects it
                why = f"oracle {case.oracle} failed on the answer: {type(exc).__name__}: {str(exc)[:200]}"
            if why:
                return Outcome("wrong", rc, why, secs)
        return Outcome("ok", rc, "", secs)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        shutil.rmtree(d, ignore_errors=True)


# ----------------------------------------------------------------------------- oracles

def _oracle_plan(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """A plan found by ``delkit plan`` must validate under ``delkit check`` (exit 0)."""
    if rc != 0:
        return ""
    res = json.loads(out)
    if res.get("status") != "solved" or not isinstance(res.get("plan"), list):
        return f"exit 0 but the JSON says {res.get('status')!r}"
    libs = [argv[i + 1] for i in range(1, len(argv) - 1) if argv[i] in ("--library", "-l")]
    specs = [a for a in argv[1:] if not a.startswith("-") and Path(a).suffix in (".epddl", ".txt", ".pddl")
             and Path(a).exists() and a not in libs]
    plan_file = Path(d) / "found.plan"
    plan_file.write_text("\n".join(res["plan"]) + "\n")
    lib_args = [x for lib in libs for x in ("--library", lib)]
    rc2, out2, err2, exc, _ = _call(["check", *specs, str(plan_file), *lib_args, "--json"])
    if rc2 != 0:
        return f"delkit check rejects the plan {res['plan']} (exit {rc2}): {(out2 or err2).strip()[:200]}"
    return ""


def _load_input_model(argv: list[str]):
    from delkit.io.formats import load

    return load([a for a in argv if Path(a).suffix in (".json", ".dot")][0])


def _bisimilar(a, b) -> bool:
    from delkit.models.bisimulation import canonical_form

    return canonical_form(a, exact=True) == canonical_form(b, exact=True)


def _oracle_model_roundtrip(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """``model dot`` / ``model contract`` output, read back, is bisimilar (event models: equal) to the input."""
    from delkit.io.formats import from_dot, loads, to_dict
    from delkit.models.kripke import KripkeModel

    src = _load_input_model(argv)
    back = from_dot(out) if argv[1] == "dot" else loads(out)
    if isinstance(src, KripkeModel):
        if not src.designated:
            return ""
        return "" if _bisimilar(src, back) else "the model read back is not bisimilar to the input"
    return "" if json.dumps(to_dict(src), sort_keys=True) == json.dumps(to_dict(back), sort_keys=True) else \
        "the event model read back differs from the input"


def _oracle_model_check(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """The truth value must be the same on the bisimulation contraction of the model."""
    from delkit.logic.formula import parse
    from delkit.models.bisimulation import contract

    m = _load_input_model(argv)
    formula = argv[3]
    if any(a.startswith("--event") or a == "-e" for a in argv):
        return ""  # formulas with event models: the events are checked by their own reader
    holds = contract(m).holds(parse(formula))
    if holds != (rc == 0):
        return f"model check says {'holds' if rc == 0 else 'fails'}, the contracted model says {holds}"
    return ""


def _oracle_model_check_event(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """[E,e]φ: the truth value must equal that of φ on the product update (contracted), computed directly."""
    from delkit.io.formats import load_event_model
    from delkit.logic.formula import Update, parse
    from delkit.models.bisimulation import contract
    from delkit.models.update import product_update

    m = _load_input_model(argv)
    em = load_event_model(str(Path(d) / "e.json"))
    f = parse(argv[3], events={"E": em})
    if not isinstance(f, Update):
        return ""
    new, pairs = product_update(m, em, return_pairs=True)
    # [E,e]φ holds at the designated worlds iff φ holds at (w, e) for every designated w where pre(e) holds
    holds = True
    for w in m.designated:
        hit = [i for i, (v, e) in enumerate(pairs.tolist()) if v == w and e == f.event]
        if hit:
            holds = holds and contract(new.with_designated(hit)).holds(f.arg)
    if holds != (rc == 0):
        return f"model check says {'holds' if rc == 0 else 'fails'}, the product update says {holds}"
    return ""


def _oracle_model_diff(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """``model diff``: a bisimulation must be one (same verdict as ``delkit.models.bisimulation``); a distinguishing
    formula
    must hold in the side it names and fail in the other, as the model checker says."""
    from delkit.io.formats import load
    from delkit.logic.formula import parse as parse_formula
    from delkit.models.bisimulation import bisimilar

    res = json.loads(out)
    a, b = (load(Path(d) / n) for n in ("a.json", "b.json"))
    if res["bisimilar"] != bisimilar(a, b):
        return f"model diff says bisimilar={res['bisimilar']}, delkit.models.bisimulation says the opposite"
    if res["bisimilar"]:
        return ""
    f = parse_formula(res["formula"])
    yes, no = (a, b) if res["true_in"] == "A" else (b, a)
    if not yes.holds(f) or no.holds(f):
        return f"the distinguishing formula {res['formula']} does not separate the models"
    return ""


def _oracle_prove(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """A counter-model printed by ``prove --json`` must falsify the formula at its world 0."""
    if rc != 1 or "--json" not in argv:
        return ""
    from delkit.io.formats import from_dict
    from delkit.logic.formula import parse

    res = json.loads(out)
    cm = res.get("counter_model")
    if cm is None:
        return "exit 1 (not valid) without a counter-model"
    m = from_dict(cm)
    f = parse(argv[1])
    if m.check(f)[0]:
        return "the counter-model satisfies the formula at world 0"
    return ""


def _oracle_json(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """An answer printed with --json is one JSON object with finite numbers."""
    if "--json" not in argv:
        return ""
    obj = json.loads(out.strip().splitlines()[-1] if out.strip() else "null")
    if not isinstance(obj, dict):
        return "--json did not print one JSON object"
    bad = [t for t in ("NaN", "Infinity") if t in out]
    return f"--json output contains {bad[0]} (not JSON)" if bad else ""


def _oracle_arms(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """A plan the arms executed must be valid on paper (symbolic replay against its world)."""
    from arms.plan import load_plan, symbolic_trace

    plan = [a for a in argv if a.endswith(".json")]
    if plan:
        symbolic_trace(load_plan(plan[0]))
    return _oracle_json(case, argv, rc, out, d)


def _oracle_inputs(case: Case, argv: list[str], rc: int, out: str, d: str) -> str:
    """Outputs never clobber inputs: every input file still holds its bytes (checked for every case too)."""
    return _inputs_changed(case, d)


def _inputs_changed(case: Case, d: str) -> str:
    if "--force" in case.argv:
        return ""
    for name, data in case.files:
        p = Path(d) / name
        if not p.exists() or p.read_bytes() != data:
            return f"the input file {name} was {'deleted' if not p.exists() else 'overwritten'}"
    return ""


ORACLES = {
    "inputs": _oracle_inputs,
    "plan": _oracle_plan,
    "model-diff": _oracle_model_diff,
    "model-roundtrip": _oracle_model_roundtrip,
    "model-check": _oracle_model_check,
    "model-check-event": _oracle_model_check_event,
    "prove": _oracle_prove,
    "json": _oracle_json,
    "arms": _oracle_arms,
}


# ----------------------------------------------------------------------------- the worker

def _worker(conn, mem_mb: int) -> None:
    soft = mem_mb * 1024 * 1024
    with contextlib.suppress(ValueError, OSError):
        resource.setrlimit(resource.RLIMIT_AS, (soft, resource.getrlimit(resource.RLIMIT_AS)[1]))
    os.environ.setdefault("MPLBACKEND", "Agg")
    signal.signal(signal.SIGALRM, _on_alarm)
    while True:
        try:
            case = conn.recv()
        except EOFError:
            return
        if case is None:
            return
        signal.setitimer(signal.ITIMER_REAL, case.budget)
        try:
            outcome = run_case(case)
        except _Hang:
            outcome = Outcome("hang", None, f"no answer within {case.budget:g} s")
        except BaseException as exc:  # noqa: BLE001 - report, keep serving
            outcome = Outcome("crash", None, f"harness: {type(exc).__name__}: {str(exc)[:200]}")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        conn.send(outcome)


class Runner:
    """Runs cases in a forked worker (memory-limited, alarmed); replaces the worker after a hard hang/death."""

    def __init__(self, mem_mb: int = 3072, grace: float = 15.0) -> None:
        self.mem_mb = mem_mb
        self.grace = grace
        self._proc = None
        self._conn = None

    def _start(self) -> None:
        ctx = mp.get_context("fork")
        parent, child = ctx.Pipe()
        # not a daemon: commands such as ``explore sweep`` start their own worker processes
        self._proc = ctx.Process(target=_worker, args=(child, self.mem_mb), daemon=False)
        self._proc.start()
        child.close()
        self._conn = parent

    def _kill(self) -> None:
        if self._proc is not None and self._proc.is_alive():
            os.kill(self._proc.pid, signal.SIGKILL)  # the worker this runner started, by its id
        if self._proc is not None:
            self._proc.join(5)
        self._proc = self._conn = None

    def run(self, case: Case) -> Outcome:
        if self._proc is None or not self._proc.is_alive():
            self._start()
        t0 = time.perf_counter()
        try:
            self._conn.send(case)
            if self._conn.poll(case.budget + self.grace):
                outcome = self._conn.recv()
            else:
                self._kill()
                outcome = Outcome("hang", None, f"worker unresponsive after {case.budget + self.grace:g} s")
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            code = self._proc.exitcode if self._proc is not None else None
            self._kill()
            outcome = Outcome("crash", None, f"the worker process died (exit code {code})")
        outcome.seconds = outcome.seconds or time.perf_counter() - t0
        outcome.case = case
        return outcome

    def close(self) -> None:
        if self._conn is not None:
            with contextlib.suppress(Exception):
                self._conn.send(None)
        if self._proc is not None:
            self._proc.join(5)
        self._kill()

    def __enter__(self) -> Runner:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


# ----------------------------------------------------------------------------- tallies

class Tally:
    """Counts per command and kind; keeps the cases of every bad outcome."""

    BAD = ("crash", "limit", "hang", "wrong")

    def __init__(self) -> None:
        self.counts: dict[str, Counter] = defaultdict(Counter)
        self.bad: list[Outcome] = []
        self.seconds = 0.0

    def add(self, o: Outcome) -> None:
        assert o.case is not None
        self.counts[o.case.command][o.kind] += 1
        self.seconds += o.seconds
        if o.kind in self.BAD:
            self.bad.append(o)

    @property
    def total(self) -> int:
        return sum(sum(c.values()) for c in self.counts.values())

    def table(self) -> str:
        rows = ["| command | inputs | " + " | ".join(KINDS) + " |", "|---|---:|" + "---:|" * len(KINDS)]
        tot: Counter = Counter()
        for cmd in sorted(self.counts):
            c = self.counts[cmd]
            tot.update(c)
            rows.append(f"| {cmd} | {sum(c.values())} | " + " | ".join(str(c[k]) for k in KINDS) + " |")
        rows.append(f"| **total** | **{sum(tot.values())}** | " + " | ".join(f"**{tot[k]}**" for k in KINDS) + " |")
        return "\n".join(rows)

    def report_bad(self, limit: int = 50) -> str:
        return "\n".join(f"- {o.kind}: {o.case.describe()[:300]} -> {o.detail}" for o in self.bad[:limit])


def many_free_fluents(tmp_path: Path, n: int = 22) -> list[str]:
    """An E-PDDL task with no common knowledge about f1..f{n-1}: its initial state has 2^(n-1) worlds, built
    before the search (slow to build for large n: the limit tests' task for the phases before the search)."""
    preds = " ".join(f"(f{i})" for i in range(n))
    (tmp_path / "d.epddl").write_text(f"(define (domain many) (:predicates {preds})\n"
                                      "  (:action flip :parameters () :precondition (f0) :effect (f1) "
                                      ":observers ()))")
    (tmp_path / "p.epddl").write_text("(define (problem many1) (:domain many) (:agents a b)\n"
                                      "  (:init (f0)) (:goal ([a](f1))))")
    return [str(tmp_path / "d.epddl"), str(tmp_path / "p.epddl")]
