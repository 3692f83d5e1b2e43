"""What ``vessel-gym serve`` runs: the harbour scenario (HarbourApproach, the default) or a task chosen with
``--env`` (CollisionAvoidance and its Channel preset, Berthing and BerthingTanker), made for real time, with
its default helm, the figures of its outcome line and its debrief.

- CollisionAvoidance: the own ship is the served ship; the encounter's target ships (simulated in the same
  batch) go out as ``state.targets``, AIS and the 3D viewer's ships (:mod:`~vessel_gym.net.batch_targets`); the
  debrief scores each encounter by the COLREGs (:mod:`~vessel_gym.envs.debrief`). With ``target_agent`` every
  target is an own ship of the encounter steered by that agent from its own observation
  (:class:`~vessel_gym.multiagent.OwnShipAmongAgents`): a person takes the helm against the agents.
- Berthing: helm orders carry the thrusters and tugs (``helm.assist``); the state echoes their orders and what
  they deliver and the fenders' loads; the scene has the quay and the fenders; the debrief is ``play``'s
  (:func:`~vessel_gym.envs.debrief.berthing_debrief`).
"""

from __future__ import annotations

import math
from typing import Any

#: the task classes ``--env`` serves (their registered ids' entry points end with these)
SERVED_TASKS = {"colreg:CollisionAvoidanceEnv": "colreg", "berthing:BerthingEnv": "berthing"}
#: the harbour task serve runs without ``--env``, on the scenario's own ship: the current one (v2's physics,
#: the smooth helm), so that an agent on the served helm steers the helm it was trained on
HARBOUR_ID = "vessel_gym/HarbourApproach-v3"


def served_ids() -> list[str]:
    """The registered ids ``--env`` accepts."""
    import gymnasium as gym

    import vessel_gym.envs  # noqa: F401  (registers the ids)

    return sorted(k for k, s in gym.registry.items() if _kind_of(str(s.entry_point)))


def _kind_of(entry_point: str) -> str | None:
    return next((kind for tail, kind in SERVED_TASKS.items() if entry_point.endswith(tail)), None)


class Served:
    """One served task: ``make(extra)`` builds its environment (``extra``: dt_s, max_episode_steps), ``kind``
    is ``"harbour"``, ``"colreg"`` or ``"berthing"``."""

    def __init__(self, env_id: str | None, scenario: Any = None, target_agent: str | None = None) -> None:
        import gymnasium as gym

        import vessel_gym.envs  # noqa: F401  (registers the ids)

        if env_id is None:
            self.env_id, self.kind, self.scenario = HARBOUR_ID, "harbour", scenario
        else:
            if env_id not in gym.registry or not _kind_of(str(gym.spec(env_id).entry_point)):
                raise ValueError(f"--env {env_id!r}: serve runs one of {', '.join(served_ids())}")
            self.env_id, self.kind, self.scenario = env_id, _kind_of(str(gym.spec(env_id).entry_point)), None
        if target_agent is not None and self.kind != "colreg":
            raise ValueError(
                f"--target-agent {target_agent!r}: only the CollisionAvoidance tasks have targets to steer "
                f"(not {self.env_id})"
            )
        self.target_agent = target_agent
        self._start_distance = math.nan

    def make(self, extra: dict[str, Any]) -> Any:
        import gymnasium as gym

        if self.kind == "harbour":
            from vessel_gym.envs.tasks.harbour import own_ship

            kw = {"scenario": self.scenario, **extra}
            return gym.make(self.env_id, **{**own_ship(self.scenario), **kw})
        if self.target_agent is not None:
            try:
                from vessel_gym.multiagent import OwnShipAmongAgents
            except ImportError as exc:  # the marl extra (pettingzoo) missing
                raise ValueError(f"--target-agent: {exc}") from None
            spec = self.target_agent
            return OwnShipAmongAgents(self.env_id, lambda env: _target_policy(spec, env), **extra)
        return gym.make(self.env_id, **extra)

    def default_agent(self, env: Any) -> str:
        """``pid`` where the task declares it, else its first declared pilot (Berthing: ``scripted``)."""
        pilots = getattr(getattr(env.unwrapped.task, "declaration", None), "pilots", {}) or {}
        return "pid" if "pid" in pilots or not pilots else next(iter(pilots))

    def title(self, env: Any) -> str:
        """The banner's name of what runs: the scenario (and its file), or the task id and its encounter or berth."""
        task = env.unwrapped.task
        if self.kind == "harbour":
            return f"scenario {self.scenario.name!r} ({self.scenario.path})"
        if self.kind == "berthing":
            return f"{self.env_id}: {task.scenario.name}, berth {task.berth.name!r}"
        waters = getattr(task, "waters", None)
        agents = f", targets steered by {self.target_agent!r}" if self.target_agent is not None else ""
        return f"{self.env_id}: " + (f"waters {waters.name!r}" if waters is not None else "open sea") + agents

    def started(self, info: dict) -> None:
        """An episode started with ``info``: remember what the debrief compares with."""
        if self.kind == "berthing":
            self._start_distance = float(math.hypot(info["along_error_m"], info["off_error_m"]))

    def figures(self, info: dict) -> str:
        """The task's part of the outcome line."""
        g = lambda k: float(info.get(k, math.nan))  # noqa: E731
        if self.kind == "colreg":
            return (
                f"{info.get('scenario', '')}, min separation {g('min_separation_m'):.0f} m "
                f"({g('min_separation_L'):.1f} L), COLREG score {g('colreg_score'):.2f}"
            )
        if self.kind == "berthing":
            return (
                f"contact {g('contact_speed_m_s'):.3f} m/s (limit {g('contact_speed_limit_m_s'):.3f}), "
                f"fender max {100.0 * g('max_fender_energy_fraction'):.0f} % of rated"
            )
        return (
            f"path {g('path_m'):.0f} m, min clearance {g('min_clearance_m'):.1f} m, "
            f"distance to goal {g('distance_to_goal_m'):.1f} m"
        )

    def debrief(self, env: Any, info: dict, outcome: str, steps: int) -> list[str]:
        """The debrief lines at the end of an episode (none for the harbour: its outcome line says it all)."""
        task = env.unwrapped.task
        if self.kind == "colreg":
            from vessel_gym.envs.debrief import colreg_debrief

            return colreg_debrief(task, info, outcome)
        if self.kind == "berthing":
            from vessel_gym.envs.debrief import berthing_debrief

            d = berthing_debrief(
                task.scenario.name, task.berth.name, outcome, steps, info, self._start_distance
            )
            return ["berthing debrief:"] + [f"  {label:20s}{value}" for label, value in d.items()]
        return []


def _target_policy(spec: str, env: Any) -> Any:
    """The policy that steers one target (``load_policy``'s checks: a declared pilot, or a model file whose
    observation fits the task's), its errors named as the option's."""
    from vessel_gym.policy import load_policy

    try:
        return load_policy(spec, env)
    except ValueError as exc:
        raise ValueError(f"--target-agent: {exc}") from None
