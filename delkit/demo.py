"""The core's sections of ``delkit demo``: the DEL puzzles with their literature answers, and the z3 layer
(proofs, minimal counter-models, a macro check, a reduction check). Each section is a function
``(out_dir) -> {"ok", "summary", ...}``; the layers above add theirs through ``DEMO_SECTIONS`` of their
``delkit.commands`` plugin (:mod:`delkit.cli.plugins`)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["DEMO_SECTIONS", "puzzles", "proofs"]


def puzzles(out: Path) -> dict[str, Any]:
    """The DEL puzzles with their literature answers (``puzzles.json`` in ``out``)."""
    from delkit.puzzles import summary_table

    rows = summary_table()
    (out / "puzzles.json").write_text(json.dumps(rows, indent=2, default=str))
    ok = all(r["ok"] for r in rows)
    text = "; ".join(f"{r['puzzle']}: {r['answer']}" for r in rows)
    return {"ok": ok, "rows": rows, "summary": text}


def proofs(out: Path | str) -> dict[str, Any]:
    """The z3 layer end to end, for ``delkit demo``: prove the S5 axioms (exact for one agent), refute
    truth of belief on KD45 and "mutual ⇒ common knowledge" on S5 with minimal counter-models (written to
    ``out`` as JSON and DOT, re-checked explicitly), check a sensing;ontic macro against its steps, and
    check the reduction of an mA* update against the explicit checker. Returns ``{"ok", "summary", …}``."""
    from delkit.io.formats import save, save_dot
    from delkit.logic.formula import Update, parse
    from delkit.models.compose import compose
    from delkit.models.events import ontic, sensing
    from delkit.models.kripke import KripkeModel
    from delkit.verify import check_macro, prove, reduce

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    axioms = ["K_a p -> p", "K_a p -> K_a K_a p", "~K_a p -> K_a ~K_a p", "K_a (p -> q) -> K_a p -> K_a q"]
    proved = [prove(a, logic="S5", worlds=4) for a in axioms]
    kd45 = prove("K_a p -> p", logic="KD45", worlds=3)
    mutual = prove("K_a p & K_b p -> C{a,b} p", logic="S5", worlds=4)
    for name, v in (("kd45_false_belief", kd45), ("mutual_not_common", mutual)):
        if v.counter_model is not None:
            save(v.counter_model, out / f"{name}.json")
            save_dot(v.counter_model, out / f"{name}.dot")
    look = sensing("p", ["a", "b"], full=["a"], partial=["b"], name="look")
    flip = ontic({"q": "p"}, ["a", "b"], full=["a"], name="copy")
    macro = check_macro(compose(look, flip, prune=True), [look, flip])
    f = Update(flip, 0, parse("K_a q & ~K_b q & K_b (q | ~q)"))
    m = KripkeModel.build([{"p"}, set()], {"a": [[0], [1]], "b": [[0, 1]]}, props=["p", "q"])
    reduction_ok = bool((m.check(f) == m.check(reduce(f))).all())
    ok = (all(v.valid and v.exact for v in proved) and not kd45.valid and not mutual.valid
          and macro.equivalent and reduction_ok)
    summary = (f"S5 axioms T,4,5,K proved ({sum(v.valid for v in proved)}/4, exact); KD45 false-belief "
               f"counter-model {kd45.counter_model.n_worlds if kd45.counter_model else '-'} worlds; "
               f"mutual≠common counter-model {mutual.counter_model.n_worlds if mutual.counter_model else '-'} "
               f"worlds; macro look;copy {'equals' if macro.equivalent else 'DIFFERS from'} its steps; "
               f"reduction {'agrees' if reduction_ok else 'DISAGREES'} with the explicit checker")
    return {"ok": ok, "summary": summary, "macro_problems": list(macro.problems),
            "files": sorted(str(p) for p in out.glob("*_*.json"))}


def _proofs_section(out: Path) -> dict[str, Any]:
    return proofs(out / "verify")


#: the core's demo sections (order, title, function); the layers above add theirs
DEMO_SECTIONS: list[tuple[float, str, Callable[[Path], dict[str, Any]]]] = [
    (10, "DEL puzzles (literature answers)", puzzles),
    (20, "z3 proofs and counter-models", _proofs_section),
]
