"""A Gymnasium wrapper that puts any vessel-gym environment on the UDP link.

:class:`UdpLinkWrapper` opens a :class:`~vessel_gym.net.link.UdpLink` for the environment's ship. At each step
it services the link (receives helm commands, sends the own ship's JSON state, NMEA 0183 and the targets as
JSON and AIS), and while a human helm panel holds the helm, the panel's orders override the agent's on the
simulation (:meth:`~vessel_gym.physics.simulation.Simulation.override_helm`, in SI units).
``info["helm"]`` says who steered the step: ``"agent"``, ``"human"`` or ``"failsafe"``.

Cost. The own ship's readings (``sim.bridge``) are computed only when the link has a client to serve or NMEA
is due, traffic is simulated only when someone reads the targets, and the link is serviced at most once per
``min_service_interval_s`` of link time. A wrapper with no peers and NMEA off therefore costs a clock read and
a comparison per step plus one non-blocking socket poll every 10 ms (well under 5 % of a step).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Mapping
from typing import Any

import gymnasium as gym
import numpy as np

from vessel_gym.net.batch_targets import BatchTargets
from vessel_gym.net.link import HelmState, LinkConfig, UdpLink
from vessel_gym.net.protocol import AssistReading, AssistUnit, Limits, ShipParticulars, StateExtras
from vessel_gym.physics.bridge import BridgeReading
from vessel_gym.physics.units import DEG, RPM
from vessel_gym.scenarios.traffic import Traffic

TAKEOVER_MODES = ("helm", "never")
STEERED_BY = ("agent", "human", "failsafe")


#: the outcome figures an ``outcome`` event carries, where the task's info has them
OUTCOME_FIGURES = (
    "path_m",
    "min_clearance_m",
    "distance_to_goal_m",
    "min_separation_m",
    "colreg_score",
    "colreg_violations",
    "contact_speed_m_s",
    "contact_speed_limit_m_s",
    "max_fender_energy_fraction",
)


def assist_units(env: gym.Env) -> tuple[AssistUnit, ...]:
    """The thrusters and tugs an environment's helm orders after rudder and engine (the Berthing task's
    ``assist``; none for the others), as the link names them."""
    from vessel_gym.physics.components.tug import Tug

    units = getattr(env.unwrapped.task, "assist", ())
    return tuple(AssistUnit(c.name, "tug" if isinstance(c, Tug) else "thruster") for c in units)


def link_limits(env: gym.Env) -> Limits:
    """Helm-order limits of an environment's ship: its rudder limit, full-ahead/astern rpm, thrusters and tugs."""
    task = env.unwrapped.task
    rudder = getattr(task.helm, "rudder_limit_rad", None)
    rudder_deg = float(rudder[0]) / DEG if rudder is not None else task.delta_max / DEG
    rpm = float(np.max(np.abs(task.helm.rev_table[0]))) * 60.0
    return Limits(
        max_rudder_deg=rudder_deg, max_rpm=rpm if rpm > 0.0 else Limits().max_rpm, assist=assist_units(env)
    )


class UdpLinkWrapper(gym.Wrapper):
    """Publish an environment's ship on the UDP link and let a human helm panel take the helm.

    Args:
        env: a single vessel-gym environment (ZigZag, TurningCircle, HarbourApproach, or any whose
            ``unwrapped`` has ``sim`` and ``task``), wrapped or not.
        config: a :class:`LinkConfig`, a mapping for :meth:`LinkConfig.from_dict`, or None for the defaults
            (JSON on 127.0.0.1:10120, NMEA to 127.0.0.1:10110). If its ``limits`` are the defaults they are
            replaced by the ship's (rudder limit, full telegraph rpm), which the helm panel shows.
        takeover: ``"helm"`` (default): while a helm panel holds the helm its orders override the agent's;
            ``"never"``: publish only, helm commands are ignored.
        agent_resume_s: after the panel loses the helm (watchdog, ``bye``), the link's failsafe orders
            (``hold`` or ``midships_stop``) apply for this long (link-clock seconds), then the agent steers
            again. None: the failsafe orders stay in force until a panel commands again.
        traffic: ``"auto"`` (the target ships simulated in the environment's own batch, as CollisionAvoidance
            has them, else the scenario's ``[[traffic]]`` ships for HarbourApproach, else none), a
            :class:`~vessel_gym.scenarios.traffic.Traffic` with the environment's control interval, or None.
        clock: link time: ``"wall"`` (default, ``time.monotonic``), ``"sim"`` (simulation time; rates and the
            watchdog then run in simulated seconds), or a function returning seconds (tests).
        min_service_interval_s: the link is serviced at most once per this many link-clock seconds (and at
            every reset). Real-time loops step slower than this and service every step; a training loop
            running thousands of steps per second services the link every 10 ms (enough for the 50 Hz
            maximum state rate) instead of every step.
        link: an open :class:`UdpLink` to use instead of opening one (``config`` must then be None); it is
            not closed by :meth:`close`.

    Human orders reach the physics as the panel gives them, whatever the environment's action type: the
    rudder order converted once from degrees to radians, the engine order as the shaft speed of the telegraph
    step (or ``rpm_order`` converted to rev/s), the thruster and tug orders (Berthing) as the fractions they
    are. The agent's action is still applied (and checked) at every step; the panel's orders override it on
    the simulation while the panel (or the link's failsafe) holds the helm (its thruster and tug orders take
    the place of the action's).
    When the agent gets the helm back, its next action sets the orders; without engine control in the action
    the panel's shaft-speed order stays, as on a ship. The wrapper works on single environments (one own ship;
    target ships in the same batch are published as targets); it reads vessel 0.
    """

    def __init__(
        self,
        env: gym.Env,
        config: LinkConfig | Mapping[str, Any] | None = None,
        *,
        takeover: str = "helm",
        agent_resume_s: float | None = 5.0,
        traffic: Traffic | str | None = "auto",
        clock: str | Callable[[], float] = "wall",
        min_service_interval_s: float = 0.01,
        link: UdpLink | None = None,
    ) -> None:
        super().__init__(env)
        base = env.unwrapped
        if not hasattr(base, "sim") or not hasattr(base, "task"):
            raise ValueError(f"UdpLinkWrapper needs a vessel-gym environment, not {type(base).__name__}")
        if getattr(base, "num_envs", 1) != 1:  # own ship 0 is the served ship: other own ships are targets
            raise ValueError("UdpLinkWrapper wraps single environments (one served own ship), not vector ones")
        if takeover not in TAKEOVER_MODES:
            raise ValueError(f"takeover must be one of {TAKEOVER_MODES}, not {takeover!r}")
        if agent_resume_s is not None and not (math.isfinite(agent_resume_s) and agent_resume_s >= 0.0):
            raise ValueError(f"agent_resume_s must be >= 0 or None, not {agent_resume_s!r}")
        if not (math.isfinite(min_service_interval_s) and min_service_interval_s >= 0.0):
            raise ValueError(f"min_service_interval_s must be >= 0, not {min_service_interval_s!r}")
        self.takeover = takeover
        self.agent_resume_s = agent_resume_s
        self.min_service_interval_s = float(min_service_interval_s)
        self._sim = base.sim
        task = base.task
        self._helm = task.helm
        # rev/s of telegraph steps -4..4
        self._rev_table = np.array([self._sim.telegraph_rev(t, 0) for t in range(-4, 5)], dtype=np.float64)
        self._discrete_telegraph = base.config.action_type == "discrete" and bool(task.helm.engine)

        if clock == "wall":
            self._clock: Callable[[], float] = time.monotonic
        elif clock == "sim":
            self._clock = lambda: float(self._sim.t)
        elif callable(clock):
            self._clock = clock
        else:
            raise ValueError(f"clock must be 'wall', 'sim' or a function, not {clock!r}")

        if traffic == "auto":
            scenario = getattr(task, "scenario", None)
            if BatchTargets.has_targets(base):
                traffic = BatchTargets(base)
            elif scenario is not None:
                traffic = Traffic.from_scenario(scenario, base.task.dt, base.config.control_interval_s)
            else:
                traffic = None
        elif traffic is not None and not isinstance(traffic, Traffic):
            raise ValueError(f"traffic must be 'auto', a Traffic or None, not {traffic!r}")
        if traffic is not None and abs(traffic.control_interval_s - base.config.control_interval_s) > 1e-9:
            raise ValueError(
                f"traffic control interval {traffic.control_interval_s:g} s differs from the environment's "
                f"{base.config.control_interval_s:g} s"
            )
        self.traffic: Traffic | BatchTargets | None = traffic
        self._assist = list(getattr(task, "assist", ()))  # thrusters and tugs (Berthing), in action order
        self._assist_cols = list(getattr(task, "assist_states", ()))
        self._held_assist: tuple[float, ...] | None = None  # the panel's orders while it holds the helm

        if link is not None:
            if config is not None:
                raise ValueError("give either config or link, not both")
            self.link = link
            self._owns_link = False
        else:
            if config is None:
                config = LinkConfig()
            elif isinstance(config, Mapping):
                config = LinkConfig.from_dict(config)
            elif not isinstance(config, LinkConfig):
                raise ValueError(f"config must be a LinkConfig, a mapping or None, not {config!r}")
            if config.limits == Limits():
                config = dataclasses.replace(config, limits=link_limits(env))
            self.link = UdpLink(config)
            self._owns_link = True
        if self._assist or hasattr(task, "fenders"):
            self.link.state_extras = self._state_extras

        self._steps = 0  # control steps since the last reset (the traffic's clock)
        self._total_steps = 0
        self._last_service = -math.inf
        self._next_service = -math.inf
        self._last_helm: HelmState | None = None
        self._lost_at: float | None = None
        self._who = "agent"
        self._telegraph: int | None = None  # telegraph of the overriding orders; None: the agent steers
        self._steps_by = dict.fromkeys(STEERED_BY, 0)  # steps before the current helm spell
        self._who_since = 0  # total step count when the current helm spell began
        self._episode = 0

    # --- state ------------------------------------------------------------------------------------------------

    @property
    def helm_state(self) -> HelmState:
        """The link's helm state as of the last service."""
        return self.link.helm

    @property
    def steps_by(self) -> dict[str, int]:
        """Steps steered by the agent, the human and the failsafe since the wrapper was made."""
        out = dict(self._steps_by)
        out[self._who] += self._total_steps - self._who_since
        return out

    @property
    def steered_by(self) -> str:
        """Who steers now: ``"agent"``, ``"human"`` or ``"failsafe"``."""
        return self._who

    def _nearest_step(self, rev: float) -> int:
        return int(np.argmin(np.abs(self._rev_table - rev))) - 4

    def _own_reading(self) -> BridgeReading:
        if self._telegraph is not None:
            tg = self._telegraph
        elif self._discrete_telegraph:
            tg = int(self._helm.telegraph[0])
        else:
            rev = float(self._sim.rev_order[0])
            tg = 0 if rev == 0.0 else self._nearest_step(rev)
        return self._sim.bridge(0, tg)

    # --- helm -------------------------------------------------------------------------------------------------

    def _override(self, helm: HelmState) -> None:
        """Hold the orders of ``helm`` on the simulation, in SI units (the link speaks degrees and rpm)."""
        if helm.telegraph is not None:
            telegraph = int(helm.telegraph)
            rev = float(self._rev_table[telegraph + 4])
        elif helm.rpm_order is not None:
            rev = float(helm.rpm_order) * RPM
            telegraph = 0 if rev == 0.0 else self._nearest_step(rev)
        else:  # pragma: no cover - a command always has one engine order
            rev = float(self._sim.rev_order[0])
            telegraph = self._nearest_step(rev)
        self._sim.override_helm(0, rudder_order_rad=float(helm.rudder_order_deg) * DEG, rev_order=rev)
        self._telegraph = telegraph
        if self._assist:
            held = tuple(helm.assist) if len(helm.assist) == len(self._assist) else (0.0,) * len(self._assist)
            for c, o in zip(self._assist, held):
                c.set_order(o, 0, 1)
            self._held_assist = held

    def _release(self) -> None:
        """Hand the helm back to the agent (its next action sets the orders)."""
        if self._telegraph is not None:
            self._sim.override_helm(0)
            self._telegraph = None
        self._held_assist = None

    def _with_held_assist(self, action: Any) -> Any:
        """The action with the panel's thruster and tug orders in place of the agent's while it holds the helm
        (they follow rudder and engine in the Berthing action)."""
        if self._held_assist is None:
            return action
        a = np.array(action, dtype=np.float32).reshape(-1).copy()
        a[2 : 2 + len(self._held_assist)] = self._held_assist
        return a

    def _state_extras(self) -> StateExtras:
        """The thrusters' and tugs' orders and deliveries and the fenders' loads of vessel 0, for the state."""
        assist: tuple[AssistReading, ...] = ()
        if self._assist:
            names = self.link.config.limits.assist
            z = self._sim.component_states[:1]
            assist = tuple(
                AssistReading(u.name, u.kind, float(c.orders(1)[0]), float(c.delivered(z[:, cols])[0]))
                for c, cols, u in zip(self._assist, self._assist_cols, names)
            )
        load: tuple[float, ...] = ()
        overlay = getattr(self.env.unwrapped.task, "overlay", None)
        if hasattr(self.env.unwrapped.task, "fenders") and overlay is not None:
            load = tuple(float(x) for x in overlay(0)["berth"]["fender_load"])
        return StateExtras(assist=assist, fender_load=load)

    def _decide(self, now: float, helm: HelmState) -> None:
        """Who steers, given the link's helm state at link time ``now``."""
        if self.takeover == "never" or not helm.has_orders:
            who = "agent"
            self._lost_at = None
        elif helm.helm_ok:
            who = "human"
            self._lost_at = None
        else:
            if self._lost_at is None:
                self._lost_at = now
            resumed = self.agent_resume_s is not None and now - self._lost_at >= self.agent_resume_s
            who = "agent" if resumed else "failsafe"
        if who == "agent":
            self._release()
        elif helm is not self._last_helm or self._telegraph is None:
            self._override(helm)
        self._last_helm = helm
        if who != self._who:
            self._steps_by[self._who] += self._total_steps - self._who_since
            self._who_since = self._total_steps
            self._who = who

    def _service(self, now: float) -> None:
        targets = self.traffic.lazy_targets(self._steps) if self.traffic is not None else ()
        helm = self.link.service(now, self._own_reading, targets)
        self._last_service = now
        self._next_service = now + self.min_service_interval_s
        self._decide(now, helm)

    def service(self) -> HelmState:
        """Service the link now, between steps (a real-time loop's finer ticks: state at the clients' rates).

        Orders received take effect from the next step, as orders received at a step do."""
        self._service(self._clock())
        return self.link.helm

    # --- gymnasium API ----------------------------------------------------------------------------------------

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        obs, info = self.env.reset(seed=seed, options=options)
        self._steps = 0
        if self.traffic is not None:
            self.traffic.reset()
        self._episode += 1
        self._publish_scene()
        self._service(self._clock())
        info["helm"] = self._who
        return obs, info

    def step(self, action: Any):
        now = self._clock()
        if not self._last_service <= now < self._next_service:  # due (or the clock went back)
            self._service(now)
        obs, reward, terminated, truncated, info = self.env.step(self._with_held_assist(action))
        self._steps += 1
        self._total_steps += 1
        info["helm"] = self._who
        if terminated or truncated:
            self._publish_outcome(info, truncated and not terminated)
        return obs, reward, terminated, truncated, info

    # --- protocol v2 ------------------------------------------------------------------------------------------

    def _publish_scene(self) -> None:
        """Scenario, sea state and particulars for v2 viewers, and the ``reset`` event (once per episode)."""
        task = self.env.unwrapped.task
        p = task.ship.particulars
        ships = [ShipParticulars(0, task.ship.name, p.L_m, p.B_m, p.T_m)]
        if self.traffic is not None:
            tr = self.traffic
            # ships of the encounter only (an encounter may leave target slots of the batch empty)
            taking_part = set(tr.active()) if isinstance(tr, BatchTargets) else set(range(len(tr.ids)))
            for j, (tid, spec, ship) in enumerate(zip(tr.ids, tr.specs, tr.ships)):
                if j not in taking_part:
                    continue
                q = ship.particulars
                ships.append(ShipParticulars(tid, spec.name, q.L_m, q.B_m, q.T_m))
        environments = getattr(self._sim, "environments", None)
        scenario = getattr(task, "scenario", None) or getattr(task, "waters", None)
        self.link.set_scene(
            scenario, ships, environments[0] if environments else None, features=task_features(task)
        )
        self.link.publish_event("reset", float(self._sim.t), self._episode)

    def _publish_outcome(self, info: dict[str, Any], time_limit: bool) -> None:
        outcome = (
            "time_limit"
            if time_limit and info.get("outcome", "running") == "running"
            else info.get("outcome")
        )
        t = float(self._sim.t)
        if outcome in ("contact", "grounding"):
            own = self._own_reading()
            self.link.publish_event("contact", t, self._episode, what=outcome, x_m=own.x_m, y_m=own.y_m)
        figures = {k: float(info[k]) for k in OUTCOME_FIGURES if k in info}
        self.link.publish_event("outcome", t, self._episode, outcome=str(outcome or "ended"), **figures)

    def close(self) -> None:
        self._release()
        if self._owns_link:
            self.link.close()
        super().close()


def task_features(task: Any) -> list[dict]:
    """Scene features a task adds to its scenario's (protocol v2 ``scenario.features``): a berth's fenders
    (``fender``, a quadrilateral from the quay to the unloaded face, in order) and the own ship's route
    (``route``, CollisionAvoidance: start and goal)."""
    out: list[dict] = []
    fenders = getattr(task, "fenders", None)
    if fenders is not None:
        H = task.berth.fender.height_m  # m, the fender's depth from quay to face
        base = fenders.faces - H * np.asarray(fenders.to_water)
        half = 0.5 * H * np.asarray(task.along_dir)  # m: drawn as wide as it is deep
        for j, (b, f) in enumerate(zip(base, fenders.faces)):
            quad = [b - half, b + half, f + half, f - half]
            out.append(
                {"kind": "fender", "name": f"fender {j + 1}", "points": [list(map(float, p)) for p in quad]}
            )
    ts = getattr(task, "ts", None)
    if ts is not None and hasattr(task, "world"):
        from vessel_gym.envs.tasks.colreg_columns import S

        s = ts[0]
        out.append(
            {
                "kind": "route",
                "name": "route",
                "points": [[float(s[S.n0]), float(s[S.e0])], [float(s[S.n1]), float(s[S.e1])]],
            }
        )
    return out


__all__ = [
    "OUTCOME_FIGURES",
    "STEERED_BY",
    "TAKEOVER_MODES",
    "UdpLinkWrapper",
    "assist_units",
    "link_limits",
    "task_features",
]
