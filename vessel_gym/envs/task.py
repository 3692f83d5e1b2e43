"""The task base: one simulation of N vessels, its start states, features, reward terms and episode ends.

A task is declared once (:class:`~vessel_gym.envs.declare.TaskSpec`: reward terms and features by name) and
asks the physics for named quantities; its per-step arithmetic runs in one compiled call for all N vessels
(the task's ``kernel``). The single environment is a task of N = 1, the vector environment the same task of
N = num_envs (:mod:`vessel_gym.envs.env`).
"""

from __future__ import annotations

import abc
import math
import operator
from collections import namedtuple
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

import numpy as np

from vessel_gym.envs.config import ShipEnvConfig, make_config
from vessel_gym.envs.declare import Feature, TaskSpec
from vessel_gym.envs.helm import make_helm
from vessel_gym.envs.observation import ObservationLayout
from vessel_gym.physics.linear import stable_step
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.simulation import Simulation, steps_for
from vessel_gym.physics.units import DEG

PHASE_SKIP = 0  # vessel untouched this call
PHASE_STEP = 1  # vessel advanced one control step: update task state, reward terms, outcome
PHASE_RESET = 2  # vessel just reset: features only


# The default physics step keeps the ship's fastest mode at the steady run (on small models the shaft's, the
# steering gear being solved exactly) within 0.7 of the integrator's stability limit. Over the operating
# envelope (astern, low speed, hard over, shaft overspeed) that mode is up to 1.1x faster on kvlcc2_l7, so the
# step stays within 0.77 of the limit everywhere. Stability is not accuracy: the rudder's path within a step
# (slewing, then settling) is forcing the step must also resolve, so the ship travels at most 5 % of its length
# per step at its test speed (the Mariner, stable to 22 s steps, converges at 0.06 L and is off by 0.07 deg at
# 0.12 L). docs/envs.md, "Physics step", has the envelope and the convergence studies.
STEP_MARGIN = 0.7
STEP_TRAVEL_L = 0.05  # ship lengths travelled per default step, at most


def physics_step(config: ShipEnvConfig, ship: Ship, shallow_water: bool = False) -> float:
    """``config.dt_s``, or the default: the longest control_interval_s / k within STEP_MARGIN x the stable step
    and STEP_TRAVEL_L ship lengths of travel at the test speed.

    An explicit ``dt_s`` beyond the stable step raises SpecError (the integration would diverge).
    """
    limit = stable_step(ship, config.method, shallow_water=shallow_water)
    if config.dt_s is None:
        longest = min(STEP_MARGIN * limit, STEP_TRAVEL_L * ship.particulars.L_m / ship.test_speed_m_s)
        return config.control_interval_s / math.ceil(config.control_interval_s / longest - 1e-9)
    if config.dt_s > limit:
        raise SpecError(
            f"dt_s = {config.dt_s:g} s is beyond the stable {config.method} step of ship {ship.name!r}, "
            f"{limit:.3g} s (set by its fastest mode); use a shorter dt_s or leave it unset"
        )
    return float(config.dt_s)


#: the framework's record of the vessels' arrays, the kernel's ``v``: the simulation's state rows ``x``, input
#: rows ``inp`` and environment rows ``env`` (current, wind as the physics sees them), ``alive``; the reward
#: weights ``w`` (term-column order) and the observation encoding ``enc`` (:func:`encode_row
#: <vessel_gym.envs.tasks.common.encode_row>`); the rows the kernel writes: features ``feat``, observations
#: ``obs``, weighted reward terms ``terms``, ``reward``, ``done`` (terminated) and the ``info`` entries the kernel
#: writes (``info``, columns ``spec.INFO``)
Vessels = namedtuple(
    "Vessels", ("x", "inp", "env", "alive", "w", "enc", "feat", "obs", "terms", "reward", "done", "info")
)

#: the framework's arrays an ``info`` entry may read (``v.feat``, ...), one row per vessel
INFO_ARRAYS = ("feat", "terms", "reward", "alive", "done")


def task_arrays(name: str, module: str, vessel: Sequence[str], shared: Sequence[str] = ()) -> Any:
    """The record class of a task's own arrays, the kernel's ``t``: a namedtuple named ``name`` (define it at
    module level in ``module`` under that name, so that compiled kernels cache) whose fields are the task's
    attributes of those names. ``vessel``: arrays with one row (or entry) per vessel, which ``info`` entries
    may read too; ``shared``: the others (parameter rows, chart tables, scratch)."""
    cls = namedtuple(name, (*vessel, *shared), module=module)  # type: ignore[misc]
    cls.vessel, cls.shared = tuple(vessel), tuple(shared)
    return cls


def kernel_records(task: Task) -> tuple[Any, Any]:
    """(v, t): the :data:`Vessels` record of ``task`` and its own record (``task.Arrays`` of its attributes)."""
    sim = task.sim
    v = Vessels(
        sim.state,
        sim.inputs,
        sim.env,
        sim.alive,
        task.weights,
        task.enc,
        task.feat,
        task.obs,
        task.terms,
        task.reward,
        task.terminated,
        task.info_rows,
    )
    return v, task.Arrays(*(getattr(task, f) for f in task.Arrays._fields))


class _Vessels:
    """The vessels' arrays by name for the ``info`` entries, ``task`` the task and ``memo`` the values computed
    once per ``info`` (:func:`~vessel_gym.envs.declare.once`)."""

    def __init__(self, task: Task) -> None:
        self.task = task
        self.memo: dict = {}


class _Probe(_Vessels):
    """All vessels' arrays by name, the columns read recorded (:class:`InfoPlan` learns which arrays and columns
    its entries read)."""

    def __init__(self, task: Task, arrays: dict[str, np.ndarray]) -> None:
        super().__init__(task)
        self._arrays = arrays
        self.read: dict[str, set[int]] = {}

    def __getattr__(self, name: str) -> Any:
        a = self._arrays.get(name)
        if a is None:
            raise AttributeError(f"info entries read {', '.join(self._arrays)}, task and memo, not {name!r}")
        cols = self.read.setdefault(name, set())
        if a.ndim == 1:
            value: Any = a.copy()
        else:
            value = _Columns(a, cols, name)
        setattr(self, name, value)
        return value


class _Columns:
    """Column j of a 2-D array of all vessels, copied, recorded in ``cols``."""

    def __init__(self, a: np.ndarray, cols: set[int], name: str) -> None:
        self._a, self._cols, self.name = a, cols, name

    def __getitem__(self, j: int) -> np.ndarray:
        if not isinstance(j, (int, np.integer)):
            raise TypeError(f"info entries read one column of a vessel array at a time, not [{j!r}]")
        self._cols.add(int(j))
        return self._a[:, j].copy()

    def every_column(self) -> np.ndarray:
        """The whole array (:func:`~vessel_gym.envs.declare.whole_rows`), every column recorded as read."""
        self._cols.update(range(self._a.shape[1]))
        return self._a.copy()


class InfoPlan:
    """The ``info`` entries of a task for its config: ``reward_terms`` (the weighted terms by name), then the
    declared :class:`~vessel_gym.envs.declare.Info` entries that apply, in declaration order (:func:`vessel_info`,
    :func:`batch_info`). An entry the kernel writes is a column of the task's info rows (``info_rows``), taken
    with the others in one pass; an entry with a ``value`` is a function of the vessels' arrays by name, and
    the arrays those read are found by evaluating them once on all vessels, so that a call copies those alone."""

    def __init__(self, task: Task) -> None:
        self.term_names = task.term_names
        self.task = task
        self.n = task.n
        INFO = task.spec.INFO
        names: list[str] = []  # the entries that apply, in order
        cols: list[int] = []  # their columns of the info rows
        single: list[tuple[str, Any]] = []
        batch: list[tuple[str, Any]] = []
        #: (entry, its column of the info rows) of the entries given as an int, a bool (the others are the
        #: column's float)
        self.ints: list[tuple[str, int]] = []
        self.bools: list[tuple[str, int]] = []
        self.repeats: list[tuple[str, str]] = []  # (entry, the entry whose value it repeats)
        self.consts: list[tuple[str, float]] = []  # (entry, its value under this config: when false, otherwise)
        for e in task.spec.info:
            kept = (e.name, getattr(INFO, e.name))
            if e.when is not None and not e.when(task.config):
                if e.otherwise is None:
                    continue
                self.consts.append((e.name, e.otherwise))
            elif e.same_as is not None:  # its place in the dict now, its value once the other's is made
                self.repeats.append((e.name, e.same_as))
            elif e.written:
                if e.kind is int:
                    self.ints.append(kept)
                elif e.kind is bool:
                    self.bools.append(kept)
            else:
                single.append((e.name, e.value))
                batch.append((e.name, e.value))
            names.append(e.name)
            cols.append(kept[1])
        self.names = tuple(names)
        self.info_rows = task.info_rows
        #: the columns of the entries that apply, or None where those are all columns in order
        self.cols: list[int] | None = None if cols == list(range(len(INFO))) else cols
        self.pick: Any = None  # a row's values of those columns (itemgetter gives a tuple of two or more)
        if self.cols is not None:
            self.pick = operator.itemgetter(*cols) if len(cols) > 1 else lambda r: [r[j] for j in cols]
        self.single, self.batch = tuple(single), tuple(batch)
        framework = (task.feat, task.terms, task.reward, task.sim.alive, task.terminated)
        arrays = {**dict(zip(INFO_ARRAYS, framework)), **{f: getattr(task, f) for f in task.Arrays.vessel}}
        probe = _Probe(task, arrays)
        with np.errstate(all="ignore"):  # the values now are of no interest, only what they read
            for name, value in self.batch:
                if isinstance(value(probe), _Columns):
                    raise TypeError(
                        f"info entry {name!r} gives a vessel array itself: read its columns [j], or all of each "
                        "vessel's row with vessel_gym.envs.declare.whole_rows"
                    )
        self.read = probe.read  # by array, the columns its entries read
        used = {name: arrays[name] for name in probe.read}
        self.rows = tuple((name, a) for name, a in used.items() if a.ndim == 2)
        self.items = tuple((name, a) for name, a in used.items() if a.ndim == 1)
        #: the vector environment's copies of each 2-D array: the columns the entries read (None: all of them,
        #: the transposed array in one copy, where fewer would save little)
        self.columns = tuple((name, a, self._columns(a, probe.read.get(name))) for name, a in self.rows)
        #: the single environment's view, refilled at each call (its values are Python numbers and lists
        #: made anew, so an entry that returns one shares nothing with a later call)
        self.one = _Vessels(task)

    def _columns(self, a: np.ndarray, read: set[int] | None) -> list[int] | None:
        """The columns of ``a`` to copy for the entries, or None for all: a copy of the columns read pays where
        it leaves out at least COPY_SAVES elements (of smaller arrays a single copy of all costs less)."""
        if read is None or len(read) == a.shape[1] or self.n * (a.shape[1] - len(read)) < COPY_SAVES:
            return None  # every column read (an entry reads the array whole: whole_rows), or too few left out
        return sorted(read)


#: elements left out of a copy from which copying the columns an info reads beats one copy of all (measured
#: on ZigZag-v1: at 16 ships the whole copy, at 1024 the columns read)
COPY_SAVES = 4096


def _none(v: Any) -> None:
    return None


def info_plan(task: Task) -> InfoPlan:
    plan = task._infos
    if plan is None:
        plan = task._infos = InfoPlan(task)
    return plan


def vessel_info(task: Task, k: int) -> dict[str, Any]:
    """Vessel k's ``info`` dict now, Python values: its info row's entries in one pass, then the entries with a
    ``value`` of its arrays' rows as Python numbers (a row a list of floats)."""
    plan = task._infos or info_plan(task)
    row = plan.info_rows[k].tolist()
    info = {"reward_terms": dict(zip(plan.term_names, task.terms[k].tolist()))}
    info.update(zip(plan.names, row if plan.pick is None else plan.pick(row)))
    for name, j in plan.ints:
        info[name] = int(row[j])
    for name, j in plan.bools:
        info[name] = row[j] != 0.0
    for name, c in plan.consts:
        info[name] = c
    if plan.single:
        v = plan.one
        d = v.__dict__
        d["memo"] = {}
        for name, a in plan.rows:
            d[name] = a[k].tolist()
        for name, a in plan.items:
            d[name] = a.item(k)
        for name, value in plan.single:
            info[name] = value(v)
    for name, same in plan.repeats:
        info[name] = info[same]
    return info


def batch_info(task: Task) -> dict[str, Any]:
    """The ``info`` of all vessels (the vector environment's), each entry a new array over the vessels: the
    info rows' entries from one fresh copy of their columns, the entries with a ``value`` of fresh copies of
    the arrays they read (of a 2-D array the columns the entries read, ``[j]`` column j of every vessel), so no
    entry is a view of an array a later step changes."""
    plan = task._infos or info_plan(task)
    rows = plan.info_rows.T.copy()  # [j]: column j of every vessel (one copy of all: fewer rows cost more)
    info: dict[str, Any] = {"reward_terms": dict(zip(plan.term_names, task.terms.T.copy()))}
    info.update(zip(plan.names, rows if plan.cols is None else [rows[j] for j in plan.cols]))
    for name, j in plan.ints:
        info[name] = rows[j].astype(np.int64)
    for name, j in plan.bools:
        info[name] = rows[j] != 0.0
    for name, c in plan.consts:
        info[name] = np.full(plan.n, c)
    if plan.batch:
        v = _Vessels(task)
        d = v.__dict__
        for name, a, cols in plan.columns:  # [j]: column j of every vessel, a fresh copy
            d[name] = a.T.copy() if cols is None else dict(zip(cols, a.T[cols]))
        for name, a in plan.items:
            d[name] = a.copy()
        for name, value in plan.batch:
            info[name] = value(v)
    for name, same in plan.repeats:
        info[name] = info[same].copy()
    return info


class Task(abc.ABC):
    """A task over one simulation of N vessels: start states, observations, reward terms, episode end.

    Subclasses define ``spec`` (their :class:`~vessel_gym.envs.declare.TaskSpec`: reward terms, features and
    ``info`` entries by name), ``Config`` (a :class:`ShipEnvConfig` subclass whose ``reward`` table is
    ``spec``'s weights class), their ``kernel`` and the record of the arrays it reads (``Arrays``,
    :func:`task_arrays`), ``observed()`` (the names of the observed features) and ``reset_vessel()``;
    ``scales()`` and ``feature_counts()`` when their features need more than the shared scale names.
    """

    Config: ClassVar[type[ShipEnvConfig]] = ShipEnvConfig
    spec: ClassVar[TaskSpec]
    kernel: ClassVar[Any]  # the update of the vessels in phase: kernel(phase, v, t) (kernel_records)
    Arrays: ClassVar[Any]  # the task's record: its arrays by name (task_arrays)
    ts: np.ndarray  # per-vessel task state (N, the task's columns), made by the task

    def __init__(
        self,
        config: Any,
        n: int,
        ship: str | Ship | None = None,
        reference_latlon_deg: tuple[float, float] = (0.0, 0.0),
        shallow_water: bool = False,
    ) -> None:
        self.config = config
        self.n = n
        self.preset: str | None = None  # the registered preset it was made with (from_config)
        ship = load_ship(ship if ship is not None else config.ship)
        self.dt = physics_step(config, ship, shallow_water)
        try:
            self.nsub = steps_for(config.control_interval_s, self.dt)
        except ValueError:
            raise SpecError(
                f"control_interval_s = {config.control_interval_s:g} s is not a whole multiple of "
                f"dt_s = {self.dt:g} s"
            ) from None
        self.sim = Simulation(
            ship,
            n=n,
            dt=self.dt,
            method=config.method,
            reference_latlon_deg=reference_latlon_deg,
            shallow_water=shallow_water,
        )
        self.ship: Ship = self.sim.ship(0)
        self.helm = make_helm(config, self.sim)
        self.U_T = self.ship.test_speed_m_s
        self.L = self.ship.particulars.L_m
        self.delta_max = float(self.ship.steering_gear.max_angle_deg * DEG)
        self.rev_full = float(np.max(np.abs(self.helm.rev_table[0]))) or 1.0
        self.layout = ObservationLayout(observation_features(self), config.observation_type == "normalized")
        self.term_names = self.spec.term_names  # the keys of info["reward_terms"], in kernel column order
        self.weights = self.spec.weight_vector(config.reward)
        self.n_features = self.spec.n_features(self.feature_counts())
        self.feat = np.zeros((n, self.n_features))
        self.terms = np.zeros((n, len(self.term_names)))  # weighted reward terms (they sum to the reward)
        self.reward = np.zeros(n)
        self.terminated = np.zeros(n, dtype=np.bool_)
        self.phase = np.full(n, PHASE_STEP, dtype=np.int8)
        self.info_rows = np.zeros((n, len(self.spec.INFO)))  # the info entries the kernel writes (InfoPlan)
        self.rngs: Sequence[np.random.Generator] = ()  # per-vessel generators, set by the environment
        self._starts: tuple[list, ...] | None = None  # the starts gathered by reset_vessels, else None
        self.enc = np.stack(
            [
                self.layout.columns.astype(np.float64),
                self.layout.scale,
                np.full(len(self.layout), 1.0 if self.layout.normalized else 0.0),
            ],
            axis=1,
        )
        self.obs = np.zeros((n, len(self.layout)), dtype=np.float32)
        self._records: tuple = ()  # the kernel's records (kernel_records), bound at the first update
        self._kernel_call: Any = None  # the kernel's compiled code for them (compiled_entry)
        self._infos: InfoPlan | None = None  # the declared info entries for this config (info_plan)

    @classmethod
    def from_config(cls, config: Any, overrides: Mapping[str, Any], n: int) -> Task:
        """The task of ``n`` vessels from a config (instance, mapping, TOML path or None) and keyword overrides
        (:func:`task_config`)."""
        over = dict(overrides)
        preset = over.pop("preset", None)
        task = cls(task_config(cls, config, over, preset), n)
        task.preset = preset
        return task

    # subclass interface
    @abc.abstractmethod
    def observed(self) -> Sequence[str]:
        """The names of the observed features, in observation order (see
        :func:`~vessel_gym.envs.tasks.common.motion_observed`)."""

    @abc.abstractmethod
    def reset_vessel(self, k: int, rng: np.random.Generator, options: Mapping | None) -> None:
        """Put vessel k at a new start drawn with ``rng`` (``options`` as the environment's reset)."""

    def reset_batch(self, idx: np.ndarray, rng: Any, options: Mapping | None) -> None:
        """Reset the vessels ``idx`` (int64 array) at once, in numpy over arrays: each draw of ``rng`` gives one
        number per vessel (:class:`~vessel_gym.envs.generators.BatchDraws`: vessel k's from its own stream) or,
        for one vessel, a numpy Generator's number. A task that writes its start this way defines it (then
        :func:`reset_vessels` calls it, and its :meth:`reset_vessel` is the one-vessel case); the others start
        one vessel at a time."""
        raise NotImplementedError

    def started(self, k: int | np.ndarray) -> None:  # noqa: B027 (a task that keeps nothing has nothing to do)
        """Copy what the task keeps of the vessels' start states (``k`` one index or an array of them) once
        the simulation has them (:func:`start`)."""

    def scales(self) -> dict[str, float]:
        """What each scale name of the declared features is worth for this task's ship (extend in a task)."""
        U, L = self.U_T, self.L
        return {
            "U_T": U,  # ship test speed, m/s
            "U_T / L": U / L,  # 1/s
            "L": L,  # ship length, m
            "rudder max": self.delta_max,  # steering-gear limit, rad
            "full rev": self.rev_full,  # largest telegraph shaft speed, rev/s
            "pi": math.pi,
        }

    def feature_counts(self) -> dict[str, int]:
        """Copies of each repeated feature (config key -> count); none unless a task declares one."""
        return {}

    def update(self, phase: np.ndarray) -> None:
        """Run the task kernel; fill ``feat``, ``terms`` and ``terminated`` for the vessels in ``phase``."""
        call = self._kernel_call
        if call is not None:
            call(phase, *self._records)
            return
        records = self._records = kernel_records(self)
        self.kernel(phase, *records)  # compiles, or loads from the cache, the kernel for these records
        self._kernel_call = compiled_entry(self.kernel, phase, records)

    def __getstate__(self) -> dict:
        state = self.__dict__.copy()
        state["_kernel_call"] = None  # a compiled entry point does not pickle; bound again at the first update
        state["_infos"] = None
        return state


# --- what the framework does with a task: its config, starts, observation layout --------------------------------
def task_config(cls: type[Task], config: Any, overrides: Mapping[str, Any], preset: str | None) -> Any:
    """The config of a task of class ``cls``: the class defaults, the registered preset's values
    (:mod:`vessel_gym.envs.registration`), ``config`` (instance, mapping, TOML path or None), ``overrides``."""
    presets = getattr(getattr(cls, "declaration", None), "presets", {})
    if preset is not None and preset not in presets:
        raise SpecError(f"{cls.__name__}: no preset {preset!r} (have: {', '.join(presets)})")
    where = f"{preset or cls.__name__} config"
    return make_config(cls.Config, config, where=where, base=presets.get(preset), **overrides)


def reset_vessels(task: Task, idx: np.ndarray, options: Mapping | None) -> None:
    """Reset the vessels ``idx``: vessel k by the task's ``reset_vessel`` with its generator ``rngs[k]``, so
    each draws exactly what a lone reset draws, and the simulation's starts (:func:`start`) gathered into one
    batched ``Simulation.reset`` (numpy over the vessels, one steady-state solve per distinct approach); a task
    that defines ``reset_batch`` resets them all at once."""
    if type(task).reset_batch is not Task.reset_batch:  # a start written over arrays: all at once
        task.reset_batch(idx, task.rngs.draws(idx), options)  # type: ignore[attr-defined]
        return
    rng = getattr(task.rngs, "lazy", task.rngs.__getitem__)  # lazy: made at a first draw (env.py)
    if len(idx) == 1:
        k = int(idx[0])
        task.reset_vessel(k, rng(k), options)
        return
    task._starts = starts = ([], [], [], [], [])
    try:
        for k in idx.tolist():
            task.reset_vessel(k, rng(k), options)
    finally:
        task._starts = None
    if not starts[0]:  # a task that resets the simulation itself
        return
    ks = np.array(starts[0], dtype=np.int64)
    sp, hd, xs, ys = (np.array(v, dtype=float) for v in starts[1:])
    task.sim.reset(speed_m_s=sp, heading_deg=hd, x_m=xs, y_m=ys, k=ks)
    task.started(ks)


def start(task: Task, k: int, speed: float, heading: float, x_m: float = 0.0, y_m: float = 0.0) -> None:
    """Vessel k in a steady straight approach (``Simulation.reset``) at ``speed`` (m/s) on ``heading`` (deg)
    at (``x_m``, ``y_m``), then the task's ``started``: at once, or with the others of a :func:`reset_vessels`
    batch (the simulation's state of vessel k is then new only after the task's ``reset_vessel``)."""
    starts = task._starts
    if starts is None:
        task.sim.reset(speed_m_s=speed, heading_deg=heading, x_m=x_m, y_m=y_m, k=k)
        task.started(k)
        return
    for column, value in zip(starts, (k, speed, heading, x_m, y_m)):
        column.append(value)


def start_batch(task: Task, idx: np.ndarray, speed: Any, heading: Any, x_m: Any = 0.0, y_m: Any = 0.0) -> None:
    """:func:`start` of the vessels ``idx`` at once (values scalars or arrays over ``idx``): one batched
    ``Simulation.reset``, then the task's ``started`` (one vessel: the simulation's scalar path)."""
    k: Any = idx
    if len(idx) == 1:
        k = int(idx[0])
        speed, heading, x_m, y_m = (float(np.ravel(v)[0]) for v in (speed, heading, x_m, y_m))
    task.sim.reset(speed_m_s=speed, heading_deg=heading, x_m=x_m, y_m=y_m, k=k)
    task.started(k)


def observation_features(task: Task) -> list[Feature]:
    """The observation entries, in order: the declared features the task observes, scales resolved."""
    return task.spec.layout(task.observed(), task.scales(), task.feature_counts())


def compiled_entry(kernel: Any, phase: np.ndarray, records: tuple) -> Any:
    """The compiled code of the numba dispatcher ``kernel`` for ``phase`` and ``records`` of these types, called
    without the dispatcher, which works out the numba type of every argument on every call (about 50 ns per
    array: for the 12-22 arrays of a task's records more than a one-ship update costs). Later calls must pass
    a phase of the same type (an int8 row). ``kernel`` itself if it is not compiled (a plain function,
    ``NUMBA_DISABLE_JIT=1``) or has no code for these types."""
    overloads = getattr(kernel, "overloads", None)
    if not overloads:
        return kernel
    from numba import typeof

    compiled = overloads.get((typeof(phase), *(typeof(r) for r in records)))
    return kernel if compiled is None else compiled.entry_point


def compiled_call(kernel: Any, args: tuple) -> tuple[Any, tuple]:
    """(code, arguments) of the numba dispatcher ``kernel`` for ``args`` of these types, called without the
    dispatcher (as :func:`compiled_entry`, for a kernel without a phase); ``(kernel, args)`` if it has no
    compiled code for them (``NUMBA_DISABLE_JIT=1``, or not called with them yet)."""
    overloads = getattr(kernel, "overloads", None)
    if overloads:
        from numba import typeof

        compiled = overloads.get(tuple(typeof(a) for a in args))
        if compiled is not None:
            return compiled.entry_point, args
    return kernel, args


def _uniform(rng: Any, rng_range: Sequence[float]) -> Any:
    """A number uniform in [min, max) of ``rng_range`` (min when the range is empty: no draw): a float from a
    numpy Generator, an array of one per vessel from :class:`~vessel_gym.envs.generators.BatchDraws`."""
    lo, hi = float(rng_range[0]), float(rng_range[1])
    return lo if hi <= lo else rng.uniform(lo, hi)
