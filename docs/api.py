"""Build the API reference from the docstrings with pdoc (``make docs``): HTML into ``--out``.

Every warning pdoc (or a module imported for it) raises while documenting makes the build fail: a module
that does not import, a docstring pdoc cannot read. ``--packages`` picks what to document (default: the
four packages; ``arms`` needs ``delkit[arms]``)::

    python docs/api.py --out build/api [--packages delkit,planners,sim,arms]
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("delkit", "planners", "sim", "arms")


def build(out: Path, packages: tuple[str, ...] = PACKAGES) -> list[str]:
    """Write the HTML reference of ``packages`` into ``out``; returns the warnings (empty: a clean build)."""
    import pdoc
    import pdoc.render

    pdoc.render.configure(docformat="restructuredtext", footer_text="delkit API reference",
                          search=True, show_source=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # import every module first, as a user would: pdoc imports with subprocess mocked out, and some
        # third-party imports (glfw, under mujoco's renderer) run a subprocess when they load
        import importlib
        import pkgutil

        modules = []
        for name in packages:
            package = importlib.import_module(name)
            modules.append(name)
            for info in pkgutil.walk_packages(package.__path__, prefix=f"{name}."):
                importlib.import_module(info.name)
                if not any(part.startswith("_") for part in info.name.split(".")):
                    modules.append(info.name)
        # every public module by name: a package's __all__ (delkit's re-exports) would otherwise hide them
        pdoc.pdoc(*modules, output_directory=out)
    listed_twice = "but a module with this name has already been added"  # a package and its modules, both listed
    return [f"{w.category.__name__}: {w.message}" for w in caught if listed_twice not in str(w.message)
            and (not issubclass(w.category, (DeprecationWarning, PendingDeprecationWarning))
                 or "pdoc" in str(w.filename))]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "api")
    ap.add_argument("--packages", default=",".join(PACKAGES))
    args = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    t0, c0 = time.perf_counter(), time.process_time()
    problems = build(args.out, tuple(p for p in args.packages.split(",") if p))
    pages = len(list(args.out.rglob("*.html"))) - 1  # not the index
    print(f"API reference: {pages} pages in {args.out} ({time.perf_counter() - t0:.1f} s wall, "
          f"{time.process_time() - c0:.1f} s CPU); {len(problems)} warning(s)")
    for p in problems:
        print("  " + p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
