"""``delkit puzzle …``: the epistemic puzzles of :mod:`delkit.puzzles` with their literature answers.

Every command prints one JSON object with ``--json``, a rich table otherwise. Heavy imports stay inside
the commands. ``--symbolic`` runs a puzzle on the BDD backend (:mod:`delkit.backends.symbolic`); its ``seconds``
field is then the CPU time of building the structure and running the protocol, imports excluded, and
the ``timed`` field says so.
"""

from __future__ import annotations

import json
from typing import Any

import typer


def _emit(data: dict[str, Any], as_json: bool, title: str) -> None:
    if as_json:
        typer.echo(json.dumps(data))
        return
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    table = Table(title=title)
    table.add_column("field")
    table.add_column("value")
    for key, value in data.items():
        table.add_row(key, escape(value if isinstance(value, str) else json.dumps(value)))
    Console().print(table)


_TIMED = ("CPU seconds (time.process_time) of building the knowledge structure and running the protocol; "
          "imports excluded")


def register(app: typer.Typer) -> None:
    """Attach the ``puzzle`` sub-app to the top-level app."""
    from delkit.cli.plugins import group

    # a group, so that a layer above the core can add its own puzzles (planners: ``puzzle muddy-plan``)
    sub = group(app, "puzzle", "Epistemic puzzles solved with DEL (literature answers).")

    @sub.callback(invoke_without_command=True)
    def puzzles(ctx: typer.Context,
                list_: bool = typer.Option(False, "--list", help="list the puzzles, their answers and sources"),
                as_json: bool = typer.Option(False, "--json", help="with --list: print one JSON object")) -> None:
        """Epistemic puzzles solved with DEL (literature answers)."""
        if not list_:
            return
        from delkit.cli.plugins import plugin_puzzles
        from delkit.puzzles import CATALOGUE

        catalogue = CATALOGUE + plugin_puzzles()
        if as_json:
            typer.echo(json.dumps({"puzzles": catalogue}))
        else:
            from rich.console import Console
            from rich.markup import escape
            from rich.table import Table

            table = Table(title="delkit puzzle …")
            for col in ("command", "answer (literature)", "backends", "source", "docs"):
                table.add_column(col)
            for row in catalogue:
                table.add_row(escape(row["command"]), escape(row["answer"]), escape(", ".join(row["backends"])),
                              escape(row["source"]), escape(row["docs"]))
            Console().print(table)
        raise typer.Exit(0)

    @sub.command("muddy")
    def muddy(children: int = typer.Option(3, "--children", "-n", help="number of children N"),
              muddy: int = typer.Option(2, "--muddy", "-m", help="number of muddy children M (1..N)"),
              symbolic: bool = typer.Option(False, "--symbolic", help="use the BDD backend (large N)"),
              timeout: float = typer.Option(0.0, "--timeout", min=0.0,
                                            help="wall-clock limit in seconds (0: none)"),
              as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Muddy children: "nobody knows" is announced M-1 times, then the muddy children know."""
        from delkit.errors import ModelError
        from delkit.resources import deadline

        if children < 1 or not 1 <= muddy <= children:
            raise ModelError(f"puzzle muddy: need 1 <= --muddy <= --children, got --children {children} "
                             f"--muddy {muddy}")
        with deadline(timeout, f"puzzle muddy -n {children}"):
            if symbolic:
                from delkit.backends.symbolic import muddy_symbolic
                from delkit.resources import require

                # measured (n = 500..2000): the "nobody knows" BDDs grow with n², 45-60 bytes per child²
                require(1024.0 * children + 64.0 * float(children) ** 2, f"puzzle muddy --symbolic -n {children}",
                        "use a smaller --children")

                data = muddy_symbolic(children, muddy).as_dict() | {"timed": _TIMED}
            else:
                from delkit.puzzles.muddy import solve_muddy

                data = solve_muddy(children, muddy).as_dict()
        _emit(data, as_json, f"muddy children N={children}, M={muddy}")

    @sub.command("sum-product")
    def sum_product(limit: int = typer.Option(100, "--limit", help="x + y <= LIMIT"),
                    symbolic: bool = typer.Option(False, "--symbolic", help="use the BDD backend (SMCDEL's "
                                                  "encoding: bits of x, y, x+y, x*y)"),
                    smcdel: bool = typer.Option(False, "--smcdel", help="with --symbolic: evaluate SMCDEL's own "
                                                "protocol formula (knows = OR over pairs of K(x=a & y=b))"),
                    timeout: float = typer.Option(0.0, "--timeout", min=0.0,
                                                  help="wall-clock limit in seconds (0: none)"),
                    as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Freudenthal's Sum and Product: the unique solution (4, 13) for 1 < x < y, x + y <= 100."""
        from delkit.errors import ModelError
        from delkit.puzzles.sum_product import smcdel_sum_product, solve_sum_product
        from delkit.resources import deadline, require, sum_product_bytes

        if limit < 5:
            raise ModelError(f"puzzle sum-product: --limit must be at least 5, got {limit}")
        if smcdel and not symbolic:
            raise ModelError("puzzle sum-product: --smcdel needs --symbolic")
        # the symbolic structure is built from the same pairs (numpy.triu_indices(limit)): the same estimate
        require(sum_product_bytes(limit), f"puzzle sum-product --limit {limit}{' --symbolic' if symbolic else ''}",
                "use a smaller --limit")
        with deadline(timeout, f"puzzle sum-product --limit {limit}"):
            if smcdel:
                pairs, seconds = smcdel_sum_product(limit)
                data = {"puzzle": "sum-product", "engine": "symbolic", "formula": "smcdel",
                        "solutions": [list(p) for p in pairs], "seconds": seconds, "timed": _TIMED}
            else:
                data = solve_sum_product(limit, symbolic=symbolic).as_dict()
                if symbolic:
                    data["timed"] = _TIMED
        _emit(data, as_json, "Sum and Product")

    @sub.command("cheryl")
    def cheryl(as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Cheryl's birthday: July 16."""
        from delkit.puzzles.cheryl import solve_cheryl

        _emit(solve_cheryl().as_dict(), as_json, "Cheryl's birthday")

    @sub.command("russian-cards")
    def russian_cards(as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Russian cards: 102 safe announcements of 5, 6 or 7 hands by Alice (deal 012|345|6)."""
        from delkit.puzzles.russian_cards import solve_russian_cards

        _emit(solve_russian_cards().as_dict(), as_json, "Russian cards")

    @sub.command("drinking")
    def drinking(wants: str = typer.Option("111", "--wants", help="one digit per logician: 1 wants a drink"),
                 n: int = typer.Option(None, "--n", help="N logicians who all want a drink (instead of --wants)"),
                 symbolic: bool = typer.Option(False, "--symbolic", help="use the BDD backend (hundreds of "
                                               "logicians)"),
                 formula: bool = typer.Option(False, "--formula", help="evaluate SMCDEL's single nested formula "
                                              "(all want; answers: true) instead of the turn-by-turn protocol"),
                 as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Logicians in a bar: "Does everyone want a drink?"."""
        from delkit.errors import ModelError
        from delkit.puzzles.drinking import check_thirsty, solve_drinking

        if n is not None:
            if n < 1:
                raise ModelError(f"puzzle drinking: --n must be at least 1, got {n}")
            wants = "1" * n
        if not wants or set(wants) - {"0", "1"}:
            raise ModelError(f"puzzle drinking: --wants must be digits 0/1, got {wants!r}")
        if not symbolic and len(wants) > 16:
            raise ModelError(f"puzzle drinking: {len(wants)} logicians means 2^{len(wants)} explicit worlds (at "
                             "most 16 explicitly); add --symbolic for the BDD backend")
        if formula:
            if set(wants) != {"1"}:
                raise ModelError("puzzle drinking: --formula is SMCDEL's check for the state where all want; "
                                 "use --n N (or --wants 11…1)")
            ok, seconds = check_thirsty(len(wants), symbolic=symbolic)
            data = {"puzzle": "drinking", "engine": "symbolic" if symbolic else "explicit", "formula": "smcdel",
                    "n": len(wants), "holds": ok, "seconds": seconds}
        else:
            data = solve_drinking(tuple(c == "1" for c in wants), symbolic=symbolic).as_dict()
        data["timed"] = _TIMED.replace("knowledge structure", "model" if not symbolic else "knowledge structure")
        _emit(data, as_json, "drinking logicians")

    @sub.command("dining")
    def dining(n: int = typer.Option(3, "--n", help="number of cryptographers"),
               payer: int = typer.Option(0, "--payer", help="who paid: 0..n-1, or -1 for the NSA"),
               coins: int = typer.Option(0, "--coins", help="the coins as a bitmask (bit i: coin i heads)"),
               symbolic: bool = typer.Option(False, "--symbolic", help="use the BDD backend (large n)"),
               smcdel: bool = typer.Option(False, "--smcdel", help="with --symbolic: check SMCDEL's benchmark "
                                           "formula on SMCDEL's encoding (complete graph of shared bits)"),
               as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Dining cryptographers: everybody learns whether one of them paid, not who."""
        from delkit.errors import ModelError
        from delkit.puzzles.dining import smcdel_dining_check, solve_dining

        cap = None if symbolic else 10
        if n < 2 or (cap is not None and n > cap) or not -1 <= payer < n or not 0 <= coins < (1 << n):
            limit = "" if cap is None else f" <= {cap} (explicit; add --symbolic for more)"
            raise ModelError(f"puzzle dining: need 2 <= --n{limit}, -1 <= --payer < n, 0 <= --coins < 2^n; got "
                             f"--n {n} --payer {payer} --coins {coins}")
        if smcdel and not symbolic:
            raise ModelError("puzzle dining: --smcdel needs --symbolic")
        if smcdel:
            ok, seconds = smcdel_dining_check(n)
            data = {"puzzle": "dining", "engine": "symbolic", "formula": "smcdel", "n": n, "valid": ok,
                    "seconds": seconds}
        else:
            data = solve_dining(n, None if payer < 0 else payer, coins, symbolic=symbolic).as_dict()
        data["timed"] = _TIMED.replace("knowledge structure", "model" if not symbolic else "knowledge structure")
        _emit(data, as_json, "dining cryptographers")

    @sub.command("gossip")
    def gossip(n: int = typer.Option(4, "--n", help="number of agents (2..4; 4 takes ~20 s CPU, ~1 min with "
                                     "--variant kw)"),
               variant: str = typer.Option("s5", "--variant", help="s5: who has whose secret (SMCDEL's GossipS5); "
                                           "kw: secrets as facts, experts know whether (SMCDEL's GossipKw)"),
               symbolic: bool = typer.Option(True, "--symbolic/--explicit", help="with --variant kw: belief "
                                             "structure or explicit model (explicit: n <= 3)"),
               as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Gossip: the least number of calls making everyone an expert (2n-4 for n >= 4); symbolic."""
        from delkit.errors import ModelError

        if not 2 <= n <= 4:
            raise ModelError(f"puzzle gossip: --n must be 2..4 (the search is a depth-first search over call "
                             f"sequences), got {n}")
        if variant not in ("s5", "kw"):
            raise ModelError(f"puzzle gossip: --variant must be s5 or kw, got {variant!r}")
        if not symbolic and (variant != "kw" or n > 3):
            raise ModelError("puzzle gossip: --explicit needs --variant kw and --n <= 3 (16 x 6^k worlds after k "
                             "calls for n = 4)")
        timed = _TIMED.replace("running the protocol", "searching the call sequences")
        if variant == "kw":
            from delkit.puzzles.gossip import solve_gossip_kw

            data = solve_gossip_kw(n, symbolic=symbolic).as_dict() | {
                "timed": timed if symbolic else timed.replace("knowledge structure", "model")}
        else:
            from delkit.puzzles.gossip import solve_gossip

            data = solve_gossip(n).as_dict() | {"timed": timed}
        _emit(data, as_json, f"gossip ({variant}), {n} agents")

    @sub.command("what-sum")
    def what_sum(bound: int | None = typer.Option(None, "--bound", help="SMCDEL's bounded model, numbers 1..BOUND "
                                                  "(default: the unbounded puzzle, decided exactly)"),
                 anne_says: int = typer.Option(50, "--anne-says", help="the number Anne finally announces"),
                 symbolic: bool = typer.Option(True, "--symbolic/--explicit", help="BDD backend or explicit model"),
                 as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """What Sum: three "I don't know my number"s, then Anne knows hers."""
        from delkit.errors import ModelError
        from delkit.puzzles.what_sum import solve_what_sum

        if bound is None:
            if anne_says < 1:
                raise ModelError(f"puzzle what-sum: --anne-says must be a positive integer, got {anne_says}")
        elif not 3 <= bound <= 255 or not 1 <= anne_says <= bound:
            raise ModelError(f"puzzle what-sum: need 3 <= --bound <= 255 and 1 <= --anne-says <= --bound, got "
                             f"--bound {bound} --anne-says {anne_says}")
        timed = _TIMED if bound is not None else "CPU seconds (time.process_time) of the unbounded decision"
        data = solve_what_sum(bound, anne_says, symbolic=symbolic).as_dict() | {"timed": timed}
        _emit(data, as_json, "What Sum")

    @sub.command("door-mat")
    def door_mat(as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Door mat: tryTake gets Bob the key, but only after Anne's announcement does he know it will."""
        from delkit.puzzles.door_mat import solve_door_mat

        _emit(solve_door_mat().as_dict() | {"timed": _TIMED}, as_json, "door mat")

    @sub.command("hanabi")
    def hanabi(players: int = typer.Option(2, "--players", help="number of players"),
               cards: int = typer.Option(5, "--cards", help="cards 0..CARDS-1 (the undealt ones are the deck)"),
               hand: int = typer.Option(2, "--hand", help="cards per player"),
               player: int = typer.Option(1, "--player", help="the player who gets the hints (1..players)"),
               symbolic: bool = typer.Option(True, "--symbolic/--explicit", help="knowledge structure or explicit "
                                             "model"),
               as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Hanabi-style hints: which hints make playing card 0 safe (2 players, cards 0-4: hint 0, or 1 and 4)."""
        from delkit.puzzles.hanabi import solve_hanabi

        data = solve_hanabi(players, cards, hand, player=player, symbolic=symbolic).as_dict()
        data["timed"] = _TIMED.replace("running the protocol", "checking every hint and pair of hints")
        if not symbolic:
            data["timed"] = data["timed"].replace("knowledge structure", "model")
        _emit(data, as_json, "Hanabi-style hints")

    @sub.command("all")
    def all_puzzles(as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Run every puzzle and compare with the literature answers."""
        from delkit.progress import progress
        from delkit.puzzles import N_PUZZLES, summary_table

        with progress(quiet=as_json) as bar:
            job = bar.add_task("puzzles", total=N_PUZZLES)
            rows = summary_table(lambda row: bar.advance(job))
        if as_json:
            typer.echo(json.dumps({"puzzles": rows, "ok": all(r["ok"] for r in rows)}))
        else:
            from rich.console import Console
            from rich.markup import escape
            from rich.table import Table

            table = Table(title="delkit puzzles")
            for col in ("puzzle", "answer", "expected", "ok", "seconds"):
                table.add_column(col)
            for r in rows:
                table.add_row(escape(r["puzzle"]), escape(json.dumps(r["answer"])), escape(json.dumps(r["expected"])),
                              "yes" if r["ok"] else "NO", f"{r['seconds']:.3f}")
            Console().print(table)
        if not all(r["ok"] for r in rows):
            raise typer.Exit(1)

    # ---- protocols: prisoners, letter passing, coin flip, number triangle
    @sub.command("prisoners")
    def prisoners(n: int = typer.Option(4, "--prisoners", "-n", help="number of prisoners (prisoner 1 counts)"),
                  days: int = typer.Option(500, "--days", help="at most this many days (the bound)"),
                  seed: int = typer.Option(0, "--seed", help="seed of the uniformly random schedule"),
                  schedule: str = typer.Option("", "--schedule", help="the prisoners interviewed, day by day, e.g. "
                                               "2,1,3,1 (instead of a random schedule)"),
                  symbolic: bool = typer.Option(False, "--symbolic", help="knowledge structure and transformers "
                                                "instead of the explicit model (more than 7 prisoners: the same "
                                                "reduced structure by a relational product, up to 200)"),
                  as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """100 prisoners and a light bulb (bounded): the counter knows exactly when his count reaches n-1."""
        from delkit.errors import ModelError
        from delkit.puzzles.prisoners import MAX_EXPLICIT, MAX_TRANSFORMER, solve_prisoners
        from delkit.resources import require

        engine = "symbolic" if symbolic else "explicit"
        sched = None
        if schedule:
            try:
                sched = [int(x) for x in schedule.split(",")]
            except ValueError:
                raise ModelError(f"puzzle prisoners: --schedule must be prisoner numbers separated by commas, e.g. "
                                 f"2,1,3,1; got {schedule!r}") from None
        if symbolic and n > MAX_TRANSFORMER:
            engine = "image"  # the same reduced structure, by a relational product (module docstring)
            # measured: the law peaks at ~1.25 n^2 nodes (12,401 at n = 100); CUDD ~40 bytes a node, plus
            # the transition relations and the computed table: 400 bytes per n^2 is generous
            require(400.0 * n * n + (1 << 24), f"puzzle prisoners -n {n} --symbolic", "use fewer --prisoners")
        if not symbolic and 2 <= n <= MAX_EXPLICIT:
            # the contracted model has at most 2·3^(n-1)·2 worlds (light, each other prisoner: not seen /
            # seen / switched, the counter seen) and the product n events per world, ~200 bytes per pair
            require(200.0 * n * 4 * 3.0 ** (n - 1), f"puzzle prisoners -n {n}", "use fewer --prisoners")
        data = solve_prisoners(n, days, seed, schedule=sched, engine=engine).as_dict()
        data["timed"] = _TIMED.replace("knowledge structure", "structure" if symbolic else "model").replace(
            "running the protocol", "every day's update and reduction")
        _emit(data, as_json, f"{n} prisoners and a light bulb")

    @sub.command("letter-passing")
    def letter_passing(n: int = typer.Option(3, "--agents", "-n", help="agents 1..N in a line"),
                       to: int = typer.Option(None, "--to", help="the addressee, 2..N (default N)"),
                       symbolic: bool = typer.Option(False, "--symbolic", help="use the BDD backend"),
                       as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Letter passing: who knows the address (and the goal) after each pass 1->2->...->addressee."""
        from delkit.puzzles.letter_passing import solve_letter_passing

        data = solve_letter_passing(n, to, engine="symbolic" if symbolic else "explicit").as_dict()
        data["timed"] = _TIMED.replace("knowledge structure", "structure" if symbolic else "model")
        _emit(data, as_json, f"letter passing, {n} agents")

    @sub.command("coin-flip")
    def coin_flip(outcome: str = typer.Option("tails", "--outcome", help="heads or tails"),
                  oblivious: bool = typer.Option(False, "--oblivious", help="Anne does not notice the flip (KD45) "
                                                 "instead of watching it without seeing the outcome"),
                  symbolic: bool = typer.Option(False, "--symbolic", help="BDD backend: a knowledge structure, or a "
                                                "belief structure with --oblivious"),
                  as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Coin flip shown to Bob: he knows the outcome; Anne knows he does, or (oblivious) still believes heads."""
        from delkit.errors import ModelError
        from delkit.puzzles.coin_flip import solve_coin_flip

        if outcome not in ("heads", "tails"):
            raise ModelError(f"puzzle coin-flip: --outcome must be heads or tails, got {outcome!r}")
        mode = "oblivious" if oblivious else "partial"
        engine = ("belief" if oblivious else "symbolic") if symbolic else "explicit"
        data = solve_coin_flip(outcome == "heads", mode, engine=engine).as_dict() | {"timed": _TIMED}
        _emit(data, as_json, "coin flip")

    @sub.command("number-triangle")
    def number_triangle(children: int = typer.Option(10, "--children", "-n", help="number of children N"),
                        muddy: int = typer.Option(4, "--muddy", "-m", help="number of muddy children M"),
                        quantifier: str = typer.Option("some", "--quantifier", "-q", help="the father's announcement "
                                                       "'Q of you are muddy': some, all, none, even, odd, "
                                                       "at-least-K, at-most-K, exactly-K, more-than-K, "
                                                       "fewer-than-K, or counts like 1,3,4"),
                        explicit: bool = typer.Option(False, "--explicit", help="run the same protocol on the "
                                                      "classical 2^N-world model instead of the triangle"),
                        symbolic: bool = typer.Option(False, "--symbolic", help="run it on a knowledge structure "
                                                      "(V = the N muddy bits) instead of the triangle"),
                        as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Muddy children on the number triangle: 2N+1 points; 'some' gives M-1 rounds of 'nobody knows'."""
        from delkit.errors import ModelError
        from delkit.puzzles.number_triangle import MAX_CHILDREN, solve_number_triangle
        from delkit.resources import require

        if explicit and symbolic:
            raise ModelError("puzzle number-triangle: choose one of --explicit and --symbolic")
        engine = "explicit" if explicit else "symbolic" if symbolic else "triangle"
        if engine == "triangle" and 1 <= children <= MAX_CHILDREN:
            require(64.0 * (children + 1), f"puzzle number-triangle -n {children}", "use fewer --children")
        data = solve_number_triangle(children, muddy, quantifier, engine=engine).as_dict()
        data["timed"] = _TIMED.replace("knowledge structure", "knowledge structure" if symbolic else "model")
        _emit(data, as_json, f"number triangle N={children}, M={muddy}, Q={quantifier}")
