"""The class's codes: one instructor code, one spectator code (read-only), one helm code per ship.

Every code is 128 random bits from :mod:`secrets` (22 URL-safe characters), so guessing one is hopeless even
at the join rate the server allows (:data:`~vessel_gym.classroom.server.JOIN_RATE_PER_HOST_HZ`). A code given
at a join is compared with every code of the class in constant time (:func:`hmac.compare_digest` over UTF-8
bytes, :func:`vessel_gym.net.access.token_bytes`), all of them every time, so neither the time taken nor an
early exit tells which code came close. Codes are shown on the instructor's page and printed once at start
(the instructor's own code); they are never written to a log. ``revoke`` gives a ship a new helm code, and the
old one stops working at once.
"""

from __future__ import annotations

import hmac
import secrets
from dataclasses import dataclass

from vessel_gym.net.access import token_bytes

CODE_BYTES = 16  # 128 bits of randomness per code
#: a code given at a join longer than this is refused before any comparison (the codes are 22 characters)
MAX_CODE_CHARS = 64


@dataclass(frozen=True)
class Role:
    """Who a code admits: ``instructor``, ``spectator`` or ``helm`` (with its ``ship``)."""

    kind: str
    ship: int = -1


def new_code() -> str:
    return secrets.token_urlsafe(CODE_BYTES)


class ClassCodes:
    """The codes of one class of ``ships`` ships (module doc)."""

    def __init__(self, ships: int) -> None:
        self.instructor = new_code()
        self.spectator = new_code()
        self.helm = [new_code() for _ in range(ships)]

    def role(self, code: object) -> Role | None:
        """The role ``code`` admits, or None (not a str, too long, or no code of the class)."""
        if not isinstance(code, str) or not 0 < len(code) <= MAX_CODE_CHARS:
            return None
        given = token_bytes(code)
        found: Role | None = None
        candidates = [(self.instructor, Role("instructor")), (self.spectator, Role("spectator"))]
        candidates += [(c, Role("helm", k)) for k, c in enumerate(self.helm)]
        for expected, role in candidates:  # all of them, whatever matched: no early exit
            if hmac.compare_digest(given, token_bytes(expected)) and found is None:
                found = role
        return found

    def revoke(self, ship: int) -> str:
        """A new helm code for ``ship`` (the old one no longer admits anyone); returns it."""
        self.helm[ship] = new_code()
        return self.helm[ship]
