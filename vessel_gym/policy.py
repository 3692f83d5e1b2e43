"""Load a helm policy by name or file: the scripted and classical baselines, or a trained SB3 agent.

``load_policy(spec, env)`` returns a callable ``action = policy(observation)`` (single or batched
observations) with a ``reset(mask=None)`` method:

* ``"scripted"``, ``"pid"``, ``"pid-nomoto"`` - the classical pilots the task declares (``pilots`` of its
  ``register_task``: e.g. the IMO zig-zag rule, a heading PID with gains tuned for the id (``pid``, the tuned
  parameters in ``vessel_gym/envs/pilots.toml``) and the same PID with the untuned Nomoto design
  (``pid-nomoto``)),
* a path to a Stable-Baselines3 ``.zip`` (the algorithm is read from the file; needs the ``rl`` extra).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

BASELINES = ("pid", "pid-nomoto", "scripted")
#: the tuned parameters of the classical pilots, per environment id (docs/agents.md, "Classical pilots")
PILOTS_FILE = Path(__file__).resolve().parent / "envs" / "pilots.toml"


class _SB3Policy:
    """A trained model; ``stats`` is the ``VecNormalize`` its training saved when it normalised observations
    (``<stem>_vecnormalize.pkl`` beside the model): the model only ever saw normalised observations, so every
    user of the model (evaluation, ``serve``, the classroom) must apply the same statistics."""

    def __init__(self, model: Any, stats: Any = None) -> None:
        self.model = model
        self.stats = stats

    def reset(self, mask: np.ndarray | None = None) -> None:
        pass

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        if self.stats is not None:
            obs = self.stats.normalize_obs(np.asarray(obs, dtype=np.float32))
        action, _ = self.model.predict(obs, deterministic=True)
        return action


def _observation_stats(path: Path) -> Any:
    """The observation statistics saved beside the model at ``path`` (None when training did not normalise
    observations); an unreadable file is a ValueError naming it."""
    import pickle

    vn = path.with_name(path.stem + "_vecnormalize.pkl")
    if not vn.is_file():
        return None
    try:
        with open(vn, "rb") as f:
            stats = pickle.load(f)
    except Exception as exc:  # a truncated/foreign file: one clear line
        raise ValueError(f"{vn}: not readable observation statistics ({exc})") from None
    if not getattr(stats, "norm_obs", False):
        return None
    stats.training = False
    return stats


def nomoto_pid_kwargs(env: Any, omega_n_UL: float = 0.6, zeta: float = 0.9) -> dict[str, float]:
    """Gains of :class:`vessel_gym.envs.policies.PIDHeadingAutopilot` (nondimensional on L/U) from the
    Nomoto pole placement of :func:`vessel_gym.control.nomoto_pid_gains` for the env's ship: closed-loop
    natural frequency ``omega_n_UL`` in units of U/L (the default 0.6 is the design's own) and relative
    damping ``zeta``."""
    from vessel_gym.control import nomoto_pid_gains

    task = env.unwrapped.task
    if not (omega_n_UL > 0.0 and zeta > 0.0):
        raise ValueError(f"omega_n_UL {omega_n_UL:g} and zeta {zeta:g} must be > 0")
    g = nomoto_pid_gains(task.ship, task.U_T, omega_n=omega_n_UL * task.U_T / task.L, zeta=zeta)
    T = task.L / task.U_T
    return {"Kp": g.K_p, "Ki": g.K_i * T, "Kd": g.K_d / T}


def read_pilots(path: str | Path = PILOTS_FILE) -> dict[str, dict[str, dict[str, float]]]:
    """The tuned pilot parameters of ``path``: ``{env id: {pilot name: {parameter: value}}}``; a clear
    ``ValueError`` for a file that is not of that shape."""
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    try:
        data = tomllib.loads(Path(path).read_text())
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"{path}: not a readable pilots file ({exc})") from None
    for env_id, pilots in data.items():
        if not isinstance(pilots, dict):
            raise ValueError(f"{path}: {env_id!r} must be a table of pilots")
        for name, values in pilots.items():
            if not isinstance(values, dict) or not all(
                isinstance(v, int | float) and not isinstance(v, bool) for v in values.values()
            ):
                raise ValueError(f"{path}: [{env_id!r}.{name}] must be a table of numbers")
    return data


def pilot_gains(env: Any, pilot: str = "pid") -> dict[str, float]:
    """The parameters ``pilot`` is tuned with for ``env``'s id (:data:`PILOTS_FILE`), ``{}`` for an id not
    tuned (the pilot's own defaults, the untuned design)."""
    from vessel_gym.envs.registration import preset_of

    base = env.unwrapped
    preset = preset_of(base)
    decl = getattr(base.task, "declaration", None)
    if preset is None or decl is None:
        return {}
    return dict(read_pilots().get(f"{decl.namespace}/{preset}", {}).get(pilot, {}))


ALGORITHMS = ("PPO", "A2C", "SAC", "TD3", "DDPG", "DQN")


def sb3_algorithm(path: str | Path) -> str:
    """Algorithm of an SB3 model file from its name: ``agents/train.py`` saves ``<algo>[_...].zip``."""
    stem = Path(path).stem.split("_")[0].upper()
    if stem not in ALGORITHMS:
        raise ValueError(
            f"agent {str(path)!r}: cannot tell the algorithm from the file name; name it "
            f"<algo>_....zip with algo one of {', '.join(a.lower() for a in ALGORITHMS)}"
        )
    return stem


class RatePI:
    """TurningCircle baseline: PI on the rate-of-turn error e = r_cmd - r (the observation's ``rate_error``),
    the law of :func:`vessel_gym.control.pid.pid_rudder` (no derivative term), gains by pole placement on
    Nomoto's first-order model (:func:`vessel_gym.control.pid.nomoto_rate_pi_gains`) at omega = ``omega_UL``
    U/L (default 1), relative damping ``zeta`` (default 1); the integral is held where K_i alone would give the
    rudder limit.
    """

    def __init__(self, env: Any, omega_UL: float = 1.0, zeta: float = 1.0) -> None:
        from vessel_gym.control.pid import nomoto_rate_pi_gains
        from vessel_gym.envs.policies import HelmPolicy
        from vessel_gym.physics.linear import nomoto

        self.helm = HelmPolicy(env)
        task = env.unwrapped.task
        m = nomoto(task.ship, task.U_T)
        if not (omega_UL > 0.0 and zeta > 0.0):
            raise ValueError(f"omega_UL {omega_UL:g} and zeta {zeta:g} must be > 0")
        self.Kp, self.Ki = nomoto_rate_pi_gains(m, omega_UL * task.U_T / task.L, zeta)
        self.dt = float(env.unwrapped.config.control_interval_s)
        self.integral: np.ndarray | float = 0.0

    def reset(self, mask: np.ndarray | None = None) -> None:
        self.integral = (
            0.0 if mask is None or np.ndim(self.integral) == 0 else np.where(mask, 0.0, self.integral)
        )

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        from vessel_gym.control.pid import pid_integral_batch, pid_rudder_batch

        e = self.helm.get(obs, "rate_error")
        lim = self.helm.rudder_limit_rad
        self.integral = pid_integral_batch(self.integral, e, self.dt, lim / abs(self.Ki), np.inf)
        d = pid_rudder_batch(e, self.integral, 0.0, self.Kp, self.Ki, 0.0, lim)
        return self.helm.action(d, self.helm.hold_engine(obs))


def load_policy(spec: str, env: Any, algo: str | None = None):
    """A policy for ``env`` from a baseline name or an SB3 model file (see the module docstring)."""
    base = env.unwrapped
    if spec in BASELINES:
        pilots = getattr(getattr(base.task, "declaration", None), "pilots", {})
        if spec not in pilots:
            raise ValueError(f"no {spec} helm declared for {type(base.task).__name__}")
        return pilots[spec](env)
    path = Path(spec)
    if not path.exists():
        raise ValueError(f"agent {spec!r}: not a baseline ({', '.join(BASELINES)}) and no such file")
    try:
        import stable_baselines3 as sb3
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise ValueError(
            "loading a trained agent needs the 'rl' extra: pip install 'vessel-gym[rl]'"
        ) from exc
    name = (algo or sb3_algorithm(path)).upper()
    cls = getattr(sb3, name, None)
    if cls is None:
        raise ValueError(f"agent {spec!r}: unknown algorithm {name!r}")
    try:
        model = cls.load(str(path), device="cpu")
    except Exception as exc:  # a wrong/corrupt file: one clear line
        raise ValueError(f"agent {spec!r}: cannot load as {name}: {exc}") from None
    if model.observation_space.shape != base.observation_space.shape:
        raise ValueError(
            f"agent {spec!r}: observation shape {model.observation_space.shape} does not match "
            f"the environment's {base.observation_space.shape}"
        )
    return _SB3Policy(model, _observation_stats(path))


__all__ = [
    "ALGORITHMS",
    "BASELINES",
    "PILOTS_FILE",
    "RatePI",
    "load_policy",
    "nomoto_pid_kwargs",
    "pilot_gains",
    "read_pilots",
]
