"""The one-ship environment's ``info``: a dict whose values are built when first read, from a copy taken at the
step.

Building an ``info`` dict (a dozen entries, the reward terms as a dict of their own, unit conversions) cost about
a quarter of a one-ship ``env.step``, and a training loop reads it at most at an episode's end. The step therefore
copies what the ``info`` is made of (the task state, the weighted reward terms and the features of the vessel, as
Python lists: a few hundred nanoseconds) and returns a :class:`LazyInfo`; the entries are computed from that copy
the first time anything reads the dict, so a value read later is the value of its step, exactly as the eagerly
built dict gave it.

A :class:`LazyInfo` is a ``dict`` (``isinstance(info, dict)``) and behaves as one for every Python-level use:
indexing, ``get``, ``in``, iteration, ``len``, ``keys()``/``values()``/``items()``, comparison, ``repr``,
``dict(info)``, ``{**info}``, ``f(**info)``, assignment and deletion (a wrapper adding ``"episode"`` or
``"TimeLimit.truncated"``), and ``json.dumps`` (its keys are in the dict from the start, so C code that asks a
dict for its size sees the right one). ``copy.copy``, ``copy.deepcopy``, ``pickle`` and ``info.copy()`` give a plain
``dict`` of the built entries (what travels between processes, e.g. SB3's ``SubprocVecEnv``). Only
``type(info) is dict`` tells it apart.
"""

from __future__ import annotations

import copy
from typing import Any


class LazyInfo(dict):
    """A dict of ``build(snapshot)``'s entries, built at the first read (see the module docstring).

    Made as ``info = LazyInfo(keys); info._src = (build, snapshot)``: ``keys`` is a dict whose keys are those
    ``build`` returns, in order (values ignored), so that they are in the dict from the start (with None for
    values until it is built); dict's own constructor takes them, with no Python-level ``__init__`` to run (this
    is made once per environment step). Without ``_src`` it is a plain dict of what it was made with.
    """

    __slots__ = ("_src",)

    def _fill(self) -> None:
        src = getattr(self, "_src", None)
        if src is None:
            return
        self._src = None
        build, snap = src
        built = build(snap)
        if built.keys() != dict.keys(self):  # keys other than announced: take the built dict's, in its order
            dict.clear(self)
        dict.update(self, built)

    # reads
    def __getitem__(self, key: Any) -> Any:
        self._fill()
        return dict.__getitem__(self, key)

    def get(self, key: Any, default: Any = None) -> Any:
        self._fill()
        return dict.get(self, key, default)

    def __contains__(self, key: Any) -> bool:
        self._fill()
        return dict.__contains__(self, key)

    def __iter__(self):
        self._fill()
        return dict.__iter__(self)

    def __reversed__(self):
        self._fill()
        return dict.__reversed__(self)

    def __len__(self) -> int:
        self._fill()
        return dict.__len__(self)

    def keys(self):  # type: ignore[override]
        self._fill()
        return dict.keys(self)

    def values(self):  # type: ignore[override]
        self._fill()
        return dict.values(self)

    def items(self):  # type: ignore[override]
        self._fill()
        return dict.items(self)

    def __repr__(self) -> str:
        self._fill()
        return dict.__repr__(self)

    def __eq__(self, other: object) -> bool:
        self._fill()
        if isinstance(other, LazyInfo):
            other._fill()
        return dict.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        eq = self.__eq__(other)
        return eq if eq is NotImplemented else not eq

    __hash__ = None  # type: ignore[assignment]

    def __or__(self, other: Any) -> Any:
        self._fill()
        return dict.__or__(self, other)

    def __ror__(self, other: Any) -> Any:
        self._fill()
        return dict.__ror__(self, other)

    # copies: plain dicts of the built entries
    def copy(self) -> dict:  # type: ignore[override]
        self._fill()
        return dict.copy(self)

    def __copy__(self) -> dict:
        return self.copy()

    def __deepcopy__(self, memo: dict) -> dict:
        return copy.deepcopy(self.copy(), memo)

    def __reduce_ex__(self, protocol: Any) -> tuple:
        return (dict, (self.copy(),))

    def __reduce__(self) -> tuple:
        return (dict, (self.copy(),))

    # writes: built first, so that the built entries keep their order and never overwrite what is written
    def __setitem__(self, key: Any, value: Any) -> None:
        self._fill()
        dict.__setitem__(self, key, value)

    def __delitem__(self, key: Any) -> None:
        self._fill()
        dict.__delitem__(self, key)

    def __ior__(self, other: Any) -> LazyInfo:
        self._fill()
        dict.update(self, other)
        return self

    def update(self, *args: Any, **kwargs: Any) -> None:
        self._fill()
        dict.update(self, *args, **kwargs)

    def setdefault(self, key: Any, default: Any = None) -> Any:
        self._fill()
        return dict.setdefault(self, key, default)

    def pop(self, key: Any, *default: Any) -> Any:
        self._fill()
        return dict.pop(self, key, *default)

    def popitem(self) -> tuple:
        self._fill()
        return dict.popitem(self)

    def clear(self) -> None:
        self._src = None
        dict.clear(self)


class BatchInfo(LazyInfo):
    """The vector environment's batched ``info`` (:meth:`Task.lazy_batch_info`): a :class:`LazyInfo` whose
    build reads the task's arrays as they are, with no copy taken at the step. The environment keeps a weak
    reference to it and builds it before its next ``step`` or ``reset`` changes those arrays
    (``ShipVectorEnv._settle_info``), so an ``info`` still held then gets its own step's values, and one
    already dropped (a training loop that never reads it) costs nothing."""

    __slots__ = ("__weakref__",)


__all__ = ["BatchInfo", "LazyInfo"]
