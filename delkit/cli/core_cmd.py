"""Top-level commands owned by the core: ``delkit demo`` and ``delkit version``."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    """Attach this module's commands to the top-level app."""

    @app.command()
    def version() -> None:
        """Print the delkit version."""
        from delkit import __version__

        typer.echo(__version__)
