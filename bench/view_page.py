"""``delkit view`` page benchmark: load a page and evaluate one formula, in headless Chromium.

For each model (the README's two-world coin after "a peeks", 4 worlds; muddy3 from SMCDEL, 8; a seeded random
S5 model of 1,000 worlds, 10 propositions, 3 agents, classes of 5 — ``delkit.view.samples.random_s5``), the
document is built once (server start-up: reading, layout, the page's JSON; CPU seconds of this process) and then
``--rounds`` times:

* **load** — a fresh navigation to the page until it has drawn its graph (``performance.now()`` in the page
  at the end of its first render: HTML, the scripts incl. cytoscape.js, the document JSON, drawing);
* **eval** — the formula typed into the box's function: the request to ``api/eval`` (the server parses with
  delkit's parser and evaluates with ``KripkeModel.check``) and the highlighting of the answer
  (``performance.now()`` around it, in the page);
* **total** = load + eval; the server's own CPU for the evaluation is timed separately (``process_time``).

Times in the page are wall-clock milliseconds of Chromium (its CPU time is not observable from the page),
so the load average is printed beside them. The target: total ≤ 500 ms for 1,000 worlds.

    .venv/bin/python bench/view_page.py [--rounds 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def models(tmp: Path) -> list[tuple[str, list[Path], str]]:
    from delkit import KripkeModel, product_update, sensing
    from delkit.io.formats import dumps
    from delkit.view.samples import random_s5

    coin = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0, 1]], "c": [[0, 1]]}, designated=[0])
    after = product_update(coin, sensing("p", ["a", "b", "c"], full=["a"], partial=["b"]))
    (tmp / "after.json").write_text(dumps(after))
    (tmp / "big.json").write_text(dumps(random_s5(1000)))
    return [("README coin after peek (4 worlds)", [tmp / "after.json"], "K_b Kw_a p"),
            ("muddy3.smcdel.txt (8 worlds)", [ROOT / "specs/smcdel/muddy3.smcdel.txt"], "amy knows whether 1"),
            ("random S5, 1,000 worlds", [tmp / "big.json"], "K_a p0 & ~K_b p1")]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    from delkit.view.browser import chromium, open_page, why_unavailable
    from delkit.view.document import evaluate, load_document
    from delkit.view.server import start

    why = why_unavailable()
    if why:
        print(f"skipped: {why}")
        return
    rows = []
    with tempfile.TemporaryDirectory() as d, chromium() as drv:
        for name, files, formula in models(Path(d)):
            t0 = time.process_time()
            doc = load_document(files)
            srv = start(doc)  # builds the page's JSON (layout) before serving
            build = time.process_time() - t0
            t0 = time.process_time()
            evaluate(doc, 0, "state", formula)
            server_eval = time.process_time() - t0
            loads, evals = [], []
            try:
                for _ in range(args.rounds):
                    loads.append(open_page(drv, srv.url, timeout=60))
                    drv.execute_async_script(
                        "const done = arguments[arguments.length - 1];"
                        "delkitView.evaluate(arguments[0]).then(() => done(delkitView.timings.eval));", formula)
                    evals.append(float(drv.execute_script("return delkitView.timings.eval")))
            finally:
                srv.stop()
            tot = [a + b for a, b in zip(loads, evals, strict=True)]
            rows.append((name, build, server_eval * 1000, statistics.median(loads), statistics.median(evals),
                         statistics.median(tot), max(tot)))
    load = Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else ["?"] * 3
    print(f"delkit view page: load + one formula in headless Chromium, {args.rounds} rounds, median "
          f"(load average {' '.join(load)})")
    print(f"{'model':36s} {'start-up CPU s':>14s} {'server eval CPU ms':>18s} {'load ms':>8s} {'eval ms':>8s} "
          f"{'total ms':>9s} {'worst ms':>9s}")
    for r in rows:
        print(f"{r[0]:36s} {r[1]:14.2f} {r[2]:18.1f} {r[3]:8.0f} {r[4]:8.0f} {r[5]:9.0f} {r[6]:9.0f}")


if __name__ == "__main__":
    main()
