"""Top-down chart of one ship: land, breakwaters, quays, depth shading, the ship outline to scale, its track,
wind and current arrows and an instrument panel (speed, heading, rate of turn, rudder, rpm, telegraph).

The renderer only reads: the simulation's named quantities and bridge readings, the scenario geometry and
what the task hands over as an overlay (target heading, goal). pygame is imported on first use, so the
environments work without it; set ``SDL_VIDEODRIVER=dummy`` to render headless.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from vessel_gym.physics.bridge import Telegraph
from vessel_gym.physics.shipfile import Ship
from vessel_gym.scenarios.geometry import hull_outline

WATER = (168, 205, 230)
DEEP = (120, 170, 210)
LAND = (222, 208, 170)
LAND_EDGE = (150, 130, 90)
BREAKWATER = (130, 130, 130)
QUAY = (90, 90, 95)
SHOAL = (235, 225, 185)
GOAL = (40, 160, 60)
START = (90, 90, 160)
SHIP = (200, 40, 30)
TRACK = (30, 30, 120)
PANEL = (28, 32, 40)
TEXT = (230, 232, 235)
DIM = (140, 145, 155)
WIND = (80, 150, 255)
CURRENT = (60, 200, 120)
TARGET = (230, 140, 0)
TRAFFIC = (150, 60, 170)
QUAY_FACE = (25, 25, 30)  # a berth's quay face (fender line)
BERTH_TARGET = (0, 120, 200)  # the berthed pose's outline


def fender_colour(fraction: float) -> tuple[int, int, int]:
    """A fender's colour by how much of its rating is used (energy absorbed, or compression now, against the
    rated one): white unused, green to yellow to red at the rating, magenta beyond it."""
    if fraction <= 0.0:
        return (245, 245, 245)
    if fraction > 1.0:
        return (230, 0, 200)
    if fraction <= 0.5:
        return (int(round(510 * fraction)), 200, 40)
    return (255, int(round(200 - 400 * (fraction - 0.5))), 40)


def depth_colour(depth_m: float, draught_m: float, deep_m: float) -> tuple[int, int, int]:
    """Chart shading: shallower is lighter; below the draught a sand colour (a grounding area)."""
    if depth_m < draught_m:
        return SHOAL
    f = float(np.clip((depth_m - draught_m) / max(deep_m - draught_m, 1e-6), 0.0, 1.0))
    return tuple(int(round(a + (b - a) * f)) for a, b in zip((200, 228, 240), DEEP))  # type: ignore[return-value]


def task_renderer(task: Any, mode: str) -> ChartRenderer:
    """A chart renderer of an environment task's ship and chart (its ``scenario`` if it has one), at its control
    rate."""
    return ChartRenderer(
        mode,
        ship=task.ship,
        scenario=getattr(task, "scenario", None),
        fps=1.0 / task.config.control_interval_s,
    )


class ChartRenderer:
    """Draws a chart of vessel k of a simulation; ``mode`` "human" (window) or "rgb_array" (returns frames).

    Args:
        mode: "human" or "rgb_array".
        ship: the ship drawn (outline from L and B).
        scenario: a :class:`~vessel_gym.scenarios.Scenario` (fixed chart of its bounds), or None for open
            water (the view follows the ship).
        fps: frames per second in human mode (real time = 1 / control interval).
        size: (width, height) in pixels; the right 200 px are the instrument panel.
    """

    def __init__(
        self,
        mode: str,
        ship: Ship,
        scenario: Any = None,
        fps: float = 4.0,
        size: tuple[int, int] = (800, 600),
    ) -> None:
        if mode not in ("human", "rgb_array"):
            raise ValueError(f"mode must be 'human' or 'rgb_array', got {mode!r}")
        import pygame

        self.pg = pygame
        self.mode = mode
        self.ship = ship
        self.scenario = scenario
        self.fps = fps
        self.width, self.height = size
        self.panel_w = 200
        self.chart_w = self.width - self.panel_w
        pygame.font.init()
        if mode == "human":
            pygame.display.init()
            self.screen = pygame.display.set_mode(size)
            pygame.display.set_caption("vessel-gym")
        else:
            self.screen = pygame.Surface(size)
        self.font = pygame.font.Font(None, 20)
        self.small = pygame.font.Font(None, 16)
        self.big = pygame.font.Font(None, 26)
        self.clock = pygame.time.Clock()
        self.hull = np.array(hull_outline(ship.particulars.L_m, ship.particulars.B_m))
        self._background = None
        self.inset_rect: tuple[int, int, int, int] | None = None  # the berth inset (x, y, w, h), once drawn
        self.view: tuple[float, float, float] = (0.0, 0.0, 1.0)  # centre north, centre east, px per m
        if scenario is not None:
            n0, n1, e0, e1 = scenario.bounds_m
            scale = min(self.chart_w / (e1 - e0), self.height / (n1 - n0))
            self.view = (0.5 * (n0 + n1), 0.5 * (e0 + e1), scale)

    # --- geometry ---------------------------------------------------------------------------------------------
    def to_screen(self, north: float, east: float) -> tuple[float, float]:
        nc, ec, s = self.view
        return (self.chart_w / 2 + (east - ec) * s, self.height / 2 - (north - nc) * s)

    def _poly(self, pts: Sequence[Sequence[float]]) -> list[tuple[float, float]]:
        return [self.to_screen(p[0], p[1]) for p in pts]

    def _follow(self, north: float, east: float, track: Sequence[tuple[float, float]]) -> None:
        # centred on the ship, zoomed out to keep the recent track in view
        L = self.ship.particulars.L_m
        reach = 0.0
        if track:
            pts = np.asarray(track[-2000:], dtype=float)
            reach = float(np.max(np.hypot(pts[:, 0] - north, pts[:, 1] - east)))
        extent = max(12.0 * L, 2.2 * reach)
        self.view = (north, east, min(self.chart_w, self.height) / extent)

    # --- drawing --------------------------------------------------------------------------------------------
    def _chart_background(self, goal: bool = True) -> Any:
        """The chart without the ship; ``goal``: the scenario's goal area and start area (not for a task
        whose goal is a berth)."""
        pg = self.pg
        surf = pg.Surface((self.chart_w, self.height))
        sc = self.scenario
        if sc is None:
            surf.fill(WATER)
            return surf
        T = self.ship.particulars.T_m
        deep = max([sc.water_depth_m] + [d.depth_m for d in sc.depth_area])
        surf.fill(depth_colour(sc.water_depth_m, T, deep))
        for d in sorted(sc.depth_area, key=lambda a: -a.depth_m):
            pg.draw.polygon(surf, depth_colour(d.depth_m, T, deep), self._poly(d.points))
            if d.depth_m < T:
                pg.draw.polygon(surf, (200, 170, 90), self._poly(d.points), 1)
        if goal:
            pg.draw.polygon(surf, START, self._poly(sc.start.points), 1)
        for kind, colour in (("land", LAND), ("breakwater", BREAKWATER), ("quay", QUAY)):
            for a in getattr(sc, kind):
                pg.draw.polygon(surf, colour, self._poly(a.points))
                pg.draw.polygon(surf, LAND_EDGE if kind == "land" else (60, 60, 60), self._poly(a.points), 1)
        if not goal:
            return surf
        pg.draw.polygon(surf, GOAL, self._poly(sc.goal.points), 2)
        gp = self.to_screen(*sc.goal_point)
        h = math.radians(sc.goal.heading_deg)
        tip = (gp[0] + 18 * math.sin(h), gp[1] - 18 * math.cos(h))
        pg.draw.line(surf, GOAL, gp, tip, 2)
        pg.draw.circle(surf, GOAL, (int(gp[0]), int(gp[1])), 3)
        return surf

    def _grid(self, surf: Any) -> None:
        nc, ec, s = self.view
        span = self.chart_w / s
        step = 10 ** math.floor(math.log10(span / 4))
        for mult in (1, 2, 5):
            if span / (step * mult) <= 8:
                step *= mult
                break
        n_lo = nc - self.height / 2 / s
        e_lo = ec - self.chart_w / 2 / s
        for i in range(int(math.floor(e_lo / step)), int(math.ceil((e_lo + span) / step)) + 1):
            x = self.to_screen(0.0, i * step)[0]
            self.pg.draw.line(surf, (150, 190, 215), (x, 0), (x, self.height), 1)
        for i in range(int(math.floor(n_lo / step)), int(math.ceil((n_lo + self.height / s) / step)) + 1):
            y = self.to_screen(i * step, 0.0)[1]
            self.pg.draw.line(surf, (150, 190, 215), (0, y), (self.chart_w, y), 1)

    def _scale_bar(self, surf: Any) -> None:
        s = self.view[2]
        target = self.chart_w / 5 / s
        length = 10 ** math.floor(math.log10(target))
        for mult in (5, 2, 1):
            if length * mult <= target:
                length *= mult
                break
        x0, y0 = 12, self.height - 16
        px = length * s
        self.pg.draw.line(surf, (0, 0, 0), (x0, y0), (x0 + px, y0), 2)
        self.pg.draw.line(surf, (0, 0, 0), (x0, y0 - 4), (x0, y0 + 4), 2)
        self.pg.draw.line(surf, (0, 0, 0), (x0 + px, y0 - 4), (x0 + px, y0 + 4), 2)
        surf.blit(self.small.render(f"{length:g} m", True, (0, 0, 0)), (x0 + px + 6, y0 - 6))

    def _arrow(
        self,
        surf: Any,
        centre: tuple[float, float],
        bearing_rad: float,
        length: float,
        colour: tuple,
        width: int = 3,
    ) -> None:
        """Arrow pointing towards ``bearing_rad`` (clockwise from north) on the screen."""
        cx, cy = centre
        dx, dy = math.sin(bearing_rad), -math.cos(bearing_rad)
        tail = (cx - dx * length / 2, cy - dy * length / 2)
        tip = (cx + dx * length / 2, cy + dy * length / 2)
        self.pg.draw.line(surf, colour, tail, tip, width)
        left = (tip[0] - 8 * dx + 5 * dy, tip[1] - 8 * dy - 5 * dx)
        right = (tip[0] - 8 * dx - 5 * dy, tip[1] - 8 * dy + 5 * dx)
        self.pg.draw.polygon(surf, colour, [tip, left, right])

    def draw(
        self,
        sim: Any,
        k: int,
        track: Sequence[tuple[float, float]],
        telegraph: int | None = None,
        overlay: dict | None = None,
        targets: Sequence[Any] = (),
    ) -> np.ndarray | None:
        """Draw vessel ``k`` of ``sim`` and the other ships ``targets`` (:class:`~vessel_gym.net.protocol.Target`,
        outlines to scale, named); return an (H, W, 3) uint8 frame in rgb_array mode."""
        pg = self.pg
        overlay = overlay or {}
        north, east, psi = float(sim.north[k]), float(sim.east[k]), float(sim.heading[k])
        finite = math.isfinite(north) and math.isfinite(east) and math.isfinite(psi)
        if self.scenario is None and finite:
            self._follow(north, east, list(track))
            chart = self._chart_background()
            self._grid(chart)
        else:
            if self._background is None:
                self._background = self._chart_background(goal="berth" not in overlay)
            chart = self._background.copy()
        if "original_course_rad" in overlay:
            o = overlay.get("origin_m", track[0] if track else (north, east))
            c = overlay["original_course_rad"]
            a = self.to_screen(*o)
            far = 1e4
            b = self.to_screen(o[0] + far * math.cos(c), o[1] + far * math.sin(c))
            pg.draw.line(chart, DIM, a, b, 1)
        if len(track) > 1:
            pg.draw.lines(chart, TRACK, False, self._poly(track), 2)
        berth = overlay.get("berth")
        if berth is not None:
            self._berth(chart, berth, 3)
        for t in targets:
            r = t.reading
            if not (math.isfinite(r.x_m) and math.isfinite(r.y_m) and math.isfinite(r.hdg_deg)):
                continue
            h = math.radians(r.hdg_deg)
            c, s = math.cos(h), math.sin(h)
            outline = [
                self.to_screen(r.x_m + c * x - s * y, r.y_m + s * x + c * y)
                for x, y in hull_outline(t.length_m, t.beam_m)
            ]
            pg.draw.polygon(chart, TRAFFIC, outline)
            label = self.small.render(str(t.name), True, TRAFFIC)
            px, py = self.to_screen(r.x_m, r.y_m)
            chart.blit(label, (px + 8, py + 6))
        if finite:
            if "target_heading_rad" in overlay:
                t = overlay["target_heading_rad"]
                reach = 3.0 * self.ship.particulars.L_m
                pg.draw.line(
                    chart,
                    TARGET,
                    self.to_screen(north, east),
                    self.to_screen(north + reach * math.cos(t), east + reach * math.sin(t)),
                    2,
                )
            c, s = math.cos(psi), math.sin(psi)
            outline = [self.to_screen(north + c * x - s * y, east + s * x + c * y) for x, y in self.hull]
            pg.draw.polygon(chart, SHIP, outline)
            pg.draw.polygon(chart, (80, 0, 0), outline, 1)
        self._scale_bar(chart)
        if berth is not None:
            self._berth_inset(chart, berth, (north, east, psi) if finite else None)
        title = overlay.get("title")
        if title:
            chart.blit(self.font.render(title, True, (0, 0, 0)), (10, 8))
        self.screen.blit(chart, (0, 0))
        self._panel(sim, k, telegraph, overlay)
        if self.mode == "human":
            pg.event.pump()
            pg.display.flip()
            if self.fps > 0:
                self.clock.tick(self.fps)
            return None
        return np.transpose(np.array(pg.surfarray.pixels3d(self.screen)), axes=(1, 0, 2)).copy()

    def _berth(self, surf: Any, berth: dict, fender_px: int) -> None:
        """A berth of the overlay (``BerthingTask.overlay``): the quay face, the berthed pose's outline and
        the fenders coloured by :func:`fender_colour`, each at least ``fender_px`` pixels across."""
        pg = self.pg
        pg.draw.line(surf, QUAY_FACE, *self._poly(berth["quay_m"]), 3)
        n, e, psi = berth["target"]
        c, s = math.cos(psi), math.sin(psi)
        pg.draw.polygon(
            surf,
            BERTH_TARGET,
            [self.to_screen(n + c * x - s * y, e + s * x + c * y) for x, y in self.hull],
            1,
        )
        for base, face, fraction in zip(berth["fender_base_m"], berth["fender_face_m"], berth["fender_load"]):
            a, b = self.to_screen(*base), self.to_screen(*face)
            w = max(fender_px, int(round(math.hypot(b[0] - a[0], b[1] - a[1]))))
            centre = (int(round(0.5 * (a[0] + b[0]))), int(round(0.5 * (a[1] + b[1]))))
            rect = pg.Rect(0, 0, w, w)
            rect.center = centre
            pg.draw.rect(surf, fender_colour(float(fraction)), rect)
            if w >= 6:  # an outline where there is room for it
                pg.draw.rect(surf, QUAY_FACE, rect, 1)

    def _berth_inset(self, chart: Any, berth: dict, pose: tuple[float, float, float] | None) -> None:
        """A magnified view of the berth (one and a half ship lengths across) in the chart's lower right
        corner: the quay, the berthed pose, the fenders at scale and the ship when it is in the view."""
        pg = self.pg
        w, h = min(240, self.chart_w // 2), min(180, self.height // 3)
        L = self.ship.particulars.L_m
        n0, e0, _psi = berth["target"]
        saved = (self.view, self.chart_w, self.height)
        self.view, self.chart_w, self.height = (n0, e0, w / (1.5 * L)), w, h
        try:
            inset = pg.Surface((w, h))
            inset.fill(WATER)
            sc = self.scenario
            for a in () if sc is None else (*sc.quay, *sc.breakwater, *sc.land):
                pg.draw.polygon(inset, QUAY, self._poly(a.points))
            self._berth(inset, berth, 7)
            if pose is not None:
                n, e, psi = pose
                c, s = math.cos(psi), math.sin(psi)
                outline = [self.to_screen(n + c * x - s * y, e + s * x + c * y) for x, y in self.hull]
                pg.draw.polygon(inset, SHIP, outline)
                pg.draw.polygon(inset, (80, 0, 0), outline, 1)
            inset.blit(self.small.render(berth.get("name", "berth"), True, (0, 0, 0)), (4, h - 14))
        finally:
            self.view, self.chart_w, self.height = saved
        x0, y0 = self.chart_w - w - 6, self.height - h - 6
        chart.blit(inset, (x0, y0))
        pg.draw.rect(chart, QUAY_FACE, (x0 - 1, y0 - 1, w + 2, h + 2), 1)
        self.inset_rect = (x0, y0, w, h)

    def _panel(self, sim: Any, k: int, telegraph: int | None, overlay: dict) -> None:
        pg = self.pg
        x0 = self.chart_w
        pg.draw.rect(self.screen, PANEL, (x0, 0, self.panel_w, self.height))
        try:
            b = sim.bridge(k, telegraph or 0)
        except Exception:  # a diverged vessel has no readings to show
            b = None
        y = 10

        def line(label: str, value: str, colour: tuple = TEXT) -> None:
            nonlocal y
            self.screen.blit(self.small.render(label, True, DIM), (x0 + 10, y))
            self.screen.blit(self.font.render(value, True, colour), (x0 + 90, y - 2))
            y += 22

        if b is None or not math.isfinite(b.hdg_deg):
            line("state", "diverged", (255, 90, 90))
            return
        line("time", f"{b.t_s:7.1f} s")
        line("SOG", f"{b.sog_kn:5.2f} kn")
        line("STW", f"{b.stw_kn:5.2f} kn")
        line("heading", f"{b.hdg_deg:05.1f} deg")
        line("COG", f"{b.cog_deg:05.1f} deg")
        line("ROT", f"{b.rot_dpm:+6.1f} deg/min")
        line("rudder", f"{b.rudder_deg:+5.1f} deg")
        line("order", f"{b.rudder_order_deg:+5.1f} deg", TARGET)
        line("rpm", f"{b.rpm:+6.0f}")
        tg = (
            "-"
            if telegraph is None
            else Telegraph(int(np.clip(telegraph, -4, 4))).name.replace("_", " ").lower()
        )
        line("telegraph", tg)
        if "clearance_m" in overlay:
            line("clearance", f"{overlay['clearance_m']:5.1f} m")
        for label, value in overlay.get("rows", ()):
            line(label, value)
        if overlay.get("outcome") not in (None, "running"):
            line("outcome", str(overlay["outcome"]), (255, 200, 80))
        # rudder indicator: order (orange tick) and actual (bar), +-35 deg
        cy = y + 12
        cx = x0 + self.panel_w // 2
        half = 80
        pg.draw.rect(self.screen, (60, 64, 72), (cx - half, cy - 6, 2 * half, 12))
        lim = 35.0
        ra = float(np.clip(b.rudder_deg / lim, -1, 1)) * half
        pg.draw.rect(
            self.screen, (220, 80, 60) if ra < 0 else (60, 200, 90), (cx + min(0, ra), cy - 5, abs(ra), 10)
        )
        ro = float(np.clip(b.rudder_order_deg / lim, -1, 1)) * half
        pg.draw.line(self.screen, TARGET, (cx + ro, cy - 9), (cx + ro, cy + 9), 2)
        self.screen.blit(self.small.render("P", True, DIM), (cx - half - 10, cy - 6))
        self.screen.blit(self.small.render("S", True, DIM), (cx + half + 3, cy - 6))
        # compass: heading (red), wind towards (blue), current towards (green)
        rc = 58
        ccx, ccy = cx, self.height - rc - 28
        pg.draw.circle(self.screen, (60, 64, 72), (ccx, ccy), rc, 1)
        self.screen.blit(self.small.render("N", True, DIM), (ccx - 4, ccy - rc - 14))
        env = sim.environments[k]
        h = math.radians(b.hdg_deg)
        pg.draw.line(self.screen, SHIP, (ccx, ccy), (ccx + rc * math.sin(h), ccy - rc * math.cos(h)), 2)
        if env.wind_speed_m_s > 0.0:
            self._arrow(self.screen, (ccx, ccy), math.radians(env.wind_from_deg) + math.pi, rc * 1.2, WIND)
        if env.current_speed_m_s > 0.0:
            self._arrow(self.screen, (ccx, ccy), math.radians(env.current_to_deg), rc * 0.8, CURRENT)
        legend = f"wind {env.wind_speed_m_s:.1f} m/s  current {env.current_speed_m_s:.2f} m/s"
        self.screen.blit(self.small.render(legend, True, DIM), (x0 + 8, self.height - 18))

    def surface(self) -> Any:
        """The pygame surface last drawn (for saving a picture)."""
        return self.screen

    def close(self) -> None:
        if self.mode == "human":
            self.pg.display.quit()
