"""The one home of the command lines' conventions, shared by ``vessel-gym``, ``vessel-cfd`` and the agent
scripts: bad input is a :class:`UsageError` or an argparse error, printed as ONE line on stderr (control
characters escaped) with exit code 2; ``--help`` shows each option's default; argument types check numbers
against their range and name the option; a missing optional extra is one line naming it. Also the link's
options: HOST:PORT addresses that resolve and bind, and the JSON channel's token."""

from __future__ import annotations

import argparse
import importlib.util
import math
import os
import sys
from typing import Any, NoReturn


class UsageError(ValueError):
    """Bad command-line input (exit code 2)."""


def printable(text: object) -> str:
    """``text`` with each character that is not printable (a NUL, a newline, an escape) written as Python's
    repr writes it (``x\\x00.toml``): the one home of how a file name or other user input goes into a one-line
    error (:func:`error_line`, and the errors that name a file, :func:`vessel_gym.physics.schema.read_toml`),
    so that the line stays one line and shows what was given."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


def error_line(message: object) -> None:
    """Print an error on stderr as exactly one line: control characters from the user's input are escaped
    (:func:`printable`)."""
    print(printable(message), file=sys.stderr)


class DefaultsFormatter(argparse.HelpFormatter):
    """Help that shows each option's allowed range (of the :func:`number_in` and :func:`int_in` types) and its
    default (where it has one worth showing), unless the help text already says them."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        bounds = getattr(action.type, "bounds", None)
        if bounds is not None and not all(b in text for b in bounds if b not in ("-inf", "inf")):
            lo, hi = bounds
            text += f" (>= {lo})" if hi == "inf" else f" (<= {hi})" if lo == "-inf" else f" (range: [{lo}, {hi}])"
        if (
            "%(default)" not in text
            and "default" not in text.lower()
            and action.default not in (None, False, argparse.SUPPRESS)
            and (action.option_strings or action.nargs in (argparse.OPTIONAL, argparse.ZERO_OR_MORE))
        ):
            text += " (default: %(default)s)"
        return text


class OneLineParser(argparse.ArgumentParser):
    """argparse with defaults in the help and a one-line error on stderr, exit code 2 (argparse prints the
    usage lines too)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", DefaultsFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        error_line(f"{self.prog}: error: {message}")
        raise SystemExit(2)


def require_extra(modules: tuple[str, ...], extra: str, what: str) -> None:
    """UsageError naming the extra unless every module of ``modules`` can be imported (found, not imported:
    the check costs nothing and runs before any work)."""
    for name in modules:
        try:
            found = importlib.util.find_spec(name) is not None
        except (ImportError, ValueError):  # a parent package missing, or a module set to None in sys.modules
            found = False
        if not found:
            raise UsageError(
                f"{what}: needs the '{extra}' extra ({name} is missing): pip install 'vessel-gym[{extra}]'"
            )


def number_in(kind: str, lo: float | None = None, hi: float | None = None):
    """argparse type: a finite number in [lo, hi] (None: no bound), the message naming the option ``kind``."""

    def conv(text: str) -> float:
        try:
            x = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{kind} must be a number, got {text!r}") from None
        if not math.isfinite(x):
            raise argparse.ArgumentTypeError(f"{kind} must be finite, got {text!r}")
        if (lo is not None and x < lo) or (hi is not None and x > hi):
            low = "-inf" if lo is None else f"{lo:g}"
            high = "inf" if hi is None else f"{hi:g}"
            raise argparse.ArgumentTypeError(f"{kind} {x:g} outside [{low}, {high}]")
        return x

    conv.bounds = ("-inf" if lo is None else f"{lo:g}", "inf" if hi is None else f"{hi:g}")  # type: ignore[attr-defined]
    return conv


def int_in(kind: str, lo: int, hi: int | None = None):
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

    conv.bounds = (str(lo), "inf" if hi is None else str(hi))  # type: ignore[attr-defined]
    return conv


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
