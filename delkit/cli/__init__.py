"""The single ``delkit`` command.

The core's own commands (``demo``, ``version``, ``puzzle``, ``model``, ``smcdel``, ``prove``) live here; every
other command is registered by the package that owns it through the ``delkit.commands`` entry-point group
(:mod:`delkit.cli.plugins`), so the core imports nothing from the layers above it. Commands import their
heavy dependencies inside the command functions, so that ``delkit --help`` stays fast. A
:class:`delkit.errors.DelkitError` is printed as one line on stderr with exit status 2, never as a traceback.
"""

from __future__ import annotations

import os
import sys

__all__ = ["main", "run"]

# numpy's bundled OpenBLAS starts a thread per core when numpy is imported; on this project's machines that
# costs ~70 ms of CPU (more than half of a small `delkit plan`'s 0.12 s) and buys nothing: delkit's matrices
# are small. The CLI runs BLAS on one thread unless the user chose otherwise (OPENBLAS_NUM_THREADS is read
# once, when numpy is first imported, so this must come before any import of numpy).
if "numpy" not in sys.modules:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _build_app():
    """The typer app: the core's own commands, then every ``delkit.commands`` plugin (see :mod:`.plugins`)."""
    import typer

    from delkit.cli import core_cmd, model_cmd, plugins, puzzle_cmd, smcdel_cmd, view_cmd

    app = typer.Typer(
        name="delkit",
        help="delkit: dynamic epistemic logic for multi-agent robotics.",
        no_args_is_help=True,
        add_completion=True,  # --install-completion / --show-completion (bash, zsh, fish, PowerShell)
        pretty_exceptions_enable=False,
    )

    def _print_version(value: bool) -> None:
        if value:
            from delkit import __version__

            typer.echo(f"delkit {__version__}")
            raise typer.Exit(0)

    @app.callback()
    def _root(version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                           help="Print the delkit version and exit.")) -> None:
        """delkit: dynamic epistemic logic for multi-agent robotics (run `delkit COMMAND --help`)."""

    core_cmd.register(app)
    puzzle_cmd.register(app)
    model_cmd.register(app)
    smcdel_cmd.register(app)
    view_cmd.register(app)
    for _, module in plugins.plugin_modules():
        module.register(app)
    return app


def _plain_flags(command) -> None:
    """Show on/off options as flags in the help (``--json``, ``--macros / --no-macros``), without the
    ``<bool>`` type column that typer adds to them; recursively for every sub-command."""
    for param in getattr(command, "params", ()):
        if getattr(param, "is_flag", False) and param.metavar is None:
            param.metavar = ""
    make_help = command.get_help_option

    def help_option(ctx):  # click makes --help per command on demand: the same for it
        option = make_help(ctx)
        if option is not None and option.metavar is None:
            option.metavar = ""
        return option

    command.get_help_option = help_option
    for sub in getattr(command, "commands", {}).values():
        _plain_flags(sub)


class _ClosedStream:
    """``sys.stdout`` / ``sys.stderr`` when the process was started with that descriptor closed (``>&-``):
    writing an answer to it is bad input (exit 2, one line on stderr if stderr is open), not a traceback."""

    def __init__(self, name: str) -> None:
        self.name = name

    def write(self, text: str) -> int:
        from delkit.errors import DelkitError

        if not text:
            return 0
        raise DelkitError(f"standard {self.name} is closed, so the answer cannot be written; start delkit with "
                          f"standard {self.name} open, or send it to a file (e.g. >answer.json)")

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False

    def fileno(self) -> int:
        raise OSError(9, f"standard {self.name} is closed")


def _open_streams() -> None:
    """Replace a stdout / stderr that was closed at start (Python sets it to None) by :class:`_ClosedStream`."""
    if sys.stdout is None:
        sys.stdout = _ClosedStream("output")  # type: ignore[assignment]
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115 - nowhere to report anything: stay silent


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit status (0 ok, 1 a negative answer such as an invalid plan, 2 bad input,
    3 a limit such as ``--timeout`` reached before an answer)."""
    _open_streams()
    args = list(sys.argv[1:] if argv is None else argv)
    import delkit.resources as resources
    from delkit.resources import begin_command

    resources.JSON_LIMITS = "--json" in (args[:args.index("--")] if "--" in args else args)

    begin_command()  # every --timeout counts from here (from process start in the console script's process)
    try:
        fast = _fast_path(args)
        if fast is not None:  # a plain `plan` / `check` line: run without importing typer (start-up time)
            return fast()
        import typer.main

        command = typer.main.get_command(_build_app())
        _plain_flags(command)
        result = command.main(args=args, prog_name="delkit", standalone_mode=False)
    except BaseException as exc:  # noqa: BLE001 - each kind is mapped to its exit status below
        return _exit_status(exc)
    finally:
        resources.end_command()
    return result if isinstance(result, int) else 0


def _fast_path(args: list[str]):
    """The direct call for a plain command line that a plugin handles without typer (``delkit.fast`` entry
    points, e.g. ``plan``/``check``), or None."""
    if not FAST_PATH or not args or args[0].startswith("-"):
        return None
    from delkit.cli.plugins import fast_entry

    fast_args = fast_entry(args[0])
    return None if fast_args is None else fast_args(args)


FAST_PATH = True  # tests switch it off to compare the two paths


def _exit_status(exc: BaseException) -> int:
    """Exit status for an exception that escaped a command (printing its one-line message), or re-raise it."""
    from delkit.errors import DelkitError

    typer = sys.modules.get("typer")
    if isinstance(exc, DelkitError):
        if getattr(exc, "exit_code", 2) == 3:
            import delkit.resources as resources

            if resources.JSON_LIMITS:  # --json: a reached limit is a JSON answer too, with the counts so far
                try:
                    resources.print_limit_record(str(exc))
                except (OSError, DelkitError):  # stdout closed or full: the line on stderr still says it
                    pass
        print(f"delkit: error: {exc}", file=sys.stderr)
        return int(getattr(exc, "exit_code", 2))  # 3: a --timeout reached (delkit.resources.TimeLimit)
    if typer is not None and isinstance(exc, typer.Exit):
        return int(getattr(exc, "exit_code", 0) or 0)
    if typer is not None and isinstance(exc, typer.Abort):
        print("delkit: aborted", file=sys.stderr)
        return 1
    if isinstance(exc, RecursionError):
        # formulas are evaluated recursively: some hundreds of nested operators exceed Python's stack
        print("delkit: error: the input is nested too deeply (more than a few hundred operators inside each "
              "other); split the formula or flatten chains with E{...} / C{...}", file=sys.stderr)
        return 2
    if isinstance(exc, OSError):
        # a file or directory the user named cannot be read or written (any command): bad input, one line
        import errno

        if not exc.filename and exc.errno in (errno.EPIPE, errno.ENOSPC, errno.EBADF):
            try:  # the answer's stream failed (a closed pipe, a full disk): say so once, on stderr
                print(f"delkit: error: cannot write the answer ({exc.strerror or exc}): standard output was closed "
                      f"or is full", file=sys.stderr)
            except (OSError, ValueError):  # pragma: no cover
                pass
            return 2
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"delkit: error: {where}{exc.strerror or exc}; check the path and its permissions", file=sys.stderr)
        return 2
    if isinstance(exc, KeyboardInterrupt):
        print("delkit: interrupted", file=sys.stderr)
        return 130
    if isinstance(exc, Exception) and hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
        # usage errors (unknown option, bad option value, ...) from the click that typer bundles: one line too
        print(_usage_line(exc), file=sys.stderr)
        return int(exc.exit_code)  # type: ignore[attr-defined]
    raise exc


def _usage_line(exc: Exception) -> str:
    """``delkit: error: COMMAND: what is wrong; see 'COMMAND --help'`` for a usage error from click."""
    ctx = getattr(exc, "ctx", None)
    path = getattr(ctx, "command_path", None) or "delkit"
    message = " ".join(str(exc.format_message()).split()).rstrip(".")  # type: ignore[attr-defined]
    return f"delkit: error: {path}: {message}; see '{path} --help'"


def run() -> None:
    """Console-script entry point: run, flush, and leave at once (``os._exit``): freeing a large model or
    search space at interpreter shutdown can take seconds and must not delay the exit (or a --timeout)."""
    import delkit.resources as resources

    resources.HARD_EXIT = True
    _open_streams()
    resources.early_watchdog(sys.argv[1:])  # the --timeout holds even while the command is being imported
    try:
        rc = main()
    except SystemExit as exc:  # pragma: no cover - main returns its status
        rc = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    try:
        sys.stdout.flush()
    except OSError:  # e.g. stdout closed or /dev/full: the output could not be written
        rc = rc or 2
        try:
            sys.stderr.write("delkit: error: the answer could not be written to standard output (closed, full or "
                             "a broken pipe)\n")
        except (OSError, ValueError):  # pragma: no cover
            pass
    try:
        sys.stderr.flush()
    except OSError:  # pragma: no cover
        pass
    if rc != 3:  # a reached limit skips the exit handlers too (they may wait for workers)
        import atexit

        atexit._run_exitfuncs()
    os._exit(rc)
