"""The tasks: each module holds one task's declaration (reward terms and features by name,
:mod:`vessel_gym.envs.declare`), its configuration, the start of an episode and its compiled step, together.

The environment classes over these tasks, with their spec sheets, are :mod:`vessel_gym.envs.zigzag`,
:mod:`vessel_gym.envs.turning` and :mod:`vessel_gym.envs.harbour`. docs/envs.md carries the tables generated from
the declarations; ``python -m vessel_gym.envs.tasks docs/envs.md`` rewrites them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

DOCS_BEGIN = (
    "<!-- begin: generated from the task declarations (python -m vessel_gym.envs.tasks docs/envs.md) -->"
)
DOCS_END = "<!-- end: generated from the task declarations -->"


def specs() -> tuple[Any, ...]:
    """The declaration of every registered task, in the order of the docs."""
    from vessel_gym.envs.tasks import harbour, harbour_v1, turning, zigzag, zigzag_v1

    return (zigzag_v1.SPEC, zigzag.SPEC, turning.SPEC, harbour_v1.SPEC_V1, harbour.SPEC)


def docs_block() -> str:
    """The generated part of docs/envs.md: every task's reward and feature tables, between the markers."""
    return "\n".join([DOCS_BEGIN, "", *(s.docs() for s in specs()), DOCS_END])


def write_docs(path: str | Path) -> bool:
    """Replace the generated block of the markdown file ``path``; returns whether the file changed."""
    path = Path(path)
    text = path.read_text()
    head, sep, rest = text.partition(DOCS_BEGIN)
    _old, sep2, tail = rest.partition(DOCS_END)
    if not sep or not sep2:
        raise ValueError(f"{path}: no generated block (markers {DOCS_BEGIN!r} ... {DOCS_END!r})")
    new = head + docs_block() + tail
    if new != text:
        path.write_text(new)
    return new != text
