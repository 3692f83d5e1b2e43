"""What the agent scripts read and print beyond the command lines' shared conventions (those live in
:mod:`vessel_gym.cli_args`: the one-line parser, argument types, :class:`UsageError`): ``KEY=VALUE``
assignments and JSON-safe values.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from vessel_gym.cli_args import UsageError

#: what training and loading a saved model import (the ``rl`` extra); the baselines need none of it
RL_MODULES = ("stable_baselines3", "torch", "yaml")


def json_safe(x: Any) -> Any:
    """``x`` with non-finite floats replaced by None (JSON has no NaN or inf), through dicts and lists."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: json_safe(v) for k, v in x.items()}
    if isinstance(x, list):
        return [json_safe(v) for v in x]
    return x


def _plain_value(text: str) -> Any:
    """A value without PyYAML (``evaluate --agent pid`` needs no RL packages): JSON (numbers, true/false/null,
    lists, objects), else the text itself as a string -- what YAML gives for these forms too."""
    import json

    try:
        return json.loads(text)
    except ValueError:
        return text.strip()


def parse_assignments(items: Sequence[str] | None, what: str) -> dict[str, Any]:
    """``["gamma=0.995", "policy_kwargs.net_arch=[64, 64]"]`` -> a nested mapping (values parsed as YAML, or
    as JSON-else-string where PyYAML, of the ``rl`` extra, is not installed)."""
    try:
        import yaml
    except ImportError:
        yaml = None

    out: dict[str, Any] = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        if not sep or not key.strip():
            raise UsageError(f"{what}: expected KEY=VALUE, got {item!r}")
        if not text.strip():
            value = None
        elif yaml is None:
            value = _plain_value(text)
        else:
            try:
                value = yaml.safe_load(text)
            except yaml.YAMLError:
                raise UsageError(f"{what}: cannot parse the value of {key!r}: {text!r}") from None
        node = out
        parts = key.strip().split(".")
        for part in parts[:-1]:
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise UsageError(f"{what}: {key!r} conflicts with an earlier assignment")
        node[parts[-1]] = value
    return out
