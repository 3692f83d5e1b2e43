"""What the 3D page adds for the served tasks beyond a harbour (``vessel-gym serve --env``): the thruster and tug
controls of the helm (Berthing), the fenders coloured by their load (the chart's colours,
:func:`~vessel_gym.ui.chart.fender_colour`) and the own ship's route (CollisionAvoidance)
in the scene, and their rows of the HUD. The target ships need nothing here: they are ships of the scene like
the harbour's traffic.

Controls (shown once the link's welcome names the ship's thrusters and tugs; they act only while this page
holds the helm): per unit a "to port" and a "to starboard" button, a quarter of its range per press (the
keyboard's ``play`` step, :data:`~vessel_gym.ui.panels.ASSIST_STEP`), keys Z / X (first unit), Q / W
(second), O / P (third), and ``0`` every unit to zero. A thruster's order is its fraction of rated rpm, a tug's
the fraction of its bollard pull along its line, + towards starboard.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vessel_gym.ui.chart import fender_colour
from vessel_gym.ui.panels import ASSIST_STEP
from vessel_gym.ui.view3d_scene import COLOURS, RELIEF_T, chart_to_scene, prism

#: hotkeys (to port, to starboard) of the first three thrusters or tugs (C is the camera's, M midships)
ASSIST_HOTKEYS = (("Z", "X"), ("Q", "W"), ("O", "P"))
ZERO_HOTKEY = "0"
FENDER_RECOLOUR = 0.02  # a fender is recoloured when its load changed by more than this (fraction of rating)


class AssistControls:
    """The page's thruster and tug controls for the units ``link.assist_units()`` names (rebuilt when they
    change: a new ship after a restart of serve)."""

    def __init__(self, gui: Any, link: Any) -> None:
        self.gui = gui
        self.link = link
        self.units: list[tuple[str, str]] = []
        self.handles: list[Any] = []
        self.buttons: dict[str, Any] = {}

    def sync(self) -> None:
        """Build the controls for the link's units if they changed."""
        units = self.link.assist_units()
        if units == self.units:
            return
        for h in self.handles:
            h.remove()
        self.handles, self.buttons, self.units = [], {}, units
        if not units:
            return
        gui = self.gui
        keys = ", ".join(f"**{a}/{b}** {name}" for (name, _k), (a, b) in zip(units, ASSIST_HOTKEYS))
        self.handles.append(
            gui.add_markdown(
                f"Thrusters and tugs (+ to starboard, {ASSIST_STEP:g} per press): {keys}; **0** all to 0."
            )
        )
        for j, (name, _kind) in enumerate(units):
            for side, step in (("port", -ASSIST_STEP), ("starboard", ASSIST_STEP)):
                label = f"{name} to {side}"
                button = gui.add_button(label)
                button.on_click(lambda _e, j=j, step=step: self.step(j, step))
                self.handles.append(button)
                self.buttons[label] = button
                if j < len(ASSIST_HOTKEYS):
                    key = ASSIST_HOTKEYS[j][0 if step < 0 else 1]
                    cmd = gui.add_command(f"{name} a quarter to {side}", hotkey=key)
                    cmd.on_trigger(lambda _e, j=j, step=step: self.step(j, step))
                    self.handles.append(cmd)
        zero = gui.add_button("Thrusters and tugs to 0")
        zero.on_click(lambda _e: self.zero())
        cmd = gui.add_command("Thrusters and tugs to 0", hotkey=ZERO_HOTKEY)
        cmd.on_trigger(lambda _e: self.zero())
        self.handles += [zero, cmd]
        self.buttons["zero"] = zero

    def step(self, j: int, step: float) -> None:
        link = self.link
        if link.helm and 0 <= j < len(link.assist):
            link.set_assist(j, link.assist[j] + step)

    def zero(self) -> None:
        for j in range(len(self.link.assist)):
            self.link.set_assist(j, 0.0)


def hud_rows(st: dict, link: Any) -> list[str]:
    """HUD table rows: each thruster's or tug's order (the page's own while it holds the helm) and what it
    delivers, and the most loaded fender."""
    rows = []
    assist = st.get("assist")
    if isinstance(assist, list):
        for j, a in enumerate(assist):
            if not isinstance(a, dict):
                continue
            order, now = a.get("order"), a.get("delivered")
            mine = f" (you {link.assist[j]:+.2f})" if link.helm and j < len(link.assist) else ""
            if isinstance(order, (int, float)) and isinstance(now, (int, float)):
                rows.append(
                    f"| {str(a.get('name', ''))[:32]} | order {order:+.2f}{mine}, delivers {now:+.2f} |"
                )
    load = st.get("fender_load")
    if isinstance(load, list) and load and all(isinstance(x, (int, float)) for x in load):
        j = int(np.argmax(load))
        rows.append(f"| Fenders | fender {j + 1} at {100.0 * load[j]:.0f} % of rated |")
    return rows


def outcome_figures(event: dict) -> str:
    """The task's figures of an ``outcome`` event for the HUD: the COLREG score and violations, or the contact
    speed and the most loaded fender ("" for a harbour's)."""
    num = lambda k: event.get(k) if isinstance(event.get(k), (int, float)) else None  # noqa: E731
    parts = []
    if num("colreg_score") is not None:
        parts.append(f"COLREG score {num('colreg_score'):.2f}")
        if num("colreg_violations") is not None:
            parts.append(f"{num('colreg_violations'):.0f} in violation")
    if num("contact_speed_m_s") is not None:
        parts.append(f"contact {num('contact_speed_m_s'):.2f} m/s")
    if num("max_fender_energy_fraction") is not None:
        parts.append(f"fender max {100.0 * num('max_fender_energy_fraction'):.0f} % of rated")
    return (": " + ", ".join(parts)) if parts else ""


class TaskScene:
    """The fenders (coloured by load) and the route of the scene's ``fender`` and ``route`` features."""

    def __init__(self) -> None:
        self.fenders: list[Any] = []
        self.loads: list[float] = []

    def build(self, scene_api: Any, features: list[dict], T: float, L: float) -> None:
        """Draw the task's features (called with the rest of the scene)."""
        self.fenders, self.loads = [], []
        for f in features:
            pts = f.get("points") or []
            if f.get("kind") == "route" and len(pts) >= 2:
                xy = chart_to_scene(pts)
                z = np.full((len(xy), 1), 0.05 * T)
                line = np.column_stack([xy, z])
                segs = np.stack([line[:-1], line[1:]], axis=1)
                scene_api.add_line_segments("/chart/route", segs, COLOURS["route"], thickness=0.03 * L)
            elif f.get("kind") == "fender" and len(pts) >= 3:
                # from below the waterline to the quay's top, as a cell fender hangs on the quay face
                v, fc = prism(chart_to_scene(pts), -0.5 * T, RELIEF_T["quay"] * T)
                handle = scene_api.add_mesh_simple(
                    f"/chart/fender_{len(self.fenders)}", v, fc, color=fender_colour(0.0), flat_shading=True
                )
                self.fenders.append(handle)
                self.loads.append(0.0)

    def update(self, st: dict) -> None:
        """Recolour the fenders whose load (``state.fender_load``) changed."""
        load = st.get("fender_load")
        if not isinstance(load, list) or len(load) != len(self.fenders):
            return
        for j, (h, x) in enumerate(zip(self.fenders, load)):
            if isinstance(x, (int, float)) and math.isfinite(x) and abs(x - self.loads[j]) > FENDER_RECOLOUR:
                self.loads[j] = float(x)
                h.color = fender_colour(float(x))
