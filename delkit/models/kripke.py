"""Multi-pointed Kripke models.

A model has worlds 0..n-1, a valuation (boolean matrix worlds × propositions), one accessibility
:class:`~delkit.models.relation.Relation` per agent (a partition for S5, a sparse matrix otherwise) and a set of
designated (actual) worlds. Models are immutable; operations return new models. Truth of formulas is
computed by :mod:`delkit.logic.semantics` and memoised per model; the product M ⊗ E with an event model is
:meth:`KripkeModel.product` (the public function is :func:`delkit.models.update.product_update`). Truth of [E,e]ψ
needs the product and the product needs the truth of preconditions: the two meet in the model object
(:mod:`delkit.logic.semantics` calls ``m.product``), so neither module imports the other.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from delkit._lazy import lazy_module
from delkit.errors import ModelError, UnknownSymbolError
from delkit.logic.formula import Formula, agents_of, props_of
from delkit.models.relation import Relation, RelationError

if TYPE_CHECKING:
    from delkit.models.events import EventModel

sp = lazy_module("scipy.sparse")  # imported on first use (start-up time)

__all__ = ["KripkeModel"]


@dataclass(frozen=True, eq=False)
class KripkeModel:
    """A multi-pointed Kripke model ``(W, R, V, W_d)``.

    Build one with :meth:`build` (worlds as sets of true propositions) or :meth:`from_valuations`.
    """

    props: tuple[str, ...]
    agents: tuple[str, ...]
    valuation: np.ndarray
    relations: Mapping[str, Relation]
    designated: tuple[int, ...]
    names: tuple[str, ...] | None = None
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        val = np.asarray(self.valuation, dtype=bool)
        if val.ndim != 2 or val.shape[1] != len(self.props):
            raise ModelError(f"valuation must be worlds × {len(self.props)} propositions, got shape {val.shape}")
        object.__setattr__(self, "valuation", val)
        n = val.shape[0]
        if len(set(self.props)) != len(self.props):
            raise ModelError(f"duplicate proposition names in {self.props}")
        if len(set(self.agents)) != len(self.agents):
            raise ModelError(f"duplicate agent names in {self.agents}")
        missing = [a for a in self.agents if a not in self.relations]
        if missing:
            raise ModelError(f"no accessibility relation for agent(s) {missing}; give one per agent")
        extra = [a for a in self.relations if a not in self.agents]
        if extra:
            raise ModelError(f"relation(s) for unknown agent(s) {extra}; agents are {list(self.agents)}")
        for a, r in self.relations.items():
            if r.n != n:
                raise ModelError(f"relation of agent {a!r} is on {r.n} worlds but the model has {n}")
        des = tuple(sorted(set(int(d) for d in self.designated)))
        if any(d < 0 or d >= n for d in des):
            raise ModelError(f"designated world(s) {[d for d in des if d < 0 or d >= n]} out of range 0..{n - 1}")
        object.__setattr__(self, "designated", des)
        object.__setattr__(self, "relations", dict(self.relations))
        if self.names is not None and len(self.names) != n:
            raise ModelError(f"{len(self.names)} world names for {n} worlds")

    # ------------------------------------------------------------------ construction
    @staticmethod
    def build(worlds: Sequence[Iterable[str]] | Mapping[str, Iterable[str]],
              relations: Mapping[str, Any], designated: Iterable[int | str] = (0,),
              *, props: Iterable[str] | None = None, agents: Iterable[str] | None = None) -> KripkeModel:
        """Build a model from readable parts.

        ``worlds`` is a list (or name → set mapping) of the propositions true in each world.
        ``relations[a]`` is either a list of blocks (lists of worlds: an S5 partition) or
        ``{"pairs": [(w, v), ...]}`` for an arbitrary relation. Worlds may be given by index or name.
        """
        if isinstance(worlds, Mapping):
            names = tuple(worlds.keys())
            specs = list(worlds.values())
        else:
            names = None
            specs = list(worlds)
        for what, given in (("props", props), ("agents", agents), ("designated", designated)):
            if isinstance(given, (str, int)):  # a bare name would become its letters; a bare index fails later
                raise ModelError(f"{what} must be a list, e.g. [{given!r}], not {given!r}")
        for i, v in enumerate(specs):  # set("rain") would silently be {'r', 'a', 'i', 'n'}
            if isinstance(v, str):
                raise ModelError(f"world {names[i] if names else i!r}: give the true propositions as a set or "
                                 f"list, e.g. {{{v!r}}}, not the string {v!r}")
        truths = [set(v) for v in specs]
        index = {nm: i for i, nm in enumerate(names)} if names else {}

        def w_of(x: int | str) -> int:
            if isinstance(x, str):
                if x not in index:
                    raise ModelError(f"unknown world {x!r}; worlds are {list(index)}")
                return index[x]
            return int(x)

        all_props = tuple(sorted(set(props) if props is not None else set().union(*truths) if truths else set()))
        unknown = set().union(*truths) - set(all_props) if truths else set()
        if unknown:
            raise UnknownSymbolError(f"world(s) name proposition(s) {sorted(unknown)} not in props {list(all_props)}")
        pidx = {p: i for i, p in enumerate(all_props)}
        val = np.zeros((len(truths), len(all_props)), dtype=bool)
        for w, t in enumerate(truths):
            for p in t:
                val[w, pidx[p]] = True
        n = len(truths)
        rels: dict[str, Relation] = {}
        for a, spec in relations.items():
            try:
                if isinstance(spec, Relation):
                    rels[a] = spec
                elif isinstance(spec, Mapping) and "pairs" in spec:
                    rels[a] = Relation.from_pairs(n, [(w_of(x), w_of(y)) for x, y in spec["pairs"]])
                else:
                    rels[a] = Relation.from_blocks(n, [[w_of(x) for x in blk] for blk in spec])
            except RelationError as exc:
                raise RelationError(f"relation of agent {a!r}: {exc}") from None
        ags = tuple(agents) if agents is not None else tuple(relations.keys())
        return KripkeModel(all_props, ags, val, rels, tuple(w_of(d) for d in designated), names)

    # ------------------------------------------------------------------ basic views
    @property
    def n_worlds(self) -> int:
        return int(self.valuation.shape[0])

    def __len__(self) -> int:
        return self.n_worlds

    def prop_index(self, p: str) -> int:
        try:
            return self._prop_map()[p]
        except KeyError:
            raise UnknownSymbolError(
                f"unknown proposition {p!r}; the model has {list(self.props)}") from None

    def _prop_map(self) -> dict[str, int]:
        m = self._cache.get("__props")
        if m is None:
            m = {p: i for i, p in enumerate(self.props)}
            self._cache["__props"] = m
        return m

    def relation(self, agent: str) -> Relation:
        try:
            return self.relations[agent]
        except KeyError:
            raise UnknownSymbolError(f"unknown agent {agent!r}; the model has {list(self.agents)}") from None

    def world_name(self, w: int) -> str:
        return self.names[w] if self.names else f"w{w}"

    def true_props(self, w: int) -> set[str]:
        return {p for p, v in zip(self.props, self.valuation[w], strict=True) if v}

    def successors(self, agent: str, w: int) -> list[int]:
        return [int(v) for v in self.relation(agent).successors(w)]

    # ------------------------------------------------------------------ truth
    def check(self, formula: Formula | str) -> np.ndarray:
        """Boolean vector over worlds: where ``formula`` is true (memoised)."""
        from delkit.logic.semantics import evaluate

        return evaluate(self, formula)

    def holds(self, formula: Formula | str, worlds: Iterable[int] | None = None) -> bool:
        """True if ``formula`` holds in all the given worlds (default: the designated worlds)."""
        vec = self.check(formula)
        idx = list(self.designated if worlds is None else worlds)
        return bool(vec[idx].all()) if idx else True

    def validate_symbols(self, formula: Formula) -> None:
        """Raise :class:`UnknownSymbolError` if ``formula`` names agents or propositions not in the model."""
        bad_p = sorted(props_of(formula) - set(self.props))
        if bad_p:
            raise UnknownSymbolError(f"formula mentions unknown proposition(s) {bad_p}; the model has "
                                     f"{list(self.props)}")
        bad_a = sorted(agents_of(formula) - set(self.agents))
        if bad_a:
            raise UnknownSymbolError(f"formula mentions unknown agent(s) {bad_a}; the model has {list(self.agents)}")

    # ------------------------------------------------------------------ transformations
    def restrict(self, keep: np.ndarray | Iterable[int]) -> KripkeModel:
        """Submodel on the worlds ``keep`` (boolean mask or index array); designated worlds outside drop out.

        World i of the result is world ``keep[i]`` of this model (see :meth:`restrict_map`).
        """
        idx = self._index(keep)
        pos = np.full(self.n_worlds, -1, dtype=np.int64)
        pos[idx] = np.arange(idx.size)
        des = tuple(int(pos[d]) for d in self.designated if pos[d] >= 0)
        rels = {a: r.restrict(idx) for a, r in self.relations.items()}
        names = tuple(self.names[i] for i in idx) if self.names else None
        return KripkeModel(self.props, self.agents, self.valuation[idx], rels, des, names)

    def _index(self, keep: np.ndarray | Iterable[int]) -> np.ndarray:
        arr = np.asarray(keep if isinstance(keep, np.ndarray) else list(keep))
        if arr.dtype == bool:
            if arr.size != self.n_worlds:
                raise ModelError(f"mask of {arr.size} entries for {self.n_worlds} worlds")
            return np.flatnonzero(arr)
        return arr.astype(np.int64).ravel()

    def with_designated(self, designated: Iterable[int]) -> KripkeModel:
        return KripkeModel(self.props, self.agents, self.valuation, self.relations, tuple(designated), self.names)

    def announce(self, formula: Formula | str) -> KripkeModel:
        """Public announcement M|φ: keep the worlds where φ holds."""
        return self.restrict(self.check(formula))

    def preconditions(self, events: EventModel) -> np.ndarray:
        """Boolean matrix worlds × events: M, w ⊨ pre(e)."""
        out = np.empty((self.n_worlds, events.n_events), dtype=bool)
        for j, pre in enumerate(events.pre):
            out[:, j] = self.check(pre)
        return out

    def product(self, events: EventModel, *, designated: str = "product") -> tuple[KripkeModel, np.ndarray]:
        """M ⊗ E and the (k, 2) array of (world, event) of each new world (see :mod:`delkit.models.update`).

        ``designated="product"`` keeps the pairs of designated worlds and events; ``designated="all"`` keeps
        every designated world of M paired with any event (used for [E,e]φ).
        """
        missing = [a for a in self.agents if a not in events.relations]
        if missing:
            raise ModelError(f"event model {events.name!r} has no relation for agent(s) {missing} of the model; "
                             f"give every agent a relation (oblivious agents map events to the skip event)")
        unknown = sorted({p for m in events.post for p in m} - set(self.props))
        if unknown:
            raise ModelError(f"event model {events.name!r} assigns unknown proposition(s) {unknown}; the model "
                             f"has {list(self.props)}")
        pre = self.preconditions(events)
        w_idx, e_idx = np.nonzero(pre)  # row-major: sorted by world then event
        pairs = np.stack([w_idx, e_idx], axis=1).astype(np.int64)
        val = self.valuation[w_idx].copy()
        for j, post in enumerate(events.post):
            if not post:
                continue
            rows = np.flatnonzero(e_idx == j)
            if rows.size == 0:
                continue
            for p, f in post.items():
                val[rows, self.prop_index(p)] = self.check(f)[w_idx[rows]]
        from delkit.resources import check_time

        check_time()  # the active --timeout: a product of a large model can take seconds per relation
        rels = {}
        for a in self.agents:
            rels[a] = self.relations[a].product(events.relations[a], pairs)
            check_time()
        des_w = np.zeros(self.n_worlds, dtype=bool)
        des_w[list(self.designated)] = True
        if designated == "all":
            keep = des_w[w_idx]
        else:
            des_e = np.zeros(events.n_events, dtype=bool)
            des_e[list(events.designated)] = True
            keep = des_w[w_idx] & des_e[e_idx]
        names = None
        if self.names is not None:
            names = tuple(f"{self.names[w]}.{events.events[e]}" for w, e in pairs)
        return KripkeModel(self.props, self.agents, val, rels, tuple(np.flatnonzero(keep)), names), pairs

    def reachable(self, sources: Iterable[int] | None = None, agents: Iterable[str] | None = None) -> np.ndarray:
        """Mask of worlds reachable (in zero or more steps of the agents' relations) from ``sources``."""
        src = list(self.designated if sources is None else sources)
        ags = list(self.agents if agents is None else agents)
        mask = np.zeros(self.n_worlds, dtype=bool)
        mask[src] = True
        if not ags:
            return mask
        from delkit.logic.semantics import common_reach

        kind, data = common_reach(self, tuple(ags))  # cached per model and group
        if kind == "components":  # S5: reachable = the connected components of the sources
            return np.isin(data, data[mask])
        indptr, indices = data.rows()
        frontier = mask.copy()
        while frontier.any():
            nxt = np.zeros(self.n_worlds, dtype=bool)
            rows = np.flatnonzero(frontier)
            deg = indptr[rows + 1] - indptr[rows]
            nxt[indices[np.repeat(indptr[rows], deg) + np.arange(int(deg.sum())) - np.repeat(np.cumsum(deg) - deg,
                                                                                          deg)]] = True
            new = nxt & ~mask
            mask |= new
            frontier = new
        return mask

    def generated(self) -> KripkeModel:
        """The submodel generated by the designated worlds (all worlds reachable from them)."""
        mask = self.reachable()
        return self if mask.all() else self.restrict(mask)

    # ------------------------------------------------------------------ frame classes
    def is_s5(self) -> bool:
        """Every relation is an equivalence relation."""
        return all(r.is_partition or (r.is_reflexive() and r.is_symmetric() and r.is_transitive())
                   for r in self.relations.values())

    def is_kd45(self) -> bool:
        """Every relation is serial, transitive and euclidean (consistent introspective belief)."""
        return all(r.is_serial() and r.is_transitive() and r.is_euclidean() for r in self.relations.values())

    def frame_violations(self, logic: str = "S5") -> list[str]:
        """Human-readable reasons why the model is not of the given frame class (S5, KD45, K)."""
        out: list[str] = []
        logic = logic.upper()
        for a, r in self.relations.items():
            if logic == "S5":
                for prop, ok in (("reflexive", r.is_reflexive()), ("symmetric", r.is_symmetric()),
                                 ("transitive", r.is_transitive())):
                    if not ok:
                        out.append(f"relation of {a} is not {prop}")
            elif logic == "KD45":
                for prop, ok in (("serial", r.is_serial()), ("transitive", r.is_transitive()),
                                 ("euclidean", r.is_euclidean())):
                    if not ok:
                        out.append(f"relation of {a} is not {prop}")
            elif logic != "K":
                raise ModelError(f"unknown logic {logic!r}; use S5, KD45 or K")
        return out

    def inconsistent_agents(self, worlds: Iterable[int] | None = None) -> list[tuple[str, int]]:
        """(agent, world) pairs where the agent has no accessible world: it believes ⊥ there."""
        idx = list(self.designated if worlds is None else worlds)
        out = []
        for a in self.agents:
            has = self.relations[a].has_successor()
            out.extend((a, int(w)) for w in idx if not has[w])
        return out

    # ------------------------------------------------------------------ misc
    def relation_matrix(self, agent: str) -> sp.csr_matrix:
        return self.relation(agent).to_matrix()

    def _repr_svg_(self) -> str | None:
        """Inline picture in Jupyter (see :mod:`delkit.drawing.draw`); None (the text repr) above 200 worlds."""
        if self.n_worlds > 200:
            return None
        from delkit.drawing.draw import picture

        return picture(self).svg()

    def summary(self) -> str:
        kinds = ",".join("S5" if r.is_partition else "rel" for r in self.relations.values())
        return (f"KripkeModel({self.n_worlds} worlds, props={list(self.props)}, agents={list(self.agents)}, "
                f"relations=[{kinds}], designated={list(self.designated)})")

    def __repr__(self) -> str:
        return self.summary()
