"""UDP floods against a live ``vessel-gym serve``: does the served ship keep real time and the helm panel its helm?

    python benchmarks/bench_udp_flood.py              # about 2 min (root for the forged-source phase)
    python benchmarks/bench_udp_flood.py --phase 8    # seconds per phase

``serve harbour`` runs at time factor 1 in its own process; a helm panel (``ServerConnection``, 20 Hz state,
20 Hz commands) in this process takes the helm and records every state it receives. Each phase runs one attack
from a separate process (each attacker has a core of its own to fill on this 2-core machine, as a real one would):

- ``baseline``: no attack.
- ``forged 5000/s``: helm commands and hellos with the panel's exact source address and port, 5000 datagrams/s,
  sent through a raw socket (root only; skipped otherwise).
- ``fresh sockets``: a new socket (new source port) per hello, as fast as one process can.
- ``256 sockets``: 256 sockets sending stats requests round robin, as fast as one process can.
- ``padded hellos``: 256 sockets sending hellos padded to the 2048-byte limit, as fast as one process can.
- ``squatters``: 16 registered clients from three hosts (127.0.0.2-4) hold every slot, then the panel rejoins.

Figures per phase: the attacker's send rate; the real-time factor of the served ship (simulated seconds of the
states received / wall-clock seconds, over the phase); the states/s the panel received and its longest gap; the
share of the phase during which the panel owned the helm and how often it lost it.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import socket
import struct
import sys
import time

from vessel_gym.net import protocol as P
from vessel_gym.net.clients import ServerConnection

HOST = "127.0.0.1"


def _serve_process(port: int, duration_s: float) -> None:
    import io

    from vessel_gym.net.serve import serve

    serve("harbour", json_bind=(HOST, port), nmea=[], duration_s=duration_s, seed=0, out=io.StringIO(),
          err=io.StringIO())  # fmt: skip


def _spoofed(src: tuple[str, int], dst: tuple[str, int], payload: bytes) -> bytes:
    udp = struct.pack("!HHHH", src[1], dst[1], 8 + len(payload), 0) + payload
    ip = struct.pack("!BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0, 64, socket.IPPROTO_UDP, 0,
                     socket.inet_aton(src[0]), socket.inet_aton(dst[0]))  # fmt: skip
    return ip + udp


def _attack(kind: str, port: int, seconds: float, src_port: int, sent: mp.Value) -> None:
    dst = (HOST, port)
    end = time.monotonic() + seconds
    n = 0
    if kind == "forged":
        raw = socket.socket(socket.AF_INET, socket.SOCK_RAW, socket.IPPROTO_RAW)
        helm = {"v": 1, "type": "helm", "rudder_order_deg": 35.0, "telegraph": 4}
        packets = [_spoofed((HOST, src_port), dst, P.encode_hello("helm"))]
        packets += [_spoofed((HOST, src_port), dst, json.dumps({**helm, "seq": 2**53 - 1 - k}).encode())
                    for k in range(49)]  # fmt: skip
        t = time.monotonic()
        while t < end:  # 50 datagrams per 10 ms
            for p in packets:
                raw.sendto(p, (HOST, 0))
            n += len(packets)
            t += 0.01
            time.sleep(max(0.0, t - time.monotonic()))
        raw.close()
    elif kind == "fresh":
        hello = P.encode_hello("viewer")
        while time.monotonic() < end:
            for _ in range(100):
                s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
                try:
                    s.sendto(hello, dst)
                    n += 1
                except OSError:
                    pass
                s.close()
    else:
        data = (
            P.encode_stats_request()
            if kind == "sockets"
            else json.dumps({"v": 1, "type": "hello", "role": "helm", "pad": "." * 1980}).encode()
        )
        socks = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(256)]
        for s in socks:
            s.setblocking(False)
        while time.monotonic() < end:
            for s in socks:
                try:
                    s.sendto(data, dst)
                    n += 1
                except OSError:  # the send buffer is full: that is as fast as it goes
                    pass
        for s in socks:
            s.close()
    sent.value = n


def _squat(port: int, seconds: float, ready: mp.Event) -> None:
    conns = [ServerConnection((HOST, port), "viewer", 1.0) for _ in range(16)]
    for k, c in enumerate(conns):  # rebind on three loopback hosts: 6 + 5 + 5 slots
        c.sock.close()
        c.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        c.sock.setblocking(False)
        c.sock.bind((f"127.0.0.{2 + k % 3}", 0))
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        now = time.monotonic()
        for c in conns:
            c.keepalive(now)
            c.poll(now)
        if not ready.is_set() and all(c.session for c in conns):
            ready.set()
        time.sleep(0.01)


class Panel:
    """The legitimate helm panel: 20 Hz commands, records (wall time, t_s, owns helm) of every new state."""

    def __init__(self, port: int) -> None:
        self.conn = ServerConnection((HOST, port), "helm", 20.0, name="panel")
        self._next_cmd = 0.0
        self._k = 0

    def server_counters(self) -> dict[str, int]:
        """The server's counters, asked for in this panel's session (steering on meanwhile)."""
        c = self.conn
        self.run(1.1)  # one stats reply per second at most: let a second pass since the last request
        c.stats = None
        c._sendto(P.encode_stats_request(c.session))
        self.run(0.5)
        return dict(c.stats["counters"]) if c.stats else {}

    def rejoin(self) -> None:
        self.conn.session = self.conn.cookie = None
        self.conn.hello()

    def run(self, seconds: float) -> list[tuple[float, float, bool]]:
        c, rows = self.conn, []
        end = time.monotonic() + seconds
        while (now := time.monotonic()) < end:
            c.keepalive(now)
            before = c.states_received
            c.poll(now)
            if c.states_received > before and c.state is not None:
                rows.append((now, float(c.state["t_s"]), c.owns_helm))
            if now >= self._next_cmd:
                self._next_cmd = now + 0.05
                self._k += 1
                c.send_helm(10.0 if self._k // 40 % 2 else -10.0, telegraph=2)
            time.sleep(0.002)
        return rows


def summary(name: str, seconds: float, sent: int, rows: list[tuple[float, float, bool]], rx: int) -> str:
    read = f"{rx / seconds / 1000:5.1f} k/s" if rx >= 0 else "    ? k/s"  # no counters: no stats reply
    rate = f"sent {sent / seconds / 1000:6.1f} k/s, read {read}"
    if len(rows) < 2:
        return f"  {name:<16} {rate}  no state received"
    sim = sum(b[1] - a[1] for a, b in zip(rows, rows[1:]) if 0.0 < b[1] - a[1] < 2.0)
    wall = rows[-1][0] - rows[0][0]
    gaps = max(b[0] - a[0] for a, b in zip(rows, rows[1:]))
    owned = [o for _, _, o in rows]
    lost = sum(1 for a, b in zip(owned, owned[1:]) if a and not b)
    return (
        f"  {name:<16} {rate}  real time {sim / wall:5.3f}x  state {len(rows) / seconds:5.1f}/s  "
        f"longest gap {gaps:5.2f} s  helm owned {100.0 * sum(owned) / len(owned):5.1f} %  lost {lost}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--phase", type=float, default=10.0, help="seconds per attack phase")
    args = parser.parse_args()
    root = hasattr(os, "geteuid") and os.geteuid() == 0
    phases = ["baseline", "forged", "fresh", "sockets", "padded", "squatters"]
    if not root:
        phases.remove("forged")
    ctx = mp.get_context("spawn")
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind((HOST, 0))
        port = s.getsockname()[1]
    warmup_s = 30.0  # imports, numba cache load, the first episode's reset
    # each phase also spends ~1.6 s asking for counters; the squatters need up to 8 s to register
    total = warmup_s + len(phases) * (args.phase + 2.0) + 20.0
    server = ctx.Process(target=_serve_process, args=(port, total))
    server.start()
    panel = Panel(port)
    rows = panel.run(warmup_s)
    if not rows:
        sys.exit("the served ship sent no state during the warm-up")
    panel.run(1.0)
    src_port = panel.conn.sock.getsockname()[1]
    labels = {"forged": "forged 5000/s", "fresh": "fresh sockets", "sockets": "256 sockets",
              "padded": "padded hellos", "squatters": "squatters"}  # fmt: skip
    print(f"serve harbour at time factor 1; {args.phase:.0f} s per phase; {os.cpu_count()} cores")
    before = panel.server_counters()
    for phase in phases:
        sent = ctx.Value("q", 0)
        if phase == "baseline":
            rows = panel.run(args.phase)
        elif phase == "squatters":
            ready = ctx.Event()
            attacker = ctx.Process(target=_squat, args=(port, args.phase + 8.0, ready))
            attacker.start()
            ready.wait(8.0)
            panel.rejoin()  # a newcomer while every slot is taken
            rows = panel.run(args.phase)
            attacker.join()
        else:
            attacker = ctx.Process(target=_attack, args=(phase, port, args.phase, src_port, sent))
            attacker.start()
            rows = panel.run(args.phase)
            attacker.join()
        after = panel.server_counters()
        rx = after.get("rx_datagrams", 0) - before.get("rx_datagrams", 0) if after and before else -1
        before = after
        print(summary(labels.get(phase, phase), args.phase, sent.value, rows, rx), flush=True)
    panel.conn.close()
    server.join()


if __name__ == "__main__":
    main()
