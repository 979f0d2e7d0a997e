"""The language of a planning file is decided by its content, never by its extension; a file that is none of
mA*, E-PDDL (2021) and EPDDL (2026) is refused with an error naming it."""

from __future__ import annotations

import shutil

import pytest

from delkit.errors import ParseError
from planners.demo import specs_dir
from planners.lang import load_task, shared_benchmarks
from planners.lang.detect import detect, detect_text

BENCH = shared_benchmarks()
needs_bench = pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")


@needs_bench
def test_shared_files_by_language() -> None:
    e26 = sorted((BENCH / "epddl2026" / "plank").rglob("*.epddl"))
    assert len(e26) >= 30 and {detect(p) for p in e26} == {"epddl2026"}
    e21 = sorted((BENCH / "epddl").rglob("*.epddl"))
    assert e21 and {detect(p) for p in e21} == {"epddl2021"}
    ma = sorted((BENCH / "mastar").rglob("*.txt"))
    assert len(ma) >= 20 and {detect(p) for p in ma} == {"mastar"}


def test_repository_specs() -> None:
    d = specs_dir() / "coin_in_the_box"
    assert detect(d / "domain.epddl") == "epddl2021" and detect(d / "problem.epddl") == "epddl2021"
    assert detect(d / "pb1_twin.txt") == "mastar"


@needs_bench
def test_extension_does_not_matter(tmp_path) -> None:
    src = BENCH / "epddl2026" / "plank" / "domains" / "Gossip"
    dom, prob = tmp_path / "gossip.txt", tmp_path / "gossip_problem.pddl"
    shutil.copy(src / "gos.epddl", dom)
    shutil.copy(src / "instances" / "problem_1.epddl", prob)
    lib = tmp_path / "lib.lisp"
    shutil.copy(BENCH / "epddl2026" / "plank" / "libraries" / "intermediate.epddl", lib)
    assert detect(dom) == "epddl2026" and detect(lib) == "epddl2026"
    assert load_task(dom, prob, [lib]).name == "gos-1"
    ma = tmp_path / "cb.epddl"
    shutil.copy(BENCH / "mastar" / "CB_simple" / "CB_simple__pl_2.txt", ma)
    assert detect(ma) == "mastar" and load_task(ma).actions


@pytest.mark.parametrize("text,dialect", [
    ("(define (domain d) (:action a :act_type ontic :effect (p)))", "epddl2021"),
    ("; comment (:event\n(define (domain d) (:predicates (p)))", "epddl2021"),   # markers in comments don't count
    ("(define (domain d) (:event e) (:action a :action-type (basic (e))))", "epddl2026"),
    ("(define (problem p) (:domain d) (:agents a) (:init (:and ([C. All] (p)))) (:goal (p)))", "epddl2026"),
    ("(define (action-type-library l) (:action-type t :events (?e)))", "epddl2026"),
    ("% EFP file\nfluent p;\naction a;\nagent x;\n", "mastar"),
    ("a causes p;", "mastar"),
])
def test_detect_text(text: str, dialect: str) -> None:
    assert detect_text(text)[0] == dialect


@pytest.mark.parametrize("text", ["", "hello world\n", "(foo bar)", "{\"json\": 1}"])
def test_none_of_them_is_refused_naming_the_file(tmp_path, text: str) -> None:
    p = tmp_path / "mystery.dat"
    p.write_text(text)
    with pytest.raises(ParseError, match=r"mystery\.dat: not an mA\*, E-PDDL \(2021\) or EPDDL \(2026\) file"):
        detect(p)
    with pytest.raises(ParseError, match="mystery.dat"):
        load_task(p)


@needs_bench
def test_epddl2026_domain_without_problem_is_a_clear_error() -> None:
    dom = BENCH / "epddl2026" / "plank" / "domains" / "Gossip" / "gos.epddl"
    with pytest.raises(ParseError, match="needs a problem file"):
        load_task(dom)
