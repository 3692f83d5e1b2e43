"""Command-line helpers shared by the agent scripts: one-line argparse errors, argument types, ``KEY=VALUE``
assignments and JSON-safe values.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from typing import Any

from agents.config import UsageError


def json_safe(x: Any) -> Any:
    """``x`` with non-finite floats replaced by None (JSON has no NaN or inf), through dicts and lists."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: json_safe(v) for k, v in x.items()}
    if isinstance(x, list):
        return [json_safe(v) for v in x]
    return x


def parse_assignments(items: Sequence[str] | None, what: str) -> dict[str, Any]:
    """``["gamma=0.995", "policy_kwargs.net_arch=[64, 64]"]`` -> a nested mapping (values parsed as YAML)."""
    import yaml

    out: dict[str, Any] = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        if not sep or not key.strip():
            raise UsageError(f"{what}: expected KEY=VALUE, got {item!r}")
        try:
            value = yaml.safe_load(text) if text.strip() else None
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


class OneLineParser(argparse.ArgumentParser):
    """argparse with a one-line error on stderr and exit code 2 (argparse prints the usage too)."""

    def error(self, message: str) -> None:
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        raise SystemExit(2)


def int_at_least(name: str, lo: int):
    """argparse type: an integer >= lo, the message naming the option."""

    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer, got {text!r}") from None
        if v < lo:
            raise argparse.ArgumentTypeError(f"{name} must be >= {lo}, got {v}")
        return v

    return parse


def positive(kind: type, name: str):
    """argparse type: a finite number > 0 of ``kind`` (int or float), the message naming the option."""

    def parse(text: str) -> Any:
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}: not a number: {text!r}") from None
        if not (math.isfinite(v) and v > 0):
            raise argparse.ArgumentTypeError(f"{name} must be > 0, got {text}")
        return v

    return parse
