"""End to end with a real consumer: our NMEA/AIS over UDP into gpsd, its JSON reports read back.

gpsd (Debian package ``gpsd``; 3.22 on Debian 12) runs in the foreground on free ports:
``gpsd -N -n -b -S <tcp> udp://127.0.0.1:<udp>``. The test is skipped only when the gpsd binary is absent.
gpsd checks position, COG/SOG, time, heading (HDT -> ATT) and AIS; it has no output for ROT, RSA or RPM, which
the pynmea2 tests cover.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import time
from datetime import datetime, timedelta, timezone

import pytest

from vessel_gym.net import protocol as P
from vessel_gym.net.link import LinkConfig, UdpLink
from vessel_gym.physics.units import KNOT_M_S

from .helpers import free_tcp_port, free_udp_port, make_reading, moved

pytestmark = pytest.mark.gpsd

EPOCH = datetime(2021, 6, 1, 12, 0, 0, tzinfo=timezone.utc)
RATE_HZ = 10.0
CYCLES = 8


def _gpsd_binary() -> str | None:
    found = shutil.which("gpsd")
    if found:
        return found
    return "/usr/sbin/gpsd" if os.access("/usr/sbin/gpsd", os.X_OK) else None


class Gpsd:
    """A gpsd process reading one UDP port, and a JSON watch connection to it."""

    def __init__(self, binary: str) -> None:
        self.proc: subprocess.Popen | None = None
        self.conn: socket.socket | None = None
        for _ in range(3):  # a port taken between probing and gpsd's bind: try fresh ports
            self.udp_port, tcp_port = free_udp_port(), free_tcp_port()
            self.proc = subprocess.Popen(
                [binary, "-N", "-n", "-b", "-S", str(tcp_port), f"udp://127.0.0.1:{self.udp_port}"],
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
            deadline = time.monotonic() + 3.0
            while time.monotonic() < deadline and self.proc.poll() is None:
                try:
                    self.conn = socket.create_connection(("127.0.0.1", tcp_port), timeout=0.2)
                    break
                except OSError:
                    time.sleep(0.02)
            if self.conn is not None:
                break
            self.stop()
        if self.conn is None:
            raise RuntimeError("gpsd did not start")
        self.conn.sendall(b'?WATCH={"enable":true,"json":true,"scaled":true};\n')
        self.conn.settimeout(0.02)
        self._buf = b""
        self.reports: list[dict] = []
        # Wait for the watch to be acknowledged so no report sent after this is missed.
        self.read_until(lambda r: r.get("class") == "WATCH", 2.0)

    def read_until(self, done, timeout_s: float) -> bool:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if any(done(r) for r in self.reports):
                return True
            self.pump()
        return any(done(r) for r in self.reports)

    def pump(self) -> None:
        try:
            chunk = self.conn.recv(65536)
        except (TimeoutError, BlockingIOError):
            return
        self._buf += chunk
        *lines, self._buf = self._buf.split(b"\n")
        self.reports += [json.loads(line) for line in lines if line.strip()]

    def stop(self) -> None:
        if self.conn is not None:
            self.conn.close()
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5.0)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(5.0)


@pytest.fixture
def gpsd():
    binary = _gpsd_binary()
    if binary is None:
        pytest.skip("gpsd is not installed (Debian package gpsd)")
    daemon = Gpsd(binary)
    try:
        yield daemon
    finally:
        daemon.stop()
    assert daemon.proc.poll() is not None  # gpsd is gone


def _own(k: int):
    """Cycle k of a ship accelerating through a starboard turn near Hamburg."""
    return make_reading(
        t_s=k / RATE_HZ,
        lat_deg=53.5412 + 2.1e-5 * k,
        lon_deg=9.9876 + 3.3e-5 * k,
        sog_kn=10.0 + 0.37 * k,
        cog_deg=(350.0 + 3.3 * k) % 360.0,
        hdg_deg=(348.0 + 3.1 * k) % 360.0,
        rot_dpm=18.0,
    )


def _link_config(gpsd, **kw) -> LinkConfig:
    """A link on an ephemeral JSON port that sends NMEA to the test's gpsd at RATE_HZ, clocked from EPOCH."""
    return LinkConfig(
        json_bind=("127.0.0.1", 0),
        nmea_destinations=[("127.0.0.1", gpsd.udp_port)],
        nmea_rate_hz=RATE_HZ,
        utc_epoch=EPOCH,
        **kw,
    )


def _time(k: int) -> str:
    return (EPOCH + timedelta(seconds=k / RATE_HZ)).strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"


def test_gpsd_decodes_our_nmea_and_ais(gpsd):
    target = P.Target(
        id=1,
        name="KVLCC2 SIM",
        reading=make_reading(
            lat_deg=53.55, lon_deg=9.99, sog_kn=8.0, cog_deg=300.0, hdg_deg=299.0, rot_dpm=-16.0
        ),
        length_m=320.0,
        beam_m=58.0,
        mmsi=211000002,
        call_sign="DABC",
        draught_m=20.8,
        destination="HAMBURG",
    )
    config = _link_config(gpsd)
    with UdpLink(config) as link:
        for k in range(CYCLES):
            link.service(k / RATE_HZ, _own(k), [target])
            gpsd.read_until(lambda r, k=k: r.get("class") == "TPV" and r.get("time") == _time(k), 0.5)
        got_all = gpsd.read_until(
            lambda r: r.get("class") == "ATT" and abs(r["heading"] - _own(CYCLES - 1).hdg_deg) < 0.05, 2.0
        )
        assert link.stats()["tx_error"] == 0
    assert got_all, f"gpsd reports: {gpsd.reports[-5:]}"

    # Pair each report with the cycle of the TPV before it (gpsd sends ATT after the cycle's TPV).
    tpv: dict[int, dict] = {}
    att: dict[int, float] = {}
    times = {_time(k): k for k in range(CYCLES)}
    current = None
    for r in gpsd.reports:
        if r.get("class") == "TPV" and r.get("time") in times:
            current = times[r["time"]]
            if r.get("mode") == 3:
                tpv[current] = r
        elif r.get("class") == "ATT" and current is not None:
            att[current] = r["heading"]
    assert sorted(tpv) == list(range(CYCLES))
    assert sorted(att) == list(range(CYCLES))
    for k in range(CYCLES):
        sent = _own(k)
        assert tpv[k]["lat"] == pytest.approx(sent.lat_deg, abs=2e-6)
        assert tpv[k]["lon"] == pytest.approx(sent.lon_deg, abs=2e-6)
        assert tpv[k]["speed"] == pytest.approx(sent.sog_kn * KNOT_M_S, abs=0.004)  # gpsd reports m/s
        assert tpv[k]["track"] == pytest.approx(round(sent.cog_deg, 1), abs=1e-3)
        assert att[k] == pytest.approx(round(sent.hdg_deg, 1), abs=1e-3)

    ais = [r for r in gpsd.reports if r.get("class") == "AIS" and r.get("mmsi") == 211000002]
    pos = next(r for r in ais if r["type"] == 1)
    assert pos["lat"] == pytest.approx(53.55, abs=2e-6) and pos["lon"] == pytest.approx(9.99, abs=2e-6)
    assert pos["speed"] == 8.0 and pos["course"] == 300.0 and pos["heading"] == 299 and pos["status"] == 0
    static = next(r for r in ais if r["type"] == 5)
    assert (
        static["shipname"] == "KVLCC2 SIM"
        and static["callsign"] == "DABC"
        and static["destination"] == "HAMBURG"
    )
    dims = (static["to_bow"], static["to_stern"], static["to_port"], static["to_starboard"])
    assert dims == (160, 160, 29, 29)
    assert static["draught"] == pytest.approx(20.8)


def test_gpsd_ignores_he_heading_talker(gpsd):
    """Negative control: gpsd 3.22 drops $HEHDT, which is why heading defaults to the II talker."""
    config = _link_config(gpsd, talkers={"heading": "HE"})
    with UdpLink(config) as link:
        for k in range(3):
            link.service(k / RATE_HZ, _own(k))
            gpsd.read_until(lambda r, k=k: r.get("class") == "TPV" and r.get("time") == _time(k), 0.5)
    gpsd.read_until(lambda r: False, 0.2)  # an ATT would follow its TPV within milliseconds
    assert any(r.get("class") == "TPV" and r.get("time") == _time(2) for r in gpsd.reports)
    version = next(r for r in gpsd.reports if r.get("class") == "VERSION")["release"]
    headings = [r for r in gpsd.reports if r.get("class") == "ATT"]
    if version.startswith("3.22"):
        assert headings == []
    else:  # gpsd >= 3.23.1 accepts $HE
        assert headings


def test_gpsd_reports_the_heel_of_a_ship_with_roll(gpsd):
    """A ship with roll: gpsd's ATT report carries the heel as ``roll`` (from $PASHR on gpsd 3.22, which
    ignores XDR; newer gpsd also decodes the XDR ROLL transducer), sign kept (+ = starboard side down).
    The first cycles are a 3-DOF ship's: their ATT reports have a heading and no roll."""
    heel = [None, None, -2.5, 1.25, 7.89, -7.89]
    config = _link_config(gpsd)
    with UdpLink(config) as link:
        for k, phi in enumerate(heel):
            rate = None if phi is None else 0.1
            link.service(k / RATE_HZ, moved(_own(k), roll_deg=phi, roll_rate_dps=rate))
            gpsd.read_until(lambda r, k=k: r.get("class") == "TPV" and r.get("time") == _time(k), 0.5)
        gpsd.read_until(lambda r: r.get("class") == "ATT" and r.get("roll") == heel[-1], 2.0)
    att: dict[int, dict] = {}
    times = {_time(k): k for k in range(len(heel))}
    current = None
    for r in gpsd.reports:
        if r.get("class") == "TPV" and r.get("time") in times:
            current = times[r["time"]]
        elif r.get("class") == "ATT" and current is not None:
            att.setdefault(current, {}).update(r)
    for k, phi in enumerate(heel):
        assert k in att, f"no ATT for cycle {k}: {gpsd.reports[-6:]}"
        assert att[k]["heading"] == pytest.approx(round(_own(k).hdg_deg, 1), abs=0.01)
        if phi is None:
            assert "roll" not in att[k]
        else:
            assert att[k].get("roll") == pytest.approx(phi, abs=1e-6), [r for r in gpsd.reports if r.get("class") in ("TPV", "ATT")]
