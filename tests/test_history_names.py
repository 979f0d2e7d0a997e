"""Code, tests, docs, specs, benchmarks, README and RESULTS files say what the project does, not how it got
there: no issue numbers ("issue 23", "#24"), no work-session words ("the sixth session"), no names of the
branches work was done on ("gv25", "puzB23", tests named ``test_qa_*`` or ``*_b23``). History stays in git.

A hit is reported as ``file:line: the matched text``; rewrite the sentence to say what the code does.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: what is scanned: the four packages, tests, docs, specs, benchmarks and the top-level texts
SCANNED = ("delkit", "planners", "arms", "sim", "tests", "docs", "specs", "bench", "README.md", "Makefile",
           "pyproject.toml")
SUFFIXES = {".py", ".md", ".txt", ".toml", ".cfg", ".ini", ".epddl", ".pddl", ".smcdel", ".sh", ".yml", ".yaml",
            ".html", ".rst", ".plan", ".json", ""}
#: not ours to word: third-party files shipped as they are
SKIPPED_DIRS = {"delkit/view/static", "bench/peers"}
MAX_BYTES = 2_000_000

#: branch names used for work on this repository that are not ordinary words (more are read from git)
KNOWN_BRANCHES = {"epstart", "epsearch", "symtools", "symspeed", "integ", "explore2", "epicoplan", "viewwheel",
                  "ground4", "lead25"}

#: names with digits that are words of the trade, never taken for a branch name (py311, sha256, utf8, …)
ORDINARY_TOKEN = re.compile(r"^(?:py|sha|utf|u?int|float|md|x86|arm|v|s|kd)\d", re.I)

#: (what it is, pattern); matched case-insensitively unless the pattern says otherwise
PATTERNS: list[tuple[str, re.Pattern[str]]] = [
    ("an issue number", re.compile(r"\bissues?\s*(?:#\s*)?\d+", re.I)),
    ("an issue reference", re.compile(r"(?<![\w\"'&/=#-])#\d{2,4}\b(?![0-9a-fA-F])")),
    ("a work session", re.compile(
        r"\b(?:first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|twelfth|this|previous"
        r"|last|earlier|later|next|that|another)\s+(?:work\s+)?session\b|\bsessions?\s+\d+\b", re.I)),
    ("a branch suffix", re.compile(r"_b\d\d\b")),
    ("a QA label", re.compile(r"\btest_qa_|_qa_|\(qa\)|\bQA\b", 0)),
]

#: (file, text) pairs that may stay: citations of other projects' trackers and the like; keep it small
ALLOWED: set[tuple[str, str]] = set()

#: files whose owners rewrite them; each stays an expected failure until it is clean, and then the entry
#: must go (a strict xfail: a clean file listed here fails)
PENDING_REWRITE: set[str] = set()


def branch_names(root: Path = ROOT) -> set[str]:
    """Names of branches merged into this repository that contain a digit (``gv25``, ``puzB23``; words such
    as ``arms`` or ``epico`` are the names of parts, not history), from git when it is there."""
    names = set(KNOWN_BRANCHES)
    try:
        log = subprocess.run(["git", "-C", str(root), "log", "--all", "--format=%s"], capture_output=True,
                             text=True, timeout=30).stdout
        branches = subprocess.run(["git", "-C", str(root), "branch", "-a", "--format=%(refname:short)"],
                                  capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return names
    found = re.findall(r"[Mm]erge (?:branch )?'?([A-Za-z][\w-]*)'?(?: into '?([A-Za-z][\w-]*)'?)?", log)
    found += [(b.rsplit("/", 1)[-1], "") for b in branches.split()]
    for pair in found:
        names |= {n for n in pair if n and re.search(r"\d", n) and re.search(r"[A-Za-z]{2}", n)
                  and not ORDINARY_TOKEN.match(n)}
    return names


def history_patterns(root: Path = ROOT) -> list[tuple[str, re.Pattern[str]]]:
    names = sorted(branch_names(root), key=len, reverse=True)
    branch = re.compile(r"(?<![\w.-])(?:" + "|".join(map(re.escape, names)) + r")(?![\w-])", re.I)
    return [*PATTERNS, ("a branch name", branch)]


def scanned_files(root: Path = ROOT) -> list[Path]:
    out = []
    for entry in SCANNED:
        path = root / entry
        paths = [path] if path.is_file() else sorted(path.rglob("*")) if path.is_dir() else []
        for p in paths:
            rel = p.relative_to(root).as_posix()
            if not p.is_file() or p.suffix not in SUFFIXES or any(rel.startswith(d + "/") for d in SKIPPED_DIRS):
                continue
            if "__pycache__" in p.parts or p.stat().st_size > MAX_BYTES or p.resolve() == Path(__file__).resolve():
                continue
            out.append(p)
    return out


def history_hits(path: Path, root: Path = ROOT, patterns=None) -> list[str]:
    """``file:line: what (text)`` for every history name in the file."""
    rel = path.relative_to(root).as_posix()
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        return []
    hits = []
    for number, line in enumerate(text.splitlines(), 1):
        for what, pattern in patterns or history_patterns(root):
            for m in pattern.finditer(line):
                if (rel, m.group(0)) not in ALLOWED:
                    hits.append(f"{rel}:{number}: {what} ({m.group(0)!r})")
    return hits


def _cases():
    patterns = history_patterns()
    clean, pending = [], []
    for p in scanned_files():
        rel = p.relative_to(ROOT).as_posix()
        (pending if rel in PENDING_REWRITE else clean).append(p)
    return patterns, clean, pending


_PATTERNS, _CLEAN, _PENDING = _cases()


def test_no_history_names_in_code_tests_docs_and_results() -> None:
    hits = [h for p in _CLEAN for h in history_hits(p, patterns=_PATTERNS)]
    assert not hits, "history names (say what the code does instead):\n" + "\n".join(hits)


@pytest.mark.parametrize("path", _PENDING, ids=lambda p: p.relative_to(ROOT).as_posix())
@pytest.mark.xfail(strict=True, reason="its owner rewrites it; remove it from PENDING_REWRITE once it is clean")
def test_files_pending_a_rewrite_still_carry_history(path: Path) -> None:
    assert not history_hits(path, patterns=_PATTERNS)


def test_the_scan_covers_the_tree() -> None:
    rels = {p.relative_to(ROOT).as_posix() for p in _CLEAN}
    for expected in ("delkit/__init__.py", "planners/epistemic.py", "tests/test_layers.py", "docs/design.md",
                     "bench/RESULTS.md", "Makefile", "pyproject.toml"):
        assert expected in rels
    assert not any(r.startswith("delkit/view/static/") for r in rels)


@pytest.mark.parametrize("line, what", [
    ("# fixed in issue 23, part A", "an issue number"),
    ("see Issue #7", "an issue number"),
    ("(the cache of #24)", "an issue reference"),
    ("before the seventh session", "a work session"),
    ("main before this session", "a work session"),
    ("def test_docs_b23():", "a branch suffix"),
    ("def test_qa_cli():", "a QA label"),
    ('"""QA regressions: bad input"""', "a QA label"),
    ("merged from gv25 into main", "a branch name"),
    ("the puzB23 puzzles", "a branch name"),
])
def test_a_history_name_is_reported_with_file_and_line(tmp_path: Path, line: str, what: str) -> None:
    (tmp_path / "m.py").write_text("x = 1\n" + line + "\n")
    hits = history_hits(tmp_path / "m.py", root=tmp_path, patterns=_PATTERNS)
    assert hits and hits[0].startswith("m.py:2: " + what), hits


@pytest.mark.parametrize("line", [
    'fill="#555"', "relation of 'a' block #0: unknown world", "round 0 ranks the valuations",
    "one planning session of ENFORCEAC", "a headless browser session for the module", "for r, qa in arms:",
    "https://github.com/tulip-control/dd/issues/56", "float32 and int64 and sha256", "S5 and KD45",
    "--owner b99=robot1",
])
def test_ordinary_words_are_not_history(tmp_path: Path, line: str) -> None:
    (tmp_path / "m.py").write_text(line + "\n")
    assert history_hits(tmp_path / "m.py", root=tmp_path, patterns=_PATTERNS) == []
