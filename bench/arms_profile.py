"""Where the CPU time of one e-PICO mission on the arms goes: physics, per-tick IK, the rest.

    .venv/bin/python bench/arms_profile.py [--goal alpha] [--colors 4] [--seed N] [--ik analytic|mink]
                                           [--no-sleep]

Runs the mission once to warm the imports, then once timed (``time.process_time``) with the executor's
physics stepping (``Executor._physics``: ``mj_step`` and the arm–arm contact count), its analytic ticks
(``Executor._analytic_tick``), its mink QP ticks (``DualArmIK.step``), the arm–arm clearance bound and
the executor's construction (scene build) each timed on the thread's CPU clock. "rest" is planning,
sensing, belief updates, per-action checks and the moves' bookkeeping. Default: the seed's default
α/4 layout (``delkit epico run --goal alpha --colors 4``).
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--goal", default="alpha")
    ap.add_argument("--colors", type=int, default=4)
    ap.add_argument("--seed", type=int, default=None, help="random layout (default: the seed's layout)")
    ap.add_argument("--ik", choices=("analytic", "mink"), default="analytic")
    ap.add_argument("--no-sleep", action="store_true", help="switch MuJoCo's sleeping islands off "
                                                             "to measure what they save")
    args = ap.parse_args(argv)

    import arms.executor as executor
    import arms.ik as ik
    from arms.cli.epico_run import run_mission

    executor.DEFAULT_IK = args.ik
    if args.no_sleep:
        import mujoco

        build = executor.build_scene

        def awake(*a, **k):
            scene = build(*a, **k)
            scene.model.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_SLEEP)
            return scene

        executor.build_scene = awake
    spent: collections.Counter = collections.Counter()

    def timed(owner, name: str, label: str) -> None:
        inner = getattr(owner, name)

        def wrapper(*a, **k):
            c0 = time.thread_time()
            try:
                return inner(*a, **k)
            finally:
                spent[label] += time.thread_time() - c0

        setattr(owner, name, wrapper)

    timed(executor.Executor, "__init__", "scene build + executor set-up")
    timed(executor.Executor, "arm_clearance_bound", "arm–arm clearance bound")
    timed(executor.Executor, "_analytic_tick", "IK: analytic ticks")
    timed(ik.DualArmIK, "step", "IK: mink QP ticks")
    timed(executor.Executor, "_physics", "physics (mj_step + contact count)")
    run_mission(args.goal, args.colors, args.seed)  # warm: imports and caches
    spent.clear()
    load = os.getloadavg()[0]
    c0 = time.process_time()
    _inst, res, m = run_mission(args.goal, args.colors, args.seed)
    cpu = time.process_time() - c0
    print(f"{args.goal}/{args.colors}, layout {'default' if args.seed is None else args.seed}, per-tick IK "
          f"{args.ik}, sleeping islands {'off' if args.no_sleep else 'on'}: success {res.success}, "
          f"simulated {res.sim_seconds:.1f} s, CPU {cpu:.3f} s, "
          f"{res.sim_seconds / cpu:.1f}× real time (CPU), ticks {m.executor.ik_ticks}, "
          f"load {load:.1f} → {os.getloadavg()[0]:.1f}")
    print("| part | CPU s | share |\n|---|---|---|")
    for label, s in spent.most_common():
        print(f"| {label} | {s:.3f} | {100 * s / cpu:.0f} % |")
    rest = cpu - sum(spent.values())
    print(f"| rest (planning, sensing, beliefs, checks, bookkeeping) | {rest:.3f} | {100 * rest / cpu:.0f} % |")
    return 0 if res.success else 1


if __name__ == "__main__":
    sys.exit(main())
