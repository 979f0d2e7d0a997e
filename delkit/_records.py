"""Immutable records written by hand, without the ``dataclasses`` machinery at import time (start-up).

``import dataclasses`` costs ≈ 7 ms of CPU (it imports ``inspect``, ``ast``, ``dis``, ``tokenize``) and every
decorated class ≈ 0.5–1 ms more (it compiles ``__init__``, ``__eq__``, ``__repr__``, ``__hash__`` with
``exec``): together about a third of a small ``delkit plan``'s 0.09 s. The formula AST and the planning task's
records therefore write these methods by hand and stay compatible with the :mod:`dataclasses` functions:
:class:`DataclassFields` is a lazy ``__dataclass_fields__``, built (with ``dataclasses.make_dataclass``, so
the :class:`dataclasses.Field` objects are the real ones) the first time ``dataclasses.fields``,
``is_dataclass``, ``replace`` or ``asdict`` asks for it. :func:`frozen_setattr` is the ``__setattr__`` of a
frozen record (``dataclasses.FrozenInstanceError``, imported only then). :class:`Record` is the base of a
frozen record with a ``__dict__`` (as ``@dataclass(frozen=True)`` makes): ``repr``, ``==`` and ``hash`` over
the fields its ``__dataclass_fields__`` spec names; the subclass writes ``__init__``.
"""

from __future__ import annotations

from operator import attrgetter

__all__ = ["DataclassFields", "Factory", "Record", "frozen_setattr", "frozen_delattr"]


class Factory:
    """A field default made per object (``dataclasses.field(default_factory=...)``), with the field's flags."""

    __slots__ = ("factory", "flags")

    def __init__(self, factory, **flags) -> None:
        self.factory = factory
        self.flags = flags


class DataclassFields:
    """A class's ``__dataclass_fields__``, computed when first read.

    ``spec``: the fields in order, each a name (no default) or ``(name, default)`` (``default`` a value or a
    :class:`Factory`); ``frozen`` as for ``@dataclass``. Reading the attribute from a subclass builds the
    subclass's own fields (same spec) and stores them on it.
    """

    __slots__ = ("spec", "frozen")

    def __init__(self, *spec, frozen: bool = True) -> None:
        self.spec = spec
        self.frozen = frozen

    def __get__(self, obj, cls=None):
        import dataclasses

        cls = type(obj) if cls is None else cls
        items = []
        for entry in self.spec:
            if isinstance(entry, str):
                items.append((entry, "Any"))
                continue
            name, default = entry
            fld = (dataclasses.field(default_factory=default.factory, **default.flags) if isinstance(default, Factory)
                   else dataclasses.field(default=default))
            items.append((name, "Any", fld))
        fields = dataclasses.make_dataclass(cls.__name__, items, frozen=self.frozen).__dataclass_fields__
        type.__setattr__(cls, "__dataclass_fields__", fields)
        return fields


def frozen_setattr(self, name: str, value) -> None:
    """``__setattr__`` of a frozen record: assigning raises ``dataclasses.FrozenInstanceError``."""
    from dataclasses import FrozenInstanceError

    raise FrozenInstanceError(f"cannot assign to field {name!r}")


def frozen_delattr(self, name: str) -> None:
    """``__delattr__`` of a frozen record."""
    from dataclasses import FrozenInstanceError

    raise FrozenInstanceError(f"cannot delete field {name!r}")


class Record:
    """A frozen record with a ``__dict__``, like ``@dataclass(frozen=True)``: the subclass sets
    ``__dataclass_fields__ = DataclassFields(...)`` (the fields in order) and writes ``__init__`` (assigning
    through ``self.__dict__`` or ``object.__setattr__``); ``repr``, ``==``, ``hash`` and ``__match_args__``
    follow the fields as the dataclass's would (a :class:`Factory` field with ``compare=False`` / ``repr=False``
    is left out of them)."""

    __slots__ = ()
    __setattr__ = frozen_setattr
    __delattr__ = frozen_delattr
    _repr_fields: tuple[str, ...] = ()
    _key = staticmethod(tuple)

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        spec = cls.__dict__.get("__dataclass_fields__")
        if not isinstance(spec, DataclassFields):
            return
        names = [e if isinstance(e, str) else e[0] for e in spec.spec]
        flags = {e[0]: e[1].flags for e in spec.spec if not isinstance(e, str) and isinstance(e[1], Factory)}
        cls.__match_args__ = tuple(n for n in names if flags.get(n, {}).get("init", True))
        cls._repr_fields = tuple(n for n in names if flags.get(n, {}).get("repr", True))
        compare = [n for n in names if flags.get(n, {}).get("compare", True)]
        cls._key = staticmethod(attrgetter(*compare) if len(compare) > 1 else lambda obj: (getattr(obj, compare[0]),))

    def __repr__(self) -> str:
        inner = ", ".join(f"{n}={getattr(self, n)!r}" for n in self._repr_fields)
        return f"{type(self).__qualname__}({inner})"

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return self._key(self) == self._key(other)
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self._key(self))
