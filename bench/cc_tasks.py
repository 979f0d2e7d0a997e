"""Generator of Collaboration-and-Communication (CC) tasks in mA*, the family of EFP's ``CC_2_2_3`` scaled up.

Agents stand in a corridor of rooms 1..R (their positions are common knowledge); each of B boxes is in
exactly one room, unknown to everybody (R^B initial worlds). Actions, as in ``CC_2_2_3``:

* ``left_x`` / ``right_x``: agent x moves one room (executable if x is not at the end and believes so);
  everybody observes it;
* ``x_check_k_r``: x, in room r, senses whether box k is there (``determines at_bk_r``); only x observes it
  (the others are oblivious: their beliefs keep a copy of the old model — KD45 states with many worlds);
* ``tell_x_k_r``: x announces that box k is in room r (executable if x believes it); everybody observes it.

The goal asks agents to believe where boxes are (``B(y, at_bk_r)`` for the box's actual room). ``--length
L`` draws instances (seeded) until one whose optimal plan length, found by A* (``--heuristic``, default
h_pdb), is L.

Hardness parameters (all off by default: the defaults reproduce ``specs/cc_2_4_4``):

* ``--absent``: a box may also be in no room (more initial uncertainty: (R+1)^B initial worlds instead of
  R^B; the drawn box is still in a room);
* ``--tell room``: a ``tell`` is heard only by the agents in the teller's room (EPDDL's
  Collaboration-through-Communication observability; the others are oblivious) instead of by everybody;
* ``--check room``: the other agents in the checker's room see the check but not its result (``aware_of``:
  partially observant) instead of being oblivious;
* ``--moves room``: a move is seen only by the agents in the mover's room (before the move) and the mover.

Each makes the states' models larger (the oblivious and partially observant agents keep alternatives); see
bench/RESULTS-planner.md §11 for their cost per expansion.

    .venv/bin/python bench/cc_tasks.py --agents 2 --rooms 4 --boxes 4 --goals 2 --seed 3 > cc.txt
    .venv/bin/python bench/cc_tasks.py --agents 2 --rooms 4 --boxes 4 --length 7 --out DIR [--count 3]
    .venv/bin/python bench/cc_tasks.py --boxes 4 --goals 3 --absent --tell room --check room --moves room ...
    .venv/bin/python bench/cc_tasks.py --goals 3 --seed 3 --probe 60      # cost per expansion of each setting
"""

from __future__ import annotations

import argparse
import os
import random
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

AGENTS = "abcdefgh"


def cc_task(agents: int, rooms: int, boxes: int, *, where: list[int], start: list[int],
            goals: list[tuple[int, int]], absent: bool = False, tell: str = "public", check: str = "private",
            moves: str = "public") -> str:
    """The mA* text: ``where[k]`` is box k's room, ``start[i]`` agent i's room (1-based), ``goals`` the
    (agent index, box index) pairs of the goal B(agent, at_box_room); ``absent``, ``tell``, ``check``,
    ``moves``: the hardness parameters of the module docstring."""
    ags = AGENTS[:agents]
    rs = range(1, rooms + 1)

    def same_room(verb: str, y: str, x: str, act: str) -> list[str]:
        return [f"{y} {verb} {act} if at_{x}_{q}, at_{y}_{q};" for q in rs]

    fl = [f"at_{x}_{r}" for x in ags for r in rs] + [f"at_b{k}_{r}" for k in range(1, boxes + 1) for r in rs]
    acts: list[str] = []
    body: list[str] = []
    for x in ags:
        for d, (name, edge) in enumerate((("left", 1), ("right", rooms))):
            a = f"{name}_{x}"
            acts.append(a)
            body.append(f"executable {a} if (-at_{x}_{edge}), B({x}, -at_{x}_{edge});")
            for r in rs:
                to = r - 1 if d == 0 else r + 1
                if 1 <= to <= rooms:
                    body.append(f"{a} causes -at_{x}_{r} if at_{x}_{r};")
                    body.append(f"{a} causes at_{x}_{to} if at_{x}_{r};")
            for y in ags:
                body += same_room("observes", y, x, a) if moves == "room" and y != x else [f"{y} observes {a};"]
    for x in ags:
        for k in range(1, boxes + 1):
            for r in rs:
                a = f"{x}_check_{k}_{r}"
                acts.append(a)
                body += [f"executable {a} if B({x}, at_{x}_{r});", f"{a} determines at_b{k}_{r};",
                         f"{x} observes {a};"]
                if check == "room":
                    body += [ln for y in ags if y != x for ln in same_room("aware_of", y, x, a)]
                t = f"tell_{x}_{k}_{r}"
                acts.append(t)
                body += [f"executable {t} if B({x}, at_b{k}_{r});", f"{t} announces at_b{k}_{r};"]
                for y in ags:
                    body += same_room("observes", y, x, t) if tell == "room" and y != x else [f"{y} observes {t};"]
    init = [f"{'' if start[i] == r else '-'}at_{x}_{r}" for i, x in enumerate(ags) for r in rs]
    init += [f"{'' if where[k - 1] == r else '-'}at_b{k}_{r}" for k in range(1, boxes + 1) for r in rs]
    every = f"[{','.join(ags)}]"
    lines = [f"%%% CC: {agents} agents, {rooms} rooms, {boxes} boxes (bench/cc_tasks.py) %%%", "",
             f"fluent {', '.join(fl)};", f"action {', '.join(acts)};", "", f"agent {','.join(ags)};", "",
             *body, "", f"initially {', '.join(init)};"]
    for i, x in enumerate(ags):
        for r in rs:
            lines.append(f"initially C({every}, {'' if start[i] == r else '-'}at_{x}_{r});")
    for k in range(1, boxes + 1):
        one = " | ".join("(" + ", ".join(f"{'' if q == r else '-'}at_b{k}_{q}" for q in rs) + ")" for r in rs)
        if absent:
            one += " | (" + ", ".join(f"-at_b{k}_{q}" for q in rs) + ")"
        lines.append(f"initially C({every}, {one});")
    lines += [f"goal B({ags[i]},at_b{k + 1}_{where[k]});" for i, k in goals]
    return "\n".join(lines) + "\n"


def draw(agents: int, rooms: int, boxes: int, goals: int, seed: int, **hard: Any) -> str:
    """The seeded instance; ``hard``: the hardness keywords of :func:`cc_task` (absent, tell, check, moves)."""
    rng = random.Random(seed)
    where = [rng.randint(1, rooms) for _ in range(boxes)]
    start = [rng.randint(1, rooms) for _ in range(agents)]
    pairs = rng.sample([(i, k) for i in range(agents) for k in range(boxes)], goals)
    return cc_task(agents, rooms, boxes, where=where, start=start, goals=sorted(pairs), **hard)


def hard_name(hard: dict[str, Any]) -> str:
    """The file-name tag of the hardness parameters ("" for the defaults): A absent, T/C/M room tell/check/moves."""
    tag = ("A" if hard.get("absent") else "") + "".join(
        c for c, key in (("T", "tell"), ("C", "check"), ("M", "moves")) if hard.get(key) == "room")
    return f"_{tag}" if tag else ""


def optimal_length(text: str, timeout: float, heuristic: str = "pdb") -> tuple[int | None, float, int]:
    """(A*'s optimal plan length or None, CPU seconds, expanded nodes) of a CC task text (A* with the named
    admissible heuristic, :func:`planners.heuristics.make_heuristic`; ``timeout`` wall seconds)."""
    from planners.epistemic import Limits, best_first, make_space
    from planners.heuristics import make_heuristic
    from planners.lang.mastar import parse_mastar

    c0 = time.process_time()
    space = make_space(parse_mastar(text, "cc.txt"))
    res = best_first(space, Limits(timeout=timeout), kind="astar", h=make_heuristic(heuristic, space))
    return res.length, time.process_time() - c0, res.expanded


SETTINGS = [("defaults", {}), ("--tell room", {"tell": "room"}), ("--check room", {"check": "room"}),
            ("--moves room", {"moves": "room"}), ("--absent", {"absent": True}),
            ("--absent --tell room --check room --moves room",
             {"absent": True, "tell": "room", "check": "room", "moves": "room"})]


def probe(agents: int, rooms: int, boxes: int, goals: int, seed: int, expansions: int, engine: str = "fast") -> None:
    """Per hardness setting: the initial worlds, the worlds of the expanded states (mean, max) and the CPU
    seconds per expansion over A*'s (h_epi) first ``expansions`` expansions of the seeded instance."""
    from planners.epistemic import Limits, best_first, make_space
    from planners.heuristics import h_epi
    from planners.lang.mastar import parse_mastar

    print(f"| setting ({agents} agents, {rooms} rooms, {boxes} boxes, seed {seed}, engine {engine}) | initial worlds "
          f"| expanded | worlds of expanded states: mean | max | CPU s per expansion |")
    print("|---|--:|--:|--:|--:|--:|")
    for label, hard in SETTINGS:
        space = make_space(parse_mastar(draw(agents, rooms, boxes, goals, seed, **hard), "cc.txt"), engine=engine)
        sizes: list[int] = []
        succ = space.successors

        def counted(s: Any, succ: Any = succ, sizes: list[int] = sizes) -> Any:
            sizes.append(len(s.val) if hasattr(s, "val") else s.n_worlds)
            return succ(s)

        space.successors = counted  # type: ignore[method-assign]
        s0, _ = space.initial()
        h = h_epi(space)
        c0 = time.process_time()
        res = best_first(space, Limits(timeout=None, max_expanded=expansions), kind="astar", h=h)
        cpu = time.process_time() - c0
        n0 = len(s0.val) if hasattr(s0, "val") else s0.n_worlds
        print(f"| {label} | {n0} | {res.expanded} | {sum(sizes) / max(1, len(sizes)):.0f} | {max(sizes, default=0)} | "
              f"{cpu / max(1, res.expanded):.4f} |", flush=True)
    print(f"\nload average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--agents", type=int, default=2)
    ap.add_argument("--rooms", type=int, default=4)
    ap.add_argument("--boxes", type=int, default=4)
    ap.add_argument("--goals", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--length", type=int, default=None, help="search seeds for this optimal plan length")
    ap.add_argument("--count", type=int, default=1, help="with --length: how many instances")
    ap.add_argument("--timeout", type=float, default=120.0, help="with --length: A*'s limit per try")
    ap.add_argument("--tries", type=int, default=60)
    ap.add_argument("--heuristic", default="pdb", help="with --length: A*'s heuristic (epi, chain, elim, pdb)")
    ap.add_argument("--probe", type=int, default=None, metavar="N",
                    help="print each hardness setting's worlds and CPU per expansion over A*'s first N expansions")
    ap.add_argument("--engine", default="fast", choices=["fast", "del"], help="with --probe")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--absent", action="store_true", help="a box may be in no room ((R+1)^B initial worlds)")
    ap.add_argument("--tell", choices=["public", "room"], default="public")
    ap.add_argument("--check", choices=["private", "room"], default="private")
    ap.add_argument("--moves", choices=["public", "room"], default="public")
    a = ap.parse_args()
    hard = {"absent": a.absent, "tell": a.tell, "check": a.check, "moves": a.moves}
    if a.probe is not None:
        probe(a.agents, a.rooms, a.boxes, a.goals, a.seed, a.probe, a.engine)
        return
    if a.agents > len(AGENTS) or min(a.agents, a.rooms, a.boxes, a.goals) < 1 or a.goals > a.agents * a.boxes:
        raise SystemExit(f"need 1 ≤ agents ≤ {len(AGENTS)}, rooms ≥ 1, boxes ≥ 1, 1 ≤ goals ≤ agents·boxes")
    if a.length is None:
        sys.stdout.write(draw(a.agents, a.rooms, a.boxes, a.goals, a.seed, **hard))
        return
    found = 0
    for seed in range(a.seed, a.seed + a.tries):
        text = draw(a.agents, a.rooms, a.boxes, a.goals, seed, **hard)
        n, cpu, exp = optimal_length(text, a.timeout, a.heuristic)
        print(f"seed {seed}: optimal length {n}, A* {cpu:.2f} s CPU, {exp} expanded", file=sys.stderr, flush=True)
        if n == a.length:
            name = f"CC_{a.agents}_{a.rooms}_{a.boxes}{hard_name(hard)}_s{seed}__pl_{n}.txt"
            if a.out is not None:
                a.out.mkdir(parents=True, exist_ok=True)
                (a.out / name).write_text(text)
            print(name)
            found += 1
            if found >= a.count:
                return
    raise SystemExit(f"no instance of length {a.length} among {a.tries} seeds")


if __name__ == "__main__":
    main()
