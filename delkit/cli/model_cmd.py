"""CLI commands for the model part of delkit. Heavy imports stay inside commands."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    """Attach this module's commands to the top-level app."""
    return None
