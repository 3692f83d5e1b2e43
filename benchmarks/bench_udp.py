"""UDP link benchmark: service() cost, a live 50 Hz loop with peers, and wall-clock pacing lateness.

    python benchmarks/bench_udp.py            # about 1 min
    python benchmarks/bench_udp.py --quick    # about 20 s

Figures printed:

1. ``service()`` cost per call with no peers (median of 7 runs of 20000 calls, injected 50 Hz time): with the NMEA
   channel off, with the default 2 Hz NMEA stream, and with 10 Hz NMEA plus AIS for 5 targets.
2. A 50 Hz loop paced to wall-clock time for ``--duration`` s with one helm panel (20 Hz commands) and three
   viewers (10, 20 and 50 Hz) in a separate process: median and p99 of the service() time, and the CPU used by
   the loop's process as a share of one core.
3. Lateness p50/p99 of a 20 Hz RealTimePacer loop over ``--pacing`` s.
4. UdpLinkWrapper overhead: env.step() per CPU second (resets not counted) through ``gymnasium.make`` of each
   environment: bare, in an empty wrapper (the noise floor of the comparison) and in the UdpLinkWrapper (the same
   instance; no peers, NMEA off; interleaved blocks, median of ``--repeats``); the wrapper's own cost per step
   timed around an environment that costs nothing (the robust figure on a busy machine); and HarbourApproach
   steps per second with one helm panel (20 Hz commands), three viewers at 50 Hz and 2 Hz NMEA, without and
   with the scenario's traffic (simulated too, sent as AIS).
5. ``vessel-gym serve`` at time factor 1 (in a separate process) with viewers asking for 10, 20 and 50 Hz:
   the state rate each one receives over ``--rates`` s of wall-clock time, and how often the ``t_s`` it sees
   changes (the physics moves every 50 ms in the harbour, the agent every 250 ms).

All clients join with the cookie handshake of docs/protocol.md (``ServerConnection``).
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import socket
import time

import numpy as np

from vessel_gym.net import protocol as P
from vessel_gym.net.clients import ServerConnection
from vessel_gym.net.link import LinkConfig, UdpLink
from vessel_gym.net.pacing import RealTimePacer
from vessel_gym.physics.bridge import BridgeReading


def reading(t_s: float = 0.0) -> BridgeReading:
    return BridgeReading(
        t_s=t_s,
        x_m=1234.5 + 6.0 * t_s,
        y_m=-789.0,
        lat_deg=53.5412 + 6.0 * t_s / 111_000.0,
        lon_deg=9.9876,
        hdg_deg=123.4,
        cog_deg=124.9,
        sog_kn=12.3,
        stw_kn=12.0,
        stw_transverse_kn=-0.2,
        rot_dpm=-12.0,
        rudder_deg=-10.0,
        rudder_order_deg=-15.0,
        rpm=85.0,
        telegraph=3,
        wind_rel_angle_deg=40.0,
        wind_rel_speed_kn=15.0,
        wind_true_dir_deg=163.4,
        wind_true_speed_kn=11.0,
    )


def targets(n: int) -> list[P.Target]:
    return [
        P.Target(id=i, name=f"SHIP {i}", reading=reading(), length_m=200.0, beam_m=32.0, mmsi=211000000 + i)
        for i in range(n)
    ]


def sink_port() -> tuple[socket.socket, int]:
    """A bound UDP socket that nobody reads (so NMEA sends succeed without a consumer)."""
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", 0))
    return s, s.getsockname()[1]


def bench_service(label: str, config: LinkConfig, n_targets: int, calls: int = 20_000) -> None:
    own = reading()
    tg = targets(n_targets)
    runs = []
    with UdpLink(config) as link:
        for r in range(7):
            start = time.perf_counter()
            for k in range(calls):
                link.service((r * calls + k) * 0.02, own, tg)
            runs.append((time.perf_counter() - start) / calls)
    print(f"  {label:<44} {np.median(runs) * 1e6:7.2f} us/call (median of 7 x {calls})")


def _clients(
    server: tuple[str, int], duration_s: float, viewer_rates: tuple[float, ...] = (10.0, 20.0, 50.0)
) -> None:
    """One helm panel at 20 Hz and viewers at ``viewer_rates``, keep-alive every 0.5 s, draining their sockets."""
    conns = [ServerConnection(server, "helm", 20.0)]
    conns += [ServerConnection(server, "viewer", r) for r in viewer_rates]
    helm = conns[0]
    start = time.monotonic()
    next_helm = start
    while time.monotonic() - start < duration_s:
        now = time.monotonic()
        for c in conns:
            c.keepalive(now)
            c.poll(now)
        if now >= next_helm:
            helm.send_helm(10.0 * np.sin(now), telegraph=3)  # sent once the handshake gave a session
            next_helm += 0.05
        time.sleep(0.005)
    for c in conns:
        c.close()


def bench_live_loop(duration_s: float) -> None:
    sink, port = sink_port()
    config = LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=[("127.0.0.1", port)], nmea_rate_hz=10)
    with UdpLink(config) as link:
        proc = mp.get_context("fork").Process(target=_clients, args=(link.json_address, duration_s + 0.5))
        proc.start()
        tg = targets(3)
        pacer = RealTimePacer(50.0)
        times = []
        wall0, cpu0 = time.perf_counter(), time.process_time()
        t0 = time.monotonic()
        while time.monotonic() - t0 < duration_s:
            now = time.monotonic() - t0
            start = time.perf_counter()
            link.service(now, reading(now), tg)
            times.append(time.perf_counter() - start)
            pacer.wait()
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        proc.join()
        stats = link.stats()
    sink.close()
    t = np.array(times)
    print(f"  loop iterations                              {len(t)} in {wall:.1f} s ({len(t) / wall:.1f} Hz)")
    print(
        f"  service() time median / p99                  {np.median(t) * 1e6:.1f} / {np.percentile(t, 99) * 1e6:.1f} us"
    )
    print(f"  CPU of the loop process (incl. pacing)      {100.0 * cpu / wall:.2f} % of one core")
    print(
        f"  sent: {stats['tx_state']} states, {stats['tx_nmea_datagrams']} NMEA datagrams; "
        f"received {stats['rx_datagrams']} ({stats['rx_accepted']} accepted); helm_ok at end: {link.helm.helm_ok}"
    )


def bench_pacing(duration_s: float) -> None:
    with UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=())) as link:
        pacer = RealTimePacer(20.0)
        own = reading()
        for _ in range(int(duration_s * 20)):
            link.service(pacer.sim_time_s, own)
            pacer.wait()
        s = pacer.stats()
    print(f"  ticks {s['ticks']}, skipped {s['skipped']}")
    print(
        f"  lateness p50 / p99 / max                     "
        f"{s['late_p50_ms']:.3f} / {s['late_p99_ms']:.3f} / {s['late_max_ms']:.3f} ms"
    )


def _block(env, action, steps: int) -> float:
    """CPU seconds of this process per env.step() over ``steps`` steps, not counting resets at episode ends.

    CPU time rather than wall time: on a shared machine the time other processes take the core is not counted.
    """
    clock = time.process_time
    t0 = clock()
    for _ in range(steps):
        _o, _r, term, trunc, _i = env.step(action)
        if term or trunc:
            t1 = clock()
            env.reset()
            t0 += clock() - t1
    return (clock() - t0) / steps


def _zero_action(env):
    import gymnasium as gym

    space = env.action_space
    if isinstance(space, gym.spaces.Box):
        return np.zeros(space.shape, dtype=np.float32)
    return space.sample() * 0


class _PassThrough:
    """A wrapper that only forwards step() (and sets the same info key): the control of the comparison."""

    def __init__(self, env) -> None:
        self.env = env

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        info["helm"] = "agent"
        return obs, reward, terminated, truncated, info

    def reset(self, **kw):
        return self.env.reset(**kw)


class _NullEnv:
    """Stands in for the environment inside a wrapper to time the wrapper alone."""

    def step(self, action):
        return None, 0.0, False, False, {}


def bench_wrapper(repeats: int, block_steps: int, peers_s: float) -> None:
    import gymnasium as gym

    import vessel_gym.envs  # noqa: F401
    from vessel_gym.net.wrapper import UdpLinkWrapper

    no_peers = LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=())
    for env_id in ("vessel_gym/ZigZag-v1", "vessel_gym/TurningCircle-v0", "vessel_gym/HarbourApproach-v2"):
        wrapped = UdpLinkWrapper(gym.make(env_id), no_peers)
        bare = wrapped.env  # the same environment instance, stepped with and without the wrapper
        control = _PassThrough(bare)  # an empty wrapper: the noise floor of the comparison
        wrapped.reset(seed=0)
        action = _zero_action(bare)
        envs = {"bare": bare, "pass": control, "udp": wrapped}
        times: dict[str, list[float]] = {k: [] for k in envs}
        for e in envs.values():
            _block(e, action, block_steps)  # warm-up (compilation, caches)
        for r in range(repeats):
            for k in list(envs)[:: 1 if r % 2 == 0 else -1]:
                times[k].append(_block(envs[k], action, block_steps))
        tb, tp, tw = (float(np.median(times[k])) for k in envs)
        # the wrapper alone, around an environment that costs nothing
        wrapped.env, null = _NullEnv(), _NullEnv()
        own = []
        for _ in range(repeats):
            t_null = _block(null, action, 10 * block_steps)
            own.append(_block(wrapped, action, 10 * block_steps) - t_null)
        wrapped.env = bare
        t_own = float(np.median(own))
        name = env_id.split("/")[1]
        print(
            f"  {name:<18} bare {1.0 / tb:6.0f}, empty wrapper {1.0 / tp:6.0f} ({100.0 * (tp / tb - 1.0):+5.1f} %), "
            f"UdpLinkWrapper {1.0 / tw:6.0f} steps/s ({100.0 * (tw / tb - 1.0):+5.1f} %); "
            f"the wrapper alone {t_own * 1e6:.2f} us/step = {100.0 * t_own / tb:.1f} % of the bare step"
        )
        wrapped.close()

    print("  HarbourApproach + 1 helm (20 Hz) + 3 viewers at 50 Hz + NMEA 2 Hz, stepped as fast as it goes:")
    for traffic in (None, "auto"):
        _wrapper_with_peers(traffic, block_steps, peers_s)


def _wrapper_with_peers(traffic, block_steps: int, peers_s: float) -> None:
    import gymnasium as gym

    from vessel_gym.net.wrapper import UdpLinkWrapper

    sink, port = sink_port()
    config = LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=[("127.0.0.1", port)])
    wrapped = UdpLinkWrapper(gym.make("vessel_gym/HarbourApproach-v2"), config, traffic=traffic)
    bare = wrapped.env
    wrapped.reset(seed=0)
    action = _zero_action(bare)
    proc = mp.get_context("fork").Process(
        target=_clients, args=(wrapped.link.json_address, peers_s + 1.0, (50.0, 50.0, 50.0))
    )
    proc.start()
    time.sleep(0.5)  # let the clients register
    b, w = [], []
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < peers_s:
        b.append(_block(bare, action, block_steps))
        w.append(_block(wrapped, action, block_steps))
    proc.join()
    tb, tw = float(np.median(b)), float(np.median(w))
    stats = wrapped.link.stats()
    tr = wrapped.traffic
    label = f"with {tr.n} traffic ships (simulated too, AIS)" if tr is not None else "without traffic"
    print(
        f"    {label:<42} bare {1.0 / tb:6.0f} steps/s, wrapped {1.0 / tw:6.0f} steps/s "
        f"({100.0 * (tw / tb - 1.0):+4.0f} %); sent {stats['tx_state']} states, "
        f"{stats['tx_nmea_datagrams']} NMEA datagrams, accepted {stats['rx_accepted']}; helm: {wrapped.steered_by}"
    )
    wrapped.close()
    sink.close()


def _serve_process(port: int, duration_s: float) -> None:
    import io

    from vessel_gym.net.serve import serve

    serve("harbour", json_bind=("127.0.0.1", port), nmea=[], duration_s=duration_s, seed=0, out=io.StringIO())


def bench_serve_rates(duration_s: float, rates: tuple[float, ...] = (10.0, 20.0, 50.0)) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    warmup_s = 8.0  # imports, numba cache load and the handshake
    proc = mp.get_context("spawn").Process(target=_serve_process, args=(port, warmup_s + duration_s + 2.0))
    proc.start()
    conns = {r: ServerConnection(("127.0.0.1", port), "viewer", r) for r in rates}
    seen: dict[float, list[float]] = {r: [] for r in rates}
    start = time.monotonic()
    t_window = None
    while time.monotonic() - start < warmup_s + duration_s + 1.0:
        now = time.monotonic()
        for r, c in conns.items():
            c.keepalive(now)
            before = c.states_received
            c.poll(now)
            if c.states_received > before and t_window is not None and 0.0 <= now - t_window < duration_s:
                seen[r].append(float(c.state["t_s"]))
        if t_window is None and all(c.states_received > 0 for c in conns.values()):
            t_window = time.monotonic() + 0.5
        time.sleep(0.001)
    for c in conns.values():
        c.close()
    proc.join()
    for r in rates:
        ts = seen[r]
        changes = int(np.count_nonzero(np.diff(ts))) if len(ts) > 1 else 0
        print(
            f"  requested {r:4.0f} Hz: received {len(ts) / duration_s:5.1f} states/s, "
            f"t_s changed {changes / duration_s:5.1f} times/s"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=5.0, help="live 50 Hz loop length, s")
    parser.add_argument("--pacing", type=float, default=10.0, help="20 Hz pacing run length, s")
    parser.add_argument("--repeats", type=int, default=15, help="wrapper overhead: timing blocks per env")
    parser.add_argument("--rates", type=float, default=10.0, help="serve state-rate window, s")
    parser.add_argument(
        "--quick", action="store_true", help="short runs (2 s loop, 2 s pacing, 7 repeats, 4 s rates)"
    )
    args = parser.parse_args()
    block_steps, peers_s = 1000, 5.0
    if args.quick:
        args.duration, args.pacing, args.repeats, args.rates = 2.0, 2.0, 7, 4.0
        block_steps, peers_s = 500, 2.0

    print("1. service() with no peers")
    bind = ("127.0.0.1", 0)
    bench_service("NMEA off", LinkConfig(json_bind=bind, nmea_destinations=()), 0)
    sink, port = sink_port()
    dest = [("127.0.0.1", port)]
    bench_service("NMEA 2 Hz (default), amortised", LinkConfig(json_bind=bind, nmea_destinations=dest), 0)
    bench_service(
        "NMEA 10 Hz + AIS for 5 targets, amortised",
        LinkConfig(json_bind=bind, nmea_destinations=dest, nmea_rate_hz=10),
        5,
    )
    sink.close()
    print(f"2. 50 Hz loop with 1 helm + 3 viewers, NMEA 10 Hz, 3 targets, {args.duration:.0f} s")
    bench_live_loop(args.duration)
    print(f"3. 20 Hz pacing over {args.pacing:.0f} s")
    bench_pacing(args.pacing)
    print(f"4. UdpLinkWrapper overhead (no peers, NMEA off; median of {args.repeats} x {block_steps} steps)")
    bench_wrapper(args.repeats, block_steps, peers_s)
    print(f"5. serve at time factor 1: delivered state rate per viewer over {args.rates:.0f} s")
    bench_serve_rates(args.rates)


if __name__ == "__main__":
    main()
