"""Golden rollouts: every environment id (single and native vector env) and every built-in ship's physics,
on fixed seeds, as recorded before a refactor; ``test_golden.py`` replays them and compares.

``python -m tests.golden.rollouts`` (from the repository root) records them again into ``data/``: do that only
for an intended change, and name the change in docs (docs/envs.md or docs/physics.md) with the version bump.

What is recorded:

- envs: for each id, the single env (``gym.make``) and the native vector env of 3 vessels
  (``vectorization_mode="vector_entry_point"``), both from seed 7, with actions from the action space seeded 0,
  through resets; observations, rewards, terminated, truncated and the numeric info entries. The ids are those
  registered when the file was recorded (they are data here, stored in the file).
- physics: each built-in ship in a batch of 3 vessels from its steady approach, vessel 0 hard to starboard,
  vessel 1 at 10 deg to port with half the approach shaft speed, vessel 2 straight at full astern (a crash
  stop), in deep calm water and, for every ship, once more in wind, current, waves and (MMG hulls) shallow water; the whole
  state every 10 s of 300 s.
"""

from __future__ import annotations

import gzip
import pickle
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parent / "data"
SEED = 7
SINGLE_STEPS = 300
VECTOR_N = 3
VECTOR_STEPS = 150
PHYSICS_T_S = 300.0
PHYSICS_SAMPLE_S = 10.0


def _numeric(info: dict) -> dict:
    """The entries of an info dict that are numbers or numeric arrays (nested dicts flattened with '/')."""
    out = {}
    for k, v in info.items():
        if isinstance(v, dict):
            out.update({f"{k}/{kk}": vv for kk, vv in _numeric(v).items()})
            continue
        a = np.asarray(v) if not isinstance(v, str) else None
        if a is not None and a.dtype.kind in "biuf":
            out[k] = a.copy()
    return out


def env_rollout(env_id: str, vector: bool, kwargs: dict | None = None) -> list[tuple]:
    import gymnasium as gym

    import vessel_gym  # noqa: F401  (registers the ids)

    if vector:
        env = gym.make_vec(env_id, num_envs=VECTOR_N, vectorization_mode="vector_entry_point", **(kwargs or {}))
        steps = VECTOR_STEPS
    else:
        env = gym.make(env_id, **(kwargs or {}))
        steps = SINGLE_STEPS
    env.action_space.seed(0)
    obs, info = env.reset(seed=SEED)
    out = [(np.array(obs), 0.0, False, False, _numeric(dict(info)))]
    for _ in range(steps):
        obs, r, te, tr, info = env.step(env.action_space.sample())
        out.append((np.array(obs), np.array(r), np.array(te), np.array(tr), _numeric(dict(info))))
        if not vector and (te or tr):
            obs, info = env.reset()
            out.append((np.array(obs), 0.0, False, False, _numeric(dict(info))))
    env.close()
    return out


WEATHER = dict(
    wind_speed_m_s=12.0, wind_from_deg=30.0, current_speed_m_s=0.5, current_to_deg=100.0, Hs_m=2.0, Tp_s=9.0
)


def physics_rollout(ship: str, weather: bool) -> np.ndarray:
    from vessel_gym.physics.environment import Environment
    from vessel_gym.physics.shipfile import load_ship
    from vessel_gym.physics.simulation import Simulation

    s = load_ship(ship)
    env = Environment()
    if weather:
        # scaled to the ship: model-scale ships get model-scale weather; depth 1.5 draughts (shallow water)
        scale = min(1.0, s.particulars.L_m / 100.0)
        env = Environment(
            wind_speed_m_s=WEATHER["wind_speed_m_s"] * scale**0.5,
            wind_from_deg=WEATHER["wind_from_deg"],
            current_speed_m_s=WEATHER["current_speed_m_s"] * scale**0.5,
            current_to_deg=WEATHER["current_to_deg"],
            Hs_m=WEATHER["Hs_m"] * scale,
            Tp_s=max(1.0, WEATHER["Tp_s"] * scale**0.5),
            depth_m=1.5 * s.particulars.T_m,
        )
    # a whole fraction of the sample interval, within 0.7 of the stable step and 5 % of a length per step
    from vessel_gym.physics.linear import stable_step

    longest = min(0.7 * stable_step(s, "rk4"), 0.05 * s.particulars.L_m / s.test_speed_m_s)
    dt = PHYSICS_SAMPLE_S / np.ceil(PHYSICS_SAMPLE_S / longest)
    try:
        sim = Simulation(ship, n=3, dt=dt, environment=env)
    except ValueError:  # the shallow-water corrections are for MMG hulls only: deep water for the others
        env = Environment(**{**{f: getattr(env, f) for f in env.__dataclass_fields__}, "depth_m": np.inf})
        sim = Simulation(ship, n=3, dt=dt, environment=env)
    sim.reset()
    rev0 = sim.inputs[0, :].copy()
    from vessel_gym.physics import layout as lo

    rev = float(rev0[lo.U_REV_C])
    sim.set_helm(rudder_order_rad=np.radians(35.0), k=0)
    sim.set_helm(rudder_order_rad=np.radians(-10.0), rev_order=0.5 * rev, k=1)
    astern = float(sim.telegraph_rev(-4, k=2)) if s.engine is not None else -rev
    sim.set_helm(rudder_order_rad=0.0, rev_order=astern, k=2)
    rows = [sim.state.copy()]
    t = 0.0
    while t < PHYSICS_T_S - 1e-9:
        sim.advance(PHYSICS_SAMPLE_S)
        t += PHYSICS_SAMPLE_S
        rows.append(sim.state.copy())
    return np.stack(rows)


def builtin_ships() -> list[str]:
    from vessel_gym.physics.shipfile import SHIP_DIR

    return sorted(p.stem for p in Path(SHIP_DIR).glob("*.toml"))


def registered_ids() -> list[str]:
    import gymnasium as gym

    import vessel_gym  # noqa: F401

    return sorted(i for i in gym.registry if i.startswith("vessel_gym/"))


# config variants (single env), as the API tests exercised them when the goldens were recorded (those of the
# removed ids ZigZag-v0 and HarbourApproach-v0 dropped with their data)
VARIANTS: list[tuple[str, dict]] = [
    ("vessel_gym/ZigZag-v1", {"action_type": "discrete", "first_change_s": [0.0, 0.0]}),
    (
        "vessel_gym/ZigZag-v1",
        {"ship": "mariner", "wind_speed_m_s": [5.0, 15.0], "current_speed_m_s": [0.2, 1.0], "Hs_m": [1.0, 3.0]},
    ),
    ("vessel_gym/ZigZagRandom-v1", {"leg_time_s": [2.0, 4.0], "engine_control": True}),
    ("vessel_gym/TurningCircle-v0", {"mode": "radius"}),
    ("vessel_gym/TurningCircle-v0", {"current_speed_m_s": [0.05, 0.2], "current_to_rel_deg": [60.0, 120.0]}),
    ("vessel_gym/TurningCircle-v0", {"mode": "reverse", "action_type": "discrete", "engine_control": True}),
    ("vessel_gym/HarbourApproach-v1", {"action_type": "discrete"}),
    ("vessel_gym/HarbourApproach-v2", {"observation_type": "physical"}),
]


def path(kind: str, name: str) -> Path:
    return DATA / f"{kind}__{name.replace('/', '__')}.pkl.gz"


def save(p: Path, obj) -> None:
    p.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(p, "wb", compresslevel=9) as f:
        pickle.dump(obj, f, protocol=4)


def load(p: Path):
    with gzip.open(p, "rb") as f:
        return pickle.load(f)


def record() -> None:
    import warnings

    warnings.simplefilter("ignore", DeprecationWarning)
    ids = registered_ids()
    save(DATA / "index.pkl.gz", {"ids": ids, "ships": builtin_ships(), "variants": VARIANTS})
    for env_id in ids:
        for vector in (False, True):
            save(path("vector" if vector else "single", env_id), env_rollout(env_id, vector))
            print("recorded", env_id, "vector" if vector else "single", flush=True)
    for j, (env_id, kw) in enumerate(VARIANTS):
        save(path("variant", f"{j:02d}"), env_rollout(env_id, False, kw))
        print("recorded", env_id, kw, flush=True)
    for ship in builtin_ships():
        for weather in (False, True):
            save(path("weather" if weather else "calm", ship), physics_rollout(ship, weather))
            print("recorded", ship, "weather" if weather else "calm", flush=True)


if __name__ == "__main__":
    record()
