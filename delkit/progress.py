"""The progress display for long work: one rich bar on stderr, silent when it would get in the way.

Anything that can run longer than about two seconds shows its progress with :func:`progress` (or
:func:`track` for a loop)::

    from delkit.progress import progress

    with progress(quiet=as_json) as bar:
        task = bar.add_task("missions", total=len(jobs))
        for job in jobs:
            run(job)
            bar.advance(task)

The display goes to **stderr** (stdout stays the command's answer, so ``delkit … --json | jq`` works), is
**transient** (erased when done), and is **disabled** — nothing is drawn, the calls cost next to nothing —
when ``quiet`` is true (pass the command's ``--json``), when stderr is not a terminal (pipes, CI, tests),
or when ``DELKIT_PROGRESS=0``. An unknown total (``total=None``) shows a pulsing bar and the count.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterable, Iterator
from typing import Any, TypeVar

__all__ = ["progress", "track", "enabled"]

T = TypeVar("T")


def enabled(quiet: bool = False) -> bool:
    """Whether a progress display would be drawn: not quiet, stderr a terminal, DELKIT_PROGRESS not 0."""
    if quiet or os.environ.get("DELKIT_PROGRESS", "1").strip() in ("0", "false", "no", "off"):
        return False
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # replaced or closed stderr
        return False


def progress(*, quiet: bool = False, transient: bool = True) -> Any:
    """A :class:`rich.progress.Progress` on stderr (description, bar, done/total, elapsed time), disabled
    unless :func:`enabled`. Use it as a context manager; ``add_task``/``update``/``advance`` as in rich."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(TextColumn("[progress.description]{task.description}"), BarColumn(), MofNCompleteColumn(),
                    TimeElapsedColumn(), console=Console(stderr=True), transient=transient,
                    disable=not enabled(quiet))


def track(items: Iterable[T], description: str, *, total: float | None = None, quiet: bool = False) -> Iterator[T]:
    """Iterate over ``items`` with a progress display (``total`` defaults to ``len(items)`` when it has one)."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)  # type: ignore[arg-type]
    if not enabled(quiet):
        yield from items
        return
    with progress() as bar:
        task = bar.add_task(description, total=total)
        for item in items:
            yield item
            bar.advance(task)
