"""Bad input to ``delkit demo``: a ``--only`` that matches no section, or an ``--out`` that cannot be a
directory, is bad input (exit 2, one line) instead of an empty "ok" run or a traceback."""

from __future__ import annotations

from delkit.cli import main


def _error(capsys, argv: list[str]) -> str:
    rc = main(argv)
    captured = capsys.readouterr()
    assert rc == 2 and captured.out == "" and len(captured.err.strip().splitlines()) == 1
    assert captured.err.startswith("delkit: error: ")
    return captured.err


def test_only_that_matches_nothing_is_bad_input(tmp_path, capsys) -> None:
    err = _error(capsys, ["demo", "--out", str(tmp_path / "d"), "--only", "puzzles", "--only", "nosuch", "--json"])
    assert "--only 'nosuch' matches no demo section" in err and "DEL puzzles" in err
    assert not (tmp_path / "d").exists()      # nothing was run


def test_out_that_is_a_file_is_bad_input(tmp_path, capsys) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert "cannot create the output directory" in _error(capsys, ["demo", "--out", str(blocker / "x"),
                                                                    "--only", "puzzles"])
