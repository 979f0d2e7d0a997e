"""The conventions a Python user expects of the command: --version, python -m delkit, shell completion, and
help that reads as help (flags without a <bool> type, no internal jargon such as "seed 002")."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from delkit import __version__
from delkit.cli import _build_app, main

ROOT = Path(__file__).resolve().parents[2]


def _paths(command, prefix=()):
    yield prefix
    for name, sub in sorted(getattr(command, "commands", {}).items()):
        yield from _paths(sub, (*prefix, name))


def test_version_flag_and_python_m(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"delkit {__version__}"
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    out = subprocess.run([sys.executable, "-m", "delkit", "--version"], capture_output=True, text=True, env=env,
                         check=True).stdout
    assert out.strip() == f"delkit {__version__}"


def test_every_help_page_is_readable(capsys):
    import typer.main

    paths = list(_paths(typer.main.get_command(_build_app())))
    assert len(paths) > 20
    for path in paths:
        assert main([*path, "--help"]) == 0, path
        text = capsys.readouterr().out
        where = "delkit " + " ".join(path)
        assert "<bool>" not in text, f"{where} --help shows a flag as <bool>"
        assert not re.search(r"\bseed 00[024]\b", text), f"{where} --help speaks of the papers by file number"
        if path == ():
            assert "--install-completion" in text and "--version" in text
    capsys.readouterr()


def test_model_help_names_the_formats_it_reads(capsys):
    assert main(["model", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "draw them (DOT)" not in text and "SVG, PNG, TikZ" in text.replace("│ ", "")


def test_epico_table_has_a_legend():
    from planners.cli.epico_cmd import LEGEND, format_tables

    cell = {"goal": "gamma", "colors": 1, "status": "ND"}
    text = format_tables([cell])
    assert LEGEND in text
    for column in ("reading", "off", "on", "CPU s", "exp", "br", "off/on", "init", "paper init", "echosys",
                   "cpu ms", "calls", "max ms", "paper calls"):
        assert column in text.split("Legend:")[0] and column in LEGEND, column
    assert "TO =" in LEGEND and "ND =" in LEGEND


def test_shell_completion_completes_command_names():
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", "_DELKIT_COMPLETE": "complete_bash",
           "COMP_WORDS": "delkit mo", "COMP_CWORD": "1"}
    out = subprocess.run([sys.executable, "-m", "delkit"], capture_output=True, text=True, env=env).stdout
    assert out.split() == ["model"]
