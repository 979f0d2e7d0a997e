"""Bad input to ``delkit arms``: unreadable plans, unwritable outputs and impossible options are one
``delkit: error:`` line with exit status 2 (no traceback, and no simulation run before the check)."""

from __future__ import annotations

from pathlib import Path

import pytest

from delkit.cli import main

DEMO = str(Path(__file__).resolve().parents[2] / "arms" / "demo_plan.json")


def _error(capsys, argv: list[str]) -> str:
    rc = main(argv)
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1 and err.startswith("delkit: error: "), err
    return err


def test_plan_that_is_a_directory(tmp_path, capsys) -> None:
    assert f"{tmp_path}: the plan file is a directory" in _error(capsys, ["arms", "run", str(tmp_path)])


def test_plan_that_is_not_text(tmp_path, capsys) -> None:
    p = tmp_path / "p.json"
    p.write_bytes(bytes(range(128, 256)))
    assert "not a text file" in _error(capsys, ["arms", "run", str(p)])


def test_scene_written_onto_a_directory(tmp_path, capsys) -> None:
    assert "cannot write the MJCF file" in _error(capsys, ["arms", "scene", str(tmp_path)])


def test_unusable_out_directory_is_reported_before_simulating(tmp_path, capsys) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    err = _error(capsys, ["arms", "run", DEMO, "--out", str(blocker / "sub"), "--no-video"])
    assert "cannot create the output directory" in err


@pytest.mark.parametrize(("argv", "fragment"), [
    (["arms", "run", DEMO, "--tolerance", "-1"], "--tolerance must be a positive distance"),
    (["arms", "bench-ik", "--targets", "1", "--budget-ms", "0"], "--budget-ms must be a positive time"),
])
def test_impossible_options(capsys, argv, fragment) -> None:
    assert fragment in _error(capsys, argv)
