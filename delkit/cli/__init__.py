"""The single ``delkit`` command.

Sub-commands live in their own modules and import the heavy layers (planners, sim, arms) lazily, inside
the command functions, so that ``delkit --help`` stays fast. A :class:`delkit.errors.DelkitError` is
printed as one line on stderr with exit status 2, never as a traceback.
"""

from __future__ import annotations

import sys

__all__ = ["main", "run"]


def _build_app():
    import typer

    from delkit.cli import arms_cmd, consistency_cmd, core_cmd, explore_cmd, model_cmd, plan_cmd, puzzle_cmd, smcdel_cmd

    app = typer.Typer(
        name="delkit",
        help="delkit: dynamic epistemic logic for multi-agent robotics.",
        no_args_is_help=True,
        add_completion=False,
        pretty_exceptions_enable=False,
    )

    @app.callback()
    def _root() -> None:
        """delkit: dynamic epistemic logic for multi-agent robotics (run `delkit COMMAND --help`)."""

    core_cmd.register(app)
    puzzle_cmd.register(app)
    model_cmd.register(app)
    plan_cmd.register(app)
    consistency_cmd.register(app)
    explore_cmd.register(app)
    arms_cmd.register(app)
    smcdel_cmd.register(app)
    return app


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit status (0 ok, 1 a negative answer such as an invalid plan, 2 bad input)."""
    import typer

    from delkit.errors import DelkitError

    application = _build_app()
    try:
        result = application(args=list(sys.argv[1:] if argv is None else argv), prog_name="delkit",
                             standalone_mode=False)
    except DelkitError as exc:
        print(f"delkit: error: {exc}", file=sys.stderr)
        return 2
    except typer.Exit as exc:
        return int(getattr(exc, "exit_code", 0) or 0)
    except typer.Abort:
        print("delkit: aborted", file=sys.stderr)
        return 1
    except RecursionError:
        # formulas are evaluated recursively: some hundreds of nested operators exceed Python's stack
        print("delkit: error: the input is nested too deeply (more than a few hundred operators inside each "
              "other); split the formula or flatten chains with E{...} / C{...}", file=sys.stderr)
        return 2
    except OSError as exc:
        # a file or directory the user named cannot be read or written (any command): bad input, one line
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"delkit: error: {where}{exc.strerror or exc}; check the path and its permissions", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("delkit: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:
        # usage errors (unknown option, bad option value, ...) from the click that typer bundles: one line too
        if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
            print(_usage_line(exc), file=sys.stderr)
            return int(exc.exit_code)
        raise
    return result if isinstance(result, int) else 0


def _usage_line(exc: Exception) -> str:
    """``delkit: error: COMMAND: what is wrong; see 'COMMAND --help'`` for a usage error from click."""
    ctx = getattr(exc, "ctx", None)
    path = getattr(ctx, "command_path", None) or "delkit"
    message = " ".join(str(exc.format_message()).split()).rstrip(".")  # type: ignore[attr-defined]
    return f"delkit: error: {path}: {message}; see '{path} --help'"


def run() -> None:
    """Console-script entry point."""
    sys.exit(main())
