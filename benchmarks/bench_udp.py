"""UDP link benchmark: service() cost, a live 50 Hz loop with peers, and wall-clock pacing lateness.

    python benchmarks/bench_udp.py            # about 20 s
    python benchmarks/bench_udp.py --quick    # about 5 s

Figures printed:

1. ``service()`` cost per call with no peers (median of 7 runs of 20000 calls, injected 50 Hz time): with the NMEA
   channel off, with the default 2 Hz NMEA stream, and with 10 Hz NMEA plus AIS for 5 targets.
2. A 50 Hz loop paced to wall-clock time for ``--duration`` s with one helm panel (20 Hz commands) and three
   viewers (10, 20 and 50 Hz) in a separate process: median and p99 of the service() time, and the CPU used by
   the loop's process as a share of one core.
3. Lateness p50/p99 of a 20 Hz RealTimePacer loop over ``--pacing`` s.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import socket
import sys
import time
from pathlib import Path

import numpy as np

try:
    import vessel_gym  # noqa: F401
except ImportError:  # running from a source checkout without installing
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from vessel_gym.net import protocol as P
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


def _clients(server: tuple[str, int], duration_s: float) -> None:
    """One helm panel at 20 Hz and viewers at 10/20/50 Hz, keep-alive every 0.5 s, draining their sockets."""
    socks = []
    for role, rate in (("helm", 20.0), ("viewer", 10.0), ("viewer", 20.0), ("viewer", 50.0)):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.setblocking(False)
        s.bind(("127.0.0.1", 0))
        socks.append((s, P.encode_hello(role, rate)))
    helm = socks[0][0]
    start = time.monotonic()
    next_hello = next_helm = start
    seq = 0
    while time.monotonic() - start < duration_s:
        now = time.monotonic()
        if now >= next_hello:
            for s, hello in socks:
                s.sendto(hello, server)
            next_hello += 0.5
        if now >= next_helm:
            seq += 1
            helm.sendto(P.encode_helm(seq, 10.0 * np.sin(now), telegraph=3), server)
            next_helm += 0.05
        for s, _ in socks:
            while True:
                try:
                    s.recv(65536)
                except BlockingIOError:
                    break
        time.sleep(0.005)
    for s, _ in socks:
        s.close()


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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=5.0, help="live 50 Hz loop length, s")
    parser.add_argument("--pacing", type=float, default=10.0, help="20 Hz pacing run length, s")
    parser.add_argument("--quick", action="store_true", help="short runs (2 s loop, 2 s pacing)")
    args = parser.parse_args()
    if args.quick:
        args.duration, args.pacing = 2.0, 2.0

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


if __name__ == "__main__":
    main()
