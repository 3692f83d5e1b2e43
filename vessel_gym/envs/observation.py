"""The observation vector's layout: names, units and scales of its entries; decoding into physical units."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from gymnasium import spaces

from vessel_gym.envs.declare import Feature

__all__ = ["Feature", "ObservationLayout"]


class ObservationLayout:
    """Names, units and scales of the observation vector; decodes observations into physical units."""

    def __init__(self, features: Sequence[Feature], normalized: bool) -> None:
        self.features = tuple(features)
        self.normalized = normalized
        self.names = tuple(f.name for f in self.features)
        self.scale = np.array([f.scale for f in self.features], dtype=np.float64)
        self.columns = np.array([f.column for f in self.features], dtype=np.int64)
        self._index = {n: i for i, n in enumerate(self.names)}
        if len(self._index) != len(self.names) or not np.all(self.scale > 0.0):
            raise ValueError("observation features need unique names and positive scales")

    def __len__(self) -> int:
        return len(self.features)

    def index(self, name: str) -> int:
        """Position of feature ``name`` in the observation vector."""
        try:
            return self._index[name]
        except KeyError:
            raise KeyError(f"no observation feature {name!r} (have: {', '.join(self.names)})") from None

    def value(self, obs: np.ndarray, name: str) -> np.ndarray:
        """Feature ``name`` of an observation (or a batch) in physical units."""
        i = self.index(name)
        x = np.asarray(obs, dtype=np.float64)[..., i]
        return x * self.scale[i] if self.normalized else x

    def space(self) -> spaces.Box:
        hi = np.ones(len(self)) if self.normalized else self.scale
        return spaces.Box(-hi.astype(np.float32), hi.astype(np.float32), dtype=np.float32)

    def table(self) -> str:
        """Markdown table of the layout (for documentation)."""
        rows = ["| # | name | unit | scale | meaning |", "|---|---|---|---|---|"]
        rows += [
            f"| {i} | `{f.name}` | {f.unit} | {f.scale:.4g} | {f.doc} |" for i, f in enumerate(self.features)
        ]
        return "\n".join(rows)
