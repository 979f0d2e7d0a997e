"""Why an epistemic mission is slower than its ideal twin: a per-mission timeline and the rule or
parameter each part of the delay comes from.

Input: two sweep rows of the same (case, map, team size) with ``"diagnosis"`` (``SweepSpec(diagnose=True)``),
the epistemic one and the ideal one. The excess ``t_epi − t_ideal`` is split into

* ``discovery``: how much later the epistemic team found the last task it completed (exploration while
  disconnected: Voronoi cells of believed, not true, positions);
* ``allocation → completion``: the rest up to the last completion, in which the rules act — ruleset 1
  exclusions (``false`` when the excluded robot was in fact not busy; with its distance from the state the
  gossiper sought and from its own common-belief particle c_j, the particle it tracks while disconnected) and
  waits at a task that ended in giving up (``wait_timeout``);
* ``after the last completion``: the remainder (the rest of the exploration — a disconnected robot does not
  know that the tasks are done — and the way home).

The cause named first is the one that accounts for the largest part (a heuristic attribution from the
timeline, stated as such); the variants of ``bench/explore.py --diagnose`` then re-run the mission with each
rule changed to measure what each one costs.
"""

from __future__ import annotations

from typing import Any

from sim.status_model import BUSY

__all__ = ["attribute", "timeline"]

COMM_RANGE = 10.0  # r_c of §6 (the distance below which a sought robot would have been found)


def _last_completion(row: dict) -> float | None:
    done = [c for _, _, c in row["diagnosis"]["task_times"] if c is not None]
    return max(done) if done else None


def _last_discovery(row: dict) -> float | None:
    times = [d for _, d, _ in row["diagnosis"]["task_times"]]
    return max(times) if times else None


def attribute(epi: dict, ideal: dict) -> dict[str, Any]:
    """The split of the excess mission time of ``epi`` over ``ideal`` and the named causes."""
    d = epi["diagnosis"]
    excess = epi["mission_time"] - ideal["mission_time"]
    de, di = _last_discovery(epi), _last_discovery(ideal)
    ce, ci = _last_completion(epi), _last_completion(ideal)
    discovery = (de - di) if de is not None and di is not None else 0.0
    completion = ((ce - de) - (ci - di)) if None not in (ce, de, ci, di) else 0.0
    home = excess - discovery - completion
    false_ex = [e for e in d["exclusions"] if e[4] not in BUSY]
    mismatch = [e for e in false_ex if e[5] > COMM_RANGE and e[6] <= COMM_RANGE]
    gave_up = [w for w in d["waits"] if w[4]]
    waited = sum(w[3] - w[2] for w in gave_up)
    causes: list[str] = []
    if mismatch:
        causes.append(f"ruleset 1 on a wrong belief: {len(mismatch)} exclusion(s) of a robot that was exploring, "
                      f"{min(e[5] for e in mismatch):.0f}–{max(e[5] for e in mismatch):.0f} m from the particle "
                      f"the gossiper sought (most recent timestamp) but within r_c of its common-belief particle "
                      f"(the one it tracks): gossip_target")
    other = [e for e in false_ex if e not in mismatch]
    if other:
        causes.append(f"ruleset 1 on a drifted belief: {len(other)} exclusion(s) of a robot not busy, "
                      f"{min(e[5] for e in other):.0f}–{max(e[5] for e in other):.0f} m from where it was sought")
    if gave_up:
        causes.append(f"wait_timeout: {len(gave_up)} wait(s) at a task ended by giving up after "
                      f"{min(w[3] - w[2] for w in gave_up):.0f}–{max(w[3] - w[2] for w in gave_up):.0f} s "
                      f"({waited:.0f} robot-seconds)")
    if discovery > 0.5 * excess:
        causes.insert(0, f"later discovery: the last task was found {discovery:.0f} s later than by the ideal team")
    if not causes:
        causes.append("none of the rules acted: travel and exploration differences only")
    return {"case": epi["case"], "n_robots": epi["n_robots"], "seed": epi["seed"],
            "epistemic": epi["mission_time"], "ideal": ideal["mission_time"], "excess": round(excess, 1),
            "discovery": round(discovery, 1), "completion": round(completion, 1), "home": round(home, 1),
            "false_exclusions": len(false_ex), "target_mismatch": len(mismatch), "timeouts": len(gave_up),
            "causes": causes}


def timeline(row: dict) -> list[str]:
    """The mission's rule events in time order, one line each."""
    d = row["diagnosis"]
    ev: list[tuple[float, str]] = []
    for task, found, done in d["task_times"]:
        ev.append((found, f"task {task} discovered"))
        if done is not None:
            ev.append((done, f"task {task} completed"))
    for t, g, j, why, status, dist, dcommon in d["exclusions"]:
        ev.append((t, f"robot {g} excludes robot {j} (ruleset 1, {why}); robot {j} was {status}, {dist:.1f} m from "
                      f"the sought state, {dcommon:.1f} m from its common-belief particle"))
    for robot, task, start, end, gave in d["waits"]:
        if gave:
            ev.append((end, f"robot {robot} gives up waiting at task {task} after {end - start:.1f} s"))
    return [f"{t:7.1f} s  {text}" for t, text in sorted(ev)]
