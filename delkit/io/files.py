"""Reading any model file the core reads by itself: delkit's JSON model format, DOT and SMCDEL's language
(``model draw``, ``model diff``, ``model show``, ``delkit view``)."""

from __future__ import annotations

from pathlib import Path

from delkit.paths import (  # noqa: F401  (re-exported: the guards' first home)
    INPUT_ENV,
    check_input,
    max_input_bytes,
    read_input,
    read_input_bytes,
    refuse_overwrite_input,
)

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up)
if TYPE_CHECKING:
    from typing import Any

__all__ = ["ANY_FORMATS", "is_smcdel", "load_any", "structure_model", "check_input", "read_input",
           "read_input_bytes", "refuse_overwrite_input", "max_input_bytes", "INPUT_ENV"]


def is_smcdel(path: str) -> bool:
    return str(path).lower().endswith(".smcdel.txt")


#: what :func:`load_any` reads (``model draw``, ``model diff``, ``model show``)
ANY_FORMATS = "delkit's JSON model format (.json), DOT (.dot/.gv) or SMCDEL's language (.smcdel.txt)"


def load_any(path: str) -> Any:
    """A KripkeModel or EventModel (JSON/DOT), or a knowledge/belief structure (SMCDEL's language: a
    ``.smcdel.txt`` file, or one whose text starts ``VARS … LAW …``)."""
    from delkit.io.formats import load, sniff

    smcdel = is_smcdel(path)
    if not smcdel and Path(path).suffix.lower() not in (".json", ".dot", ".gv"):
        try:
            smcdel = sniff(read_input(path, "model file")) == "smcdel"
        except (OSError, UnicodeDecodeError):
            smcdel = False  # load() below says what is wrong with the file
    if smcdel:
        from delkit.errors import ParseError
        from delkit.io.smcdel import parse_smcdel, structure

        try:
            text = read_input(path, "SMCDEL file")
        except UnicodeDecodeError:
            raise ParseError("not UTF-8 text; is it an SMCDEL file?", source=str(path)) from None
        return structure(parse_smcdel(text, source=str(path)))
    return load(path, formats=ANY_FORMATS)


def structure_model(obj: Any, path: str, max_worlds: int):
    """The explicit model of a symbolic structure, worlds named by their true variables, e.g. ``{1,3}``."""
    from delkit.errors import ModelError
    from delkit.models.bisimulation import as_kripke
    from delkit.models.kripke import KripkeModel
    from delkit.resources import require, structure_kripke_bytes

    try:
        if hasattr(obj, "count_states") and obj.count_states() <= max_worlds:  # estimated before it is built
            require(structure_kripke_bytes(obj), f"{path}: the explicit model of its {obj.count_states()} states",
                    "use a lower --max-worlds or the symbolic engine (two .smcdel.txt files)")
        m = as_kripke(obj, max_worlds=max_worlds)
    except ModelError as exc:
        raise ModelError(f"{path}: {exc}") from None
    names = tuple(_state_name(s, obj.vocabulary) for s in obj.states())
    return KripkeModel(m.props, m.agents, m.valuation, m.relations, m.designated, names)


def _state_name(state: dict[str, bool], vocabulary) -> str:
    return "{" + ",".join(v for v in vocabulary if state[v]) + "}"
