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


class PlanningError(DelkitError):
    """A planning task that cannot be built or searched (the *result* of a failed search is not an error)."""


class SimulationError(DelkitError):
    """Invalid set-up of a simulation or experiment."""
