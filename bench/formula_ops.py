"""Micro-benchmark of the formula AST's hot operations: construction, first hash, cached hash, equality of
equal distinct objects, dictionary look-up, pickling — CPU nanoseconds per operation (``time.process_time``,
best of ``--repeat`` rounds, in a child process per checkout). ``--ab DIR`` runs a second checkout (e.g. ``git
worktree add --detach /tmp/old COMMIT``) in alternation with this one: the formula classes before and after a
change, same machine, same load.

    .venv/bin/python bench/formula_ops.py [--ab DIR] [--repeat 7]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

_CHILD = r'''
import json, pickle, sys, time
from delkit.logic.formula import And, K, Not, Prop
repeat = int(sys.argv[1])
ps = [Prop(f"p{i}") for i in range(64)]
fs = [K("a", Not(And((ps[i & 63], ps[(i + 1) & 63])))) for i in range(1024)]
gs = [K("a", Not(And((ps[i & 63], ps[(i + 1) & 63])))) for i in range(1024)]
for f in fs + gs:
    hash(f)
d = {f: i for i, f in enumerate(fs)}
blob = pickle.dumps(fs)

def build(n):
    for i in range(n):
        K("a", Not(And((ps[i & 63], ps[(i + 1) & 63]))))

def build_hash(n):
    for i in range(n):
        hash(K("a", Not(And((ps[i & 63], ps[(i + 1) & 63])))))

def cached(n):
    for i in range(n):
        hash(fs[i & 1023])

def equal(n):
    for i in range(n):
        fs[i & 1023] == gs[i & 1023]

def lookup(n):
    for i in range(n):
        d[gs[i & 1023]]

def prop(n):
    for i in range(n):
        Prop("x")

def unpickle(n):
    for _ in range(n // 1024):
        pickle.loads(blob)

out = {}
for name, fn, n, per in (("build K(a, ~(p & q)) (3 nodes)", build, 50000, 1),
                         ("build + first hash (3 nodes)", build_hash, 50000, 1),
                         ("hash, cached", cached, 200000, 1), ("== of equal distinct formulas", equal, 200000, 1),
                         ("dict look-up, equal distinct key", lookup, 200000, 1), ("Prop('x')", prop, 200000, 1),
                         ("pickle.loads, per formula (4 nodes)", unpickle, 51200, 1)):
    best = min((lambda t: (fn(n), time.process_time() - t)[1])(time.process_time()) for _ in range(repeat))
    out[name] = best / n * 1e9
print(json.dumps(out))
'''


def _run(root: Path, repeat: int) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(root))
    proc = subprocess.run([sys.executable, "-c", _CHILD, str(repeat)], env=env, cwd=root, capture_output=True,
                          text=True, check=True)
    return json.loads(proc.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ab", type=Path, default=None)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--rounds", type=int, default=3, help="child processes per checkout (alternating); best kept")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    roots = [ROOT] + ([args.ab] if args.ab else [])
    best: list[dict[str, float]] = [{} for _ in roots]
    for _ in range(args.rounds):
        for k, root in enumerate(roots):
            for name, ns in _run(root, args.repeat).items():
                best[k][name] = min(ns, best[k].get(name, float("inf")))
    print(f"formula operations, CPU ns per operation, best of {args.rounds} x {args.repeat} (python "
          f"{sys.version.split()[0]}, load average {load0:.1f} before, {os.getloadavg()[0]:.1f} after)")
    head = "| operation | this tree |" + (f" {args.ab} | ratio |" if args.ab else "")
    print(head)
    print("|---|---:|" + ("---:|---:|" if args.ab else ""))
    for name, ns in best[0].items():
        tail = f" {best[1][name]:.0f} | {ns / best[1][name]:.2f} |" if args.ab else ""
        print(f"| {name} | {ns:.0f} |{tail}")


if __name__ == "__main__":
    main()
