"""Helm ownership of the UDP link: which helm panel steers, the orders in force, and the failsafe when the owner
is lost.

:class:`HelmOwner` applies the rules of ``docs/protocol.md``; the link (:mod:`vessel_gym.net.link`) decides who
is a registered helm client, counts, and tells v2 clients who owns the helm:

- The first command while nobody owns the helm takes ownership; commands from other panels are refused
  (``not_owner``) while an owner exists.
- When the owner is lost (watchdog, bye, timeout, role change, new session) ``helm_ok`` becomes false and the
  failsafe policy applies to the orders: ``hold`` keeps the last order, ``midships_stop`` orders rudder 0,
  telegraph STOP (or 0 rpm) and every thruster and tug to 0.
"""

from __future__ import annotations

from dataclasses import dataclass

from vessel_gym.net.access import Address
from vessel_gym.net.protocol import HelmCommand

FAILSAFE_POLICIES = ("hold", "midships_stop")
HELM_CHANGE_REASONS = ("command", "watchdog", "timeout", "bye", "viewer", "new_session")
MAX_PENDING_CHANGES = 1000  # helm changes kept until popped (bounded if nobody pops them)


@dataclass(frozen=True)
class HelmState:
    """The helm orders in force and who gives them.

    ``rudder_order_deg`` (deg, + = starboard) and one of ``telegraph`` (-4..4) / ``rpm_order`` (rev/min) are None
    until a helm panel has commanded; the caller's own control applies then. ``helm_ok`` is true while the owner's
    commands are fresh; ``failsafe`` is true when the orders come from the failsafe policy after the owner was
    lost (they stay in force until a panel commands again). ``seq`` is the seq of the command in force.
    """

    rudder_order_deg: float | None = None
    telegraph: int | None = None
    rpm_order: float | None = None
    owner: Address | None = None
    helm_ok: bool = False
    failsafe: bool = False
    seq: int | None = None
    assist: tuple[float, ...] = ()  # thruster and tug orders, fractions in [-1, 1] (HelmCommand.assist)

    @property
    def has_orders(self) -> bool:
        """True once a helm panel has commanded (orders are set, fresh or failsafe)."""
        return self.rudder_order_deg is not None


NO_HELM = HelmState()


@dataclass(frozen=True)
class HelmChange:
    """The helm changed hands at link time ``t_s``: ``owner`` took it (``reason`` "command") or ``previous``
    lost it (``reason`` one of "watchdog", "timeout", "bye", "viewer", "new_session"; ``owner`` is then None).
    Names are the clients' hello names."""

    t_s: float
    reason: str
    owner: Address | None = None
    owner_name: str = ""
    previous: Address | None = None
    previous_name: str = ""


class HelmOwner:
    """Owner, orders and failsafe of one link's helm; ``state`` is the :class:`HelmState` in force."""

    def __init__(self, failsafe: str) -> None:
        if failsafe not in FAILSAFE_POLICIES:
            raise ValueError(f"failsafe must be one of {FAILSAFE_POLICIES}, not {failsafe!r}")
        self.policy = failsafe
        self.owner: Address | None = None
        self.owner_name = ""
        self.last_command_s = 0.0  # link time of the owner's last command
        self.state = NO_HELM
        self._last_owner: Address | None = None  # the owner before the current one (for HelmChange)
        self._last_name = ""
        self._orders: HelmCommand | None = None
        self._failsafe = False
        self._changes: list[HelmChange] = []

    def command(self, now_s: float, addr: Address, name: str, cmd: HelmCommand) -> str:
        """Apply a helm client's in-session, fresh command: ``"takeover"`` (it took the free helm), ``"applied"``
        (from the owner) or ``"not_owner"`` (refused: another panel owns the helm)."""
        outcome = "applied"
        if self.owner is None:
            self.owner = addr
            self.owner_name = name
            self._record(HelmChange(now_s, "command", addr, name, self._last_owner, self._last_name))
            outcome = "takeover"
        elif self.owner != addr:
            return "not_owner"
        self.last_command_s = now_s
        self._orders = cmd
        self._failsafe = False
        self._update()
        return outcome

    def release(self, now_s: float, reason: str) -> None:
        """The owner is lost (``reason`` of :data:`HELM_CHANGE_REASONS`): free the helm, apply the failsafe."""
        self._record(HelmChange(now_s, reason, previous=self.owner, previous_name=self.owner_name))
        self._last_owner, self._last_name = self.owner, self.owner_name
        self.owner = None
        orders = self._orders
        if orders is not None:
            self._failsafe = True
            if self.policy == "midships_stop":
                self._orders = HelmCommand(
                    seq=orders.seq,
                    rudder_order_deg=0.0,
                    telegraph=None if orders.telegraph is None else 0,
                    rpm_order=None if orders.rpm_order is None else 0.0,
                    assist=(0.0,) * len(orders.assist),
                )
        self._update()

    def pop_changes(self) -> list[HelmChange]:
        """The ownership changes since the last call, oldest first."""
        out, self._changes = self._changes, []
        return out

    def rebase(self, delta: float) -> None:
        """The caller's clock jumped by ``delta``: shift the stored command time so the watchdog interval holds."""
        self.last_command_s += delta

    def _record(self, change: HelmChange) -> None:
        if len(self._changes) < MAX_PENDING_CHANGES:
            self._changes.append(change)

    def _update(self) -> None:
        o = self._orders
        self.state = HelmState(
            rudder_order_deg=None if o is None else o.rudder_order_deg,
            telegraph=None if o is None else o.telegraph,
            rpm_order=None if o is None else o.rpm_order,
            owner=self.owner,
            helm_ok=self.owner is not None and o is not None and not self._failsafe,
            failsafe=self._failsafe,
            seq=None if o is None else o.seq,
            assist=() if o is None else o.assist,
        )
