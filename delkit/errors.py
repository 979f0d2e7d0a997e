"""One error hierarchy for the whole toolkit.

Every error a user can cause is a :class:`DelkitError` whose message says *what* is wrong, *where*
(file, line, column, agent, proposition, ...) and, where it can, *how to fix it*. The CLI prints the
message on one line and exits with status 2; it never shows a traceback for a ``DelkitError``.
"""

from __future__ import annotations


def io_reason(exc: OSError | UnicodeDecodeError) -> str:
    """Why a file could not be read, for a one-line message: the OS's reason, or that it is not text."""
    if isinstance(exc, UnicodeDecodeError):
        return f"not UTF-8 text (byte {exc.start}); is it the right file?"
    return exc.strerror or str(exc)


class DelkitError(Exception):
    """Base class of every error delkit reports to its users."""


class ParseError(DelkitError):
    """Text that does not follow a grammar. Carries the source name, line and column (1-based)."""

    def __init__(self, message: str, *, source: str = "<text>", line: int | None = None,
                 column: int | None = None, expected: list[str] | None = None) -> None:
        self.source = source
        self.line = line
        self.column = column
        self.expected = expected or []
        where = source
        if line is not None:
            where += f":{line}"
            if column is not None:
                where += f":{column}"
        text = f"{where}: {message}"
        if self.expected:
            text += f" (expected one of: {', '.join(self.expected)})"
        self.bare_message = message
        super().__init__(text)


class ModelError(DelkitError):
    """A Kripke or event model that is malformed or does not fit the formula/model it is used with."""


class UnknownSymbolError(ModelError):
    """A formula names an agent or proposition that the model does not have."""


class VerificationError(DelkitError):
    """A formula outside the fragment a verification tool handles, or a solver answer that failed the
    explicit re-check (the latter is a bug: please report it with the formula)."""


class PlanningError(DelkitError):
    """A planning task that cannot be built or searched (the *result* of a failed search is not an error)."""


class SimulationError(DelkitError):
    """Invalid set-up of a simulation or experiment."""


class MissingExtraError(DelkitError):
    """A feature whose optional dependencies (a pip extra of delkit) are not installed."""


def require_extra(extra: str, *modules: str, what: str = "this command") -> None:
    """Raise a one-line :class:`MissingExtraError` naming ``delkit[extra]`` when one of ``modules`` is missing
    (``pip install delkit`` is the core; the heavy parts are extras: arms, sim, asp, dask, all)."""
    import sys
    from importlib.util import find_spec

    def missing(module: str) -> bool:
        if module in sys.modules:
            return False
        try:
            return find_spec(module) is None
        except (ImportError, ValueError):
            return True

    absent = [m for m in modules if missing(m)]
    if absent:
        raise MissingExtraError(f"{what} needs the optional dependencies of delkit[{extra}] (missing: "
                                f"{', '.join(absent)}); install them with: pip install 'delkit[{extra}]'")
