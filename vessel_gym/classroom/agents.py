"""Trained agents on some ships of the class: a shipped SB3 HarbourApproach agent (``agents/trained/``) steers
them beside the students, with the helm it was trained on.

The class runs HarbourApproach-v2 with ``play``'s discrete helm (rudder in 5 degree steps, telegraph steps) at
0.25 s; the shipped harbour agents act on the continuous helm every 0.99 s: ``ppo_HarbourApproach-v3`` asks for a
rudder that the order follows as a capped lag (the smooth helm, on v2's physics: the class's), and
``ppo_HarbourApproach-v1`` orders the rudder directly (trained in deep water, without the chart's depth). So an
agent ship keeps its own helm: the agent reads its ship's observation (the same task's, the same 33 features),
acts once per its own control interval, and its orders go to the ship through the helm object of the task and
version it was trained on (``envs.helm.ContinuousHelm`` or ``envs.tasks.harbour_helm.LagHelm``, one home for
either); between its actions the orders stand, as they do in training.

An agent is checked before the class opens, each failure one line: the file loads as its algorithm; its JSON
sidecar names a HarbourApproach version (``env_id``) made with the scenario's ship; the observation features
are the class's by name and order; the action is the continuous rudder and engine; no observation
normalisation is needed.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np

HARBOUR_IDS = (
    "vessel_gym/HarbourApproach-v1",
    "vessel_gym/HarbourApproach-v2",
    "vessel_gym/HarbourApproach-v3",
)


class _OneShip:
    """Ship ``k`` of the class's simulation as the single vessel a trained helm object steers."""

    def __init__(self, sim: Any, k: int) -> None:
        self.sim, self.k = sim, k

    @property
    def rudder_order(self) -> np.ndarray:
        return np.array([float(self.sim.rudder_order[self.k])])

    def set_helm(self, rudder_order_rad: Any = None, rev_order: Any = None, k: Any = None) -> None:
        self.sim.set_helm(rudder_order_rad=rudder_order_rad, rev_order=rev_order, k=self.k)


class AgentShips:
    """Ships ``ships`` of ``harbour``'s task steered by the agent at ``path`` (module doc). ValueError (one
    line) for an agent that does not fit."""

    def __init__(self, path: str | Path, scenario: Any, layout: Any, dt_s: float, ships: np.ndarray) -> None:
        import gymnasium as gym

        from vessel_gym.envs.tasks.harbour import own_ship
        from vessel_gym.policy import load_policy

        path = Path(path)
        name = path.name
        if path.suffix != ".zip" or not path.is_file():
            raise ValueError(f"--agent {name}: no such agent (an SB3 .zip, e.g. agents/trained/*.zip)")
        side = path.with_suffix(".json")
        try:
            meta = json.loads(side.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            raise ValueError(f"--agent {name}: no readable sidecar {side.name} naming its task") from None
        env_id = meta.get("env_id") if isinstance(meta, dict) else None
        if env_id not in HARBOUR_IDS:
            raise ValueError(
                f"--agent {name}: trained on {env_id!r}; the class's ships need a HarbourApproach agent "
                f"({', '.join(i.split('/')[1] for i in HARBOUR_IDS)})"
            )
        if (meta.get("hyperparams") or {}).get("normalize", {}).get("norm_obs"):
            raise ValueError(
                f"--agent {name}: trained on normalised observations, which the class does not apply"
            )
        kwargs = meta.get("env_kwargs") or {}
        try:
            # v1 is "out of date" to gymnasium: docs/classroom.md says why it runs
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message=".*out of date.*")
                env = gym.make(env_id, **{**own_ship(scenario), "scenario": scenario, **kwargs})
        except (TypeError, ValueError) as exc:
            raise ValueError(f"--agent {name}: its task does not build for this scenario: {exc}") from None
        base = env.unwrapped
        if base.observation_layout.names != layout.names:
            raise ValueError(f"--agent {name}: its observation features are not the class's ({env_id})")
        shape = getattr(base.action_space, "shape", None)
        if shape != (2,):
            raise ValueError(f"--agent {name}: its action is {base.action_space}, not the rudder and engine")
        self.policy = load_policy(str(path), env)  # ValueError: the file does not load, or the shape differs
        self.env_id, self.name = env_id, name
        self.helm = base.task.helm  # the trained helm: ContinuousHelm (v1, v2) or LagHelm (v3)
        #: the agent acts every this many class steps: its own control interval (0.99 s for the shipped)
        self.every = max(1, round(float(base.config.control_interval_s) / dt_s))
        self.ships = np.asarray(ships, dtype=np.int64)
        self.held: dict[int, tuple[float, float]] = {}  # ship -> its orders in force (rudder rad, rev/s)

    def start(self, k: int, sim: Any) -> None:
        """Ship ``k`` starts a run: its orders in force are those of its start."""
        self.held[k] = (float(sim.rudder_order[k]), float(sim.rev_order[k]))

    def steer(self, sim: Any, obs: np.ndarray, steps: np.ndarray, live: np.ndarray) -> None:
        """After the class's helm wrote every ship's orders: the agent ships' own orders, a new action each
        ``every`` steps of each ship's run (from its observation ``obs[k]``), else the orders held."""
        acting = [k for k in self.ships.tolist() if live[k] and steps[k] % self.every == 0]
        actions = np.asarray(self.policy(obs[acting])) if acting else np.zeros((0, 2))
        for k in self.ships.tolist():
            if not live[k]:
                continue  # an ended run: midships and stop, as the class's helm set them
            rudder, rev = self.held.get(k, (float(sim.rudder_order[k]), float(sim.rev_order[k])))
            sim.set_helm(rudder_order_rad=rudder, rev_order=rev, k=k)
            if k in acting:
                self.helm.sim = _OneShip(sim, k)
                self.helm.apply_single(actions[acting.index(k)])
                self.held[k] = (float(sim.rudder_order[k]), float(sim.rev_order[k]))
