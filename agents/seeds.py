"""The seed sets of training, validation and test, defined here only and disjoint by construction.

* Training: a run with seed ``s`` and ``n_envs`` copies seeds copy k with ``s + k``; every later episode of
  a copy continues that copy's random stream. Training seeds must stay below :data:`VALIDATION_START`.
* Validation (model selection during training, hyperparameter sweeps): episode i starts from
  ``reset(seed=VALIDATION_START + i)``, the same episodes at every periodic evaluation, so the "best"
  model is chosen on a fixed set and not on whichever starts the evaluation happened to draw.
* Test (the final evaluation and the results table): episode i starts from ``reset(seed=TEST_START + i)``,
  never seen by training or model selection.
"""

from __future__ import annotations

VALIDATION_START = 1_000_000
TEST_START = 2_000_000
#: at most this many episodes per set, so the sets cannot overlap
SET_SIZE = TEST_START - VALIDATION_START


SPLITS = {"validation": VALIDATION_START, "test": TEST_START}


def episode_seeds(split: str, n: int) -> list[int]:
    """The first ``n`` episode seeds of ``split`` (``validation`` or ``test``)."""
    if split not in SPLITS:
        raise ValueError(f"unknown seed set {split!r} (have: {', '.join(SPLITS)})")
    if not 0 <= n <= SET_SIZE:
        raise ValueError(f"{split} set: 0 to {SET_SIZE} episodes, got {n}")
    return list(range(SPLITS[split], SPLITS[split] + n))


def check_training_seed(seed: int, n_envs: int) -> None:
    """``ValueError`` unless copies ``seed .. seed + n_envs - 1`` stay below the validation set."""
    if seed < 0 or seed + n_envs > VALIDATION_START:
        raise ValueError(
            f"training seed {seed} with {n_envs} copies must satisfy 0 <= seed and seed + n_envs <= "
            f"{VALIDATION_START} (validation and test episodes use seeds from {VALIDATION_START})"
        )


__all__ = ["SET_SIZE", "SPLITS", "TEST_START", "VALIDATION_START", "check_training_seed", "episode_seeds"]
