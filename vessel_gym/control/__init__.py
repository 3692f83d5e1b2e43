"""Control rules, each in one place: angle wrapping, the Nomoto-tuned PID autopilot, waypoint guidance, the
zig-zag rule with its overshoot tracker, and the turning-circle geometry (docs/control.md).

The manoeuvre trials, the environments' kernels and baselines, the scenarios' traffic and the evaluation
scripts call these functions; the physics does not depend on this package.
"""


from vessel_gym.control.angles import wrap_pi, wrap_pi_upper
from vessel_gym.control.guidance import leg_frame, los_heading, pursuit_heading, waypoint_reached
from vessel_gym.control.pid import (
    PidAutopilot,
    PidGains,
    nomoto_pid_gains,
    nomoto_rate_pi_gains,
    pid_integral,
    pid_rudder,
)
from vessel_gym.control.turning import (
    ADVANCE_HEADING_RAD,
    TACTICAL_HEADING_RAD,
    at_crossing,
    course_axes,
    crossing_fraction,
)
from vessel_gym.control.zigzag import (
    OVERSHOOT_IMO,
    OVERSHOOT_V1,
    OvershootTracker,
    overshoot_excursion,
    overshoot_step,
    target_reached,
    zigzag_execute,
)

__all__ = [
    "ADVANCE_HEADING_RAD",
    "OVERSHOOT_IMO",
    "OVERSHOOT_V1",
    "TACTICAL_HEADING_RAD",
    "OvershootTracker",
    "PidAutopilot",
    "PidGains",
    "at_crossing",
    "course_axes",
    "crossing_fraction",
    "leg_frame",
    "los_heading",
    "nomoto_pid_gains",
    "nomoto_rate_pi_gains",
    "overshoot_excursion",
    "overshoot_step",
    "pid_integral",
    "pid_rudder",
    "pursuit_heading",
    "target_reached",
    "waypoint_reached",
    "wrap_pi",
    "wrap_pi_upper",
    "zigzag_execute",
]
