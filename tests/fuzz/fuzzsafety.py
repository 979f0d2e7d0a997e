"""Fuzz families for what a command does with the files, processes and limits around it.

* ``links`` — every output option given a path that is one of the command's inputs: the same path, another
  spelling of it (``./x``, ``d/../x``), a symbolic link, a hard link, a path through a symlinked folder; a
  fresh path as the control. Expected: exit 2 with one line and every input byte-for-byte unchanged (or, for
  the control, the answer).
* ``devices`` — every input position given a FIFO, ``/dev/zero``, ``/dev/null``, ``/dev/urandom``, a
  directory or a file over the input size cap. Expected: exit 2 with one line, at once (a blocked read is a
  hang).
* ``addresses`` — ``--scheduler`` and ``--jobs`` values (malformed, out of range, TLS, loopback ports where
  nothing listens — never an address outside 127.0.0.0/8 or ::1: nothing else is contacted) and the puzzle
  numbers that used to escape as tracebacks. Expected: exit 2 with one line (or an answer).
* ``batches`` — ``delkit plan`` / ``check`` batches run as a process (the console script): per-task
  ``--timeout``, good, bad, FIFO and slow tasks mixed, SIGTERM / SIGINT to the main process at a random
  moment, a closed stdout. Expected: a record per task and a summary (unless stdout is closed), the exit
  status of the worst task (128 + signal when interrupted), no traceback, no process left behind.
* ``limit-answers`` — single commands with ``--json --timeout T`` on work that cannot finish, run as a
  process. Expected: exit 3, one JSON object with ``status`` ``limit`` and the counters so far (a search
  stopped while searching has expanded > 0), within T + 0.5 s of process start (+ ``DELKIT_LIMIT_MARGIN``).

The process families run ``python -c 'from delkit.cli import run; run()'`` — the console script — with
``DELKIT_FUZZ_TAG`` set to a fresh value; after the process ends, any process still carrying that value in
its environment is a worker left behind (reported, then killed by its id).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

from hypothesis import strategies as st

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
SPECS = REPO / "specs"
COIN = SPECS / "coin_in_the_box"
SLOW_SEARCH = sorted((SPECS / "cc_2_4_4").glob("*.txt"))  # a search that expands ~100 nodes a second

#: extra seconds allowed past T + 0.5 s on a loaded machine (0 on an idle one, as for the limit tests)
MARGIN = float(os.environ.get("DELKIT_LIMIT_MARGIN", "0"))


def _case(*a, **k):
    from fuzzkit import Case

    return Case(*a, **k)


def _model_bytes() -> bytes:
    from delkit.io.formats import dumps
    from delkit.puzzles.muddy import muddy_model

    return (dumps(muddy_model(2, 1)) + "\n").encode()


def _world_bytes() -> bytes:
    from fuzzgen import epico_world

    return json.dumps(epico_world()).encode()


MAP = b"type octile\nheight 30\nwidth 30\nmap\n" + b"\n".join([b"." * 30] * 30) + b"\n"

# ----------------------------------------------------------------------------- links


def _link_target(draw, name: str) -> tuple[str, tuple]:
    """(the output path to give, the setup that makes it name ``name``'s file) for a random link kind."""
    kind = draw(st.sampled_from(["same", "dot", "dotdot", "symlink", "hardlink", "symdir", "symlink-chain", "fresh"]))
    if kind == "same":
        return "{d}/" + name, ()
    if kind == "dot":
        return "{d}/./" + name, ()
    if kind == "dotdot":
        return "{d}/sub/../" + name, (("sub", "dir", ""),)
    if kind == "symlink":
        return "{d}/ln_" + name, (("ln_" + name, "symlink", name),)
    if kind == "hardlink":
        return "{d}/hl_" + name, (("hl_" + name, "hardlink", name),)
    if kind == "symdir":
        return "{d}/via/" + name, (("via", "symlink", "."),)
    if kind == "symlink-chain":
        return "{d}/l2_" + name, (("l1_" + name, "symlink", name), ("l2_" + name, "symlink", "l1_" + name))
    return "{d}/fresh_out" + Path(name).suffix, ()


@st.composite
def link_cases(draw):
    which = draw(st.sampled_from(["trace-plan", "trace-domain", "trace-problem", "trace-props", "dot", "contract",
                                  "draw", "epico", "explore", "convert"]))
    coin = {"d.epddl": (COIN / "domain.epddl").read_bytes(), "p.epddl": (COIN / "problem.epddl").read_bytes(),
            "x.plan": (COIN / "problem.plan").read_bytes(), "x.props": b"eventually T\n"}
    if which.startswith("trace"):
        victim = {"trace-plan": "x.plan", "trace-domain": "d.epddl", "trace-problem": "p.epddl",
                  "trace-props": "x.props"}[which]
        out, links = _link_target(draw, victim)
        argv = ("check", "{d}/d.epddl", "{d}/p.epddl", "{d}/x.plan", "--trace-json", out,
                *(("--properties", "{d}/x.props") if victim == "x.props" or draw(st.booleans()) else ()),
                *(("--json",) if draw(st.booleans()) else ()))
        files = tuple(coin.items())
        label = "check --trace-json"
    elif which in ("dot", "contract", "draw"):
        victim = "m.json"
        out, links = _link_target(draw, victim)
        if which == "draw":
            suffix = draw(st.sampled_from([".svg", ".tex"]))
            links = tuple((n, k, t) for n, k, t in links)
            if out.endswith(".json"):
                # a picture name that is a link to the model: the link carries the picture's suffix
                base = out.rsplit("/", 1)[-1]
                out = out[: -len(".json")] + suffix
                links = tuple((n.replace(".json", suffix) if n == base else n, k, t) for n, k, t in links)
        files = (("m.json", _model_bytes()),)
        argv = ("model", which, "{d}/m.json", "-o", out)
        label = f"model {which} -o"
    elif which == "epico":
        victim = "w.json"
        out, links = _link_target(draw, victim)
        files = (("w.json", _world_bytes()),)
        argv = ("epico", "solve", "--goal", "alpha", "--colors", "1", "--world", "{d}/w.json", "--out", out, "--json")
        label = "epico solve --out"
    elif which == "explore":
        victim = "m.map"
        out, links = _link_target(draw, victim)
        out = out if not out.endswith("fresh_out.map") else "{d}/snap.png"
        files = (("m.map", MAP),)
        argv = ("explore", "run", "--map", "{d}/m.map", "--robots", "1", "--t-max", "5", "--method", "ideal",
                "--png", out, "--json")
        label = "explore run --png"
    else:
        files = (("spec.txt", (COIN / "pb1_twin.txt").read_bytes()),)
        links = ((("via", "symlink", "."),) if draw(st.booleans()) else ())
        folder = "{d}/via" if links else "{d}"
        argv = ("convert", "{d}/spec.txt", "--to", "mastar", "-o", folder, "--name", "spec")
        label = "convert -o"
    return _case(label, argv, files, oracle="inputs", budget=60.0, note="links", links=links)


# ----------------------------------------------------------------------------- devices


@st.composite
def device_cases(draw):
    kind = draw(st.sampled_from(["fifo", "/dev/zero", "/dev/null", "/dev/urandom", "dir", "big"]))
    setup: tuple = ()
    env: tuple = ()
    if kind == "fifo":
        bad, setup = "{d}/in.fifo", (("in.fifo", "fifo", ""),)
    elif kind == "dir":
        bad, setup = "{d}/folder", (("folder", "dir", ""),)
    elif kind == "big":
        bad, env = "{d}/big.txt", (("DELKIT_MAX_INPUT_MB", "0.001"),)
    else:
        bad = kind
    files = [("d.epddl", (COIN / "domain.epddl").read_bytes()), ("p.epddl", (COIN / "problem.epddl").read_bytes()),
             ("x.plan", (COIN / "problem.plan").read_bytes()), ("m.json", _model_bytes())]
    if kind == "big":
        files.append(("big.txt", b"; padding\n" * 400))
    where = draw(st.sampled_from([
        ("plan", [bad]), ("plan", ["{d}/d.epddl", bad]), ("plan", [bad, "{d}/p.epddl"]),
        ("plan", ["{d}/d.epddl", "{d}/p.epddl", "--library", bad]),
        ("check", ["{d}/d.epddl", "{d}/p.epddl", bad]), ("check", [bad, "{d}/p.epddl", "{d}/x.plan"]),
        ("check", ["{d}/d.epddl", "{d}/p.epddl", "{d}/x.plan", "--properties", bad]),
        ("model show", [bad]), ("model check", [bad, "p"]), ("model dot", [bad]), ("model contract", [bad]),
        ("model draw", [bad, "-o", "{d}/o.svg"]), ("model diff", ["{d}/m.json", bad]),
        ("model draw", ["{d}/d.epddl", "{d}/p.epddl", "--plan", bad, "-o", "{d}/o.svg"]),
        ("smcdel", [bad]), ("epico solve", ["--world", bad]), ("explore run", ["--map", bad, "--t-max", "5"]),
        ("convert", [bad, "-o", "{d}/conv"]), ("model macro", [bad, "{d}/m.json"]),
        ("plan batch", ["{d}/d.epddl", "{d}/p.epddl", bad, "--jobs", "1"]),
    ]))
    label, rest = where
    argv = tuple(label.replace(" batch", "").split()) + tuple(rest) + (("--json",) if draw(st.booleans()) else ())
    # a batch reports the bad task in its records (exit 2 overall) and goes on with the others
    oracle = None
    return _case(label, argv, tuple(files), oracle=oracle, budget=30.0, note=f"devices:{kind}", links=setup, env=env)


# ----------------------------------------------------------------------------- addresses and numbers

PORTS = ["1", "0", "65535", "65536", "99999999999999999999", "", "-1", "8786x", "+2", " 1"]


@st.composite
def address_cases(draw):
    kind = draw(st.sampled_from(["scheduler", "jobs", "numbers"]))
    spec = ["{d}/d.epddl", "{d}/p.epddl"]
    files = (("d.epddl", (COIN / "domain.epddl").read_bytes()), ("p.epddl", (COIN / "problem.epddl").read_bytes()),
             ("x.plan", (COIN / "problem.plan").read_bytes()))
    if kind == "scheduler":
        scheme = draw(st.sampled_from(["tcp://", "tls://", "", "inproc://", "ws://", "wss://", "TCP://", "tcp:/",
                                       "ucx://", "tcp://tcp://"]))
        host = draw(st.sampled_from(["127.0.0.1", "[::1]", "localhost", "", "127.0.0.1.", "[::1", "::1",
                                     "127.0.0.1:1", "x" * 300]))
        value = draw(st.sampled_from([f"{scheme}{host}:{draw(st.sampled_from(PORTS))}", "", " ", "tcp://",
                                      f"{scheme}{host}", "tcp://127.0.0.1:1/extra"]))
        cmd = draw(st.sampled_from(["plan", "check"]))
        argv = (cmd, *spec, *(["{d}/x.plan"] if cmd == "check" else []), "--scheduler", value,
                *(("--json",) if draw(st.booleans()) else ()))
        return _case(cmd, argv, files, budget=30.0, note="addresses:scheduler")
    if kind == "jobs":
        value = draw(st.sampled_from(["+2", "1000000000", "0", "-1", "0x2", "1e3", "2.0", " 2", "", "257", "1", "2",
                                      "99999999999999999999"]))
        cmd = draw(st.sampled_from(["plan", "check"]))
        spelling = draw(st.sampled_from([["--jobs", value], [f"--jobs={value}"], ["-j", value]]))
        argv = (cmd, *spec, *(["{d}/x.plan"] if cmd == "check" else []), *spelling, "--json")
        return _case(cmd, argv, files, oracle="json", budget=60.0, note="addresses:jobs")
    num = draw(st.sampled_from(["1000000000", "99999999999999999999", "-1", "0", "-99999999999999999999"]))
    argv = draw(st.sampled_from([
        ("puzzle", "number-triangle", "-n", num), ("puzzle", "number-triangle", "-n", num, "--explicit"),
        ("puzzle", "number-triangle", "-n", num, "--symbolic"), ("puzzle", "number-triangle", "-m", num),
        ("puzzle", "prisoners", "--seed", num), ("puzzle", "prisoners", "--days", num),
        ("puzzle", "prisoners", "-n", num), ("puzzle", "letter-passing", "-n", num),
        ("puzzle", "letter-passing", "--to", num), ("puzzle", "muddy", "-n", num),
    ]))
    return _case(" ".join(argv[:2]), (*argv, "--json"), budget=30.0, oracle="json", note="addresses:numbers")


# ----------------------------------------------------------------------------- process families

#: the task kinds a batch mixes: (files to write, the task's words on the command line)
def _slow_initial(d: Path) -> list[str]:
    from fuzzkit import many_free_fluents

    (d / "slow").mkdir(exist_ok=True)
    return many_free_fluents(d / "slow")


@st.composite
def batch_cases(draw):
    n = draw(st.integers(2, 8))
    kinds = [draw(st.sampled_from(["good", "good", "slow", "slow-search", "missing", "garbage", "fifo", "problem"]))
             for _ in range(n)]
    cmd = draw(st.sampled_from(["plan", "plan", "check"]))
    timeout = draw(st.sampled_from(["0.5", "1", "1.5", "2"]))
    jobs = draw(st.sampled_from(["1", "2", "3"]))
    sig = draw(st.sampled_from([None, None, "SIGTERM", "SIGINT"]))
    delay = draw(st.sampled_from([0.3, 0.8, 1.5, 2.5]))
    stdout = draw(st.sampled_from(["pipe", "pipe", "pipe", "closed"]))
    as_json = draw(st.booleans()) or stdout == "closed"
    spec = {"kinds": kinds, "cmd": cmd, "timeout": timeout, "jobs": jobs, "signal": sig, "delay": delay,
            "stdout": stdout, "json": as_json}
    return _case(f"{cmd} batch", (cmd,), budget=90.0, note="batches:" + json.dumps(spec), mode="process")


LIMIT_COMMANDS = ["plan-search", "plan-initial", "plan-astar", "check-initial", "prove", "sum-product", "muddy",
                  "epico", "smcdel", "plan-batch-limit"]


@st.composite
def limit_answer_cases(draw):
    which = draw(st.sampled_from(LIMIT_COMMANDS))
    t = draw(st.sampled_from(["0.5", "1", "1.5", "2"]))
    spelling = draw(st.sampled_from(["space", "equals"]))
    spec = {"which": which, "timeout": t, "spelling": spelling}
    return _case(f"limit {which}", (which,), budget=60.0, note="limit-answers:" + json.dumps(spec), mode="process")


FAMILIES = {
    "links": (link_cases, 10),
    "devices": (device_cases, 10),
    "addresses": (address_cases, 8),
    "batches": (batch_cases, 3),
    "limit-answers": (limit_answer_cases, 4),
}


# ----------------------------------------------------------------------------- running the process cases


def _tagged_pids(tag: str) -> list[int]:
    """Processes still alive whose environment carries ``DELKIT_FUZZ_TAG=tag`` (left behind by a case)."""
    needle = f"DELKIT_FUZZ_TAG={tag}".encode()
    out = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/environ", "rb") as fh:
                if needle in fh.read():
                    out.append(int(entry))
        except OSError:
            continue
    return out


def _run_process(argv: list[str], d: str, *, signal_at: tuple[float, str] | None = None, stdout: str = "pipe",
                 budget: float = 60.0) -> dict:
    """Run the console script on ``argv``; returns rc, out, err, wall (from just before the process is
    started), orphans (pids left behind, killed), hung (killed at the budget)."""
    tag = uuid.uuid4().hex
    env = {**os.environ, "PYTHONPATH": str(REPO), "DELKIT_FUZZ_TAG": tag, "DELKIT_PROGRESS": "0"}
    env.pop("DELKIT_MEMORY_BUDGET", None)
    cmd = [sys.executable, "-c", "from delkit.cli import run; run()", *argv]
    outf, errf = open(Path(d) / ".out", "w+b"), open(Path(d) / ".err", "w+b")  # noqa: SIM115
    hung = False
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=outf if stdout == "pipe" else None, stderr=errf, env=env, cwd=d,
                         preexec_fn=(lambda: os.close(1)) if stdout == "closed" else None)
    try:
        if signal_at is not None:
            try:
                p.wait(signal_at[0])
            except subprocess.TimeoutExpired:
                p.send_signal(getattr(signal, signal_at[1]))
        try:
            p.wait(budget)
        except subprocess.TimeoutExpired:
            hung = True
            p.kill()
            p.wait()
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    wall = time.monotonic() - t0
    # a worker killed at the parent's death (or multiprocessing's resource tracker, which leaves at the end of
    # its pipe) needs a moment to be gone: what is still there after 3 s is left behind
    deadline = time.monotonic() + 3.0
    orphans = _tagged_pids(tag)
    while orphans and time.monotonic() < deadline:
        time.sleep(0.1)
        orphans = _tagged_pids(tag)
    names = []
    for pid in orphans:
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as fh:
                names.append(fh.read().replace(b"\0", b" ").decode(errors="replace")[:120])
        except OSError:
            pass
    for pid in orphans:
        try:
            os.kill(pid, signal.SIGKILL)  # a process this case started (it carries the case's tag)
        except OSError:
            pass
    outf.seek(0)
    errf.seek(0)
    res = {"rc": p.returncode, "out": outf.read().decode(errors="replace"), "err": errf.read().decode(errors="replace"),
           "wall": wall, "orphans": orphans, "orphan_names": names, "hung": hung}
    outf.close()
    errf.close()
    return res


def _write_task(kind: str, i: int, d: Path, cmd: str) -> list[str]:
    """The command-line words of one task of a batch (its files written into ``d``)."""
    if kind == "good":
        return [str(COIN / "domain.epddl"), str(COIN / "problem.epddl")] + (
            [str(COIN / "problem.plan")] if cmd == "check" else [])
    if kind == "slow":
        words = _slow_initial(d)
        if cmd == "check":
            (d / "flip.plan").write_text("flip\n")
            words = [*words, str(d / "flip.plan")]
        return words
    if kind == "slow-search":
        if cmd == "check":  # a check of a long plan on the slow initial state
            words = _slow_initial(d)
            (d / "flip2.plan").write_text("flip\nflip\n")
            return [*words, str(d / "flip2.plan")]
        return [str(SLOW_SEARCH[i % len(SLOW_SEARCH)])]
    if kind == "missing":
        return [str(d / f"missing{i}.txt")] + ([str(d / f"missing{i}.plan")] if cmd == "check" else [])
    if kind == "garbage":
        (d / f"g{i}.txt").write_bytes(b"\x00\xffnot a spec (((\n")
        return [str(d / f"g{i}.txt")] + ([str(COIN / "problem.plan")] if cmd == "check" else [])
    if kind == "fifo":
        fifo = d / f"f{i}.fifo"
        if not fifo.exists():
            os.mkfifo(fifo)
        return [str(fifo)] + ([str(COIN / "problem.plan")] if cmd == "check" else [])
    # a lone problem (its domain missing)
    return [str(COIN / "problem.epddl")] + ([str(COIN / "problem.plan")] if cmd == "check" else [])


def _json_lines(text: str) -> list[dict]:
    out = []
    for ln in text.splitlines():
        ln = ln.strip()
        if ln.startswith("{"):
            try:
                out.append(json.loads(ln))
            except ValueError:
                out.append({"unparsable": ln[:100]})
    return out


def run_batch_case(case, d: str):
    """A batch under per-task limits and signals (see the module docstring); returns an Outcome."""
    from fuzzkit import Outcome

    spec = json.loads(case.note.split(":", 1)[1])
    dd = Path(d)
    cmd = spec["cmd"]
    words: list[str] = []
    for i, kind in enumerate(spec["kinds"]):
        words += _write_task(kind, i, dd, cmd)
    argv = [cmd, *words, "--timeout", spec["timeout"], "--jobs", spec["jobs"], *(["--json"] if spec["json"] else [])]
    # how many tasks the batch has: as the batch itself groups the files
    sys.path.insert(0, str(REPO))
    from planners.batch import check_units, plan_units

    n_tasks = len(plan_units([Path(w) for w in words]) if cmd == "plan" else check_units([Path(w) for w in words]))
    signal_at = (spec["delay"], spec["signal"]) if spec["signal"] else None
    r = _run_process(argv, d, signal_at=signal_at, stdout=spec["stdout"], budget=case.budget)
    detail = f"rc {r['rc']}, {r['wall']:.2f} s"
    if r["hung"]:
        return Outcome("hang", None, f"the batch did not end within {case.budget:g} s", r["wall"])
    if "Traceback (most recent call last)" in r["err"]:
        return Outcome("crash", r["rc"], "traceback: " + r["err"].strip().splitlines()[-1][:200], r["wall"])
    if r["orphans"]:
        return Outcome("wrong", r["rc"], f"{len(r['orphans'])} worker process(es) left behind: "
                       f"{r['orphan_names']}", r["wall"])
    interrupted = r["rc"] in (130, 143, -2, -15)
    if interrupted and spec["signal"] and not r["out"].strip():
        # the signal came before the batch had started anything (interpreter start-up, imports): the process
        # ended at once, by the signal's default action or as KeyboardInterrupt; no worker existed
        return Outcome("ok", r["rc"], f"ended before the batch began ({detail})", r["wall"])
    if spec["signal"] is None and interrupted:
        return Outcome("wrong", r["rc"], "interrupted without a signal", r["wall"])
    if spec["stdout"] == "closed":
        if r["rc"] not in (2, 130, 143):
            return Outcome("wrong", r["rc"], f"stdout closed: exit {r['rc']}, expected 2", r["wall"])
        return Outcome("error", r["rc"], detail, r["wall"])
    if spec["json"]:
        lines = _json_lines(r["out"])
        records = [x for x in lines if "summary" not in x]
        summary = [x for x in lines if x.get("summary")]
        if len(records) != n_tasks:
            return Outcome("wrong", r["rc"], f"lost records: {len(records)} of {n_tasks} tasks reported ({detail})",
                           r["wall"])
        if len(summary) != 1 or lines[-1] is not summary[0]:
            return Outcome("wrong", r["rc"], f"{len(summary)} summary line(s), not last ({detail})", r["wall"])
        if summary[0]["tasks"] != n_tasks:
            return Outcome("wrong", r["rc"], f"summary counts {summary[0]['tasks']} tasks of {n_tasks}", r["wall"])
        limit = float(spec["timeout"])
        for rec in records:
            if rec.get("status") == "limit":
                if rec.get("exit") != 3 or "expanded" not in rec and "seconds" not in rec:
                    return Outcome("wrong", r["rc"], f"a limit record without exit 3 / counters: {rec}", r["wall"])
                if rec.get("wall") is not None and rec["wall"] > limit + 0.5 + MARGIN:
                    return Outcome("late", r["rc"], f"a task's limit answer came {rec['wall'] - limit:.2f} s after "
                                   f"its --timeout {limit:g} (per task: T + 0.5 s), load "
                                   f"{os.getloadavg()[0]:.1f}", r["wall"])
        if interrupted and not summary[0].get("interrupted"):
            return Outcome("wrong", r["rc"], "interrupted but the summary does not say so", r["wall"])
        # a bad task's error is in its record and on stderr (one of them may have met its --timeout first,
        # e.g. while a fresh worker imports: then its record is a limit)
        errors = [x for x in records if x.get("status") == "error"]
        from planners.batch import _name

        missing = [x for x in errors if f"delkit: error: {_name(x)}: " not in r["err"]]
        if missing:
            return Outcome("wrong", r["rc"], f"{len(missing)} bad task error(s) not on stderr", r["wall"])
    if not interrupted and r["rc"] not in (0, 1, 2, 3):
        return Outcome("wrong", r["rc"], f"exit {r['rc']}", r["wall"])
    return Outcome("ok", r["rc"], detail, r["wall"])


def _limit_argv(which: str, t: str, d: Path, spelling: str) -> tuple[list[str], bool]:
    """(command line, whether a stop while searching must report expanded > 0)."""
    opt = [f"--timeout={t}"] if spelling == "equals" else ["--timeout", t]
    if which == "plan-search":
        return ["plan", str(SLOW_SEARCH[0]), "--json", *opt], True
    if which == "plan-astar":  # its heuristic's set-up may take the whole budget: expanded may be 0
        return ["plan", str(SLOW_SEARCH[-1]), "--search", "astar", "--json", *opt], False
    if which == "plan-initial":
        return ["plan", *_slow_initial(d), "--json", *opt], False
    if which == "check-initial":
        (d / "flip.plan").write_text("flip\n")
        return ["check", *_slow_initial(d), str(d / "flip.plan"), "--json", *opt], False
    if which == "prove":
        return ["prove", "C{a,b} p -> K_a K_b K_a p", "--worlds", "12", "--json", *opt], False
    if which == "sum-product":
        return ["puzzle", "sum-product", "--limit", "6000", "--json", *opt], False
    if which == "muddy":
        return ["puzzle", "muddy", "-n", "2000", "-m", "1000", "--symbolic", "--json", *opt], False
    if which == "epico":
        return ["epico", "solve", "--goal", "delta", "--colors", "4", "--sensing", "color", "--no-macros", "--json",
                *opt], False
    if which == "smcdel":
        n = 26
        (d / "big.smcdel.txt").write_text("VARS " + ",".join(str(i) for i in range(1, n + 1)) + "\nLAW Top\n"
                                          "OBS alice: 1\nbob: 2\n" + "VALID? alice knows whether 1\n" * 3000)
        return ["smcdel", str(d / "big.smcdel.txt"), "--json", *opt], False
    # a batch of slow searches: each task's record is a limit answer with its own counters
    return ["plan", *[str(p) for p in SLOW_SEARCH], "--jobs", "2", "--json", *opt], True


def run_limit_case(case, d: str):
    """One limit answer (see the module docstring); returns an Outcome."""
    from fuzzkit import Outcome

    spec = json.loads(case.note.split(":", 1)[1])
    argv, searching = _limit_argv(spec["which"], spec["timeout"], Path(d), spec["spelling"])
    limit = float(spec["timeout"])
    r = _run_process(argv, d, budget=case.budget)
    late = r["wall"] - limit
    detail = f"exit {r['rc']}, {r['wall']:.2f} s (T + {late:.2f} s)"
    if r["hung"]:
        return Outcome("hang", None, f"no answer within {case.budget:g} s", r["wall"])
    if "Traceback (most recent call last)" in r["err"]:
        return Outcome("crash", r["rc"], "traceback: " + r["err"].strip().splitlines()[-1][:200], r["wall"])
    if r["orphans"]:
        return Outcome("wrong", r["rc"], f"{len(r['orphans'])} process(es) left behind", r["wall"])
    batch = spec["which"] == "plan-batch-limit"
    if r["rc"] != 3:
        return Outcome("wrong", r["rc"], f"a limit answer with exit {r['rc']}, not 3 ({detail})", r["wall"])
    lines = _json_lines(r["out"])
    answers = [x for x in lines if not x.get("summary")]
    if not answers or any("unparsable" in x for x in lines) or (not batch and len(lines) != 1):
        return Outcome("wrong", r["rc"], f"--json limit answer is not one JSON object: {r['out'][:200]!r}", r["wall"])
    for rec in answers:
        if rec.get("status") != "limit":
            return Outcome("wrong", r["rc"], f"JSON status {rec.get('status')!r}, not 'limit'", r["wall"])
        # the search ran for at least T - 1 s (start-up takes < 1 s): it has expanded something by then
        if searching and limit >= 1.5 and "while searching" in str(rec.get("reason")) and not rec.get("expanded"):
            return Outcome("wrong", r["rc"], f"stopped while searching but expanded = {rec.get('expanded')}",
                           r["wall"])
        if spec["which"].startswith("plan") and "expanded" not in rec:
            return Outcome("wrong", r["rc"], "a plan limit answer without counters", r["wall"])
    # a batch: each task's T counts from its own start in its worker: its record's wall, not the batch's
    late = max((float(x.get("wall") or 0) for x in answers), default=0.0) if batch else r["wall"]
    if late > limit + 0.5 + MARGIN:
        return Outcome("late", r["rc"], f"{detail}; the bound is T + 0.5 s"
                       + (f" + {MARGIN:g} s margin" if MARGIN else "") + f", load {os.getloadavg()[0]:.1f}",
                       r["wall"])
    return Outcome("ok", r["rc"], detail, r["wall"])


def run_process_case(case, d: str):
    fam = case.note.split(":", 1)[0]
    return run_batch_case(case, d) if fam == "batches" else run_limit_case(case, d)
