"""Lark parsers built once per grammar and then loaded from a cache file (start-up time).

Building the LALR tables of the formula grammar costs ~25 ms per process; lark's ``cache=`` option pickles
the analysed parser and loads it in ~2 ms. The cache lives in the user's cache directory
(``$XDG_CACHE_HOME/delkit`` or ``~/.cache/delkit``, created private), one file per grammar text, lark
version and Python version; lark itself checks a SHA-256 of grammar + options stored in the file and
rebuilds on any mismatch or unreadable file. If no cache directory can be created (read-only home, no
home), the parser is simply built in memory as before: the cache is an optimisation, never a requirement.
``DELKIT_NO_CACHE=1`` disables it.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path
from typing import Any

__all__ = ["cache_dir", "build_lark"]


def cache_dir() -> Path | None:
    """The delkit cache directory (created, mode 0700), or None if caching is off or impossible."""
    if os.environ.get("DELKIT_NO_CACHE"):
        return None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    d = Path(base) / "delkit"
    try:
        d.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError:
        return None
    return d if os.access(d, os.W_OK | os.X_OK) else None


def build_lark(name: str, grammar: str, **options: Any) -> Any:
    """``Lark(grammar, parser="lalr", **options)``, cached in :func:`cache_dir` when there is one."""
    import lark

    d = cache_dir()
    if d is not None:
        tag = hashlib.sha256(f"{grammar}\0{sorted(options.items())!r}".encode()).hexdigest()[:16]
        fn = d / f"{name}-{tag}-lark{lark.__version__}-py{sys.version_info[0]}{sys.version_info[1]}.lark"
        try:
            return lark.Lark(grammar, parser="lalr", cache=str(fn), **options)
        except OSError:  # pragma: no cover - lark reports its own cache I/O errors and carries on
            pass
    return lark.Lark(grammar, parser="lalr", **options)
