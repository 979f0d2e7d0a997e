"""The robots' epistemic state about block colours, updated by DEL event models (delkit).

For every block *b* a small multi-pointed S5 model M_b: one world per candidate colour *c* (the
proposition ``col_b_c`` true there), both robots' relations universal (nobody knows *b*'s colour at the
start), every world designated (the mission itself does not know the colours either: it only learns
them by observing). The colours of different blocks are independent, so the product of the M_b is the
full model; keeping the factors apart keeps every update O(#colours).

* ``sense``: robot *r* saw *b* with colour *c*. Update with the mA* sensing event model
  ``delkit.events.sensing(col_b_c, full=[r], partial=[others])`` (r learns whether col_b_c, the other
  robot sees that r looked), then keep as designated the worlds of the outcome that was observed.
* ``announce``: robot *r* tells ``to`` that *b* has colour *c*: ``delkit.events.announcement(col_b_c,
  full=[r, *to], partial=[rest])``, whose precondition is col_b_c. A speaker may only announce what it
  believes, checked before the update.

Every update is logged (simulated time, kind, robot(s), block, colour). :meth:`Beliefs.believed` is
"K_r col_b_c holds at every designated world" (``delkit`` semantics).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

from delkit.events import announcement, sensing
from delkit.kripke import KripkeModel
from delkit.update import product_update

__all__ = ["Beliefs", "BeliefEvent", "prop"]


def prop(block: str, colour: str) -> str:
    """The proposition 'block has colour' (names made safe for the formula syntax)."""
    return "col_" + re.sub(r"[^A-Za-z0-9_]", "_", block) + "_" + re.sub(r"[^A-Za-z0-9_]", "_", colour)


@dataclass(frozen=True)
class BeliefEvent:
    """One logged epistemic update."""

    time: float
    kind: str            # "sense" or "announce"
    robot: str
    block: str
    colour: str
    to: tuple[str, ...] = ()

    def to_json(self) -> dict:
        return {"t_sim_s": round(self.time, 3), "kind": self.kind, "robot": self.robot, "block": self.block,
                "colour": self.colour, "to": list(self.to)}

    def __str__(self) -> str:
        to = f" → {', '.join(self.to)}" if self.to else ""
        return f"t={self.time:.2f}s {self.kind} {self.robot}{to}: {self.block} is {self.colour}"


class Beliefs:
    """Per-block DEL models of both robots' knowledge of the colours (see module docstring)."""

    def __init__(self, agents: tuple[str, ...], blocks: tuple[str, ...], colours: tuple[str, ...]) -> None:
        self.agents = tuple(agents)
        self.colours = tuple(sorted(set(colours)))
        self.models: dict[str, KripkeModel] = {}
        self.log: list[BeliefEvent] = []
        for b in blocks:
            self.add_block(b)

    def add_block(self, block: str) -> None:
        n = len(self.colours)
        self.models[block] = KripkeModel.build(
            [{prop(block, c)} for c in self.colours], {a: [list(range(n))] for a in self.agents},
            designated=list(range(n)), props=[prop(block, c) for c in self.colours], agents=self.agents)

    def _check_colour(self, colour: str) -> None:
        if colour not in self.colours:
            raise ValueError(f"colour {colour!r} is not one of the candidate colours {list(self.colours)}")

    def sense(self, robot: str, block: str, colour: str, time: float) -> None:
        """Robot saw ``block`` with ``colour``: sensing update, then the observed outcome is the actual one."""
        self._check_colour(colour)
        p = prop(block, colour)
        others = [a for a in self.agents if a != robot]
        m = product_update(self.models[block], sensing(p, self.agents, full=[robot], partial=others,
                                                       name="sense"))
        truth = m.check(p)
        des = tuple(w for w in m.designated if truth[w])
        if not des:  # the observation contradicts what every designated world says: start that block afresh
            self.add_block(block)
            return self.sense(robot, block, colour, time)
        self.models[block] = replace(m, designated=des, _cache={})
        self.log.append(BeliefEvent(time, "sense", robot, block, colour))

    def announce(self, robot: str, to: tuple[str, ...], block: str, colour: str, time: float) -> None:
        """``robot`` announces to ``to`` that ``block`` has ``colour`` (it must believe so)."""
        self._check_colour(colour)
        if self.believed(robot, block) != colour:
            raise ValueError(f"{robot} cannot announce that {block} is {colour}: it does not believe so")
        others = [a for a in self.agents if a not in (robot, *to)]
        self.models[block] = product_update(
            self.models[block], announcement(prop(block, colour), self.agents, full=[robot, *to], partial=others,
                                             name="announce"))
        self.log.append(BeliefEvent(time, "announce", robot, block, colour, tuple(to)))

    def believed(self, robot: str, block: str) -> str | None:
        """The colour ``robot`` believes ``block`` has (K_robot col_block_c at the designated worlds), or None."""
        m = self.models.get(block)
        if m is None:
            return None
        for c in self.colours:
            if m.holds(f"K{{{robot}}} {prop(block, c)}"):
                return c
        return None

    def known(self) -> dict[str, dict[str, str]]:
        """robot ↦ {block: believed colour} for every belief the robots hold."""
        out: dict[str, dict[str, str]] = {a: {} for a in self.agents}
        for a in self.agents:
            for b in self.models:
                c = self.believed(a, b)
                if c is not None:
                    out[a][b] = c
        return out
