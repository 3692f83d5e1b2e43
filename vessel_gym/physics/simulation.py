"""Simulation: vessel(s) + environment & sea state + motion constraints + a fixed-step integrator.

The five top-level parts of a simulation are Bridge & Navigation (:mod:`~vessel_gym.physics.bridge`),
Vessel (:mod:`~vessel_gym.physics.vessel`), Motion Constraints (free 3-DOF here; captive in
:mod:`~vessel_gym.physics.constraints`), Sea-State and Environment & Atmosphere
(:class:`~vessel_gym.physics.environment.Environment`). State is batched over N vessels; N = 1 and
N = 16384 run the same compiled code.

Its jobs live beside it: the steady approach a reset starts from (:mod:`~vessel_gym.physics.steady`), runaway
detection (:mod:`~vessel_gym.physics.runaway`), the helm and its override (:mod:`~vessel_gym.physics.helm`),
the choice of batch driver (:mod:`~vessel_gym.physics.drivers`), the evaluation of a user's Python
components (:mod:`~vessel_gym.physics.components.batch`), and the named quantities, forces and instrument
readings of the vessels (:mod:`~vessel_gym.physics.readings`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

import numpy as np

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import ForceRecord
from vessel_gym.physics.components.batch import ComponentBatch
from vessel_gym.physics.components.compose import compose, named_forces
from vessel_gym.physics.drivers import threaded
from vessel_gym.physics.environment import (
    CALM,
    FIELDS,
    Environment,
    EnvironmentList,
    environment_rows,
    environment_values,
)
from vessel_gym.physics.helm import Helm
from vessel_gym.physics.integrate import EULER, RK4, drivers_for, run_with_components
from vessel_gym.physics.readings import Readings
from vessel_gym.physics.runaway import RUNAWAY_OK, flag_runaway, runaway_limits
from vessel_gym.physics.shallow_water import check_hull
from vessel_gym.physics.shipfile import Ship, load_ship
from vessel_gym.physics.steady import (
    STEADY_MAX_ITERATIONS,
    _SteadyApproach,
    distinct_rows,
    steady_rows,
    steady_state,
)
from vessel_gym.physics.units import DEG
from vessel_gym.physics.vessel import pack

# steady approaches cached per simulation (each two rows of NX and NU floats)
STEADY_CACHE_SIZE = 1024  # entries
# distinct approaches in one reset above which the cache is not searched: a look-up costs ~1.5 us of Python and
# a hit saves one solve (~25 us), but at most STEADY_CACHE_SIZE of them can hit, so beyond ~16 x that many the
# look-ups cost more than they can save (the rows are the same either way: a cached row is a solved one)
STEADY_LOOKUP_MAX = 16 * STEADY_CACHE_SIZE  # approaches
# distinct approaches in one reset above which they are solved in one compiled loop (steady_rows: ~40 % less
# time per approach than one call each, but one more compiled function: resets of a few approaches keep the
# scalar solver)
STEADY_BATCH_MIN = 64
# environment row entries with a direction: while all are zero no force depends on the heading
_DIRECTIONAL_ENV = [lo.E_CUR_N, lo.E_CUR_E, lo.E_WIND_N, lo.E_WIND_E, lo.E_ZETA2]


class ForceComponent(Protocol):
    """A user component written in plain Python: extra forces on every vessel of the batch.

    ``forces`` receives the simulation and the state array being evaluated (N, NX) (inside an RK4 stage
    this is the stage state, not ``sim.state``) and returns an (N, 3) array of X (N), Y (N), N (N m) at the
    body origin. It is called once per stage for the whole batch (and a few times per ``reset``, whatever the
    number of vessels reset), so a component written with numpy array operations costs O(N). Plug a whole
    replacement hull in by giving the ship file ``[hull] model`` of your own and returning its forces here
    (see docs/components.md). A component that owns states (``states``, :class:`~vessel_gym.physics.components.
    State` entries) gets them as a third argument ``s`` (N, k) and gives their rates with ``rates(sim, x, s)``;
    an engine or a steering gear subclasses :class:`~vessel_gym.physics.components.Engine` or
    :class:`~vessel_gym.physics.components.SteeringGear`.
    """

    def forces(self, sim: Simulation, x: np.ndarray) -> np.ndarray: ...


class Simulation(Readings, Helm):
    """N vessels integrated together with a fixed step.

    Args:
        ships: a ship (name, path or :class:`Ship`) or a sequence of them.
        n: number of vessels (default: one per ship given).
        ship_index: which ship each vessel is (length n); default 0 for all when one ship, else range.
        dt: physics step, s.
        method: "rk4" (default) or "euler".
        environment: one :class:`Environment` for all vessels (``set_environment`` changes one vessel).
        components: user :class:`ForceComponent` objects (evaluated in Python for the whole batch at every
            RK stage, :func:`~vessel_gym.physics.integrate.run_with_components`).
        replace: slots whose built-in component a user component replaces: "hull" (with its added mass; the
            replacing hull gives ``added_mass()``), "rudder" (with a derivative rudder's hull delta terms),
            "windage", "wave_drift" ("wind", "waves" too), "engine" (with its governor, reversing gear and
            inertia; the replacing ``Engine`` drives the shaft), "steering_gear" (the replacing ``SteeringGear``
            gives the rudder rate). A component in a slot a built-in fills without ``replace``, or two in one
            slot, raise ValueError (docs/components.md).
        reference_latlon_deg: geodetic reference point of local x/y (north/east) for bridge readings.
        shallow_water: the vessels will meet shallow water after the start (a depth written into their
            environment rows later, e.g. a chart's under each ship): the shallow-water kind of the compiled
            equations serves the drivers and the steady approaches from the start, in deep water too, so that
            only that kind is compiled. The results are those of the deep-water kind to the bit (each
            shallow-water factor is its deep-water value at T/h = 0); only compile time differs.
    """

    _kernels_checked = False  # whether the drivers' kind was checked against the rows since it was chosen

    def __init__(
        self,
        ships: str | Ship | Sequence[str | Ship],
        n: int | None = None,
        ship_index: Sequence[int] | None = None,
        dt: float = 0.1,
        method: str = "rk4",
        environment: Environment = CALM,
        components: Sequence[ForceComponent] = (),
        replace: Sequence[str] = (),
        reference_latlon_deg: tuple[float, float] = (0.0, 0.0),
        shallow_water: bool = False,
    ) -> None:
        self.shallow_water = bool(shallow_water)
        seq = [ships] if isinstance(ships, (str, Ship)) or not isinstance(ships, Sequence) else list(ships)
        self.ships: list[Ship] = [load_ship(s) for s in seq]
        if n is None:
            n = len(self.ships)
        if n < 1:
            raise ValueError(f"n must be >= 1, got {n}")
        if ship_index is None:
            ship_index = [0] * n if len(self.ships) == 1 else list(range(n))
        self.ship_index = np.asarray(ship_index, dtype=np.int64)
        if (
            self.ship_index.shape != (n,)
            or self.ship_index.min() < 0
            or self.ship_index.max() >= len(self.ships)
        ):
            raise ValueError(f"ship_index must have {n} entries in [0, {len(self.ships) - 1}]")
        if not (dt > 0.0 and np.isfinite(dt)):
            raise ValueError(f"dt must be a positive number of seconds, got {dt}")
        if method not in ("rk4", "euler"):
            raise ValueError(f"method must be 'rk4' or 'euler', got {method!r}")
        self.dt = float(dt)
        self.method = RK4 if method == "rk4" else EULER
        self.Ps = np.stack([pack(s) for s in self.ships])
        # the user's components act on every vessel, a ship file's on that ship's vessels; each slot is filled
        # once and a replaced built-in contributes nothing (components.compose)
        self._batch = ComponentBatch(n)
        for c in components:
            self._batch.add(c)
        for si, s in enumerate(self.ships):
            own = [e.build(s) for e in s.components]
            slots = [*replace, *(e.slot for e in s.components if e.replace)]
            where = f"Simulation of {s.path or s.name}"
            self.Ps[si] = compose(s, self.Ps[si], [*components, *own], slots, where)
            mask = self.ship_index == si
            if mask.any():
                for c in own:
                    self._batch.add(c, None if mask.all() else mask)
        self.components = self._batch.components
        # the states the components own (N, NZ), columns named in component_state_names
        self.component_states = self._batch.initial_states()
        self.component_state_names = tuple(self._batch.state_names)
        self.n = n
        self.state = np.zeros((n, lo.NX))
        self.inputs = np.zeros((n, lo.NU))
        self.env = np.zeros((n, lo.NE))
        self.F_ext = np.zeros((n, 3))
        self.alive = np.ones(n, dtype=np.bool_)
        # why each vessel stopped (RUNAWAY_*, 0 while alive) and the bounds it is held to, by ship
        self.why_dead = np.zeros(n, dtype=np.int64)
        self._runaway_limits = np.array([runaway_limits(s) for s in self.ships], dtype=float)
        # steady approaches solved so far, by (parameter row, speed, heading, environment row): environments
        # reset ships one at a time, mostly to the same approach
        self._steady_cache: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
        self.t = 0.0
        self.reference_latlon_deg = reference_latlon_deg
        self.environments = EnvironmentList(environment, n)
        # the compiled batch drivers (serial, threaded) of this batch's kind: deep or shallow water, with or
        # without roll (integrate.drivers); set_environment chooses them, step again when the kind changed
        self.set_environment(environment)
        # Ps rows as bytes, by ship, for the steady-state cache keys: one object shared by every entry of a
        # ship while its parameters are unchanged (a row is ~7.5 kB; one copy per entry would dominate)
        self._param_bytes: dict[int, bytes] = {}

    # --- set-up -------------------------------------------------------------------------------------------
    def ship(self, k: int = 0) -> Ship:
        return self.ships[self.ship_index[k]]

    def set_environment(self, environment: Environment, k: int | None = None) -> None:
        """Set the environment of vessel k (all vessels when k is None)."""
        for s in self.ships if k is None else [self.ship(k)]:
            check_hull(s, environment.depth_m)  # a finite depth needs a hull the corrections are for
        if k is None:  # one row per ship, spread over the vessels in one numpy operation
            rows = np.stack([environment.row(s.particulars.L_m, s.particulars.T_m) for s in self.ships])
            self.env[:] = rows[self.ship_index]
            self.environments[:] = [environment] * self.n
            self._kernels = drivers_for(self.Ps, self.env, self.shallow_water)
            self._kernels_checked = False
            return
        # one vessel: the drivers check the batch's kind themselves and :meth:`step` chooses again when needed
        s = self.ship(k)
        self.env[k] = environment.row(s.particulars.L_m, s.particulars.T_m)
        self.environments[k] = environment

    def set_environments(self, idx: np.ndarray, **fields: float | np.ndarray) -> None:
        """Set the environments of the vessels ``idx`` at once: ``Environment`` fields given as arrays over
        ``idx`` (or scalars), the others at their defaults; the same rows as :meth:`set_environment` of each,
        computed over arrays, with no Environment object kept per vessel (``environments[k]`` makes one; in a
        simulation of one vessel, where numpy's fixed costs would make it ten times slower, by
        :meth:`set_environment`)."""
        idx = np.asarray(idx, dtype=np.int64)
        if self.n == 1 and len(idx) == 1:  # a one-ship environment's reset: its Environment, ~10 x less time
            one = {key: float(np.ravel(v)[0]) for key, v in fields.items()}
            self.set_environment(Environment(**one), int(idx[0]))
            return
        vals = environment_values(fields, len(idx))
        if len(self.ships) == 1:  # one ship type (a vector env's): no grouping (an automatic reset of a few)
            groups: list = [(self.ships[0], idx, vals)]
        else:
            si = self.ship_index[idx]
            groups = [(self.ships[i], idx[si == i], vals[si == i]) for i in np.unique(si).tolist()]
        for s, mine, v in groups:
            depth = v[:, FIELDS.index("depth_m")]
            for d in [float(depth[0])] if len(depth) and (depth == depth[0]).all() else np.unique(depth).tolist():
                check_hull(s, d)
            self.env[mine] = environment_rows(v, s.particulars.L_m, s.particulars.T_m)
        self.environments.set_values(idx, vals)

    def reset(
        self,
        speed_m_s: float | np.ndarray | None = None,
        heading_deg: float | np.ndarray = 0.0,
        x_m: float | np.ndarray = 0.0,
        y_m: float | np.ndarray = 0.0,
        k: int | np.ndarray | None = None,
    ) -> None:
        """Put vessel k (all when None) in a steady straight approach at ``speed_m_s`` through the water.

        ``k`` may be an array of vessel indices (a batched partial reset, O(len(k)) in numpy): then an array
        value of ``speed_m_s``, ``heading_deg``, ``x_m`` or ``y_m`` has one entry per listed vessel.

        The shaft-speed order is solved for zero surge acceleration and the governor integrator is set to
        the fuel index that holds it (IMO trials start from a steady approach). Speed None: the ship's
        IMO test speed. Raises SimulationError if the engine cannot make that speed.
        """
        speed_m_s = np.nan if speed_m_s is None else speed_m_s
        listed = k is not None and np.ndim(k) == 1
        if k is not None and not listed and not self.components:  # one ship: scalar code
            self._reset_one(k, speed_m_s, heading_deg, x_m, y_m)
            return
        idx = np.arange(self.n) if k is None else np.atleast_1d(np.asarray(k, dtype=np.int64))
        heading_at = self._at(heading_deg, idx, listed)  # before the spread below changes what it is
        if self.components:  # user forces take part in the equilibrium: solved for all vessels at once
            if listed:  # values per listed vessel: spread to per-vessel arrays
                speed_m_s, heading_deg = self._spread(speed_m_s, idx), self._spread(heading_deg, idx)
            sp = self._per_vessel(speed_m_s)
            hd = self._per_vessel(heading_deg)
            self._reset_with_components(idx.tolist(), sp, hd)
        else:
            self._reset_steady(idx, self._at(speed_m_s, idx, listed), heading_at)
        # every vessel's row is set above (state and inputs), position and flag here: numpy over idx, O(N)
        self.state[idx, lo.X_PSI] = heading_at * DEG
        self.state[idx, lo.X_N] = self._at(x_m, idx, listed)
        self.state[idx, lo.X_E] = self._at(y_m, idx, listed)
        self.alive[idx] = True
        self.why_dead[idx] = RUNAWAY_OK
        if k is None:
            self.t = 0.0

    def _spread(self, value: float | np.ndarray, idx: np.ndarray) -> float | np.ndarray:
        """A scalar as it is; an array with one entry per vessel of ``idx`` as a per-vessel array (the others
        zero, never read)."""
        if np.ndim(value) == 0:
            return value
        full = np.zeros(self.n)
        full[idx] = np.broadcast_to(np.asarray(value, dtype=float), idx.shape)
        return full

    def _at(self, value: float | np.ndarray, idx: np.ndarray, listed: bool = False) -> np.ndarray:
        """A scalar or per-vessel ``value`` as floats of the vessels ``idx`` (``listed``: an array value has
        one entry per vessel of ``idx`` already)."""
        if listed:
            return np.broadcast_to(np.asarray(value, dtype=float), idx.shape)
        return np.broadcast_to(np.asarray(value, dtype=float), (self.n,))[idx]

    def _one(self, value: float | np.ndarray, k: int) -> float:
        """A scalar or per-vessel ``value`` of vessel k, as a float."""
        if isinstance(value, (float, int)):
            return float(value)
        return float(np.broadcast_to(np.asarray(value, dtype=float), (self.n,))[k])

    def _reset_one(self, k: int, speed_m_s, heading_deg, x_m, y_m) -> None:
        """:meth:`reset` of vessel k alone (no user components), in scalar code."""
        si = int(self.ship_index[k])
        sp = self._one(speed_m_s, k)
        speed = self.ships[si].test_speed_m_s if math.isnan(sp) else sp
        hd = self._one(heading_deg, k)
        env = self.env[k]
        hkey = hd if env[_DIRECTIONAL_ENV].any() else 0.0
        self.state[k], self.inputs[k] = self._steady_row(si, speed, hkey, env)
        self.state[k, lo.X_PSI] = hd * DEG
        self.state[k, lo.X_N] = self._one(x_m, k)
        self.state[k, lo.X_E] = self._one(y_m, k)
        self.alive[k] = True
        self.why_dead[k] = RUNAWAY_OK

    def _reset_steady(self, idx: np.ndarray, speed_m_s: np.ndarray, heading_deg: np.ndarray) -> None:
        """Steady approaches of the vessels ``idx`` without user components (speed NaN: the test speed;
        headings, deg; one entry per vessel of ``idx``), one solve per distinct approach (:meth:`_steady_row`),
        found with numpy (O(N log N) in C) and spread over the vessels by indexing."""
        si = self.ship_index[idx]
        test = np.array([s.test_speed_m_s for s in self.ships], dtype=float)
        sp = speed_m_s
        speed = np.where(np.isnan(sp), test[si], sp)
        env = self.env[idx]
        directional = (env[:, _DIRECTIONAL_ENV] != 0.0).any(axis=1)
        hkey = np.where(directional, heading_deg, 0.0)
        keys = np.column_stack([si.astype(float), speed, hkey, env])
        if len(idx) == 1 or (keys == keys[0]).all():
            first, inverse = np.zeros(1, dtype=np.int64), np.zeros(len(idx), dtype=np.int64)
        else:
            first, inverse = distinct_rows(keys)
        rows_x = np.empty((len(first), lo.NX))
        rows_u = np.empty((len(first), lo.NU))
        if len(first) > STEADY_BATCH_MIN:
            self._steady_batch(first, si, speed, hkey, env, rows_x, rows_u)
        else:
            for q, f in enumerate(first):
                rows_x[q], rows_u[q] = self._steady_row(int(si[f]), float(speed[f]), float(hkey[f]), env[f])
        self.state[idx] = rows_x[inverse.reshape(-1)]
        self.inputs[idx] = rows_u[inverse.reshape(-1)]

    def _steady_batch(self, first, si, speed, hkey, env, rows_x, rows_u) -> None:
        """:meth:`_steady_row` of the approaches ``first`` (rows of ``si``, ``speed``, ``hkey``, ``env``) into
        ``rows_x``, ``rows_u``: those not in the cache solved in one compiled loop per ship
        (:func:`steady_rows`), the last STEADY_CACHE_SIZE of them cached."""
        cache = self._steady_cache
        pkey = {s: self._params_key(s) for s in np.unique(si[first]).tolist()}
        sp, hk = speed.tolist(), hkey.tolist()
        sis = si.tolist()
        if not cache or len(first) > STEADY_LOOKUP_MAX:
            mq = np.arange(len(first))
        else:
            missing = []
            for q, f in enumerate(first.tolist()):
                hit = cache.get((pkey[sis[f]], sp[f], hk[f], env[f].tobytes()))
                if hit is None:
                    missing.append(q)
                else:
                    rows_x[q], rows_u[q] = hit
            mq = np.array(missing, dtype=np.int64)
        ship_of = si[first[mq]]
        for s in np.unique(ship_of).tolist():
            sel = mq[ship_of == s]
            f = first[sel]
            rows_x[sel], rows_u[sel] = steady_rows(
                self.ships[s], self.Ps[s], speed[f], hkey[f] * DEG, env[f], self.shallow_water
            )
        for q in mq[-STEADY_CACHE_SIZE:].tolist():
            f = int(first[q])
            if len(cache) >= STEADY_CACHE_SIZE:
                cache.clear()
            cache[(pkey[sis[f]], sp[f], hk[f], env[f].tobytes())] = (rows_x[q].copy(), rows_u[q].copy())

    def _steady_row(
        self, si: int, speed: float, hkey: float, env: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(state row, input row) of ship si's steady approach, from the cache or solved (:func:`steady_state`).

        An approach is keyed by the ship's parameter row as it is now, the speed, the environment row and the
        heading ``hkey`` (deg) -- the heading only where the environment has a direction (wind, current or
        waves; else the caller passes 0): in still air and water over a calm sea no force depends on it (the
        rotations meet zero vectors), so the solution is the same to the bit and only X_PSI differs, which the
        caller sets. The cache holds at most STEADY_CACHE_SIZE entries at any time, within a call too.
        """
        cache = self._steady_cache
        key = (self._params_key(si), speed, hkey, env.tobytes())
        hit = cache.get(key)
        if hit is None:
            hit = steady_state(
                self.ships[si], self.Ps[si], speed, env=env, heading_rad=hkey * DEG, shallow=self.shallow_water
            )
            if len(cache) >= STEADY_CACHE_SIZE:  # random headings or speeds: keep it bounded
                cache.clear()
            cache[key] = hit
        return hit

    def _params_key(self, si: int) -> bytes:
        """Ship ``si``'s parameter row as bytes (the parameters as they are now), the same object while they
        are unchanged."""
        b = self.Ps[si].tobytes()
        old = self._param_bytes.get(si)
        if old == b:
            return old
        self._param_bytes[si] = b
        return b

    def _reset_with_components(self, idx, sp, hd) -> None:
        """Steady approaches of the vessels ``idx`` with the user components' forces in the balance.

        The components are evaluated for the whole batch at once (the vessels being reset at their trial
        states, the others as they are), the surge balance is solved again for the vessels whose forces
        changed, up to :data:`STEADY_MAX_ITERATIONS` times: O(N) work and a bounded number of component calls.
        """
        solvers = {}
        for j in idx:
            si = int(self.ship_index[j])
            speed = self.ships[si].test_speed_m_s if math.isnan(sp[j]) else float(sp[j])
            solvers[j] = _SteadyApproach(
                self.ships[si], self.Ps[si], speed, self.env[j], hd[j] * DEG, self.shallow_water
            )
        X = self.state.copy()
        for j, s in solvers.items():
            X[j] = s.x
        with np.errstate(all="ignore"):
            F = self._ext(X)
        pending = [j for j, s in solvers.items() if s.start(F[j])]
        for _ in range(STEADY_MAX_ITERATIONS - 1):
            if not pending:
                break
            for j in pending:
                X[j] = solvers[j].x
            with np.errstate(all="ignore"):
                F_new = self._ext(X)
            pending = [j for j in pending if not np.array_equal(F_new[j], F[j])]
            for j in pending:
                F[j] = F_new[j]
                solvers[j].balance(F[j])
        Q_hold = np.zeros(self.n)
        for j, s in solvers.items():
            self.state[j], self.inputs[j] = s.finish()
            Q_hold[j] = s.Q_hold
        if self._batch.nz:
            with np.errstate(all="ignore"):
                self._batch.steady_states(self, self.state, Q_hold, self.component_states, list(solvers))

    def _per_vessel(self, value: float | np.ndarray) -> np.ndarray:
        """``value`` as one float per vessel (a scalar is repeated without copying)."""
        if isinstance(value, (float, int)):
            return _Repeat(float(value))
        return np.broadcast_to(np.asarray(value, dtype=float), (self.n,))

    # --- integration ----------------------------------------------------------------------------------------
    def _driver_args(self, nsteps: int) -> tuple:
        """The batch drivers' arguments for a call of ``nsteps`` steps, in their order."""
        return (
            self.Ps,
            self.ship_index,
            self.state,
            self.inputs,
            self.env,
            self.F_ext,
            self.dt,
            nsteps,
            self.method,
            self.alive,
        )

    def step(self, nsteps: int = 1) -> int:
        """Advance all vessels ``nsteps`` physics steps with the helm held. Returns the number alive."""
        if nsteps < 0:
            raise ValueError("nsteps must be >= 0")
        args = self._driver_args(nsteps)
        if self.components:
            # a diverging vessel overflows in the components' numpy; it is flagged, not warned about
            with np.errstate(all="ignore"):
                run_with_components(*args, self._evaluate_components, self.component_states)
        else:
            which = threaded(self.n, nsteps)  # serial or threaded by problem size (drivers.threaded)
            if not self._kernels_checked:
                # the first step since the drivers were chosen: rows written since (a chart's depth under the
                # ship) are seen here, in one pass of numpy, rather than by a driver compiled only to refuse
                self._kernels = drivers_for(self.Ps, self.env, self.shallow_water)
                self._kernels_checked = True
            if self._kernels[which](*args) < 0:
                # the batch is no longer of the kind its drivers were compiled for (Ps or env written
                # directly): nothing was integrated; choose the drivers again
                self._kernels = drivers_for(self.Ps, self.env, self.shallow_water)
                self._kernels[which](*args)
        self.t += nsteps * self.dt
        return int(flag_runaway(self.state, self.ship_index, self._runaway_limits, self.alive, self.why_dead))

    def advance(self, duration_s: float) -> int:
        """Advance ``duration_s`` seconds; it must be a whole multiple of dt (else ValueError)."""
        return self.step(steps_for(duration_s, self.dt))

    def _evaluate_components(self, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """What the Python components give the kernel (N, NF) and their own states' rates (N, NZ), at the
        stage states ``x`` and own states ``z`` (components.batch.ComponentBatch.evaluate)."""
        return self._batch.evaluate(self, x, z)

    def _component_forces(self, x: np.ndarray) -> np.ndarray:
        """Sum of the user components' forces (N, 3) on the batch of states ``x`` (N, NX)."""
        return self._batch.forces(self, x, self.component_states)

    def component_forces(self, x: np.ndarray | None = None) -> list[tuple[str, np.ndarray]]:
        """(name, forces (N, 3)) of each Python component at the states ``x`` (default: the current state),
        zero on vessels of other ships for a ship file's component."""
        return self._batch.forces_each(self, self.state if x is None else x, self.component_states)

    def component_state(self, name: str) -> np.ndarray:
        """A state a Python component owns, per vessel (a view): ``name`` is "Component.state", one of
        :attr:`component_state_names` (unit in the component's ``states``)."""
        if name not in self.component_state_names:
            raise KeyError(f"no component state {name!r} (one of {', '.join(self.component_state_names)})")
        return self.component_states[:, self.component_state_names.index(name)]

    def named_forces(self) -> dict[str, ForceRecord]:
        """Forces of every component at the current state by component name, each a record of X (N), Y (N),
        N (N m) per vessel (components.compose.named_forces)."""
        return named_forces(self)

    def _ext(self, x: np.ndarray) -> np.ndarray:
        """All external forces (N, 3) at the states ``x``: ``F_ext`` plus the user components'."""
        return self.F_ext + self._component_forces(x)


class _Repeat:
    """A scalar indexed like a per-vessel array (``Simulation.reset`` of one vessel should cost little)."""

    __slots__ = ("value",)

    def __init__(self, value: float) -> None:
        self.value = value

    def __getitem__(self, j: int) -> float:
        return self.value


def steps_for(duration_s: float, dt: float) -> int:
    """Number of physics steps in ``duration_s``; raises ValueError unless it is a whole multiple of dt."""
    k = round(duration_s / dt)
    if k < 0 or abs(k * dt - duration_s) > 1e-9 * max(1.0, abs(duration_s)):
        raise ValueError(f"interval {duration_s:g} s is not a whole multiple of the physics step {dt:g} s")
    return int(k)
