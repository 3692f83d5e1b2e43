"""Keyboard helm in the pygame chart window, in real time, and a scored debrief at the end.

Keys: Left / Right (or A / D) move the rudder order 5 degrees to port / starboard, Space (or M) puts the
rudder amidships; Up / Down (or W / S) move the engine telegraph one step ahead / astern; 1, 2, 3, 4 set the
time speed-up to x1, x2, x4, x8 (+ / - step it); P pauses; Esc or Q ends the run. The debrief (time, minimum
clearance, contacts, score) is returned, and a track plot is written as a PNG.

Headless and scripted (tests, demonstrations): ``SDL_VIDEODRIVER=dummy`` and
``play("harbour", keys=[(0, "up"), (40, "left")], realtime=False, max_steps=500)`` posts the keys as pygame
key events at the given steps, so they take the same path as a person's key presses.
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vessel_gym.envs.tasks.harbour_env import HarbourApproachEnv
from vessel_gym.outputs import check_free, safe_name, write_new

RUDDER_STEP_DEG = 5.0
RUDDER_ORDERS_DEG = tuple(float(x) for x in np.arange(-35.0, 35.0 + 1e-9, RUDDER_STEP_DEG))
TELEGRAPH_STEPS = tuple(range(-4, 5))
SPEEDUPS = (1.0, 2.0, 4.0, 8.0)


@dataclass
class Debrief:
    """The scored result of one play run (times in s, distances in m)."""

    scenario: str
    outcome: str  # success, contact, grounding, out_of_bounds, diverged, time_limit, quit, max_steps
    time_s: float
    steps: int
    min_clearance_m: float
    contacts: int  # contacts and groundings (the run ends at the first)
    path_m: float
    start_distance_m: float
    final_distance_m: float
    final_speed_m_s: float
    final_heading_error_deg: float
    score: float  # 0..100
    track_png: str | None = None
    track: list[tuple[float, float]] = field(default_factory=list, repr=False)

    def items(self) -> list[tuple[str, str]]:
        """(label, value) rows of the debrief."""
        rows = [
            ("scenario", self.scenario),
            ("outcome", self.outcome),
            ("time", f"{self.time_s:.1f} s ({self.steps} steps)"),
            ("minimum clearance", f"{self.min_clearance_m:.2f} m"),
            ("contacts", f"{self.contacts}"),
            ("distance sailed", f"{self.path_m:.1f} m"),
            (
                "to goal at end",
                f"{self.final_distance_m:.1f} m at {self.final_speed_m_s:.2f} m/s, "
                f"heading error {self.final_heading_error_deg:+.1f} deg",
            ),
            ("score", f"{self.score:.0f} / 100"),
        ]
        return rows + ([("track plot", self.track_png)] if self.track_png else [])

    def summary(self) -> str:
        """Human-readable debrief, one item per line."""
        return "\n".join(f"{label:18s}{value}" for label, value in self.items())


def score(
    outcome: str,
    time_s: float,
    min_clearance_m: float,
    start_distance_m: float,
    final_distance_m: float,
    L_m: float,
    U_T_m_s: float,
) -> float:
    """Debrief score 0..100.

    Success: 50 + 25 x clearance (minimum clearance / half a ship length, capped at 1) + 25 x pace (the time a
    ship would need at 60 % of the test speed along the straight distance / the time taken, capped at 1).
    Otherwise: 40 x fraction of the distance to the goal made good, halved after a contact or grounding.
    """
    clearance = min(max(min_clearance_m / (0.5 * L_m), 0.0), 1.0)
    if outcome == "success":
        t_ref = start_distance_m / (0.6 * U_T_m_s)
        pace = min(t_ref / max(time_s, 1e-9), 1.0)
        return 50.0 + 25.0 * clearance + 25.0 * pace
    made_good = min(max(1.0 - final_distance_m / max(start_distance_m, 1e-9), 0.0), 1.0)
    return 40.0 * made_good * (0.5 if outcome in ("contact", "grounding") else 1.0)


class HarbourConsole:
    """The keyboard helm of HarbourApproach: rudder orders in 5 degree steps and the engine telegraph."""

    def __init__(self, scenario: str, env_overrides: Mapping[str, Any]) -> None:
        from vessel_gym.envs.tasks.harbour import own_ship
        from vessel_gym.scenarios import load_scenario
        from vessel_gym.scenarios.traffic import Traffic

        sc_loaded = load_scenario(scenario)
        self.env = HarbourApproachEnv(
            preset="HarbourApproach-v2",
            scenario=sc_loaded,
            action_type="discrete",
            engine_control=True,
            rudder_orders_deg=RUDDER_ORDERS_DEG,
            telegraph_steps=TELEGRAPH_STEPS,
            **{**own_ship(sc_loaded), **env_overrides},
        )
        self.task = self.env.task
        self.name = self.task.scenario.name
        self.rudder_i = RUDDER_ORDERS_DEG.index(0.0)
        self.tele_i = 0
        self.traffic = Traffic.from_scenario(
            self.task.scenario, self.task.dt, self.env.config.control_interval_s
        )
        self.time_limit_s = 400.0

    def reset(self, seed: int | None) -> dict:
        _obs, info = self.env.reset(seed=seed)
        # start with the telegraph step closest to the approach shaft speed
        rev0 = float(self.env.sim.rev_order[0])
        self.tele_i = int(np.argmin(np.abs(self.task.helm.rev_table[0] - rev0)))
        self.start_distance = float(info["distance_to_goal_m"])
        return info

    def key(self, pygame: Any, k: int) -> None:
        if k in (pygame.K_LEFT, pygame.K_a):
            self.rudder_i = max(self.rudder_i - 1, 0)
        elif k in (pygame.K_RIGHT, pygame.K_d):
            self.rudder_i = min(self.rudder_i + 1, len(RUDDER_ORDERS_DEG) - 1)
        elif k in (pygame.K_SPACE, pygame.K_m):
            self.rudder_i = RUDDER_ORDERS_DEG.index(0.0)
        elif k in (pygame.K_UP, pygame.K_w):
            self.tele_i = min(self.tele_i + 1, len(TELEGRAPH_STEPS) - 1)
        elif k in (pygame.K_DOWN, pygame.K_s):
            self.tele_i = max(self.tele_i - 1, 0)

    def action(self) -> np.ndarray:
        return np.array([self.rudder_i, self.tele_i])

    @property
    def telegraph(self) -> int | None:
        return TELEGRAPH_STEPS[self.tele_i]

    def overlay(self) -> dict:
        return self.task.overlay(0)

    def targets(self, steps: int) -> Sequence[Any]:
        return self.traffic.lazy_targets(steps) if self.traffic is not None else ()

    def contact(self, info: Mapping[str, Any]) -> bool:
        return bool(info["contact"] or info["grounding"])

    def debrief(
        self, outcome: str, steps: int, contacts: int, info: Mapping[str, Any], track: list
    ) -> Debrief:
        return Debrief(
            scenario=self.name,
            outcome=outcome,
            time_s=float(info["time_s"]),
            steps=steps,
            min_clearance_m=float(info["min_clearance_m"]),
            contacts=contacts,
            path_m=float(info["path_m"]),
            start_distance_m=self.start_distance,
            final_distance_m=float(info["distance_to_goal_m"]),
            final_speed_m_s=float(info["speed_over_ground_m_s"]),
            final_heading_error_deg=float(info["heading_error_deg"]),
            score=score(
                outcome,
                float(info["time_s"]),
                float(info["min_clearance_m"]),
                self.start_distance,
                float(info["distance_to_goal_m"]),
                self.task.L,
                self.task.U_T,
            ),
            track=track,
        )


def play(
    scenario: str | None = None,
    *,
    env_id: str | None = None,
    seed: int | None = None,
    max_steps: int | None = None,
    realtime: bool = True,
    speedup: float = 1.0,
    keys: Sequence[tuple[int, str]] = (),
    out_dir: str | Path | None = ".",
    size: tuple[int, int] = (800, 600),
    force: bool = False,
    **env_overrides: Any,
) -> Any:
    """Drive the scenario's ship with the keyboard; return the debrief (:class:`Debrief`, or
    :class:`~vessel_gym.envs.debrief.BerthingDebrief` for a berthing task) and write its track PNG.

    Args:
        scenario: built-in scenario name or scenario file (default: "harbour", or the task preset's).
        env_id: a berthing task's id (``vessel_gym/Berthing-v0``, ``vessel_gym/BerthingTanker-v0``): berth
            with its thrusters or tugs (keys in :mod:`vessel_gym.ui.play_berthing`); None: HarbourApproach.
        seed: start pose and weather draw.
        max_steps: stop after this many control steps (default: the task's time limit, 400 s in the harbour).
        realtime: pace the simulation to the wall clock (x ``speedup``); False runs as fast as it can.
        speedup: initial time speed-up (keys 1-4 change it).
        keys: scripted key presses ``(step, key name)`` (pygame key names: "left", "up", "space", "q" ...),
            posted as key events before that step.
        out_dir: where the track plot ``debrief_<scenario>.png`` goes (None: no file).
        size: window size in pixels.
        force: replace an existing debrief PNG (otherwise :class:`~vessel_gym.outputs.OutputExistsError`
            is raised before the window opens).
        env_overrides: further config keys of the task.
    """
    import pygame

    from vessel_gym.ui.chart import ChartRenderer

    if env_id is None:
        console: Any = HarbourConsole(scenario or "harbour", env_overrides)
    else:
        from vessel_gym.ui.play_berthing import BerthingConsole

        overrides = dict(env_overrides, **({} if scenario is None else {"scenario": scenario}))
        console = BerthingConsole(env_id, overrides)
    env, task = console.env, console.task
    png = None if out_dir is None else Path(out_dir) / f"debrief_{safe_name(console.name)}.png"
    if png is not None:
        check_free([png], force, "--out")
    dt = env.config.control_interval_s
    limit = int(round(console.time_limit_s / dt)) if max_steps is None else int(max_steps)
    info = console.reset(seed)
    view = ChartRenderer("human", ship=task.ship, scenario=task.scenario, fps=0.0, size=size)
    clock = pygame.time.Clock()
    scripted: dict[int, list[int]] = {}
    for step, name in keys:
        scripted.setdefault(int(step), []).append(pygame.key.key_code(name))
    track = [(float(env.sim.north[0]), float(env.sim.east[0]))]
    outcome = "max_steps"
    contacts = 0
    paused = False
    steps = 0
    quit_ = False
    try:
        while steps < limit:
            for code in scripted.pop(steps, []):
                pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=code, mod=0, unicode="", scancode=0))
            for ev in pygame.event.get():
                if ev.type == pygame.QUIT:
                    quit_ = True
                elif ev.type == pygame.KEYDOWN:
                    k = ev.key
                    if k in (pygame.K_ESCAPE, pygame.K_q):
                        quit_ = True
                    elif k in (pygame.K_1, pygame.K_2, pygame.K_3, pygame.K_4):
                        speedup = SPEEDUPS[k - pygame.K_1]
                    elif k in (pygame.K_PLUS, pygame.K_EQUALS, pygame.K_KP_PLUS):
                        speedup = min(speedup * 2.0, 64.0)
                    elif k in (pygame.K_MINUS, pygame.K_KP_MINUS):
                        speedup = max(speedup / 2.0, 0.125)
                    elif k == pygame.K_p:
                        paused = not paused
                    else:
                        console.key(pygame, k)
            if quit_:
                outcome = "quit"
                break
            if paused:
                view.draw(
                    env.sim,
                    0,
                    track,
                    telegraph=console.telegraph,
                    overlay={**console.overlay(), "title": f"{console.name}  (paused)"},
                    targets=console.targets(steps),
                )
                clock.tick(20)
                continue
            _obs, _r, terminated, _truncated, info = env.step(console.action())
            steps += 1
            track.append((float(env.sim.north[0]), float(env.sim.east[0])))
            view.draw(
                env.sim,
                0,
                track,
                telegraph=console.telegraph,
                overlay={**console.overlay(), "title": f"{console.name}  x{speedup:g}"},
                targets=console.targets(steps),
            )
            if realtime:
                clock.tick(speedup / dt)
            if terminated:
                outcome = info["outcome"]
                contacts += int(console.contact(info))
                break
        else:
            if max_steps is None:
                outcome = "time_limit"
    finally:
        view.close()
    debrief = console.debrief(outcome, steps, contacts, info, track)
    if png is not None:
        debrief.track_png = str(write_track_png(env, debrief, png, size, force))
    env.close()
    return debrief


def write_track_png(
    env: Any,
    debrief: Any,
    path: Path,
    size: tuple[int, int] = (800, 600),
    force: bool = False,
) -> Path:
    """The chart with the whole track, start and end marks and the debrief text, as a PNG (an existing
    file is not replaced unless ``force``)."""
    import pygame

    from vessel_gym.ui.chart import ChartRenderer

    task = env.task
    chart = ChartRenderer("rgb_array", ship=task.ship, scenario=task.scenario, size=size)
    chart.draw(
        env.sim,
        0,
        debrief.track,
        telegraph=None,
        overlay={**task.overlay(0), "title": f"Debrief: {debrief.scenario}"},
    )
    surf = chart.surface()
    if debrief.track:
        pygame.draw.circle(surf, (20, 120, 20), [int(v) for v in chart.to_screen(*debrief.track[0])], 5)
        pygame.draw.circle(surf, (200, 30, 30), [int(v) for v in chart.to_screen(*debrief.track[-1])], 5)
    x0 = chart.chart_w
    pygame.draw.rect(surf, (28, 32, 40), (x0, 0, chart.panel_w, chart.height))
    y = 12
    for label, value in debrief.items():
        if label == "track plot":
            continue
        surf.blit(chart.small.render(label, True, (140, 145, 155)), (x0 + 10, y))
        for part in _wrap(value.strip(), 26):
            surf.blit(chart.small.render(part, True, (230, 232, 235)), (x0 + 10, y + 14))
            y += 14
        y += 22
    big = chart.big.render(f"score {debrief.score:.0f}", True, (255, 200, 80))
    surf.blit(big, (x0 + 10, chart.height - 40))
    buf = io.BytesIO()
    pygame.image.save(surf, buf, "png")
    chart.close()
    return write_new(path, buf.getvalue(), force)


def _wrap(text: str, width: int) -> list[str]:
    words, lines, cur = text.split(), [], ""
    for w in words:
        if cur and len(cur) + 1 + len(w) > width:
            lines.append(cur)
            cur = w
        else:
            cur = f"{cur} {w}".strip()
    return lines + ([cur] if cur else [])
