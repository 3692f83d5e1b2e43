"""Registration of the vessel-gym environments with Gymnasium (idempotent, string entry points)."""

from __future__ import annotations

#: id -> (single entry point, vector entry point, max_episode_steps or None: the environment truncates)
ENVIRONMENTS: dict[str, tuple[str, str, int | None]] = {
    "vessel_gym/ZigZag-v0": (
        "vessel_gym.envs.zigzag:ZigZagEnv",
        "vessel_gym.envs.zigzag:ZigZagVectorEnv",
        480,
    ),
    "vessel_gym/ZigZag-v1": (
        "vessel_gym.envs.zigzag:ZigZagV1Env",
        "vessel_gym.envs.zigzag:ZigZagV1VectorEnv",
        480,
    ),
    "vessel_gym/ZigZagRandom-v1": (
        "vessel_gym.envs.zigzag:ZigZagRandomEnv",
        "vessel_gym.envs.zigzag:ZigZagRandomVectorEnv",
        480,
    ),
    "vessel_gym/TurningCircle-v0": (
        "vessel_gym.envs.turning:TurningCircleEnv",
        "vessel_gym.envs.turning:TurningCircleVectorEnv",
        480,
    ),
    "vessel_gym/HarbourApproach-v0": (
        "vessel_gym.envs.harbour:HarbourApproachEnv",
        "vessel_gym.envs.harbour:HarbourApproachVectorEnv",
        1600,
    ),
    # time limit in seconds, applied by the environment itself (HarbourApproachV1Config.time_limit_s)
    "vessel_gym/HarbourApproach-v1": (
        "vessel_gym.envs.harbour:HarbourApproachV1Env",
        "vessel_gym.envs.harbour:HarbourApproachV1VectorEnv",
        None,
    ),
    # v1's task with the harbour physics (cross-flow hull, depth from the chart); its own time limit as v1
    "vessel_gym/HarbourApproach-v2": (
        "vessel_gym.envs.harbour:HarbourApproachV2Env",
        "vessel_gym.envs.harbour:HarbourApproachV2VectorEnv",
        None,
    ),
}


def register_envs() -> list[str]:
    """Register every vessel-gym environment id with Gymnasium; safe to call any number of times.

    Imports nothing heavy (entry points are strings). Returns the registered ids.
    """
    from gymnasium.envs.registration import register, registry

    for env_id, (entry, vector_entry, max_steps) in ENVIRONMENTS.items():
        if env_id in registry:
            continue
        register(id=env_id, entry_point=entry, vector_entry_point=vector_entry, max_episode_steps=max_steps)
    return list(ENVIRONMENTS)
