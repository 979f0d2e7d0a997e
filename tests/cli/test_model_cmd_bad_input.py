"""Bad input to ``delkit model``: a model without designated worlds is bad input for ``check`` and
``contract`` (no vacuous "holds" for both p and ~p, no unreadable contracted file)."""

from __future__ import annotations

import json

import pytest

from delkit import KripkeModel
from delkit.cli import main
from delkit.io.formats import save


@pytest.fixture
def unpointed(tmp_path):
    path = tmp_path / "m.json"
    save(KripkeModel.build({"u": {"p"}, "v": set()}, {"a": [["u", "v"]]}, designated=[]), path)
    assert json.loads(path.read_text())["designated"] == []
    return str(path)


@pytest.mark.parametrize("argv", [["model", "check", "{m}", "p"], ["model", "check", "{m}", "~p", "--json"],
                                  ["model", "contract", "{m}"]])
def test_model_without_designated_world_is_bad_input(capsys, unpointed, argv) -> None:
    rc = main([a.format(m=unpointed) for a in argv])
    out, err = capsys.readouterr()
    assert rc == 2 and out == ""
    assert err.strip() == (f"delkit: error: {unpointed}: the model has no designated world, so every formula "
                           f"would vacuously hold there; list the actual world(s) in \"designated\"")


def test_pointed_model_still_checks(capsys, tmp_path) -> None:
    path = tmp_path / "m.json"
    save(KripkeModel.build({"u": {"p"}, "v": set()}, {"a": [["u", "v"]]}, designated=["v"]), path)
    assert main(["model", "check", str(path), "~p", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["true_at"] == ["v"]
    assert main(["model", "check", str(path), "p"]) == 1


def test_model_show_json(capsys, tmp_path) -> None:
    from delkit import public_announcement

    km, ev = tmp_path / "m.json", tmp_path / "e.json"
    save(KripkeModel.build({"u": {"p"}, "v": set()}, {"a": {"pairs": [["u", "v"], ["v", "v"]]}},
                           designated=["u"]), km)
    save(public_announcement("p", ["a", "b"], name="ann"), ev)
    assert main(["model", "show", str(km), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["kind"] == "kripke-model" and info["worlds"] == 2 and info["frames"] == ["KD45"]
    assert info["designated"] == ["u"] and info["agents"] == ["a"]
    assert main(["model", "show", str(ev), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["kind"] == "event-model" and info["name"] == "ann" and info["agents"] == ["a", "b"]


@pytest.mark.parametrize(("event", "fragment"), [
    (("p", ["a", "b"]), "the event model uses proposition(s) ['p']"),
    (("q", ["x"]), "has no relation for agent(s) ['a']"),
])
def test_event_file_that_does_not_fit_the_model_names_the_event_option(capsys, tmp_path, event, fragment) -> None:
    from delkit import public_announcement

    km, ev = tmp_path / "m.json", tmp_path / "e.json"
    save(KripkeModel.build({"u": {"q"}, "v": set()}, {"a": [["u", "v"]]}, designated=["u"]), km)
    save(public_announcement(event[0] if event[0] != "p" else "q | p", event[1]), ev)
    rc = main(["model", "check", str(km), "[F,e] q", "--event", f"F={ev}"])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith(f"delkit: error: --event F={ev}: ") and fragment in err
