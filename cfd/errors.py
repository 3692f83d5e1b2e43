"""Exceptions raised by the CFD tool.

Library code raises these; only :mod:`cfd.cli` turns them into exit codes
(2 for bad input, 1 for a failed run).
"""

from __future__ import annotations

from pathlib import Path


class InputError(ValueError):
    """An input (CLI argument or study-file key) is missing or out of range.

    ``key`` names the argument or key; the message states the allowed range.
    """

    def __init__(self, key: str, message: str) -> None:
        self.key = key
        self.message = message
        super().__init__(f"{key}: {message}")

    def __reduce__(self):  # rebuilt from its fields when it crosses a process boundary (Ray tasks)
        return type(self), (self.key, self.message)


class CfdError(RuntimeError):
    """A step of the CFD pipeline failed.

    ``step`` names the step (e.g. ``"snappyHexMesh (mesh)"``) and ``log`` the file to read.
    ``str(error)`` is a single line.
    """

    def __init__(self, step: str, message: str, log: str | Path | None = None) -> None:
        self.step = step
        self.message = " ".join(str(message).split())
        self.log = Path(log) if log is not None else None
        text = f"{step} failed: {self.message}"
        if self.log is not None:
            text += f" (log: {self.log})"
        super().__init__(text)

    def __reduce__(self):  # rebuilt from its fields in the process that started a Ray task
        return type(self), (self.step, self.message, self.log)
