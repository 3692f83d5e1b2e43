"""Whether a window can open: on Linux without a display server SDL falls back to its offscreen driver, and a
keyboard game or a panel would run unseen (SDL's only word being an unrelated XDG_RUNTIME_DIR complaint)."""

from __future__ import annotations

import os
import sys


def no_display_reason(environ: dict[str, str] | None = None, platform: str | None = None) -> str | None:
    """Why no window can be shown here, or None when one can (or SDL_VIDEODRIVER names a driver on purpose,
    such as ``dummy`` for headless runs). Decided from the environment alone: nothing is initialised."""
    env = os.environ if environ is None else environ
    plat = sys.platform if platform is None else platform
    if env.get("SDL_VIDEODRIVER"):
        return None
    if plat.startswith("linux") and not env.get("DISPLAY") and not env.get("WAYLAND_DISPLAY"):
        return "no display (DISPLAY and WAYLAND_DISPLAY are not set)"
    return None
