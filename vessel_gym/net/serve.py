"""``vessel-gym serve``: a HarbourApproach scenario, or a CollisionAvoidance or Berthing task (``env``), in real
time on the UDP link (what each task adds: :mod:`~vessel_gym.net.served`).

The scenario runs paced to wall-clock time (times ``time_factor``) by a
:class:`~vessel_gym.net.pacing.RealTimePacer` at a link tick finer than the control interval: within each
control step the physics advances in its own time steps as wall-clock time passes, and the link is serviced
every tick (at most ``LINK_TICK_S`` of wall-clock time apart), so every client gets state at the rate it asked
for (up to 50 Hz) while the agent still acts once per control interval. A human with a helm panel
(``vessel-gym helm``) takes the helm by sending orders; when nobody holds it, the ``agent`` policy steers (the
PID pilot by default); each change of helm owner is one line on stderr. Viewers (``vessel-gym view``, Unity, ...) get the JSON state with the scenario's traffic
as ``targets``, chartplotters get NMEA 0183 with the traffic as AIS. Each episode ends on success, contact,
grounding, leaving the chart or the time limit; a one-line outcome (and the task's debrief) is printed and the
scenario starts again.
Ctrl-C (or ``duration_s``) ends the run with exit code 0.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from typing import Any, TextIO

from vessel_gym.net.link import Address, HelmChange, LinkConfig, UdpLink
from vessel_gym.net.pacing import RealTimePacer

# Longest wall-clock time between two services of the link: 10 ms serves the 50 Hz maximum state rate with each
# state at most half a period late.
LINK_TICK_S = 0.01
_RELEASE_TEXT = {
    "watchdog": "no command for the watchdog time",
    "timeout": "silent for the client timeout",
    "bye": "said bye",
    "viewer": "went back to watching",
    "new_session": "joined again",
}


def link_ticks(control_interval_s: float, time_factor: float) -> int:
    """Ticks per control step: the fewest that keep a tick within LINK_TICK_S of wall-clock time."""
    return max(1, math.ceil(control_interval_s / time_factor / LINK_TICK_S - 1e-9))


def physics_steps(control_interval_s: float, dt_s: float, ticks: int) -> int:
    """Physics steps per control step for ``ticks`` ticks: a multiple of ``ticks`` (the physics moves at every
    tick) whose step is no longer than the environment's own ``dt_s`` (never a coarser integration)."""
    return ticks * max(1, math.ceil(control_interval_s / ticks / dt_s - 1e-9))


def _addr(a: Address) -> str:
    return f"{a[0]}:{a[1]}"


def outcome_line(
    episode: int, info: dict[str, Any], truncated: bool, steps_by: dict[str, int], figures: str | None = None
) -> str:
    """One line describing how an episode ended and who steered it; ``figures`` the task's figures (default:
    the harbour's path, clearance and distance to the goal)."""
    outcome = "time limit" if truncated and info.get("outcome") == "running" else info.get("outcome", "?")
    total = sum(steps_by.values()) or 1
    shares = ", ".join(f"{who} {100.0 * n / total:.0f}%" for who, n in steps_by.items() if n)
    if figures is None:
        figures = (
            f"path {info.get('path_m', math.nan):.0f} m, "
            f"min clearance {info.get('min_clearance_m', math.nan):.1f} m, "
            f"distance to goal {info.get('distance_to_goal_m', math.nan):.1f} m"
        )
    return (
        f"episode {episode}: {outcome} at t = {info.get('time_s', math.nan):.1f} s, {figures}; "
        f"helm: {shares or 'none'}"
    )


def serve(
    scenario: str | None = None,
    *,
    env: str | None = None,
    nmea: Sequence[Address] = (("127.0.0.1", 10110),),
    json_bind: Address = ("127.0.0.1", 10120),
    listen_only: Sequence[Address] = (),
    time_factor: float = 1.0,
    agent: str | None = None,
    target_agent: str | None = None,
    allow_remote: bool = False,
    failsafe: str = "hold",
    duration_s: float | None = None,
    seed: int | None = None,
    agent_resume_s: float | None = 5.0,
    max_episode_steps: int | None = None,
    out: TextIO | None = None,
    token: str | None = None,
    err: TextIO | None = None,
) -> int:
    """Run ``scenario`` (built-in name or TOML path; default ``harbour``) or the task ``env`` live on the UDP
    link until Ctrl-C or ``duration_s``.

    Args:
        env: a CollisionAvoidance or Berthing id (:func:`~vessel_gym.net.served.served_ids`) instead of a
            harbour scenario (not both).
        nmea: NMEA 0183 / AIS destinations (empty: no NMEA).
        json_bind: address of the JSON state/helm channel (port 0: any free port).
        listen_only: viewers that get the JSON state without saying hello.
        time_factor: simulated seconds per wall-clock second.
        agent: helm when no human holds it: ``"pid"``, ``"scripted"`` or an SB3 ``.zip`` (None: ``pid``, or the
            task's own pilot where it has no ``pid``: Berthing's ``scripted``).
        target_agent: CollisionAvoidance: the targets are own ships of the encounter steered by this agent
            (a declared pilot or an SB3 ``.zip``) from their own observations, the person (or ``agent``) at
            the own ship's helm.
        allow_remote: allow binding the JSON channel to a non-loopback address.
        failsafe: ``"hold"`` or ``"midships_stop"``: the orders when a helm panel falls silent, for
            ``agent_resume_s`` wall-clock seconds, after which the agent steers again.
        duration_s: stop after this many wall-clock seconds (None: run until Ctrl-C).
        seed: seed of the first episode (later episodes continue its random stream).
        max_episode_steps: episode time limit in control steps (default: the environment's registered one).
        out: where the messages go (default stdout).
        token: shared secret every client's hello must carry (None: none).
        err: where the helm-change lines go (default stderr).

    Returns 0. A bad scenario raises :class:`~vessel_gym.physics.schema.SpecError`, a bad agent, address or
    setting ``ValueError`` (one line each), before anything is bound or printed.
    """
    out = out if out is not None else sys.stdout
    err = err if err is not None else sys.stderr
    if isinstance(time_factor, bool) or not (math.isfinite(time_factor) and time_factor > 0.0):
        raise ValueError(f"time_factor must be a positive number, not {time_factor!r}")
    if duration_s is not None and not (math.isfinite(duration_s) and duration_s > 0.0):
        raise ValueError(f"duration_s must be a positive number of seconds, not {duration_s!r}")
    if max_episode_steps is not None and max_episode_steps < 1:
        raise ValueError(f"max_episode_steps must be >= 1, not {max_episode_steps!r}")
    if env is not None and scenario is not None:
        raise ValueError(f"give a scenario or --env, not both ({scenario!r} and {env!r})")
    try:
        return _serve(
            scenario=scenario or "harbour",
            env_id=env,
            nmea=nmea,
            json_bind=json_bind,
            listen_only=listen_only,
            time_factor=time_factor,
            agent=agent,
            target_agent=target_agent,
            allow_remote=allow_remote,
            failsafe=failsafe,
            duration_s=duration_s,
            seed=seed,
            agent_resume_s=agent_resume_s,
            max_episode_steps=max_episode_steps,
            out=out,
            token=token,
            err=err,
        )
    except KeyboardInterrupt:  # Ctrl-C while loading: nothing to clean up beyond what _serve closed
        print("vessel-gym serve: interrupted", file=out, flush=True)
        return 0


def _serve(
    *,
    scenario: str,
    env_id: str | None,
    nmea: Sequence[Address],
    json_bind: Address,
    listen_only: Sequence[Address],
    time_factor: float,
    agent: str | None,
    target_agent: str | None,
    allow_remote: bool,
    failsafe: str,
    duration_s: float | None,
    seed: int | None,
    agent_resume_s: float | None,
    max_episode_steps: int | None,
    out: TextIO,
    token: str | None,
    err: TextIO,
) -> int:
    from vessel_gym.net.served import Served
    from vessel_gym.net.wrapper import UdpLinkWrapper
    from vessel_gym.policy import load_policy
    from vessel_gym.scenarios import load_scenario

    served = Served(env_id, load_scenario(scenario) if env_id is None else None, target_agent)
    make_kw: dict[str, Any] = {}
    if max_episode_steps is not None:
        make_kw["max_episode_steps"] = max_episode_steps
    env = served.make(make_kw)
    # The physics must move at every link tick: shorten its step if the default one is longer than a tick.
    control, dt = env.unwrapped.config.control_interval_s, env.unwrapped.task.dt
    nsub = physics_steps(control, dt, link_ticks(control, time_factor))
    if nsub != env.unwrapped.task.nsub:
        env.close()
        env = served.make({"dt_s": control / nsub, **make_kw})
    if agent is None:
        agent = served.default_agent(env)
    try:
        policy = load_policy(agent, env)
        config = LinkConfig(
            nmea_destinations=tuple(nmea),
            json_bind=json_bind,
            json_static_destinations=tuple(listen_only),
            allow_remote=allow_remote,
            failsafe=failsafe,
            token=token,
        )
        try:
            wrapped = UdpLinkWrapper(
                env, config, agent_resume_s=agent_resume_s, clock="wall", min_service_interval_s=0.0
            )
        except OSError as exc:  # port taken, unknown host name, ...
            raise ValueError(
                f"cannot open the UDP link (JSON channel {_addr(json_bind)}): {exc.strerror or exc}"
            ) from None
    except BaseException:
        env.close()
        raise
    try:
        return _run(wrapped, served, policy, agent, time_factor, duration_s, seed, out, err)
    finally:
        wrapped.close()


def _banner(wrapped: Any, served: Any, agent: str, time_factor: float, out: TextIO) -> None:
    link: UdpLink = wrapped.link
    cfg = link.config
    base = wrapped.unwrapped
    ship = base.task.ship
    rate = 1.0 / base.config.control_interval_s
    p = lambda s: print(s, file=out, flush=True)  # noqa: E731
    p(
        f"vessel-gym serve: {served.title(wrapped)}, ship {ship.name}, control {rate:g} Hz, "
        f"time factor {time_factor:g}"
    )
    json_at = _addr(link.json_address)
    auth = ", token required" if cfg.token is not None else ""
    p(f"  JSON state/helm: listening on {json_at}{auth}")
    p(f"    join with: vessel-gym helm --server {json_at}   or   vessel-gym view --server {json_at}")
    if cfg.nmea_destinations:
        nmea = ", ".join(_addr(a) for a in cfg.nmea_destinations)
        p(f"  NMEA 0183 + AIS: sending to {nmea} at {cfg.nmea_rate_hz:g} Hz")
    else:
        p("  NMEA 0183 + AIS: off")
    views = ", ".join(_addr(a) for a in cfg.json_static_destinations) or "none"
    p(f"  listen-only viewers: {views}")
    tr = wrapped.traffic
    names = ", ".join(s.name for s in tr.specs) if tr is not None else ""
    p(f"  traffic: {tr.n} ship(s): {names}" if tr is not None else "  traffic: none")
    units = cfg.limits.assist
    if units:
        p("  thrusters/tugs on the helm: " + ", ".join(f"{u.name} ({u.kind})" for u in units))
    resume = (
        "stay until a panel commands again"
        if wrapped.agent_resume_s is None
        else f"then the agent after {wrapped.agent_resume_s:g} s"
    )
    p(
        f"  helm: agent {agent!r} until a helm panel takes it; failsafe {cfg.failsafe!r} after "
        f"{cfg.watchdog_s:g} s of silence, {resume}"
    )
    p(f"  state: up to 50 Hz per client (link tick {1e3 * LINK_TICK_S:g} ms), agent every control step")
    p("  Ctrl-C to stop.")


def helm_change_line(change: HelmChange, before: str, failsafe: str, agent_resume_s: float | None) -> str:
    """One line for a change of helm owner; ``before`` is who steered until then ("agent", "human", ...)."""

    def who(name: str, addr: Address | None) -> str:
        return f"{name or 'panel'!r} ({_addr(addr)})" if addr is not None else "nobody"

    if change.owner is not None:
        if before == "agent" or change.previous is None:
            source = "the agent"
        else:
            source = f"the failsafe after {who(change.previous_name, change.previous)}"
        return f"vessel-gym serve: helm taken by {who(change.owner_name, change.owner)} from {source}"
    then = (
        "until a panel takes it" if agent_resume_s is None else f"then the agent after {agent_resume_s:g} s"
    )
    reason = _RELEASE_TEXT.get(change.reason, change.reason)
    return (
        f"vessel-gym serve: helm released by {who(change.previous_name, change.previous)} ({reason}); "
        f"failsafe {failsafe!r}, {then}"
    )


class _Ticker:
    """Paces one control step of the physics to wall-clock time in link ticks (the environment's declared
    pacing hook, :meth:`ShipEnv.pace <vessel_gym.envs.env.ShipEnv.pace>`).

    The environment runs the control interval's physics in ``ticks`` slices; after slice i (its
    ``i * nsub // ticks`` steps made) :meth:`on_tick` waits for the tick's deadline and services the link, so the
    state a client gets is the state of the physics at that moment.
    """

    def __init__(self, wrapped: Any, time_factor: float, report: Any) -> None:
        control = wrapped.unwrapped.config.control_interval_s
        self.ticks = link_ticks(control, time_factor)
        self.pacer = RealTimePacer(self.ticks / control, time_factor)
        self.wrapped = wrapped
        self.report = report

    def on_tick(self, i: int) -> None:
        self.pacer.wait()
        if i < self.ticks:  # the last tick's service is the next step's own (UdpLinkWrapper.step)
            self.wrapped.service()
            self.report()


def _run(
    wrapped: Any,
    served: Any,
    policy: Any,
    agent: str,
    time_factor: float,
    duration_s: float | None,
    seed: int | None,
    out: TextIO,
    err: TextIO,
) -> int:
    link: UdpLink = wrapped.link
    steered = [wrapped.steered_by]

    def report() -> None:
        for change in link.pop_helm_changes():
            line = helm_change_line(change, steered[0], link.config.failsafe, wrapped.agent_resume_s)
            print(line, file=err, flush=True)
        steered[0] = wrapped.steered_by

    ticker = _Ticker(wrapped, time_factor, report)
    pacer = ticker.pacer
    wrapped.unwrapped.pace(ticker.ticks, ticker.on_tick)  # the physics and the link in ticks, paced
    start = time.monotonic()
    episode = 1
    try:
        # Compile (or load) every kernel the loop calls before saying "Ctrl-C to stop": a Ctrl-C that lands
        # inside a first compilation cannot be caught cleanly. The episode then starts afresh.
        obs, _info = wrapped.reset(seed=seed)
        policy(obs)
        if wrapped.traffic is not None:
            wrapped.traffic.step(1)
        _banner(wrapped, served, agent, time_factor, out)
        start = time.monotonic()
        obs, info = wrapped.reset(seed=seed)
        served.started(info)
        policy.reset()
        by_start = dict(wrapped.steps_by)
        pacer.reset()
        while duration_s is None or time.monotonic() - start < duration_s:
            action = policy(obs)
            obs, _r, terminated, truncated, info = wrapped.step(action)
            report()
            if terminated or truncated:
                by = {k: v - by_start[k] for k, v in wrapped.steps_by.items()}
                time_limit = truncated and not terminated
                line = outcome_line(episode, info, time_limit, by, served.figures(info))
                print(line, file=out, flush=True)
                outcome = (
                    "time_limit" if time_limit and info.get("outcome") == "running" else info.get("outcome")
                )
                for text in served.debrief(wrapped, info, str(outcome), sum(by.values())):
                    print(text, file=out, flush=True)
                episode += 1
                obs, info = wrapped.reset()
                served.started(info)
                policy.reset()
                by_start = dict(wrapped.steps_by)
    except KeyboardInterrupt:
        pass
    stats = wrapped.link.stats()
    late = pacer.stats()
    print(
        f"vessel-gym serve: stopped after {time.monotonic() - start:.1f} s, {episode - 1} episode(s) finished; "
        f"sent {stats['tx_state']} states, {stats['tx_nmea_datagrams']} NMEA datagrams; "
        f"helm takeovers {stats['helm_takeovers']}; pacing late p99 {late['late_p99_ms']:.1f} ms, "
        f"skipped {late['skipped']}",
        file=out,
        flush=True,
    )
    return 0


__all__ = ["LINK_TICK_S", "helm_change_line", "link_ticks", "outcome_line", "physics_steps", "serve"]
