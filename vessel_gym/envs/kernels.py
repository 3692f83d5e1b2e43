"""The old home of the compiled task kernels; each task's kernel now sits with its declaration, configuration and
reset in :mod:`vessel_gym.envs.tasks`, and the names are re-exported here:

* what every task shares (motion features, shared reward terms, closing a row): :mod:`vessel_gym.envs.tasks.common`;
* ZigZag: :mod:`vessel_gym.envs.tasks.zigzag`;
* TurningCircle: :mod:`vessel_gym.envs.tasks.turning`;
* HarbourApproach and its chart: :mod:`vessel_gym.envs.tasks.harbour`, :mod:`vessel_gym.envs.tasks.chart`;
* the continuous helm's clipping: :mod:`vessel_gym.envs.helm`.

The task-state and feature columns are no longer module constants numbered by hand: each task module derives them
from its declaration (``SPEC.TERM``, ``SPEC.FEAT``, ``S``, ``P``; :mod:`vessel_gym.envs.declare`).
"""

from __future__ import annotations

from vessel_gym.control.angles import PI, wrap_pi
from vessel_gym.control.zigzag import (
    OVERSHOOT_V0,
    OVERSHOOT_V1,
    overshoot_excursion,
    overshoot_step,
    target_reached,
    zigzag_execute,
)
from vessel_gym.envs.helm import clip_helm
from vessel_gym.envs.tasks.chart import (
    CONTACT,
    DIVERGED,
    GROUNDING,
    OK,
    OUT_OF_BOUNDS,
    OUTCOMES,
    SUCCESS,
    chart_query,
    chart_tables,
    inside_polygon,
)
from vessel_gym.envs.tasks.common import (
    clear_row,
    encode_row,
    motion,
    motion_features,
    rudder_activity,
    speed_loss,
)
from vessel_gym.envs.tasks.harbour import harbour_update, harbour_update_parallel
from vessel_gym.envs.tasks.turning import turning_update
from vessel_gym.envs.tasks.zigzag import zigzag_update

__all__ = [
    "CONTACT",
    "DIVERGED",
    "GROUNDING",
    "OK",
    "OUTCOMES",
    "OUT_OF_BOUNDS",
    "OVERSHOOT_V0",
    "OVERSHOOT_V1",
    "PI",
    "SUCCESS",
    "chart_query",
    "chart_tables",
    "clear_row",
    "clip_helm",
    "encode_row",
    "harbour_update",
    "harbour_update_parallel",
    "inside_polygon",
    "motion",
    "motion_features",
    "overshoot_excursion",
    "overshoot_step",
    "rudder_activity",
    "speed_loss",
    "target_reached",
    "turning_update",
    "wrap_pi",
    "zigzag_execute",
    "zigzag_update",
]
