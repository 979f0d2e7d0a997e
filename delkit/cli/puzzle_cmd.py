"""``delkit puzzle …``: the epistemic puzzles of :mod:`delkit.puzzles` with their literature answers.

Every command prints one JSON object with ``--json``, a rich table otherwise. Heavy imports stay inside
the commands.
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


def register(app: typer.Typer) -> None:
    """Attach the ``puzzle`` sub-app to the top-level app."""
    sub = typer.Typer(help="Epistemic puzzles solved with DEL (literature answers).", no_args_is_help=True)
    app.add_typer(sub, name="puzzle")

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
                from delkit.symbolic import muddy_symbolic

                data = muddy_symbolic(children, muddy).as_dict()
            else:
                from delkit.puzzles.muddy import solve_muddy

                data = solve_muddy(children, muddy).as_dict()
        _emit(data, as_json, f"muddy children N={children}, M={muddy}")

    @sub.command("sum-product")
    def sum_product(limit: int = typer.Option(100, "--limit", help="x + y <= LIMIT"),
                    timeout: float = typer.Option(0.0, "--timeout", min=0.0,
                                                  help="wall-clock limit in seconds (0: none)"),
                    as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Freudenthal's Sum and Product: the unique solution (4, 13) for 1 < x < y, x + y <= 100."""
        from delkit.errors import ModelError
        from delkit.puzzles.sum_product import solve_sum_product
        from delkit.resources import deadline

        if limit < 5:
            raise ModelError(f"puzzle sum-product: --limit must be at least 5, got {limit}")
        from delkit.resources import require, sum_product_bytes

        require(sum_product_bytes(limit), f"puzzle sum-product --limit {limit}", "use a smaller --limit")
        with deadline(timeout, f"puzzle sum-product --limit {limit}"):
            data = solve_sum_product(limit).as_dict()
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
                 as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Logicians in a bar: "Does everyone want a drink?"."""
        from delkit.errors import ModelError
        from delkit.puzzles.drinking import solve_drinking

        if not wants or set(wants) - {"0", "1"} or len(wants) > 16:
            raise ModelError(f"puzzle drinking: --wants must be 1 to 16 digits 0/1, got {wants!r}")
        _emit(solve_drinking(tuple(c == "1" for c in wants)).as_dict(), as_json, "drinking logicians")

    @sub.command("dining")
    def dining(n: int = typer.Option(3, "--n", help="number of cryptographers"),
               payer: int = typer.Option(0, "--payer", help="who paid: 0..n-1, or -1 for the NSA"),
               coins: int = typer.Option(0, "--coins", help="the coins as a bitmask (bit i: coin i heads)"),
               as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Dining cryptographers: everybody learns whether one of them paid, not who."""
        from delkit.errors import ModelError
        from delkit.puzzles.dining import solve_dining

        if not 2 <= n <= 10 or not -1 <= payer < n or not 0 <= coins < (1 << n):
            raise ModelError(f"puzzle dining: need 2 <= --n <= 10, -1 <= --payer < n, 0 <= --coins < 2^n; got "
                             f"--n {n} --payer {payer} --coins {coins}")
        _emit(solve_dining(n, None if payer < 0 else payer, coins).as_dict(), as_json, "dining cryptographers")

    @sub.command("all")
    def all_puzzles(as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Run every puzzle and compare with the literature answers."""
        from delkit.puzzles import summary_table

        rows = summary_table()
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
