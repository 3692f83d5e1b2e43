"""The sentences of the UDP link's NMEA channel: each cycle, the own ship's NMEA 0183 sentences and the AIS
reports of the targets that are due (type 1 position every ``ais_position_interval_s``, type 5 static and voyage
data every ``ais_static_interval_s``), stamped in UTC. Sending them is the link's job
(:mod:`vessel_gym.net.link`)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from datetime import datetime, timedelta, timezone

from vessel_gym.net import ais, nmea
from vessel_gym.net.link_config import LinkConfig
from vessel_gym.net.protocol import Target
from vessel_gym.physics.bridge import BridgeReading


class NmeaFeed:
    """The NMEA/AIS sentences of one link. ``on_error(text)`` is told of every sentence that cannot be encoded
    (an absurd value, say); the sentence is then left out and nothing raises."""

    def __init__(self, config: LinkConfig, on_error: Callable[[str], None]) -> None:
        self.config = config
        self._on_error = on_error
        self._epoch: datetime | None = config.utc_epoch
        self._ais_pos_due: dict[int, float] = {}
        self._ais_static_due: dict[int, float] = {}
        self._ais_seq_id = 0
        self._ais_channel = "A"

    def cycle(
        self, now_s: float, own: BridgeReading, targets: Sequence[Target], utc: datetime | None
    ) -> tuple[list[str], int]:
        """The sentences due at link time ``now_s`` (s): the own ship's first, then AIS; and how many are own."""
        cfg = self.config
        stamp = self._utc(own, utc)
        try:
            sentences = nmea.own_ship_sentences(
                own, stamp, cfg.talkers, gll_sentence=cfg.nmea_gll, zda_sentence=cfg.nmea_zda
            )
        except (ValueError, TypeError, OverflowError) as exc:  # e.g. an absurd value overflowing 82 chars
            self._on_error(f"nmea: {exc}")
            sentences = []
        n_own = len(sentences)
        if targets:
            sentences += self._ais_sentences(now_s, targets, stamp)
        return sentences, n_own

    def rebase(self, delta: float) -> None:
        """The caller's clock jumped by ``delta``: shift the AIS deadlines so their intervals are kept."""
        for table in (self._ais_pos_due, self._ais_static_due):
            for key in table:
                table[key] += delta

    def _utc(self, own: BridgeReading, utc: datetime | None) -> datetime:
        if utc is not None:
            return utc
        t = own.t_s if math.isfinite(own.t_s) and abs(own.t_s) < 1e9 else 0.0
        if self._epoch is None:
            self._epoch = datetime.now(timezone.utc) - timedelta(seconds=t)
        return self._epoch + timedelta(seconds=t)

    def _ais_sentences(self, now_s: float, targets: Sequence[Target], stamp: datetime) -> list[str]:
        cfg = self.config
        out: list[str] = []
        live = set()
        for t in targets:
            if t.mmsi is None:
                continue
            live.add(t.id)
            try:
                if now_s >= self._ais_static_due.get(t.id, -math.inf):
                    # Position reference at midships on the centreline, in whole metres.
                    bow, port = round(t.length_m / 2.0), round(t.beam_m / 2.0)
                    out += ais.static_voyage(
                        t.mmsi,
                        imo=t.imo,
                        call_sign=t.call_sign,
                        name=t.name,
                        ship_type=t.ship_type,
                        to_bow_m=bow,
                        to_stern_m=round(t.length_m) - bow,
                        to_port_m=port,
                        to_starboard_m=round(t.beam_m) - port,
                        draught_m=t.draught_m,
                        destination=t.destination,
                        seq_id=self._ais_seq_id,
                        channel=self._next_channel(),
                    )
                    self._ais_seq_id = (self._ais_seq_id + 1) % 10
                    self._ais_static_due[t.id] = now_s + cfg.ais_static_interval_s
                if now_s >= self._ais_pos_due.get(t.id, -math.inf):
                    r = t.reading
                    out += ais.position_report(
                        t.mmsi,
                        r.lat_deg,
                        r.lon_deg,
                        r.sog_kn,
                        r.cog_deg,
                        r.hdg_deg,
                        r.rot_dpm,
                        stamp.second,
                        nav_status=t.nav_status,
                        channel=self._next_channel(),
                    )
                    self._ais_pos_due[t.id] = now_s + cfg.ais_position_interval_s
            except (ValueError, TypeError, OverflowError) as exc:
                self._on_error(f"ais target {t.id}: {exc}")
        if len(self._ais_pos_due) > len(live):  # forget ships that left the scene
            for table in (self._ais_pos_due, self._ais_static_due):
                for key in [k for k in table if k not in live]:
                    del table[key]
        return out

    def _next_channel(self) -> str:
        self._ais_channel = "B" if self._ais_channel == "A" else "A"
        return self._ais_channel
