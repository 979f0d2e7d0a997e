"""Plan files as JSON: what ``delkit plan --plan-out FILE`` writes, and what ``delkit check`` and ``delkit view``
read beside plain plan text (:func:`planners.validate.read_plan` dispatches here for a file that is a JSON
object).

A plan file is one JSON object::

    {"format": "delkit-plan", "version": 1, "task": "coin_in_the_box", "sources": ["domain.epddl", ...],
     "plan": ["peek_a", ...], "length": 3, "search": "bfs", "status": "solved"}

Only ``plan`` (a list of action names, strings) is required when reading, so the object printed by
``delkit plan --json`` is a plan file too. A JSON file without a plan (e.g. ``"plan": null`` from a search
that found none) is refused with its ``status`` and ``reason``.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from delkit.errors import ParseError

__all__ = ["FORMAT", "plan_document", "check_plan_out", "write_plan_file", "parse_plan_json", "looks_like_json"]

FORMAT = "delkit-plan"


def plan_document(task_name: str, sources: Sequence[str | Path], result: dict) -> dict:
    """The plan file of a solved search (``result``: :meth:`SearchResult.to_json`)."""
    return {"format": FORMAT, "version": 1, "task": task_name, "sources": [str(s) for s in sources],
            "plan": list(result["plan"]), "length": result.get("length"), "search": result.get("search"),
            "status": result.get("status")}


def check_plan_out(out: Path, inputs: Sequence[Path], option: str = "--plan-out") -> None:
    """Refuse (exit 2, before any work) a plan output that is a directory or one of the inputs
    (:func:`delkit.paths.refuse_overwrite_input`: a symlink or a hard link to an input is caught)."""
    from delkit.paths import refuse_overwrite_input

    if str(out) == "-":
        return
    if out.is_dir():
        raise ParseError(f"{out} is a directory; give a file name, e.g. {option} plan.json", source=option)
    refuse_overwrite_input([out], inputs, option=option)


def write_plan_file(out: Path, doc: dict, inputs: Sequence[Path]) -> None:
    """Write ``doc`` to ``out`` (checked against ``inputs`` again right before writing; '-': stdout)."""
    text = json.dumps(doc, indent=2) + "\n"
    if str(out) == "-":
        print(text, end="", flush=True)
        return
    check_plan_out(out, inputs)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)  # as every --out of the CLI: missing folders are made
        tmp = out.with_name(f".{out.name}.{os.getpid()}.tmp")
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, out)  # the file is whole or absent; a link at ``out`` is replaced, not followed
    except OSError as exc:
        raise ParseError(f"{out}: cannot write the plan file ({exc.strerror})", source="--plan-out") from None


def looks_like_json(text: str) -> bool:
    """The text is a JSON object (its first non-blank character is ``{``)."""
    return text.lstrip()[:1] == "{"


def parse_plan_json(text: str, source: str) -> list[str]:
    """The action names of a JSON plan file (see the module docstring), or a :class:`ParseError` saying
    what is wrong and where."""
    try:
        obj: Any = json.loads(text)
    except ValueError as exc:
        line = getattr(exc, "lineno", None)
        col = getattr(exc, "colno", None)
        raise ParseError(f"the plan file starts with '{{' but is not JSON ({getattr(exc, 'msg', exc)}); write "
                         f"one action a line, or the JSON of delkit plan --plan-out", source=source, line=line,
                         column=col) from None
    if not isinstance(obj, dict):
        raise ParseError("a JSON plan file must be an object with a \"plan\" list", source=source)
    if "plan" not in obj:
        raise ParseError("the JSON plan file has no \"plan\" field (a list of action names); write it with "
                         "delkit plan --plan-out FILE", source=source)
    plan = obj["plan"]
    if plan is None:
        raise ParseError(f"the JSON plan file records no plan (status {obj.get('status')!r}: "
                         f"{obj.get('reason') or 'no reason given'})", source=source)
    if not isinstance(plan, list) or not all(isinstance(a, str) and a.strip() for a in plan):
        raise ParseError("\"plan\" must be a list of action names (non-empty strings)", source=source)
    return [a.strip() for a in plan]
