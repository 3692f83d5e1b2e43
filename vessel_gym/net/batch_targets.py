"""The target ships a task simulates in its own batch (CollisionAvoidance: the served own ship is vessel 0;
the other ships of its encounter - its other own ships, steered by agents, then the scripted targets - are
the targets), as link targets: ``state.targets``, AIS and the 3D viewer's ships.

The link's traffic source for such a task, in the shape :class:`~vessel_gym.net.wrapper.UdpLinkWrapper` reads
of a :class:`~vessel_gym.scenarios.traffic.Traffic` (``ids``, ``specs``, ``ships``, ``n``, ``reset``, ``step``,
``lazy_targets``), but it simulates nothing: the task moves these ships, this only reads them. Only the
targets that take part in the encounter now (``world.active``) are published.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

from vessel_gym.net.protocol import Target

#: AIS identity of target slot j: MMSI BASE_MMSI + j (MID 211: a simulated ship needs some number; these
#: are not assigned to real ships by the simulation, only unique within it)
BASE_MMSI = 211_000_100
NAV_UNDER_WAY_ENGINE = 0  # AIS navigational status
CARGO = 70  # AIS ship type


@dataclass(frozen=True)
class TargetSpec:
    """What the link shows of a target slot besides its motion: its name and MMSI."""

    name: str
    mmsi: int


class BatchTargets:
    """The slots of own ship 0's encounter after its own, in the task's simulation, read as link targets."""

    @staticmethod
    def has_targets(env: Any) -> bool:
        """The environment simulates target ships beside its own ship in one batch (a ``world`` of
        encounters, as CollisionAvoidance)."""
        task = getattr(env, "task", None)
        return task is not None and hasattr(task, "world") and env.sim.n > task.n

    def __init__(self, env: Any) -> None:
        task = env.task
        self.sim = env.sim
        self.world = task.world
        self.control_interval_s = float(env.config.control_interval_s)
        members = self.world.members[0]
        self.vessels = list(members[1:])  # the simulation's vessel index of each slot after the served ship
        self.ids = [1 + j for j in range(len(self.vessels))]  # link ids (0: the own ship): the slot
        self.specs = [TargetSpec(f"target {j + 1}", BASE_MMSI + j + 1) for j in range(len(self.vessels))]
        self.ships = [self.sim.ships[self.sim.ship_index[k]] for k in self.vessels]
        self.steps = 0

    @property
    def n(self) -> int:
        """The target slots (the encounter may use fewer: :meth:`active`)."""
        return len(self.vessels)

    def active(self) -> list[int]:
        """Slot numbers of the targets taking part now."""
        return [j for j, k in enumerate(self.vessels) if self.world.active[k]]

    def reset(self) -> None:
        self.steps = 0

    def step(self, n: int = 1) -> None:
        """Nothing to simulate: the task moves the targets with the own ship."""
        self.steps += n

    def targets(self) -> list[Target]:
        """The active targets now, as link targets (AIS: under way using engine, cargo)."""
        out = []
        for j in self.active():
            k, ship, spec = self.vessels[j], self.ships[j], self.specs[j]
            p = ship.particulars
            out.append(
                Target(
                    id=self.ids[j],
                    name=spec.name,
                    reading=self.sim.bridge(k, 0),
                    length_m=p.L_m,
                    beam_m=p.B_m,
                    mmsi=spec.mmsi,
                    ship_type=CARGO,
                    draught_m=p.T_m,
                    nav_status=NAV_UNDER_WAY_ENGINE,
                )
            )
        return out

    def lazy_targets(self, step: int) -> LazyBatchTargets:
        """The targets, read only when the link needs them (the step is the task's own)."""
        return LazyBatchTargets(self)


class LazyBatchTargets(Sequence[Target]):
    """The active targets, read on first use (their count needs no readings)."""

    __slots__ = ("_source", "_items")

    def __init__(self, source: BatchTargets) -> None:
        self._source = source
        self._items: list[Target] | None = None

    def _resolve(self) -> list[Target]:
        if self._items is None:
            self._items = self._source.targets()
        return self._items

    def __len__(self) -> int:
        return len(self._source.active())

    def __getitem__(self, i):  # type: ignore[override]
        return self._resolve()[i]

    def __iter__(self) -> Iterator[Target]:
        return iter(self._resolve())
