"""Keyboard berthing in ``vessel-gym play --env vessel_gym/Berthing-v0`` (or ``BerthingTanker-v0``): the helm of
the Berthing task (rudder, engine, then one order per thruster or tug) on keys, and the berthing debrief.

=====================  ===========================================================================
key                    order
=====================  ===========================================================================
Left / Right, A / D    rudder order 5 deg to port / starboard; Space or M: midships
Up / Down, W / S       engine order one step (a quarter of full ahead / full astern rpm) ahead / astern
Z / X                  first thruster or tug (bow thruster; bow tug) a quarter more to port / starboard
C / V                  second thruster or tug (stern thruster; stern tug) a quarter more to port / stbd
, / .                  third thruster or tug, where the ship has one
B                      every thruster and tug to zero
1-4, + / -, P, Esc/Q   time speed-up, pause, quit (as in the harbour)
=====================  ===========================================================================

A thruster's order is its fraction of rated rpm (+ pushing the ship to starboard), a tug's the fraction of its
bollard pull along its line (+ towards starboard). The instrument panel shows every order with what the unit
delivers (thrust or pull as a fraction of its maximum: the thrusters and tugs follow their orders with a lag).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from vessel_gym.envs.debrief import BerthingDebrief, berthing_debrief
from vessel_gym.physics.components.tug import Tug
from vessel_gym.ui.panels import ASSIST_KEYS, ASSIST_STEP, RUDDER_STEP_DEG

ENGINE_STEPS = 4  # engine orders in quarters of full ahead / astern rpm
_KEY_NAMES = {"z": "K_z", "x": "K_x", "c": "K_c", "v": "K_v", ",": "K_COMMA", ".": "K_PERIOD"}


def berthing_ids() -> list[str]:
    """The registered ids of the Berthing task's presets."""
    import gymnasium as gym

    import vessel_gym  # noqa: F401  (registers the ids)

    return [k for k, spec in gym.registry.items() if str(spec.entry_point).endswith("berthing:BerthingEnv")]


class BerthingConsole:
    """The keyboard helm of a Berthing task (module docstring) for :func:`vessel_gym.ui.play.play`."""

    def __init__(self, env_id: str, overrides: Mapping[str, Any]) -> None:
        import gymnasium as gym

        ids = berthing_ids()
        if env_id not in ids:
            raise ValueError(f"play --env: {env_id!r} is not a berthing task (one of {', '.join(ids)})")
        spec = gym.spec(env_id)
        env = gym.make(env_id, **overrides).unwrapped
        self.env = env
        self.task = env.task
        self.name = self.task.scenario.name
        self.time_limit_s = spec.max_episode_steps * env.config.control_interval_s  # the registered limit
        self.rudder_deg = 0.0
        self.limit_deg = float(np.degrees(self.task.helm.rudder_limit_rad[0]))
        self.engine = 0
        self.assist = np.zeros(len(self.task.assist))

    def reset(self, seed: int | None) -> dict:
        _obs, info = self.env.reset(seed=seed)
        # the orders the ship starts with: rudder midships, the engine step nearest its approach rpm
        helm = self.task.helm
        rev0 = float(self.env.sim.rev_order[0])
        full = helm.full_ahead[0] if rev0 >= 0.0 else helm.full_astern[0]
        self.engine = int(
            np.clip(np.round(ENGINE_STEPS * rev0 / max(full, 1e-9)), -ENGINE_STEPS, ENGINE_STEPS)
        )
        self.rudder_deg = 0.0
        self.assist[:] = 0.0
        self.start_distance = float(np.hypot(info["along_error_m"], info["off_error_m"]))
        return info

    def key(self, pygame: Any, k: int) -> None:
        if k in (pygame.K_LEFT, pygame.K_a):
            self.rudder_deg = max(self.rudder_deg - RUDDER_STEP_DEG, -self.limit_deg)
        elif k in (pygame.K_RIGHT, pygame.K_d):
            self.rudder_deg = min(self.rudder_deg + RUDDER_STEP_DEG, self.limit_deg)
        elif k in (pygame.K_SPACE, pygame.K_m):
            self.rudder_deg = 0.0
        elif k in (pygame.K_UP, pygame.K_w):
            self.engine = min(self.engine + 1, ENGINE_STEPS)
        elif k in (pygame.K_DOWN, pygame.K_s):
            self.engine = max(self.engine - 1, -ENGINE_STEPS)
        elif k == pygame.K_b:
            self.assist[:] = 0.0
        else:
            for j, pair in enumerate(ASSIST_KEYS[: len(self.assist)]):
                for sign, name in zip((-1.0, 1.0), pair):
                    if k == getattr(pygame, _KEY_NAMES[name]):
                        self.assist[j] = float(np.clip(self.assist[j] + sign * ASSIST_STEP, -1.0, 1.0))

    def action(self) -> np.ndarray:
        return np.concatenate([[self.rudder_deg / self.limit_deg, self.engine / ENGINE_STEPS], self.assist])

    telegraph = None  # the engine order is a fraction of full rpm, shown as a panel row

    def delivered(self) -> list[float]:
        """What each thruster or tug delivers now, as a fraction of its maximum: a thruster's thrust, a tug's
        force along its line."""
        sim = self.task.sim
        names, z = sim.component_state_names, sim.component_states[0]
        out = []
        for c in self.task.assist:
            s = np.array([z[names.index(f"{c.name}.{st.name}")] for st in c.states])
            out.append(float(np.dot(s, c.direction)) if isinstance(c, Tug) else float(s[0]))
        return out

    def overlay(self) -> dict:
        o = self.task.overlay(0)
        rows = [("engine", f"{self.engine / ENGINE_STEPS:+.2f} full")]
        for j, (c, now) in enumerate(zip(self.task.assist, self.delivered())):
            keys = "/".join(ASSIST_KEYS[j]) if j < len(ASSIST_KEYS) else "-"
            rows.append((f"{c.name[:12]} {keys}", f"{self.assist[j]:+.2f} ({now:+.2f})"))
        return {**o, "rows": rows + list(o.get("rows", ()))}

    def targets(self, steps: int) -> Sequence[Any]:
        return ()

    def contact(self, info: Mapping[str, Any]) -> bool:
        return str(info["outcome"]) in ("contact", "grounding")

    def debrief(
        self, outcome: str, steps: int, contacts: int, info: Mapping[str, Any], track: list
    ) -> BerthingDebrief:
        return berthing_debrief(
            self.name, self.task.berth.name, outcome, steps, info, self.start_distance, track
        )
