"""Agent tests: skip when the ``rl`` extra (stable-baselines3, torch, PyYAML) is missing. The ``agents``
package is installed with vessel-gym (and importable from the repository root)."""

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("yaml")
