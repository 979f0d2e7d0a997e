"""delkit.progress: drawn on stderr only for a terminal, silent with --json, DELKIT_PROGRESS=0 or a pipe."""

from __future__ import annotations

import io

from delkit import progress as pg


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_silent_unless_stderr_is_a_terminal(monkeypatch):
    monkeypatch.delenv("DELKIT_PROGRESS", raising=False)
    monkeypatch.setattr("sys.stderr", io.StringIO())
    assert not pg.enabled()
    monkeypatch.setattr("sys.stderr", _Tty())
    assert pg.enabled()
    assert not pg.enabled(quiet=True)  # --json
    monkeypatch.setenv("DELKIT_PROGRESS", "0")
    assert not pg.enabled()


def test_a_disabled_display_draws_nothing_and_track_yields_everything(monkeypatch, capsys):
    monkeypatch.setattr("sys.stderr", io.StringIO())
    with pg.progress() as bar:
        task = bar.add_task("work", total=3)
        for _ in range(3):
            bar.advance(task)
    assert list(pg.track(range(5), "items")) == [0, 1, 2, 3, 4]
    assert capsys.readouterr().out == ""


def test_an_enabled_display_goes_to_stderr_not_stdout(monkeypatch, capsys):
    err = _Tty()
    monkeypatch.delenv("DELKIT_PROGRESS", raising=False)
    monkeypatch.setattr("sys.stderr", err)
    assert list(pg.track([1, 2], "items", quiet=False)) == [1, 2]
    assert capsys.readouterr().out == ""
