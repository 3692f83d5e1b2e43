"""Hostile input: random bytes and malicious JSON never raise, are all counted, and fit a 50 Hz budget."""

from __future__ import annotations

import json
import time

import numpy as np
import pytest

from vessel_gym.net import protocol as P
from vessel_gym.net.link import LinkConfig, UdpLink

from .helpers import Peer, drain, make_reading

BUDGET_S = 1.0 / 50.0  # one step of a 50 Hz loop
# service() is timed in CPU time of this thread, so that other processes on a busy machine cannot make the test
# fail; the work itself (parsing, counting, socket calls) is what must fit the budget.
_cpu = time.thread_time

_HOSTILE_VALUES = [
    "NaN",
    "Infinity",
    "-Infinity",
    "1e308",
    "-1e308",
    "1e309",
    "1e-400",
    "9" * 1500,
    "-" + "9" * 1000,
    "true",
    "false",
    "null",
    '"10"',
    '"\\ud800"',
    '"\\u0000"',
    "[]",
    "{}",
    "[" * 900 + "]" * 900,
    '{"a":' * 300 + "1" + "}" * 300,
    "0.1e1",
    "-0",
    "1E+2",
]
_KEYS = ["v", "type", "seq", "role", "rate_hz", "rudder_order_deg", "telegraph", "rpm_order", "name", "token"]
_TYPES = ['"hello"', '"helm"', '"bye"', '"stats_request"', '"state"', '"HELM"', "1", "null"]


def hostile_datagrams(n: int, seed: int = 0) -> list[bytes]:
    """n datagrams: random bytes, hostile JSON documents, mutated valid messages, oversized and bad UTF-8."""
    rng = np.random.default_rng(seed)
    valid = [
        P.encode_hello("helm", 20.0, "fuzz"),
        P.encode_hello("viewer", 50.0),
        P.encode_helm(5, 10.0, telegraph=2),
        P.encode_helm(6, -35.0, rpm_order=80.0),
        P.encode_bye(),
        P.encode_stats_request(),
    ]
    out: list[bytes] = []
    for _ in range(n):
        kind = int(rng.integers(0, 7))
        if kind == 0:  # random bytes
            out.append(rng.bytes(int(rng.integers(0, 2100))))
        elif kind == 1:  # a JSON object of hostile values under real keys
            fields = [f'"{k}":{_HOSTILE_VALUES[int(rng.integers(len(_HOSTILE_VALUES)))]}' for k in _KEYS]
            fields[0] = '"v":1' if rng.random() < 0.7 else fields[0]
            fields[1] = f'"type":{_TYPES[int(rng.integers(len(_TYPES)))]}'
            chosen = [f for f in fields if rng.random() < 0.7]
            out.append(("{" + ",".join(chosen) + "}").encode())
        elif kind == 2:  # a valid message with random bytes flipped
            data = bytearray(valid[int(rng.integers(len(valid)))])
            for _ in range(int(rng.integers(1, 4))):
                data[int(rng.integers(len(data)))] = int(rng.integers(0, 256))
            out.append(bytes(data))
        elif kind == 3:  # oversized
            out.append(b"{" + b'"x":1,' * int(rng.integers(350, 700)) + b'"v":1}')
        elif kind == 4:  # bad UTF-8 inside otherwise fine JSON
            out.append(b'{"v":1,"type":"hello","role":"viewer","name":"' + rng.bytes(8) + b'\xc0\xaf"}')
        elif kind == 5:  # not an object / wrong version
            out.append(rng.choice([b"[]", b"null", b"42", b'"x"', b'{"v":2,"type":"bye"}', b'{"v":true}']))
        else:  # a valid message (some with stale or huge seq)
            seq = int(rng.choice([0, 1, 2**53 - 1, int(rng.integers(0, 1000))]))
            msg = {
                "v": 1,
                "type": "helm",
                "seq": seq,
                "rudder_order_deg": float(rng.normal(0, 100)),
                "telegraph": 9,
            }
            out.append(rng.choice([json.dumps(msg).encode(), *valid]))
    return out


@pytest.mark.parametrize(
    ("n", "seed"), [(20_000, 1), pytest.param(100_000, 5, marks=pytest.mark.slow, id="100k")]
)
def test_parser_never_raises_anything_but_protocol_error(n, seed):
    datagrams = hostile_datagrams(n, seed=seed)
    reasons: dict[str, int] = {}
    accepted = 0
    for data in datagrams:
        try:
            msg = P.parse_datagram(data)
        except P.ProtocolError as exc:
            reasons[exc.reason] = reasons.get(exc.reason, 0) + 1
            continue
        accepted += 1
        assert isinstance(msg, (P.Hello, P.HelmCommand, P.Bye, P.StatsRequest))
        if isinstance(msg, P.HelmCommand):
            assert -35.0 <= msg.rudder_order_deg <= 35.0
            assert msg.telegraph is None or -4 <= msg.telegraph <= 4
        if isinstance(msg, P.Hello):
            assert 1.0 <= msg.rate_hz <= 50.0
    assert accepted + sum(reasons.values()) == len(datagrams)
    assert set(reasons) == set(P.REASONS)  # every rejection path was exercised
    assert accepted > n // 100


def test_link_survives_10k_hostile_datagrams_within_a_50hz_budget(peers):
    datagrams = hostile_datagrams(10_000, seed=2)
    viewer = peers()
    fuzzers = [Peer() for _ in range(4)]
    link = UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=()))
    try:
        reading = make_reading()
        viewer.join(link.json_address, lambda: link.service(0.0, reading), "viewer", 50.0)
        viewer_sent = 2  # the two hellos of the handshake
        durations = []
        sent = 0
        i = 0
        t = 0.0
        while i < len(datagrams):
            # A batch small enough for the default socket receive buffer, sent from several source ports.
            batch_bytes = 0
            while i < len(datagrams) and batch_bytes < 48_000:
                data = datagrams[i]
                fuzzers[i % len(fuzzers)].send(link.json_address, data)
                batch_bytes += len(data) + 512
                sent += 1
                i += 1
            time.sleep(0.0005)
            start = _cpu()
            link.service(t, reading)
            durations.append(_cpu() - start)
            t += BUDGET_S
            if int(t) != int(t - BUDGET_S):
                viewer.hello(link.json_address, "viewer", 50.0)
                viewer_sent += 1
        for _ in range(5):  # drain anything still in flight
            time.sleep(0.002)
            link.service(t, reading)
            t += BUDGET_S
        stats = link.stats()
        drops = sum(v for k, v in stats.items() if k.startswith("drop_"))
        assert sent == 10_000
        assert stats["rx_datagrams"] == sent + viewer_sent  # nothing lost, nothing uncounted
        assert stats["rx_datagrams"] == stats["rx_accepted"] + drops
        assert drops > 8000
        assert stats["rx_error"] == 0 and stats["encode_error"] == 0 and stats["tx_error"] == 0
        assert stats["tx_state"] > 0.9 * len(durations)  # the viewer was served all along
        durations = np.array(durations)
        assert durations.max() < BUDGET_S, f"slowest service() took {durations.max() * 1e3:.1f} ms"
        assert np.median(durations) < BUDGET_S / 5
    finally:
        link.close()
        for f in fuzzers:
            f.close()


def test_a_full_receive_budget_of_garbage_fits_one_step():
    link = UdpLink(LinkConfig(json_bind=("127.0.0.1", 0), nmea_destinations=(), max_datagrams_per_call=256))
    fuzzer = Peer()
    try:
        rng = np.random.default_rng(3)
        junk = [b'{"v":1,"type":"helm","x":[' + b"1," * 1000 + b"NaN]}"] * 40
        junk += [rng.bytes(1500) for _ in range(40)]
        junk += [b"[" * 2000 for _ in range(40)]
        for data in junk:
            fuzzer.send(link.json_address, data)
        time.sleep(0.005)
        start = _cpu()
        link.service(0.0, make_reading())
        elapsed = _cpu() - start
        assert elapsed < BUDGET_S  # the call stops at its time budget (max_receive_ms), whatever waits
        stats = drain(link, len(junk), 0.001)  # the rest is read by the next calls
        assert stats["rx_datagrams"] == len(junk) and stats["rx_accepted"] == 0
    finally:
        link.close()
        fuzzer.close()
