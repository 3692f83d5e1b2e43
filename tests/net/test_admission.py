"""Admission of the UDP link under floods: rates by session, unverified budgets, O(1) tables, bounded reads and
slots that one host cannot squat (docs/protocol.md section 4).

A "forged" datagram with a client's address is sent from that client's own socket (to the server it is the same
as a spoofed source); the last test spoofs the source for real with a raw socket when run as root.
"""

from __future__ import annotations

import json
import os
import socket
import struct
import time

import pytest

from vessel_gym.net import protocol as P
from vessel_gym.net.access import IDLE_EVICT_S, MAX_RATE_HOSTS, Access, Client, TokenBucket
from vessel_gym.net.link import LinkConfig, UdpLink

from .helpers import Peer, make_reading

SETTLE_S = 0.003


def _link(**kw) -> UdpLink:
    kw.setdefault("json_bind", ("127.0.0.1", 0))
    kw.setdefault("nmea_destinations", ())
    return UdpLink(LinkConfig(**kw))


def _forged_helm(seq: int) -> bytes:
    return json.dumps({"v": 1, "type": "helm", "seq": seq, "rudder_order_deg": 35.0, "telegraph": 4}).encode()


# -- the pieces -----------------------------------------------------------------------------------------------


def test_token_bucket_allows_its_rate_with_bursts_of_one_second():
    b = TokenBucket(100.0, 0.0)
    assert sum(b.take(100.0, 0.0) for _ in range(150)) == 100  # the burst: one second's worth
    assert sum(b.take(100.0, 0.5) for _ in range(100)) == 50  # then the rate
    assert not b.take(100.0, 0.4)  # a clock that went back adds nothing


def test_fresh_source_ports_of_one_host_share_its_unverified_bucket():
    access = Access(None, 200.0, 16, 8, unverified_rate_per_host_hz=100.0, unverified_rate_total_hz=1000.0)
    admitted = sum(access.admit(("10.0.0.1", 1024 + k), b"{}", 0.0) for k in range(1000))
    assert admitted == 100  # a new socket per datagram buys no new allowance


def test_unverified_traffic_of_all_hosts_shares_one_budget_and_the_host_table_is_bounded():
    access = Access(None, 200.0, 16, 8, unverified_rate_per_host_hz=100.0, unverified_rate_total_hz=1000.0)
    hosts = [f"10.{k >> 16 & 255}.{k >> 8 & 255}.{k & 255}" for k in range(3 * MAX_RATE_HOSTS)]
    admitted = sum(access.admit((h, 9), b"{}", 0.0) for h in hosts)
    assert admitted == 1000
    assert len(access._hosts) == MAX_RATE_HOSTS  # least recently heard hosts are forgotten, O(1) each
    # a host refused by the shared budget keeps its own token: it is not charged for what it could not send
    assert access._hosts[hosts[-1]].tokens == 100.0


def test_a_datagram_with_its_clients_session_spends_the_clients_bucket_only():
    access = Access(None, 200.0, 16, 8, unverified_rate_per_host_hz=100.0, unverified_rate_total_hz=1000.0)
    addr = ("10.0.0.1", 5000)
    access.clients[addr] = Client("helm", 20.0, "", 0.0, 0.0, session="0123456789abcdef")
    forged = sum(access.admit(addr, b'{"type":"helm","session":"ffffffffffffffff"}', 0.0) for _ in range(500))
    own = sum(access.admit(addr, b'{"type":"helm","session":"0123456789abcdef"}', 0.0) for _ in range(500))
    assert (forged, own) == (100, 200)


def _clients(access: Access, host: str, n: int, last_seen: float = 0.0, port0: int = 1000) -> None:
    for k in range(n):
        client = Client("viewer", 10.0, "", last_seen + k * 1e-3, 0.0, session=f"s{k}")
        access.clients[(host, port0 + k)] = client


def test_a_full_registry_evicts_an_idle_client_first():
    access = Access(None, 200.0, 16, 8)
    _clients(access, "10.0.0.1", 8, last_seen=10.0)
    _clients(access, "10.0.0.2", 8, last_seen=10.0)
    access.clients[("10.0.0.2", 1003)].last_seen = 10.0 - 2 * IDLE_EVICT_S
    assert access.make_room("10.0.0.3", 10.0, owner=None) == ("10.0.0.2", 1003)


def test_a_full_registry_makes_room_from_the_host_over_its_fair_share():
    access = Access(None, 200.0, 16, 8)
    for k, host in enumerate(("10.0.0.1", "10.0.0.2", "10.0.0.3")):  # 16 slots squatted by three hosts
        _clients(access, host, (6, 5, 5)[k], last_seen=10.0)
    evict = access.make_room("10.0.0.4", 10.1, owner=None)
    assert evict == ("10.0.0.1", 1000)  # the most crowded host's longest-silent client
    owner = ("10.0.0.1", 1000)
    assert access.make_room("10.0.0.4", 10.1, owner=owner) == ("10.0.0.1", 1001)  # never the owner
    assert access.make_room("10.0.0.1", 10.1, owner=None) is False  # a host within the shares takes nothing


def test_a_host_at_its_limit_cannot_evict_others():
    access = Access(None, 200.0, 16, 4)
    _clients(access, "10.0.0.1", 4)
    assert access.make_room("10.0.0.1", 0.0, owner=None) is False


# -- on the socket ------------------------------------------------------------------------------------------------


def test_forged_datagrams_with_the_owners_address_cannot_lock_it_out(peers):
    """5000 forged datagrams per second with the helm panel's address (the attack that took 1 s to win before)."""
    with _link() as link:
        owner = peers()
        owner.join(link.json_address, lambda: link.service(0.0, make_reading()), "helm", 20.0)
        dt, seq, states = 0.02, 0, 0
        for k in range(150):  # 3 s of link time at 50 Hz
            for j in range(100):  # 5000 per second: forged helm commands and hellos in the owner's name
                forged = _forged_helm(10**9 + k * 100 + j) if j % 2 else P.encode_hello("helm")
                owner.send(link.json_address, forged)
            if k % 2 == 0:  # the panel's own 25 Hz commands, in its session
                seq += 1
                owner.helm(link.json_address, seq, -5.0, telegraph=2)
            time.sleep(SETTLE_S)
            h = link.service(k * dt, make_reading())
            time.sleep(SETTLE_S)
            states += len(owner.messages("state"))  # read as a panel does, so its socket buffer never fills
        s = link.stats()
        assert h.owner == owner.address and h.helm_ok and (h.rudder_order_deg, h.telegraph) == (-5.0, 2)
        assert s["helm_takeovers"] == 1 and s["helm_watchdog"] == 0 and h.seq == seq
        assert s["drop_rate_limited"] > 10_000  # the forgeries spent the unverified budget, not the panel's
        assert states >= 0.95 * 3 * 20  # and it kept getting its 20 Hz state


def test_a_newcomer_joins_while_another_host_floods_unverified_hellos():
    """A flood of hellos (5000/s) from one host spends that host's unverified bucket: a client from another
    host still joins at its first tries, and the flood is dropped unread."""
    with _link() as link:
        flooder, newcomer = Peer("127.0.0.1"), Peer("127.0.0.9")
        clock = [0.0]
        hello = P.encode_hello("viewer")

        def pump() -> None:
            for _ in range(50):  # 50 per 10 ms of link time
                flooder.send(link.json_address, hello)
            time.sleep(SETTLE_S)
            clock[0] += 0.01
            link.service(clock[0], make_reading())

        try:
            for _ in range(100):  # one second of flood before the newcomer says hello
                pump()
            newcomer.join(link.json_address, pump, tries=4)
            assert [c["address"] for c in link.clients] == [newcomer.address]
            assert link.stats()["drop_rate_limited"] > 3000
        finally:
            flooder.close()
            newcomer.close()


def test_a_read_stops_at_its_datagram_budget(peers):
    with _link(max_datagrams_per_call=64) as link:
        flooder = peers()
        for _ in range(200):
            flooder.send(link.json_address, b"x")
        time.sleep(SETTLE_S)
        link.service(0.0, make_reading())
        s = link.stats()
        assert s["rx_datagrams"] == 64 and s["rx_budget_spent"] == 1


def test_a_read_stops_at_its_time_budget(peers):
    """However many datagrams wait, one service() call reads for about max_receive_ms (here 0.1 ms: a few
    dozen datagrams, far below the count budget), so a flood cannot hold the simulation's tick."""
    with _link(max_receive_ms=0.1, max_datagrams_per_call=2048) as link:
        flooder = peers()
        hello = P.encode_hello("viewer")
        for _ in range(3000):
            flooder.send(link.json_address, hello)
        time.sleep(SETTLE_S)
        link.service(0.0, make_reading())
        s = link.stats()
        assert 0 < s["rx_datagrams"] < 1000 and s["rx_budget_spent"] == 1


def test_three_hosts_squatting_every_slot_cannot_lock_a_fourth_out():
    with _link(max_clients=16, max_clients_per_host=8) as link:
        pump = lambda: link.service(0.0, make_reading())  # noqa: E731
        squatters = [Peer(f"127.0.0.{2 + k // 6}") for k in range(16)]  # 6 + 6 + 4 slots
        newcomer = Peer("127.0.0.9")
        try:
            for p in squatters:
                p.join(link.json_address, pump)
            assert len(link.clients) == 16
            newcomer.join(link.json_address, pump)  # raises if it never gets a session
            addresses = [c["address"] for c in link.clients]
            assert newcomer.address in addresses and len(addresses) == 16
            assert link.stats()["clients_evicted"] == 1
            assert sum(a[0] == "127.0.0.2" for a in addresses) == 5  # taken from a most crowded host
        finally:
            for p in squatters + [newcomer]:
                p.close()


# -- a spoofed source, for real -------------------------------------------------------------------------------


def _spoofed_udp(src: tuple[str, int], dst: tuple[str, int], payload: bytes) -> bytes:
    """An IPv4 + UDP packet (IP checksum and length are filled in by Linux for IP_HDRINCL; UDP checksum 0 = none)."""
    udp = struct.pack("!HHHH", src[1], dst[1], 8 + len(payload), 0) + payload
    ip = struct.pack(
        "!BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0, 64, socket.IPPROTO_UDP, 0,
        socket.inet_aton(src[0]), socket.inet_aton(dst[0]),
    )  # fmt: skip
    return ip + udp


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="raw sockets need root")
def test_raw_socket_forged_source_cannot_take_or_keep_the_helm(peers):
    with _link() as link:
        owner = peers()
        owner.join(link.json_address, lambda: link.service(0.0, make_reading()), "helm", 20.0)
        owner.helm(link.json_address, 1, 3.0, telegraph=1)
        time.sleep(SETTLE_S)
        assert link.service(0.02, make_reading()).owner == owner.address
        raw = socket.socket(socket.AF_INET, socket.SOCK_RAW, socket.IPPROTO_RAW)
        try:
            for k in range(100):  # 5000/s for 2 s, each with the owner's exact address and a huge seq
                for j in range(100):
                    packet = _spoofed_udp(owner.address, link.json_address, _forged_helm(2**53 - 1 - j))
                    raw.sendto(packet, (link.json_address[0], 0))
                if k % 2 == 0:
                    owner.helm(link.json_address, 2 + k, 3.0, telegraph=1)
                time.sleep(SETTLE_S)
                h = link.service(0.04 + 0.02 * k, make_reading())
        finally:
            raw.close()
        s = link.stats()
        assert s["rx_datagrams"] > 5000  # the spoofed packets did arrive, with the owner's address
        assert h.owner == owner.address and h.helm_ok and (h.rudder_order_deg, h.telegraph) == (3.0, 1)
        assert s["helm_watchdog"] == 0 and s["helm_takeovers"] == 1
