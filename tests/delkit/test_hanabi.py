"""The Hanabi-style card game (delkit.puzzles.hanabi): the hand-derived answer on both backends, and both
backends against a direct count of the deals a player cannot tell apart (hypothesis)."""

from __future__ import annotations

import itertools
import json

from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.puzzles.hanabi import deal, hanabi_model, hanabi_structure, hint, safe_play, solve_hanabi


def test_default_game_answer_both_backends() -> None:
    """Player 1 holds 0 1, player 2 holds 2 3, card 4 is in the deck (module docstring): "0" alone makes
    playing 0 safe; as pairs, those with "0" and {"1", "4"}."""
    for symbolic in (True, False):
        r = solve_hanabi(symbolic=symbolic)
        assert not r.safe_initially
        assert r.safe_after_one == (0,)
        assert r.safe_after_two == ((0, 1), (0, 2), (0, 3), (0, 4), (1, 4))
        assert r.knows_position_after_one == {0: (0,), 1: (1,)}


def _oracle(players: int, cards: int, hand: int, player: int, hints: tuple[int, ...]) -> bool:
    """Safe for ``player`` after ``hints``: card 0 is at one position in every deal she cannot rule out
    (the others' cards as dealt, her own consistent with the hints)."""
    actual = deal(players, hand)
    others = {s: c for s, c in actual.items() if s[0] != player}
    free = [c for c in range(cards) if c not in others.values()]
    where = set()
    for mine in itertools.permutations(free, hand):
        if all((mine[p] == v) == (actual[player, p] == v) for v in hints for p in range(hand)):
            where.add(mine.index(0) if 0 in mine else None)
    return len(where) == 1 and None not in where


@settings(max_examples=25, deadline=None)
@given(st.tuples(st.integers(2, 3), st.integers(1, 2)).flatmap(
    lambda ph: st.tuples(st.just(ph[0]), st.integers(ph[0] * ph[1], ph[0] * ph[1] + 2), st.just(ph[1]),
                         st.integers(1, ph[0]))).flatmap(
    lambda g: st.tuples(st.just(g), st.lists(st.integers(0, g[1] - 1), max_size=3, unique=True))))
def test_backends_against_direct_count(game: tuple[tuple[int, int, int, int], list[int]]) -> None:
    (players, cards, hand, player), hints = game
    ks, km = hanabi_structure(players, cards, hand), hanabi_model(players, cards, hand)
    for v in hints:
        ks, km = ks.announce(hint(player, v, players, hand)), km.announce(hint(player, v, players, hand))
    want = _oracle(players, cards, hand, player, tuple(hints))
    assert ks.holds(safe_play(player, hand)) == want == km.holds(safe_play(player, hand))


def test_cli(capsys) -> None:
    from delkit.cli import main

    for engine in ("--symbolic", "--explicit"):
        assert main(["puzzle", "hanabi", engine, "--json"]) == 0
        data = json.loads(capsys.readouterr().out)
        assert data["safe_after_one_hint"] == [0] and [1, 4] in data["safe_after_two_hints"]
    assert main(["puzzle", "hanabi", "--players", "4", "--hand", "2", "--cards", "8"]) == 2
    assert "players*hand" in capsys.readouterr().err
