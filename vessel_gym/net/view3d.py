"""Former home of the browser 3D viewer, kept for existing imports: it is what a person sees, so it lives in
:mod:`vessel_gym.ui.view3d` (the page), :mod:`vessel_gym.ui.view3d_scene` (geometry, sea) and
:mod:`vessel_gym.ui.view3d_link` (its link client)."""

from vessel_gym.ui.view3d import *  # noqa: F403
from vessel_gym.ui.view3d_link import *  # noqa: F403
from vessel_gym.ui.view3d_scene import *  # noqa: F403
