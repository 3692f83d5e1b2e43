"""The ``vessel-gym`` command's argument checks: bad input is a :class:`UsageError` (one line, exit code 2)
naming the option -- numbers in a range, HOST:PORT addresses that resolve and bind, the JSON channel's token."""

from __future__ import annotations

import argparse
import math
import os


class UsageError(Exception):
    """Bad command-line input (exit code 2)."""


def _finite(kind: str, lo: float | None = None, hi: float | None = None):
    def conv(text: str) -> float:
        try:
            x = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must be a number, got {text!r}") from None
        if not math.isfinite(x):
            raise argparse.ArgumentTypeError(f"{kind} must be finite, got {text!r}")
        if (lo is not None and x < lo) or (hi is not None and x > hi):
            raise argparse.ArgumentTypeError(f"{kind} {x:g} outside [{lo:g}, {hi:g}]")
        return x

    return conv


def _int_in(kind: str, lo: int, hi: int | None = None):
    """argparse type: an integer in [lo, hi] (hi None: no upper bound)."""

    def conv(text: str) -> int:
        try:
            x = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must be an integer, got {text!r}") from None
        if hi is None and x < lo:
            raise argparse.ArgumentTypeError(f"{kind} must be >= {lo}, got {x}")
        if hi is not None and not lo <= x <= hi:
            raise argparse.ArgumentTypeError(f"{kind} {x} outside [{lo}, {hi}]")
        return x

    return conv


SEED_MAX = 2**32 - 1  # the seed range of numpy's legacy generators, which every seeded part accepts


TOKEN_ENV = "VESSEL_GYM_TOKEN"


def add_token_option(parser: argparse.ArgumentParser) -> None:
    """``--token`` of the JSON channel's commands (read with :func:`token_arg`)."""
    parser.add_argument(
        "--token",
        default=None,
        help=f"shared secret of the JSON channel, 1-128 characters (default: ${TOKEN_ENV}, else none)",
    )


def token_arg(args: argparse.Namespace) -> str | None:
    """The token of ``--token`` or of ``$VESSEL_GYM_TOKEN`` (which keeps it out of the process list)."""
    token = args.token if args.token is not None else os.environ.get(TOKEN_ENV) or None
    if token is not None and not 1 <= len(token) <= 128:
        where = "--token" if args.token is not None else f"${TOKEN_ENV}"
        raise UsageError(f"vessel-gym {args.command}: {where} must be 1-128 characters, got {len(token)}")
    return token


def host_port(text: str, what: str) -> tuple[str, int]:
    """'HOST:PORT' -> (host, port); raises UsageError naming the option."""
    host, sep, port = text.rpartition(":")
    if not sep or not host:
        raise UsageError(f"vessel-gym: {what}: expected HOST:PORT, got {text!r}")
    try:
        p = int(port)
    except ValueError:
        raise UsageError(f"vessel-gym: {what}: port must be an integer, got {port!r}") from None
    if not 0 <= p <= 65535:
        raise UsageError(f"vessel-gym: {what}: port {p} outside [0, 65535]")
    return host, p


def resolve_address(addr: tuple[str, int], what: str) -> tuple[str, int]:
    """Resolve the host of a UDP address to IPv4 (as the link's sockets use it); UsageError naming the
    option if the name does not resolve."""
    import socket

    try:
        return socket.gethostbyname(addr[0]), addr[1]
    except (OSError, UnicodeError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise UsageError(f"vessel-gym: {what}: cannot resolve host {addr[0]!r} ({reason})") from None


def check_bindable(addr: tuple[str, int], what: str) -> None:
    """UsageError naming the option unless a UDP socket can bind ``addr`` on this machine."""
    import socket

    host, port = resolve_address(addr, what)
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        try:
            sock.bind((host, port))
        except OSError as exc:
            raise UsageError(
                f"vessel-gym: {what}: cannot listen on {addr[0]}:{addr[1]} ({exc.strerror or exc}); "
                "give an address of this machine and a free port"
            ) from None
