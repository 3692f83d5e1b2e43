"""Task declarations: a task's reward terms and observation features are named once, and everything positional
is derived from those names.

A task module declares

* its reward terms, a tuple of :class:`Term` (name, default weight, what the term is per step);
* its features, a tuple of :class:`FeatureSpec` (name, unit, scale, meaning): every quantity the task computes
  per vessel, of which the configuration observes a subset;
* the columns of its per-vessel task state and of its parameter row, with :func:`columns`;
* its ``info`` entries, a tuple of :class:`Info` (name, value as a function of the vessel's named arrays,
  meaning): the framework builds a vessel's ``info`` dict and the vector environment's arrays from them;
* optionally, a block of reward terms that a configuration option switches on (``options``, e.g. the heel of a
  ship with roll): their kernel columns follow the terms (``spec.OPT.heel``), their weights are configuration
  fields of their own, and they are absent (no column, no ``info`` key) unless switched on.

From the one declaration :class:`TaskSpec` derives the kernel's column indices (``spec.TERM.heading_error``,
``spec.FEAT.sog``: namedtuples of ints, which numba folds to constants when a kernel reads them as module
globals), the reward-weights config class (:meth:`TaskSpec.weights_class`, its fields in declaration order), the
weight vector (by name, :meth:`TaskSpec.weight_vector`), the keys of ``info["reward_terms"]`` and the docs
tables (:meth:`TaskSpec.reward_table`, :meth:`TaskSpec.feature_table`; docs/envs.md carries them and a test
compares). Nothing is numbered by hand, so a reordered declaration moves the kernel's columns, the weights, the
``info`` keys and the docs with it.

Feature scales are a factor times a named scale of the task (``(1.5, "U_T")``: 1.5 times the ship's test
speed); each task says what its scale names are worth (:meth:`vessel_gym.envs.task.Task.scales`), and the
docs show the name.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import operator
from collections import namedtuple
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from vessel_gym.envs.config import weight


def columns(*names: str, start: int = 0, typename: str = "Columns") -> Any:
    """A namedtuple mapping each of ``names`` to its column, ``start``, ``start + 1``, ... in order.

    Module-level results are compile-time constants in numba kernels (``s[S.target]`` compiles to a fixed
    offset). ``len()`` of the result is the number of columns. Names must be unique identifiers.
    """
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise ValueError(f"{typename}: duplicate column names {dup}")
    return namedtuple(typename, names)(*range(start, start + len(names)))


@dataclass(frozen=True)
class Term:
    """A reward term: its name (the weight's config key and its ``info["reward_terms"]`` key), default weight
    and what the term is worth per step (before weighting)."""

    name: str
    weight: float
    doc: str


@dataclass(frozen=True)
class FeatureSpec:
    """A per-vessel quantity a task computes: name, unit, scale (``(factor, scale name)``; normalized
    observation = value / (factor x the task's value of that name)) and meaning.

    ``repeat`` names the config key whose value is the number of copies (``beam_0``, ``beam_1``, ...): such a
    block comes last in a declaration and ``{j}`` and ``{angle}`` in ``doc`` stand for the copy's index and for
    360 j / count.
    """

    name: str
    unit: str
    scale: tuple[float, str]
    doc: str
    repeat: str | None = None

    def scale_text(self) -> str:
        factor, name = self.scale
        if name == "1":
            return f"{factor:g}"
        return name if factor == 1.0 else f"{factor:g} {name}"


@dataclass(frozen=True)
class Feature:
    """One observation entry as the environment uses it: name, unit, scale (a number), meaning and its column
    in the task's feature array."""

    name: str
    unit: str
    scale: float
    doc: str
    column: int = 0


@dataclass(frozen=True)
class Info:
    """An ``info`` entry: its key, its value and what it means.

    Without ``value`` (and ``same_as``) the task's kernel writes the entry: a number in column
    ``spec.INFO.<name>`` of the vessel's info row (``v.info[k, INFO.name]``), given to the ``info`` as ``kind``
    (``float``; ``int``, truncated; ``bool``, true where the column is not 0). The framework then builds the
    single environment's entries from the row in one pass and the vector environment's from one copy of it,
    with no Python call per entry: what a kernel can compute is best written there.

    ``value(v)`` reads the vessels' arrays by name from ``v`` (``v.ts[S.t]``, ``v.feat[FEAT.sog]``,
    ``v.alive``, ``v.done``, any vessel array the task declares; ``v.task`` is the task): for the single
    environment ``v``'s arrays are vessel k's rows as Python numbers (a row a list of floats), for the vector
    environment they are fresh copies, one entry per vessel (row j of ``v.ts`` is column j of the task state).
    So one expression gives both; the functions below (:func:`degrees`, :func:`all_of`, ...) take either kind.

    ``when(config)`` false leaves the entry out, or with ``otherwise`` set gives it that constant value (``doc``
    says when: the docs cannot read a function); ``same_as`` names an earlier entry whose value it repeats
    (``is_success``).
    """

    name: str
    value: Callable[[Any], Any] | None = None
    doc: str = ""
    when: Callable[[Any], bool] | None = None
    otherwise: float | None = None
    same_as: str | None = None
    kind: type = float

    @property
    def written(self) -> bool:
        """The task's kernel writes it into the info row (no ``value``, no ``same_as``)."""
        return self.value is None and self.same_as is None


# --- values of one vessel (Python numbers) or of all (numpy arrays), for Info.value -------------------------
_UNSET = object()


def once(fn: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """``fn(v)``, a quantity several entries use, computed once per ``info`` (kept in ``v.memo``)."""

    @functools.wraps(fn)
    def value(v: Any) -> Any:
        out = v.memo.get(fn, _UNSET)
        if out is _UNSET:
            out = v.memo[fn] = fn(v)
        return out

    return value


_ARRAY = np.ndarray

#: degrees per rad, as a kernel writes an angle into the info row: math.degrees(x) and np.degrees(x) are
#: x * (180 / pi) to the bit (x / DEG, pi / 180 = DEG, is not)
RAD_TO_DEG = 180.0 / math.pi


def degrees(x: Any) -> Any:
    """``x`` rad in degrees."""
    return np.degrees(x) if type(x) is _ARRAY else math.degrees(x)


def hypot(a: Any, b: Any) -> Any:
    return np.hypot(a, b) if type(a) is _ARRAY else math.hypot(a, b)


def maximum(a: Any, b: Any) -> Any:
    """The larger of ``a`` and ``b`` (Python's ``max`` of one vessel's numbers, ``np.maximum`` of arrays)."""
    return np.maximum(a, b) if type(a) is _ARRAY else max(a, b)


def all_of(*conditions: Any) -> Any:
    """True where every condition holds."""
    if type(conditions[0]) is _ARRAY:
        return functools.reduce(operator.and_, conditions)
    return all(conditions)


def logical_not(x: Any) -> Any:
    return ~x if type(x) is _ARRAY else not x


def as_int(x: Any) -> Any:
    """A count kept as a float, as an integer."""
    return x.astype(np.int64) if type(x) is _ARRAY else int(x)


def pick(table: Sequence[Any], i: Any) -> Any:
    """``table[i]`` (an array of objects for an array of indices)."""
    return np.array(table, dtype=object)[i] if type(i) is _ARRAY else table[i]


def whole_rows(x: Any) -> Any:
    """A vessel array read whole (not one column ``[j]`` at a time): one vessel's row as a list, or the (N,
    columns) array of all vessels (the vector environment hands an entry each 2-D array transposed, so that
    ``[j]`` is column j over the vessels)."""
    if type(x) is list:
        return x
    every = getattr(x, "every_column", None)
    if every is not None:  # the info plan's probe: the entry reads every column
        return every()
    return x.T


def _identifier(name: str) -> str:
    if not name.isidentifier():
        raise ValueError(f"declared name {name!r} is not an identifier")
    return name


class TaskSpec:
    """The declaration of one task: reward terms and features, and what is derived from them.

    ``TERM``: namedtuple term name -> column of the kernel's reward-term rows. ``FEAT``: feature name -> column of
    the feature rows (a repeated feature: its first column; its copies follow to the end of the row). ``OPT``:
    optional term name -> its column, after the terms; the optional block is switched on as a whole
    (:meth:`term_names_with`).
    """

    def __init__(
        self,
        title: str,
        terms: Sequence[Term],
        features: Sequence[FeatureSpec],
        options: Sequence[Term] = (),
        info: Sequence[Info] = (),
    ) -> None:
        self.title = title
        self.terms = tuple(terms)
        self.info = tuple(info)
        if "reward_terms" in (i.name for i in self.info):
            raise ValueError(f"{title}: info['reward_terms'] is the framework's (the weighted terms)")
        self.features = tuple(features)
        self.options = tuple(options)
        self.term_names = tuple(_identifier(t.name) for t in self.terms)
        self.option_names = tuple(_identifier(t.name) for t in self.options)
        self.feature_names = tuple(_identifier(f.name) for f in self.features)
        self.TERM = columns(*self.term_names, typename="Terms")
        columns(*self.term_names, *self.option_names, typename="Terms")  # an option may not reuse a term's name
        self.OPT = columns(*self.option_names, start=len(self.term_names), typename="Options")
        self.FEAT = columns(*self.feature_names, typename="Features")
        #: entry name -> column of the info rows, every entry in declaration order (the kernel writes the
        #: columns of the entries without a value; the others' columns stay unused)
        self.INFO = columns(*(_identifier(i.name) for i in self.info), typename="InfoColumns")
        for i in self.info:
            if i.kind not in (float, int, bool):
                raise ValueError(f"{title}: info[{i.name!r}] kind {i.kind!r} is not float, int or bool")
        repeated = [i for i, f in enumerate(self.features) if f.repeat is not None]
        if repeated and repeated != [len(self.features) - 1]:
            raise ValueError(f"{title}: only the last feature may repeat")
        #: feature columns before a repeated block (the whole row if nothing repeats)
        self.n_fixed = len(self.features) - len(repeated)
        self._feature = {f.name: f for f in self.features}

    def variant(self, title: str, **terms: Term) -> TaskSpec:
        """The same declaration (same names in the same order: the same kernel columns) under another title,
        with the terms named in ``terms`` replaced (new default weight or description)."""
        for name, term in terms.items():
            if name not in self.term_names or term.name != name:
                raise ValueError(f"{title}: {name!r} replaces no term of {self.title} of that name")
        return TaskSpec(
            title, tuple(terms.get(t.name, t) for t in self.terms), self.features, self.options, self.info
        )

    def term_names_with(self, options_on: bool) -> tuple[str, ...]:
        """The reward-term columns (and ``info["reward_terms"]`` keys) of a task: the terms, then the optional
        block if it is switched on."""
        return self.term_names + (self.option_names if options_on else ())

    # --- reward -------------------------------------------------------------------------------------------
    def weights_class(self, name: str, module: str, doc: str, base: type | None = None) -> type:
        """A frozen config dataclass of the weights, one field per term in declaration order (default weight,
        ``doc`` in the field's metadata), named ``name`` in ``module`` (so that configs pickle). With ``base``
        (another task's weights class with the same terms) it subclasses it."""
        if base is not None:
            base_names = tuple(f.name for f in dataclasses.fields(base))
            if base_names != self.term_names:
                raise ValueError(
                    f"{name}: terms {self.term_names} differ from {base.__name__}'s {base_names}"
                )
        cls = dataclasses.make_dataclass(
            name,
            [(t.name, float, weight(t.weight, t.doc)) for t in self.terms],
            bases=(base,) if base is not None else (),
            frozen=True,
            kw_only=True,
        )
        cls.__module__ = module
        cls.__qualname__ = name
        cls.__doc__ = doc
        return cls

    def weight_vector(self, reward: Any) -> np.ndarray:
        """The weights of a reward config in term-column order (read by name)."""
        names = tuple(f.name for f in dataclasses.fields(reward))
        if sorted(names) != sorted(self.term_names):
            raise ValueError(f"{self.title}: reward weights {names} are not the terms {self.term_names}")
        return np.array([getattr(reward, t) for t in self.term_names], dtype=np.float64)

    # --- features -----------------------------------------------------------------------------------------
    def n_features(self, counts: Mapping[str, int] | None = None) -> int:
        """Columns of the feature rows: the fixed features, then the repeated block's ``counts[repeat]``."""
        last = self.features[-1] if self.features else None
        if last is None or last.repeat is None:
            return self.n_fixed
        return self.n_fixed + int((counts or {})[last.repeat])

    def layout(
        self, names: Iterable[str], scales: Mapping[str, float], counts: Mapping[str, int] | None = None
    ) -> list[Feature]:
        """The observation entries for the features ``names`` (in that order; a repeated feature expands to its
        copies), with the scales resolved from the task's scale values ``scales``."""
        out = []
        for name in names:
            spec = self._feature.get(name)
            if spec is None:
                raise KeyError(
                    f"{self.title}: no declared feature {name!r} (have: {', '.join(self.feature_names)})"
                )
            factor, sname = spec.scale
            value = factor * (1.0 if sname == "1" else scales[sname])
            col = getattr(self.FEAT, name)
            if spec.repeat is None:
                out.append(Feature(name, spec.unit, value, spec.doc, col))
                continue
            count = int((counts or {})[spec.repeat])
            for j in range(count):
                doc = spec.doc.format(j=j, angle=f"{360.0 * j / count:g}")
                out.append(Feature(f"{name}_{j}", spec.unit, value, doc, col + j))
        return out

    # --- docs ---------------------------------------------------------------------------------------------
    def reward_table(self) -> str:
        """Markdown table of the reward terms (docs/envs.md carries it)."""
        rows = ["| term | default weight | value per step |", "|---|---|---|"]
        rows += [f"| `{t.name}` | {t.weight:g} | {_md(t.doc)} |" for t in self.terms]
        rows += [f"| `{t.name}` (option) | {t.weight:g} | {_md(t.doc)} |" for t in self.options]
        return "\n".join(rows)

    def feature_table(self) -> str:
        """Markdown table of the declared features (docs/envs.md carries it)."""
        rows = ["| column | feature | unit | scale | meaning |", "|---|---|---|---|---|"]
        for f in self.features:
            name = f"{f.name}_j" if f.repeat else f.name
            col = getattr(self.FEAT, f.name)
            where = f"{col}.." if f.repeat else f"{col}"
            doc = f.doc.format(j="j", angle=f"360 j / {f.repeat}") if f.repeat else f.doc
            rows.append(f"| {where} | `{name}` | {f.unit} | {f.scale_text()} | {_md(doc)} |")
        return "\n".join(rows)

    def info_table(self) -> str:
        """Markdown table of the ``info`` entries (docs/envs.md carries it), ``reward_terms`` first."""
        rows = ["| key | meaning |", "|---|---|", "| `reward_terms` | the weighted reward terms by name |"]
        for i in self.info:
            doc = i.doc or (f"the same as `{i.same_as}`" if i.same_as else "")
            if i.when is not None and i.otherwise is not None:
                doc += f"; else {i.otherwise:g}"
            rows.append(f"| `{i.name}` | {_md(doc)} |")
        return "\n".join(rows)

    def docs(self) -> str:
        """The reward and feature tables under a heading (the generated part of docs/envs.md)."""
        return f"#### {self.title}\n\nReward terms:\n\n{self.reward_table()}\n\nFeatures:\n\n{self.feature_table()}\n"


def _md(text: str) -> str:
    """Text for a markdown table cell (a literal | escaped)."""
    return text.replace("|", "\\|")
