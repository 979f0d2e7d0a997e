"""Benchmark: Table I of seed 002 (action consistency, search and rescue) — ours beside the paper's.

Run:  .venv/bin/python bench/consistency.py [--seeds 10] [--epochs 200] [--quick] [--plot fig4.png]
      [--sections ABCDEFGHI]

Prints markdown tables:
  A. Table I, seed 0, 10×10 grid, beside the paper's figures (Julia, i7-6500U);
  B. mean ± sd over seeds on a 10×10 and a 20×20 grid; Baseline-I without (paper, default) and with re-sending
     of a lost backlog; ENFORCEAC's COMM saving counted in messages and in observations sent;
  C. time of one E = 200 episode of ENFORCEAC vs the paper's (speed-up ratio, target ≥ 10×);
  D. ablations (what a robot sends, trigger rule, tie-break, Baseline-I with/without re-sending);
  E. N = 2, 3, 4 robots;
  F. Fig. 4(a): mean objective J of ENFORCEAC vs Baseline-I (does "slightly worse" hold?);
  G. every choice the paper does not make, with its value and where it is set;
  H. Baseline-II's Not-AC under the three tie-break rules (common random / index / each robot its own);
  I. ENFORCEAC with and without the exact pruning of irrelevant observations: what it moves (COMM) and what it
     does not (Not-AC, speed), beside the paper — the like-for-like speed row;
and the number of Theorem-3.3 violations seen in every ENFORCEAC episode (must be 0).
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from delkit.progress import track  # noqa: E402
from sim.sar import (  # noqa: E402
    ALGORITHM_NAMES,
    ALGORITHMS,
    INIT_NAMES,
    PAPER_TABLE_I,
    SARConfig,
    run_episode,
    table_i,
)

VIOLATIONS = 0
EPISODES = 0


def episode(cfg: SARConfig, alg: str):
    global VIOLATIONS, EPISODES
    res = run_episode(cfg, alg)  # type: ignore[arg-type]
    VIOLATIONS += res.violations
    EPISODES += 1
    return res


def md(header: list[str], rows: list[list[str]]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(out)


def ms(values: list[float], digits: int = 0) -> str:
    m = statistics.fmean(values)
    s = statistics.pstdev(values) if len(values) > 1 else 0.0
    return f"{m:.{digits}f} ± {s:.{digits}f}"


def label(restr: int, prims: int, init: str) -> str:
    return f"restr={restr}, prim={prims}, {INIT_NAMES[init]}"


def section_a(epochs: int) -> str:
    rows = []
    for r in table_i(SARConfig(epochs=epochs, seed=0)):
        global VIOLATIONS, EPISODES
        VIOLATIONS += r.ours.violations
        EPISODES += 1
        p = r.paper
        rows.append([label(r.comm_restr, r.primitives, r.init), ALGORITHM_NAMES[r.algorithm],
                     str(r.ours.not_ac), str(p[0]), str(r.ours.comms), str(p[1]), str(r.ours.observations_sent),
                     f"{r.ours.time_s:.2f}", f"{r.ours.cpu_s:.2f}", f"{p[2]:.1f}"])
    return md(["Input", "Algorithm", "Not-AC", "paper", "COMM", "paper", "obs sent", "Time s", "CPU s", "paper s"],
              rows)


def _saving(ours: list, theirs: list, key: str) -> str:
    vals = [1 - getattr(e, key) / getattr(b, key) for e, b in zip(ours, theirs, strict=True) if getattr(b, key)]
    return f"{100 * statistics.fmean(vals):.0f} %" if vals else "–"


def section_b(epochs: int, seeds: int, width: int) -> str:
    """Table I over seeds; Baseline-I both without (the paper's reading, default) and with re-sending; ENFORCEAC's
    COMM saving counted in messages and in observations sent, against both Baseline-I variants."""
    rows = []
    for (restr, prims, init), paper in track(PAPER_TABLE_I.items(), "Table I cells", total=len(PAPER_TABLE_I)):
        m = round(restr * epochs / 200)
        per_alg = {}
        for alg, kw in (("baseline2", {}), ("baseline1", {}), ("baseline1+resend", {"resend": True}),
                        ("enforce", {})):
            per_alg[alg] = [episode(SARConfig(width=width, height=width, epochs=epochs, seed=s, comm_restr=m,
                                              primitives=prims, init=init, **kw), alg.split("+")[0])
                            for s in range(seeds)]  # type: ignore[arg-type]
        theirs_msg = 100 * (1 - paper["enforce"][1] / paper["baseline1"][1])
        for alg in ("baseline2", "baseline1", "baseline1+resend", "enforce"):
            res = per_alg[alg]
            saving = ""
            if alg == "enforce":
                saving = (f"msgs {_saving(res, per_alg['baseline1'], 'comms')} / "
                          f"obs {_saving(res, per_alg['baseline1'], 'observations_sent')}; vs resend: msgs "
                          f"{_saving(res, per_alg['baseline1+resend'], 'comms')} / obs "
                          f"{_saving(res, per_alg['baseline1+resend'], 'observations_sent')} "
                          f"(paper msgs {theirs_msg:.0f} %)")
            base = alg.split("+")[0]
            name = ALGORITHM_NAMES[base] + (" (re-send backlog, ours)" if "+" in alg else "")
            rows.append([label(restr, prims, init), name,
                         ms([r.not_ac for r in res], 1), str(paper[base][0]),
                         ms([r.comms for r in res]), str(paper[base][1]),
                         ms([r.observations_sent for r in res]), saving,
                         f"{statistics.fmean(r.team_j[-1] for r in res):.2f}"])
    return md(["Input", "Algorithm", "Not-AC", "paper", "COMM (messages)", "paper", "observations sent",
               "ENFORCEAC saving vs B-I", "final J"], rows)


def section_f(epochs: int, seeds: int) -> str:
    """Fig. 4(a): the objective J of the executed joint action, ENFORCEAC vs Baseline-I (paired by seed)."""
    rows = []
    for (restr, prims, init) in PAPER_TABLE_I:
        m = round(restr * epochs / 200)
        res = {}
        for alg, kw in (("enforce", {}), ("baseline1", {}), ("baseline1+resend", {"resend": True})):
            res[alg] = [episode(SARConfig(epochs=epochs, seed=s, comm_restr=m, primitives=prims, init=init, **kw),
                                alg.split("+")[0]) for s in range(seeds)]  # type: ignore[arg-type]
        mean_j = {a: [statistics.fmean(r.team_j) for r in v] for a, v in res.items()}
        for other in ("baseline1", "baseline1+resend"):
            diff = [e - b for e, b in zip(mean_j["enforce"], mean_j[other], strict=True)]
            rel = [d / abs(b) for d, b in zip(diff, mean_j[other], strict=True) if b]
            worse = sum(d < 0 for d in diff)
            rows.append([label(restr, prims, init), "Baseline-I" + (" (re-send)" if "+" in other else ""),
                         f"{statistics.fmean(mean_j['enforce']):.3f}", f"{statistics.fmean(mean_j[other]):.3f}",
                         ms(diff, 3), f"{100 * statistics.fmean(rel):+.1f} %", f"{worse}/{len(diff)}"])
    return md(["Input", "vs", "ENFORCEAC mean J", "B-I mean J", "difference (E − B)", "relative",
               "seeds where ENFORCEAC lower"], rows)


def section_c(epochs: int, seeds: int) -> str:
    rows = []
    worst = float("inf")
    for (restr, prims, init), paper in PAPER_TABLE_I.items():
        res = [episode(SARConfig(epochs=epochs, seed=s, comm_restr=round(restr * epochs / 200),
                                 primitives=prims, init=init), "enforce") for s in range(seeds)]  # type: ignore[arg-type]
        wall = statistics.fmean(r.time_s for r in res)
        cpu = statistics.fmean(r.cpu_s for r in res)
        ratio = paper["enforce"][2] * epochs / 200 / max(wall, cpu)
        worst = min(worst, ratio)
        rows.append([label(restr, prims, init), f"{wall:.3f}", f"{max(r.time_s for r in res):.3f}", f"{cpu:.3f}",
                     f"{paper['enforce'][2]:.1f}", f"{ratio:.0f}×"])
    table = md(["Input", "ENFORCEAC wall s (mean)", "wall s (max)", "CPU s (mean)", "paper s (Julia)",
                "speed-up"], rows)
    return table + f"\n\nSmallest speed-up (paper time / max(mean wall, mean CPU)): {worst:.0f}× (target ≥ 10×)."


def section_d(epochs: int, seeds: int) -> str:
    variants = [
        ("default: send all relevant, paper T1/T2, random common tie-break", {}),
        ("send greedy (1 observation per COMM)", {"policy": "greedy"}),
        ("send oldest (1 observation per COMM)", {"policy": "oldest"}),
        ("trigger 'useful' (T2 only when it helps)", {"trigger": "useful"}),
        ("tie-break by lowest index", {"tie_break": "index"}),
        ("sensor p_d = 0.99, p_f = 0.01", {"p_detect": 0.99, "p_false": 0.01}),
    ]
    rows = []
    for inp in ((0, 4, "max-entropy"), (20, 8, "max-entropy")):
        restr, prims, init = inp
        for name, kw in variants:
            res = [episode(SARConfig(epochs=epochs, seed=s, comm_restr=round(restr * epochs / 200),
                                     primitives=prims, init=init, **kw), "enforce")  # type: ignore[arg-type]
                   for s in range(seeds)]
            rows.append([label(*inp), "ENFORCEAC: " + name, ms([r.not_ac for r in res], 1),
                         ms([r.comms for r in res]), ms([r.observations_sent for r in res]),
                         f"{statistics.fmean(r.time_s for r in res):.2f}"])
        for tie in ("random", "index"):
            res = [episode(SARConfig(epochs=epochs, seed=s, comm_restr=round(restr * epochs / 200),
                                     primitives=prims, init=init, tie_break=tie), "baseline2")  # type: ignore[arg-type]
                   for s in range(seeds)]
            rows.append([label(*inp), f"Baseline-II, tie-break {tie}", ms([r.not_ac for r in res], 1),
                         ms([r.comms for r in res]), ms([r.observations_sent for r in res]),
                         f"{statistics.fmean(r.time_s for r in res):.2f}"])
        for resend in (True, False):
            res = [episode(SARConfig(epochs=epochs, seed=s, comm_restr=round(restr * epochs / 200),
                                     primitives=prims, init=init, resend=resend), "baseline1")  # type: ignore[arg-type]
                   for s in range(seeds)]
            rows.append([label(*inp), f"Baseline-I, resend={resend}", ms([r.not_ac for r in res], 1),
                         ms([r.comms for r in res]), ms([r.observations_sent for r in res]),
                         f"{statistics.fmean(r.time_s for r in res):.2f}"])
    return md(["Input", "Variant", "Not-AC", "COMM", "obs sent", "Time s"], rows)


def section_e(epochs: int, seeds: int) -> str:
    rows = []
    for n in (2, 3, 4):
        for prims in (4, 8):
            if n == 4 and prims == 8:
                seeds_here = max(1, seeds // 3)
            else:
                seeds_here = seeds
            for alg in ALGORITHMS:
                res = [episode(SARConfig(robots=n, primitives=prims, epochs=epochs, seed=s), alg)
                       for s in range(seeds_here)]
                rows.append([str(n), str(prims), ALGORITHM_NAMES[alg], ms([r.not_ac for r in res], 1),
                             ms([r.comms for r in res]), ms([r.observations_sent for r in res]),
                             str(max(r.violations for r in res)), f"{statistics.fmean(r.time_s for r in res):.2f}"])
    return md(["N", "prim", "Algorithm", "Not-AC", "COMM", "obs sent", "violations", "Time s"], rows)


def plot(path: str, epochs: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cfg = SARConfig(epochs=epochs, seed=0)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.5))
    for alg in ALGORITHMS:
        res = run_episode(cfg, alg)
        ax1.plot(res.team_j, label=ALGORITHM_NAMES[alg])
        if alg == "enforce":
            ax2.plot(res.since_comm, color="C2")
    ax1.set(xlabel="time step", ylabel="J of executed joint action", title="(a) J (full-information belief)")
    ax1.legend()
    ax2.set(xlabel="time step", ylabel="steps since last COMM", title="(b) ENFORCEAC")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


CHOICES = [
    ("grid", "10 × 10 (and 20 × 20 in B2)", "SARConfig.width/height", "the paper gives no size"),
    ("sensor", "P(z=1 | target) = p_d = 0.8, P(z=1 | none) = p_f = 0.2", "SARConfig.p_detect/p_false",
     "no observation model in the paper; D: 0.99/0.01 changes COMM by 20, Not-AC not at all"),
    ("targets", "each cell holds a target with probability 0.3", "SARConfig.target_density",
     "H: Baseline-II's Not-AC does not depend on it"),
    ("robot start", "random distinct cells (seeded)", "sim.sar._world", "not given"),
    ("tie-break", "one random order of joint actions per step, common to all robots", "SARConfig.tie_break",
     "not given; H: the paper's Baseline-II figures need each robot's own order"),
    ("what a message carries", "every unshared relevant observation (policy 'all')", "SARConfig.policy",
     "the paper sends 'the' observation; D: greedy/oldest"),
    ("trigger", "T1/T2 as written (trigger 'paper')", "SARConfig.trigger", "D: 'useful'"),
    ("pruning", "readings of cells no candidate action reaches are left out (exact per session)",
     "SARConfig.prune", "I: changes what a message carries, hence COMM; not the speed"),
    ("Baseline-I loss", "a reading lost on a restricted step is not re-sent", "SARConfig.resend",
     "B: re-sending reverses the Not-AC ordering"),
    ("restricted steps", "comm-restr steps drawn uniformly without replacement (seeded)", "sim.sar._world",
     "not given"),
]


def section_g() -> str:
    return md(["choice", "our value", "where", "what it moves / why"], [list(c) for c in CHOICES])


def section_h(epochs: int, seeds: int) -> str:
    rows = []
    for (restr, prims, init), paper in PAPER_TABLE_I.items():
        cells = []
        for tb in ("random", "index", "own"):
            res = [episode(SARConfig(epochs=epochs, seed=s, comm_restr=round(restr * epochs / 200), primitives=prims,
                                     init=init, tie_break=tb), "baseline2").not_ac for s in range(seeds)]  # type: ignore[arg-type]
            cells.append(ms(res, 1))
        rows.append([label(restr, prims, init), *cells, str(paper["baseline2"][0])])
    return md(["Input", "common random (default)", "lowest index", "each robot its own", "paper"], rows)


def section_i(epochs: int, seeds: int) -> str:
    rows = []
    for width in (10, 20):
        for (restr, prims, init), paper in PAPER_TABLE_I.items():
            cells = []
            for prune in (True, False):
                res, cpu = [], []
                for s in range(seeds):
                    c0 = time.process_time()
                    res.append(episode(SARConfig(epochs=epochs, seed=s, comm_restr=round(restr * epochs / 200),
                                                 primitives=prims, init=init, width=width, height=width,
                                                 prune=prune), "enforce"))  # type: ignore[arg-type]
                    cpu.append(time.process_time() - c0)
                open_steps = epochs - round(restr * epochs / 200)  # Baseline-I: one message each way per open step
                saving = 100 * (1 - statistics.fmean(r.comms for r in res) / (2 * open_steps))
                cells += [ms([r.not_ac for r in res], 1), ms([r.comms for r in res]), f"{saving:.0f} %",
                          f"{statistics.fmean(cpu):.2f}"]
            paper_saving = 100 * (1 - paper["enforce"][1] / paper["baseline1"][1])
            pe = paper["enforce"]
            rows.append([f"{width}×{width}", label(restr, prims, init), *cells,
                         f"{pe[0]} / {pe[1]} / {paper_saving:.0f} % / {pe[2]}"])
    return md(["grid", "Input", "pruned: Not-AC", "COMM", "saving vs B-I", "CPU s", "not pruned: Not-AC", "COMM",
               "saving vs B-I", "CPU s", "paper: Not-AC / COMM / saving / s"], rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--epochs", type=int, default=200)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--quick", action="store_true", help="3 seeds, 60 epochs (smoke run)")
    ap.add_argument("--plot", help="write a Fig. 4(a,b)-style PNG here")
    ap.add_argument("--sections", default="ABCDEFGHI", help="which sections to run, e.g. GHI")
    args = ap.parse_args()
    epochs, seeds = (60, 3) if args.quick else (args.epochs, args.seeds)
    start = time.perf_counter()
    print(f"# Action consistency (seed 002) — E = {epochs}, {seeds} seeds")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"\nmachine: {platform.node()} ({platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load {load:.1f} at start), Python {platform.python_version()}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}\n")
    for title, fn in (("A. Table I, seed 0, 10×10 grid", lambda: section_a(epochs)),
                      (f"B1. Table I, mean ± sd over {seeds} seeds, 10×10 grid", lambda: section_b(epochs, seeds, 10)),
                      (f"B2. Table I, mean ± sd over {seeds} seeds, 20×20 grid", lambda: section_b(epochs, seeds, 20)),
                      ("C. Speed of ENFORCEAC (one episode)", lambda: section_c(epochs, seeds)),
                      ("D. Ablations", lambda: section_d(epochs, max(3, seeds // 2))),
                      ("E. N robots (MaxEntropy-Init, comm-restr = 0)", lambda: section_e(epochs, max(2, seeds // 3))),
                      (f"F. Fig. 4(a): objective J, ENFORCEAC vs Baseline-I, {seeds} seeds, 10×10",
                       lambda: section_f(epochs, seeds)),
                      ("G. Choices the paper does not make", section_g),
                      (f"H. Baseline-II's Not-AC by tie-break rule, {seeds} seeds, 10×10",
                       lambda: section_h(epochs, seeds)),
                      (f"I. ENFORCEAC with / without the pruning of irrelevant observations, {seeds} seeds",
                       lambda: section_i(epochs, seeds))):
        if title[0] not in args.sections.upper():
            continue
        t0 = time.perf_counter()
        print(f"## {title}\n\n{fn()}\n\n({time.perf_counter() - t0:.0f} s)\n", flush=True)
    print(f"Theorem 3.3 violations over all {EPISODES} episodes: {VIOLATIONS}")
    print(f"total bench time {time.perf_counter() - start:.0f} s")
    if args.plot:
        plot(args.plot, epochs)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
