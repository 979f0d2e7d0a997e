"""Compact product update + refinement, per product, on states of growing world counts.

Three ways to build the contracted, canonical s ⊗ E (all give the very same state; checked on every row):

* **pairs + Python** — the method without the ε copy: every pair (w, e) built one
  by one (``_pair_product``), refined by the pure-Python ``_refine``;
* **copy + Python** — the skip event's pairs (w, ε) are the old state's worlds with its own successor lists
  (``_copy_product``), refined by ``_refine`` (the default below ``NP_REFINE_MIN`` worlds);
* **copy + numpy** — the same product refined by ``delkit.backends.compact_np.refine`` (vectorised; the default from
  ``NP_REFINE_MIN`` worlds on).

Timed region: one product update (the designated events' rows, building the product, refining it), CPU
seconds (``time.process_time``), the shape cache bypassed (scratch states, ``fid = -1``) and the state's copy
cache fresh each time; the state's distinct successor lists (``CompactState.cid``, computed once per state and
shared by all the actions applied to it in a search) are computed before. The median over ``--repeat`` runs
(each run: every sample once per method, interleaved).

States: random S5 models with n worlds (5 agents, random partitions of 2-8 classes, distinct valuations over
16 propositions), the event model an mA* announcement (yes/no/ε: agents a, b fully observant, c partially,
d, e oblivious); then the states of the 5-agent Grapevine BFS (``specs/grapevine5``, the products its
expansions build).

    .venv/bin/python bench/product_update.py [--sizes 16,64,256,1024,4096] [--repeat 5] [--grapevine 300]
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import delkit.backends.compact as compact  # noqa: E402
from delkit.backends.compact import CompactEngine, CompactState, PlainEvents, PlainModel  # noqa: E402
from delkit.logic.formula import Not, Prop, Top  # noqa: E402

AGENTS = ("a", "b", "c", "d", "e")
PROPS = tuple(f"p{i}" for i in range(16))


def announcement() -> PlainEvents:
    """Announcement of p0: a, b fully observant, c partially, d, e oblivious (mA*'s frame)."""
    rows = {"a": [(0,), (1,), (2,)], "b": [(0,), (1,), (2,)], "c": [(0, 1), (0, 1), (2,)],
            "d": [(2,), (2,), (2,)], "e": [(2,), (2,), (2,)]}
    return PlainEvents(("yes", "no", "eps"), AGENTS, (Prop("p0"), Not(Prop("p0")), Top()), ({}, {}, {}), rows,
                       (0,), "tell p0")


def random_state(engine: CompactEngine, n: int, rng: random.Random) -> CompactState:
    vals = rng.sample(range(1 << len(PROPS)), n)
    vals[0] |= 1  # p0 holds at the designated world: the announcement applies
    labels = {a: [rng.randrange(rng.randint(2, 8)) for _ in range(n)] for a in AGENTS}
    return engine.from_plain(PlainModel(PROPS, AGENTS, vals, labels, (0,)))


def scratch(s: CompactState) -> CompactState:
    """The state without its caches and frame number (so the shape cache is not consulted)."""
    return CompactState(s.val, s.masks, s.points)


def run(engine: CompactEngine, s: CompactState, comp: tuple, method: str) -> tuple[float, CompactState]:
    t = scratch(s)
    t.cid  # noqa: B018 - a state's distinct successor lists: once per state, shared by all its actions
    if method == "pairs + Python":
        c, lim = comp[:11] + (None,), 1 << 60
    elif method == "copy + Python":
        c, lim = comp, 1 << 60
    else:
        c, lim = comp, 0
    old = compact.NP_REFINE_MIN
    compact.NP_REFINE_MIN = lim
    try:
        t0 = time.process_time()
        out = engine.apply_compiled(t, c)
        dt = time.process_time() - t0
    finally:
        compact.NP_REFINE_MIN = old
    return dt, out


METHODS = ("pairs + Python", "copy + Python", "copy + numpy")


def measure(engine: CompactEngine, samples: list[tuple[CompactState, tuple]], repeat: int) -> dict[str, float]:
    """Median over ``repeat`` runs of the mean CPU seconds per product; asserts the three methods agree."""
    per: dict[str, list[float]] = {m: [] for m in METHODS}
    for _ in range(repeat):
        tot = dict.fromkeys(METHODS, 0.0)
        for s, comp in samples:
            outs = []
            for m in METHODS:
                dt, out = run(engine, s, comp, m)
                tot[m] += dt
                outs.append(None if out is None else (out.val, out.masks, out.points))
            assert outs[0] == outs[1] == outs[2], "the three products differ"
        for m in METHODS:
            per[m].append(tot[m] / len(samples))
    return {m: statistics.median(v) for m, v in per.items()}


def grapevine_samples(limit: int) -> list[tuple[CompactEngine, CompactState, tuple]]:
    """The (state, compiled event model) pairs the first products of the Grapevine-5 BFS are built from."""
    from planners.epistemic import Limits, bfs
    from planners.lang import load_task
    from planners.spaces import CompactSpace

    task = load_task(ROOT / "specs" / "grapevine5" / "Grapevine_5__pl_6.txt")
    space = CompactSpace(task)
    engine = space.engine
    got: list = []
    real = engine.apply_compiled

    def spy(s, comp):
        if len(got) < limit and comp[11] is not None:
            got.append((s, comp))
        return real(s, comp)

    engine.apply_compiled = spy  # type: ignore[method-assign]
    bfs(space, Limits(timeout=600, max_expanded=1200))
    engine.apply_compiled = real  # type: ignore[method-assign]
    return [(engine, s, c) for s, c in got]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="16,32,64,128,256,512,1024,2048,4096")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--per-size", type=int, default=0, help="states per size (default: 4096 // n, 1..64)")
    ap.add_argument("--grapevine", type=int, default=400, help="Grapevine-5 products sampled (0: none)")
    args = ap.parse_args()
    with open("/proc/loadavg") as fh:
        load0 = fh.read().split()[0]
    print(f"CPU s per product update (median of {args.repeat}); load average at start {load0}, 2 cores")
    print("| states | worlds of s | worlds of the result | pairs + Python | copy + Python | "
          "copy + numpy | pairs / best |")
    print("|---|--:|--:|--:|--:|--:|--:|")
    rng = random.Random(24)
    engine = CompactEngine(PROPS, AGENTS)
    comp = engine.compile(announcement())
    for n in map(int, args.sizes.split(",")):
        count = args.per_size or max(1, min(64, 4096 // n))
        samples = [(random_state(engine, n, rng), comp) for _ in range(count)]
        res = measure(engine, samples, args.repeat)
        outs = [engine.apply_compiled(scratch(s), comp) for s, _ in samples]
        rw = statistics.mean(o.n for o in outs if o is not None)
        best = min(res["copy + Python"], res["copy + numpy"])
        print(f"| random S5 | {n} | {rw:.0f} | " + " | ".join(f"{res[m] * 1e3:.3f} ms" for m in METHODS)
              + f" | {res['pairs + Python'] / best:.2f}× |", flush=True)
    if args.grapevine:
        gs = grapevine_samples(args.grapevine)
        eng = gs[0][0]
        by: dict[str, list] = {}
        for _, s, c in gs:
            by.setdefault("25-48" if s.n < 49 else "49-72" if s.n < 73 else "73+", []).append((s, c))
        for band, smp in sorted(by.items()):
            res = measure(eng, smp, args.repeat)
            best = min(res["copy + Python"], res["copy + numpy"])
            rw = statistics.mean(o.n for o in (eng.apply_compiled(scratch(x), c) for x, c in smp) if o is not None)
            print(f"| Grapevine-5 BFS ({len(smp)} products) | {band} | {rw:.0f} | "
                  + " | ".join(f"{res[m] * 1e3:.3f} ms" for m in METHODS)
                  + f" | {res['pairs + Python'] / best:.2f}× |", flush=True)
    with open("/proc/loadavg") as fh:
        print(f"load average at end {fh.read().split()[0]}")


if __name__ == "__main__":
    main()
