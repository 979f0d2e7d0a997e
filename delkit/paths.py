"""The input and output guards every command uses: inputs are regular files under a size cap (stat'ed before
they are opened), outputs never replace an input (compared by ``os.path.samefile``). Imports nothing from
delkit but its errors, so that every reader (:mod:`delkit.io.formats`, :mod:`delkit.io.smcdel`, the spec readers of the
layers above) can use it."""

from __future__ import annotations

import os
import stat as _stat

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up)
if TYPE_CHECKING:
    from collections.abc import Iterable

__all__ = ["check_input", "read_input", "read_input_bytes", "refuse_overwrite_input", "max_input_bytes",
           "INPUT_ENV"]

# ----------------------------------------------------------------------------- inputs and outputs
#
# Every file a command reads goes through :func:`check_input` (via :func:`read_input`): it is stat'ed before
# it is opened, so a FIFO (which would block the open forever), a device (``/dev/zero``: endless), a socket
# or a directory is refused with one line, and a regular file larger than the input cap is refused before it
# is read. Every file a command writes is first compared with its inputs by :func:`refuse_overwrite_input`
# (``os.path.samefile``: the same file through a symlink or a hard link counts), before anything is written.

INPUT_ENV = "DELKIT_MAX_INPUT_MB"
_DEFAULT_INPUT_MB = 256.0


def max_input_bytes() -> int:
    """The largest input file read (bytes): 256 MiB, or ``DELKIT_MAX_INPUT_MB`` (MiB)."""
    from delkit.errors import ParseError

    env = os.environ.get(INPUT_ENV, "").strip()
    if not env:
        return int(_DEFAULT_INPUT_MB * 2**20)
    try:
        mib = float(env)
    except ValueError:
        mib = float("nan")
    if not (mib > 0 and mib < 2**40):
        raise ParseError(f"{INPUT_ENV}={env!r}: give the input size cap as a positive number of MiB, e.g. "
                         f"{INPUT_ENV}=512", source="environment")
    return int(mib * 2**20)


def _kind(mode: int) -> str | None:
    """What a non-regular file is, or None for a regular file."""
    if _stat.S_ISREG(mode):
        return None
    if _stat.S_ISDIR(mode):
        return "a directory"
    if _stat.S_ISFIFO(mode):
        return "a FIFO (named pipe): reading it could block forever"
    if _stat.S_ISCHR(mode) or _stat.S_ISBLK(mode):
        return "a device, not a file (it may never end)"
    if _stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"  # pragma: no cover


def _size(n: float) -> str:
    return f"{n / 2**20:.1f} MiB" if n >= 2**20 else f"{n / 1024:.1f} KiB" if n >= 1024 else f"{n:.0f} B"


def check_input(path: str | os.PathLike, what: str = "input") -> os.stat_result:
    """Refuse (:class:`delkit.errors.ParseError`, exit 2) an input that is not a regular file (a FIFO, a device,
    a socket, a directory; symlinks are followed) or is larger than :func:`max_input_bytes`; stat only, the
    file is not opened. A missing or unreadable file raises the ``OSError`` of ``os.stat``."""
    from delkit.errors import ParseError

    st = os.stat(path)
    kind = _kind(st.st_mode)
    if kind is not None:
        raise ParseError(f"the {what} is {kind}; give a regular file (copy the data into one first)",
                         source=str(path))
    cap = max_input_bytes()
    if st.st_size > cap:
        raise ParseError(f"the {what} has {_size(st.st_size)}, more than the {_size(cap)} an input may "
                         f"have; give a smaller file, or raise the cap with {INPUT_ENV} (MiB)", source=str(path))
    return st


def read_input(path: str | os.PathLike, what: str = "input", *, encoding: str = "utf-8",
               errors: str | None = None) -> str:
    """The text of an input file, after :func:`check_input` (the same exceptions as ``Path.read_text``
    otherwise)."""
    check_input(path, what)
    with open(path, encoding=encoding, errors=errors) as fh:
        return fh.read(max_input_bytes() + 1)


def read_input_bytes(path: str | os.PathLike, what: str = "input") -> bytes:
    check_input(path, what)
    with open(path, "rb") as fh:
        return fh.read(max_input_bytes() + 1)


def _same(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):  # one of them does not exist (yet): it cannot be the other
        return False


def refuse_overwrite_input(outputs: Iterable[str | os.PathLike | None], inputs: Iterable[str | os.PathLike | None],
                           *, option: str = "-o", force: bool | None = None) -> None:
    """Refuse (:class:`delkit.errors.ParseError`, exit 2, nothing written) any output that is one of the
    ``inputs``: the same file by ``os.path.samefile`` (a symlink or a hard link to an input counts) or the same
    path. Call it for every output a command will write, before it writes or creates anything. ``None``, ``''``
    and ``-`` (stdout) are skipped. ``force``: the command has a ``--force`` option (True: given, nothing is
    refused; False: not given, the message names it; None: the command has none)."""
    from delkit.errors import ParseError

    if force:
        return
    ins = [p for p in inputs if p is not None and str(p) not in ("", "-")]
    for out in outputs:
        if out is None or str(out) in ("", "-"):
            continue
        for src in ins:
            if not (_same(out, src) or os.path.abspath(out) == os.path.abspath(src)):
                continue
            how = ""
            if os.path.abspath(out) != os.path.abspath(src):
                how = (" (the same file through a symbolic link)" if os.path.realpath(out) == os.path.realpath(src)
                       else " (the output is a hard link to it)")
            fix = f"give another {option} path" + (" or --force to overwrite it on purpose" if force is False else "")
            raise ParseError(f"{option} would overwrite the input file {src}{how}; nothing was written: {fix}",
                             source=str(out))
