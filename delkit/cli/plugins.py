"""How the ``delkit`` command finds the commands of the layers above the core.

The core owns ``delkit demo``, ``version``, ``puzzle``, ``model``, ``smcdel`` and ``prove``; every other
command belongs to the package that implements it (``planners``, ``sim``, ``arms`` or a third party) and
is registered through the ``delkit.commands`` entry-point group, the way pytest finds its plugins::

    [project.entry-points."delkit.commands"]
    planners = "planners.cli"

The entry point names a *module* with

* ``register(app)`` — attach its commands to the top-level typer app (use :func:`group` for a sub-app that
  more than one package adds to, e.g. ``delkit epico``);
* optionally ``PUZZLES`` — rows for ``delkit puzzle --list`` (the keys of ``delkit.puzzles.CATALOGUE``)
  for puzzle commands it adds to the ``puzzle`` group (planners: ``muddy-plan``);
* optionally ``DEMO_SECTIONS`` — ``(order, title, function(out_dir) -> dict)`` run by ``delkit demo``;
* optionally ``EXTRA`` and ``REQUIRES`` — the pip extra the layer needs and the modules it needs from it
  (:func:`delkit.errors.require_extra` turns a missing one into one line naming the extra).

A second group, ``delkit.fast``, maps a command name to a ``fast_args(argv) -> callable | None`` function
for command lines that must start without importing typer (``delkit plan``/``check``: start-up time). It is
read by :func:`fast_entry` from the installed ``entry_points.txt`` files with a small reader, because
``importlib.metadata`` alone costs ≈ 20 ms of start-up. Nothing in this module imports a layer above the
core by name: it only loads what the installed distributions declare.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable

from delkit.errors import require_extra  # re-exported: the plugins' way to name a missing extra

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any

__all__ = ["COMMANDS", "FAST", "plugin_modules", "group", "demo_sections", "plugin_puzzles", "fast_entry",
           "require_extra"]

COMMANDS = "delkit.commands"
FAST = "delkit.fast"


def _entry_points(group_name: str) -> list[tuple[str, str]]:
    """(name, value) of every installed entry point of ``group_name``, each name once (first on sys.path)."""
    from importlib.metadata import entry_points

    seen: dict[str, str] = {}
    for ep in entry_points(group=group_name):
        seen.setdefault(ep.name, ep.value)
    return sorted(seen.items())


def plugin_modules() -> list[tuple[str, Any]]:
    """(entry-point name, loaded module) of every ``delkit.commands`` plugin; a plugin that cannot be imported
    is skipped with one warning line on stderr (its commands are then missing, the rest works)."""
    import importlib

    out = []
    for name, value in _entry_points(COMMANDS):
        try:
            out.append((name, importlib.import_module(value.split(":")[0])))
        except ImportError as exc:
            print(f"delkit: warning: the commands of {name!r} ({value}) are not available: {exc}", file=sys.stderr)
    return out


def group(app: Any, name: str, help: str | None = None) -> Any:
    """The sub-app ``delkit NAME`` of ``app``, created on first use (so several packages can add to it)."""
    import typer

    groups: dict[str, Any] = app.__dict__.setdefault("_delkit_groups", {})
    sub = groups.get(name)
    if sub is None:
        sub = typer.Typer(help=help, no_args_is_help=True)
        app.add_typer(sub, name=name)
        groups[name] = sub
    elif help and not sub.info.help:
        sub.info.help = help
    return sub


def demo_sections() -> list[tuple[float, str, Callable[..., dict]]]:
    """Every installed plugin's demo sections, in their order."""
    from delkit.demo import DEMO_SECTIONS

    sections = list(DEMO_SECTIONS)
    for _, module in plugin_modules():
        sections += list(getattr(module, "DEMO_SECTIONS", ()))
    return sorted(sections, key=lambda s: s[0])


def plugin_puzzles() -> list[dict]:
    """Every installed plugin's ``PUZZLES`` rows (for ``delkit puzzle --list``)."""
    rows: list[dict] = []
    for _, module in plugin_modules():
        rows += [dict(r) for r in getattr(module, "PUZZLES", ())]
    return rows


# ------------------------------------------------------------------------------------------ fast path
def fast_entry(command: str) -> Callable[[list[str]], Any] | None:
    """The ``delkit.fast`` function registered for ``command``, or None (read without importlib.metadata)."""
    value = _fast_table().get(command)
    if value is None:
        return None
    import importlib

    module, _, attr = value.partition(":")
    try:
        return getattr(importlib.import_module(module.strip()), attr.strip())
    except (ImportError, AttributeError):
        return None


_FAST_CACHE: dict[str, str] | None = None


def _fast_table() -> dict[str, str]:
    """``[delkit.fast]`` of every ``*.dist-info/entry_points.txt`` on sys.path (first occurrence wins)."""
    global _FAST_CACHE
    if _FAST_CACHE is not None:
        return _FAST_CACHE
    table: dict[str, str] = {}
    for entry in sys.path:
        try:
            names = os.listdir(entry or ".")
        except OSError:
            continue
        for n in names:
            if not (n.endswith(".dist-info") or n.endswith(".egg-info")):
                continue
            try:
                with open(os.path.join(entry or ".", n, "entry_points.txt"), encoding="utf-8") as fh:
                    text = fh.read()
            except OSError:
                continue
            if f"[{FAST}]" in text:
                for key, val in _section(text, FAST).items():
                    table.setdefault(key, val)
    _FAST_CACHE = table
    return table


def _section(text: str, name: str) -> dict[str, str]:
    """``key = value`` lines of the INI section ``[name]`` (entry_points.txt's format)."""
    out: dict[str, str] = {}
    inside = False
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("["):
            inside = s == f"[{name}]"
        elif inside and "=" in s and not s.startswith(("#", ";")):
            key, _, val = s.partition("=")
            out[key.strip()] = val.strip()
    return out
