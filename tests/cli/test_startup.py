"""Start-up: ``delkit plan``/``check`` run without typer, scipy or lark; the fast argument path answers
exactly as typer does; the lark parser cache is safe; the lazy imports keep their behaviour."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import delkit.cli as cli
from delkit.testing import formulas
from planners.cli.plan_cmd import fast_args
from planners.demo import specs_dir
from planners.lang import shared_benchmarks

ROOT = Path(__file__).resolve().parents[2]
COIN = specs_dir() / "coin_in_the_box"
DOM, PROB, PLAN, PROPS = (str(COIN / f) for f in ("domain.epddl", "problem.epddl", "problem.plan", "problem.props"))
BENCH = shared_benchmarks()
CB2 = str(BENCH / "mastar" / "CB_simple" / "CB_simple__pl_2.txt") if BENCH else None


def _norm(text: str) -> str:
    """Timings differ from run to run: blank them out."""
    text = re.sub(r'"(seconds|cpu|wall|task_cpu_s|wall_s)": [0-9.e-]+', r'"\1": T', text)
    text = re.sub(r"[0-9]+\.[0-9]+ s\b", "T s", text)
    return re.sub(r"\b[0-9]+\.[0-9]{3}\b", "T", text)  # a batch's table


def _both(capsys, monkeypatch, argv: list[str]) -> tuple[tuple[int, str, str], tuple[int, str, str]]:
    out = []
    for fast in (True, False):
        monkeypatch.setattr(cli, "FAST_PATH", fast)
        rc = cli.main(list(argv))
        cap = capsys.readouterr()
        out.append((rc, _norm(cap.out), _norm(cap.err)))
    return out[0], out[1]


LINES = [
    ["plan", DOM, PROB],
    ["plan", DOM, PROB, "--json"],
    ["plan", "--json", DOM, PROB, "--search", "astar"],
    ["plan", DOM, PROB, "--search=gbfs", "--timeout", "30", "--max-memory", "4096.5"],
    ["plan", DOM, str(COIN / "common.epddl"), "--max-nodes", "2"],        # limit: exit 3
    ["plan", DOM, PROB, "--search", "dfs"],                               # bad value: exit 2
    ["plan", DOM, PROB, "--engine", "del", "--allow-inconsistent"],
    ["plan", DOM, PROB, "--timeout", "-1"],                               # typer's path (value starts with -)
    ["plan", DOM, PROB, "--timeout", "soon"],                             # typer's usage error
    ["plan", DOM, PROB, "--nodes", "3"],                                  # unknown option
    ["plan"],                                                             # missing argument
    ["plan", DOM, PROB, "extra"],                                         # a batch: one task, one bad file
    ["plan", "/nonexistent/spec.txt"],                                    # unreadable file: exit 2
    ["plan", DOM, PROB, "--json", "--json"],
    ["plan", DOM, PROB, str(COIN / "common.epddl"), "--jobs", "1", "--json"],   # a batch of two tasks
    ["plan", DOM, PROB, "--jobs", "0"],                                   # bad --jobs: exit 2
    ["plan", DOM, PROB, "--timeout", "5", "--timeout", "6"],
    ["check", DOM, PROB, PLAN],
    ["check", DOM, PROB, PLAN, "--json", "--properties", PROPS, "-p", "eventually K_b tail"],
    ["check", DOM, PROB, PLAN, "--property", "always ~opened", "-p=at end opened"],
    ["check", DOM, PROB, PLAN, "-p", "sometimes p"],                       # bad property: exit 2
    ["check", DOM, PROB],                                                  # wrong number of files
    ["check", DOM, PROB, PLAN, "--properties", "/nonexistent/props"],
    ["check"],
]


@pytest.mark.parametrize("argv", LINES, ids=lambda a: " ".join(Path(x).name if "/" in x else x for x in a))
def test_fast_path_answers_as_typer_does(capsys, monkeypatch, argv: list[str]) -> None:
    fast, slow = _both(capsys, monkeypatch, argv)
    assert fast == slow


def test_fast_path_only_takes_plain_lines() -> None:
    assert fast_args(["plan", DOM, PROB, "--json"]) is not None
    assert fast_args(["check", DOM, PROB, PLAN, "-p", "at end opened"]) is not None
    assert fast_args(["plan", DOM, PROB, PLAN]) is not None            # a batch (a domain, two problems)
    for argv in (["plan", "--help"], ["plan", DOM, "--help"], ["check", "-h"], ["plan", DOM, "--", PROB],
                 ["plan", DOM, "--timeout", "1e3"], ["plan", DOM, "--max-nodes", "2.5"], ["plan", DOM, "--json=1"],
                 ["plan", DOM, "--timeout"], ["plan"], ["check"], ["model", "show", DOM],
                 ["plan", DOM, "-x"], ["check", DOM, "-pX"], ["check", DOM, "-p=x"], ["plan", ""],
                 ["check", DOM, "-p", ""], []):
        assert fast_args(argv) is None, argv


def _modules_after(argv: list[str], ok: tuple[int, ...] = (0,)) -> set[str]:
    code = ("import sys; from delkit.cli import main; rc = main(sys.argv[1:]); "
            "print('MODULES', ' '.join(sorted(sys.modules)), file=sys.stderr); sys.exit(rc)")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, env=env, check=False)
    line = [ln for ln in proc.stderr.splitlines() if ln.startswith("MODULES ")]
    assert proc.returncode in ok and line, proc.stderr
    return {m.split(".")[0] for m in line[0].split()[1:]}


HEAVY = {"typer", "click", "rich", "pydantic", "scipy", "z3", "dd", "matplotlib", "mujoco", "lark"}
# a small task is planned on the compact backend with integers and bit operations: numpy is not loaded
SMALL_PLAN_HEAVY = HEAVY | {"numpy", "networkx"}


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_plan_small_tasks_never_imports_numpy() -> None:
    plank = BENCH / "epddl2026" / "plank"
    lines = [["plan", CB2], ["plan", CB2, "--json"], ["plan", CB2, "--search", "astar"],
             ["plan", str(BENCH / "mastar" / "Coin_In_The_Box" / "Coin_in_the_Box__pl_3.txt")],
             ["plan", str(BENCH / "mastar" / "Grapevine" / "Grapevine_3" / "Grapevine_3__pl_2.txt"),
              "--search", "gbfs"],
             ["plan", DOM, PROB],
             ["plan", str(plank / "domains" / "Coin-in-the-Box" / "cb.epddl"),
              str(plank / "domains" / "Coin-in-the-Box" / "instances" / "problem_2.epddl"),
              "-l", str(plank / "libraries" / "intermediate.epddl")]]
    for argv in lines:
        # nor the dataclasses machinery (inspect, ast, ...) nor typing: hand-written records (delkit._records)
        assert not _modules_after(argv) & (SMALL_PLAN_HEAVY | {"dataclasses", "inspect", "typing", "signal"}), argv


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_plan_and_check_import_nothing_heavy(tmp_path) -> None:
    plan_file = tmp_path / "cb2.plan"
    plan_file.write_text("peek_up_key_a\nopen_a\n")
    assert not _modules_after(["plan", CB2]) & HEAVY
    assert not _modules_after(["check", CB2, str(plan_file)]) & HEAVY
    # oblivious agents (relations built from pairs) and E-PDDL input: still no scipy
    coin = str(BENCH / "mastar" / "Coin_In_The_Box" / "Coin_in_the_Box__pl_3.txt")
    assert not _modules_after(["plan", coin, "--search", "astar"]) & HEAVY
    assert not _modules_after(["plan", DOM, PROB]) & HEAVY
    # a property in the formula syntax needs the (cached) lark parser; replaying actions with oblivious agents
    # builds delkit's sparse relations (scipy); never the CLI framework
    assert _modules_after(["check", DOM, PROB, PLAN, "--properties", PROPS]) & HEAVY <= {"lark", "scipy"}


def test_import_delkit_is_lazy() -> None:
    code = "import sys, delkit; print('numpy' in sys.modules); from delkit import *; print(KripkeModel.__name__)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=dict(os.environ, PYTHONPATH=str(ROOT))).stdout.split()
    assert out == ["False", "KripkeModel"]
    import delkit

    for name in delkit.__all__:
        assert getattr(delkit, name) is not None
    with pytest.raises(AttributeError):
        delkit.no_such_name  # noqa: B018


# ---------------------------------------------------------------------------------------------- lark cache
GRAMMAR = 'start: NAME ("," NAME)*\nNAME: /[a-z]+/\n%ignore " "\n'


def test_lark_cache_written_then_used(tmp_path, monkeypatch) -> None:
    from delkit.logic._larkcache import build_lark

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("DELKIT_NO_CACHE", raising=False)
    p = build_lark("t", GRAMMAR)
    files = list((tmp_path / "delkit").glob("t-*.lark"))
    assert len(files) == 1 and files[0].stat().st_size > 0
    assert (tmp_path / "delkit").stat().st_mode & 0o077 == 0       # private directory
    q = build_lark("t", GRAMMAR)                                   # loaded from the file
    assert p.parse("a, b").children == q.parse("a, b").children
    # a corrupt cache file is rebuilt, never trusted
    files[0].write_bytes(b"garbage\n\x00\x01")
    r = build_lark("t", GRAMMAR)
    assert [str(t) for t in r.parse("x,y").children] == ["x", "y"]
    assert files[0].read_bytes() != b"garbage\n\x00\x01"


def test_lark_cache_falls_back_when_unwritable(tmp_path, monkeypatch) -> None:
    from delkit.logic._larkcache import build_lark, cache_dir

    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    assert cache_dir() is None
    assert [str(t) for t in build_lark("t", GRAMMAR).parse("a").children] == ["a"]
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setenv("DELKIT_NO_CACHE", "1")
    assert cache_dir() is None


def test_formula_errors_same_with_and_without_cache(tmp_path) -> None:
    code = ("from delkit.logic.formula import parse\n"
            "for s in ['K_a p &', 'K_a (p', '[E,', 'C{a,b', 'p <-> ->', 'p q', '@', 'K_a p & ~K_b q']:\n"
            "    try: print(parse(s))\n"
            "    except Exception as e: print(e)\n")
    outs = []
    for extra in ({"XDG_CACHE_HOME": str(tmp_path)}, {"XDG_CACHE_HOME": str(tmp_path)}, {"DELKIT_NO_CACHE": "1"}):
        env = dict(os.environ, PYTHONPATH=str(ROOT), **extra)
        outs.append(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                                   check=True).stdout)
    assert outs[0] == outs[1] == outs[2] and "unexpected" in outs[0]
    assert list((tmp_path / "delkit").glob("formula-*.lark"))


def test_relation_from_pairs_without_scipy_matches_scipy() -> None:
    import scipy.sparse as sp

    from delkit.models.relation import Relation

    rng = np.random.default_rng(7)
    for n in (1, 2, 5, 17):
        for _ in range(20):
            pairs = [tuple(int(x) for x in rng.integers(0, n, 2)) for _ in range(int(rng.integers(0, 3 * n)))]
            r = Relation.from_pairs(n, pairs)
            want = sp.csr_matrix((np.ones(len(pairs), dtype=bool), ([p[0] for p in pairs], [p[1] for p in pairs])),
                                 shape=(n, n), dtype=bool).toarray()
            for w in range(n):
                assert r.successors(w).tolist() == np.flatnonzero(want[w]).tolist()
            assert np.array_equal(r.matrix.toarray(), want) and np.array_equal(r.to_matrix().toarray(), want)


# ---------------------------------------------------------------------------------------------- C_G components
@settings(max_examples=150, deadline=None)
@given(st.data())
def test_components_match_scipy(data) -> None:
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    from delkit.logic.semantics import _components

    n = data.draw(st.integers(1, 80))
    k = data.draw(st.integers(1, 3))
    labs = []
    for _ in range(k):
        raw = data.draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))
        labs.append(np.unique(np.asarray(raw), return_inverse=True)[1].ravel().astype(np.int64))
    rows, cols, off = [], [], n
    for lab in labs:
        rows.append(np.arange(n))
        cols.append(off + lab)
        off += int(lab.max()) + 1
    g = sp.csr_matrix((np.ones(n * k, dtype=bool), (np.concatenate(rows), np.concatenate(cols))), shape=(off, off))
    assert np.array_equal(_components(n, labs), connected_components(g, directed=False)[1][:n])


def test_components_long_chain_uses_fallback() -> None:
    from delkit.logic.semantics import _components

    n = 400  # a path of diameter 400: more rounds than the propagation does before falling back
    a, b = np.arange(n) // 2, (np.arange(n) + 1) // 2
    assert _components(n, [a, b]).max() == 0
    assert _components(n, [a, np.arange(n)]).max() == n // 2 - 1
    assert json.dumps(int(_components(1, [np.zeros(1, dtype=np.int64)])[0])) == "0"


# ---------------------------------------------------------------------------------------------- fast formula reader
def _lark_parse(text: str):
    """The formula the grammar's (lark) parser builds, or the name of its exception."""
    from delkit.logic.formula import _Build, _parser

    try:
        return _Build({}, "<formula>").build(_parser().parse(text))
    except Exception as exc:  # noqa: BLE001 - any failure is compared by its kind
        return type(exc).__name__


@settings(max_examples=300, deadline=None)
@given(formulas(["p", "q_1", "r.s'", "K", "Kw", "true_", "_x"], ["a", "b2", "robot_1", "K_a", "Tx"], max_depth=4,
                allow_common=True), st.booleans())
def test_fast_formula_reader_reads_printed_formulas_as_lark(f, diamonds) -> None:
    """Every printed formula without announcements or updates is read by the fast reader, to lark's formula."""
    from delkit.logic.formula import _fast_parse, show

    text = show(f, diamonds=diamonds)
    fast = _fast_parse(text)
    assert fast is not None, text
    assert fast == _lark_parse(text) == f


_PIECES = ["p", "q", "K", "M", "E", "T", "F", "true", "false", "K_a", "K_a_b", "M_a_b", "Kw_a.b", "B_b'", "B_b", "Kw_a",
           "M_a", "<a>", "<ab>",
           "K{", "Kw{", "M{", "B{", "E{", "C{", "D{", "Dkw{", "Ckw{", "{", "}", ",", "a", "b", "robot_1", "(", ")",
           "~", "!", "¬", "&", "|", "->", "<->", "<", ">", "[", "]", "[!", "<!", " ", "  ", "\t", "\n", "#c\n", "x'",
           "p.q", "_", "1", "Kwx", "C{a,b}", "K{T}", "E{a, b}", "K_", "Kw_", "M_", "<a", "a>", "<{", "\"e\"", "é",
           "\r", "\x0c", "Dkw", "Ckw{a}", "[E,e]", "=", "-", "T'", "B", "Kw"]


_TRICKY = ["K_a_b p", "M_a_b p", "Kw_a.b p", "B_b' p", "<->p", "K_ p", "Kw_ p", "E{T} p", "K{K_a} p", "<a>p", "<a,b> p",
           "K{a,b} p", "C{} p", "M{x}(p)", "p -> q -> r <-> s", "~!¬p", "T & true | F", "K_aK_b p", "C{a, b # x\n} p"]


def test_fast_formula_reader_on_tricky_spellings() -> None:
    from delkit.logic.formula import _fast_parse

    read = 0
    for t in _TRICKY:
        fast = _fast_parse(t)
        if fast is not None:
            read += 1
            assert fast == _lark_parse(t), t
    assert read >= 7  # the valid spellings in the subset


@settings(max_examples=600, deadline=None)
@given(st.lists(st.sampled_from(_PIECES), min_size=1, max_size=12), st.data())
def test_fast_formula_reader_never_disagrees_with_lark(pieces, data) -> None:
    """On any text — random pieces, a printed formula with pieces spliced in, the tricky spellings — the fast
    reader either declines (None: lark reads it, errors included) or builds lark's formula."""
    from delkit.logic.formula import _fast_parse, show

    f = data.draw(formulas(["p", "q"], ["a", "b"], max_depth=3))
    text = show(f)
    for piece in pieces[:3]:
        at = data.draw(st.integers(0, len(text)))
        text = text[:at] + piece + text[at:]
    for t in ("".join(pieces), text):
        fast = _fast_parse(t)
        if fast is not None:
            assert fast == _lark_parse(t), t


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_check_small_tasks_never_imports_numpy(tmp_path) -> None:
    """``delkit check`` replays a small task without numpy (planners.replay), with or without properties in
    the plain syntax (the fast formula reader: no lark either) — and the (cached) lark parser only for a
    property the fast reader leaves to it."""
    plan_file = tmp_path / "cb2.plan"
    plan_file.write_text("peek_up_key_a\nopen_a\n")
    plank = BENCH / "epddl2026" / "plank" / "domains" / "Coin-in-the-Box"
    (tmp_path / "p2.plan").write_text("open_A\npeek_A\n")
    for argv in (["check", CB2, str(plan_file)], ["check", CB2, str(plan_file), "-p", "at end opened"],
                 ["check", CB2, str(plan_file), "-p", "always ~K_a ~has_key_a | K_a has_key_a", "--json"],
                 ["check", DOM, PROB, PLAN, "--properties", PROPS],
                 ["check", str(plank / "cb.epddl"), str(plank / "instances" / "problem_2.epddl"),
                  str(tmp_path / "p2.plan"), "-l", str(BENCH / "epddl2026" / "plank" / "libraries" /
                                                       "intermediate.epddl")]):
        got = _modules_after(argv, ok=(0, 1))
        assert not got & (SMALL_PLAN_HEAVY | {"dataclasses", "inspect"}), (argv, got & SMALL_PLAN_HEAVY)
    assert "lark" in _modules_after(["check", CB2, str(plan_file), "-p", "at end [!opened] opened"])
