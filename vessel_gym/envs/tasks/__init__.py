"""The built-in tasks, one file each: declaration (reward terms and features by name,
:mod:`vessel_gym.envs.declare`), ids as presets of the configuration (``register_task``,
:mod:`vessel_gym.envs.registration`), configuration, the start of an episode and the compiled step, together
(HarbourApproach, too long for one module, has its columns, compiled step and environment classes beside
``harbour.py`` in ``harbour_*.py``).

docs/envs.md carries tables generated from the registered tasks (ids and presets, config keys, reward terms,
features); ``python -m vessel_gym.envs.tasks docs/envs.md`` rewrites them and ``--check`` fails when they are
stale.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

DOCS_BEGIN = (
    "<!-- begin: generated from the task declarations (python -m vessel_gym.envs.tasks docs/envs.md) -->"
)
DOCS_END = "<!-- end: generated from the task declarations -->"
IDS_BEGIN = "<!-- begin: ids generated from the task declarations -->"
IDS_END = "<!-- end: ids -->"


def tasks(decls: dict[str, Any] | None = None) -> list[Any]:
    """Every registered task class once, in registration order (built-in tasks first)."""
    from vessel_gym.envs.registration import registered, task_class

    out: list[type] = []
    for env_id in decls if decls is not None else registered():
        cls = task_class(env_id)
        if cls not in out:
            out.append(cls)
    return out


def specs() -> tuple[Any, ...]:
    """The declaration of every registered task, in the order of the docs."""
    return tuple(t.spec for t in tasks())


def _md(text: Any) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _value(v: Any) -> str:
    if v is None:
        return "none"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return str(v)


def _type(f: dataclasses.Field) -> str:
    t = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
    return t.replace(" | None", " or None").replace("tuple[float, ...]", "tuple").replace("tuple[int, ...]", "tuple")


def _range(md: Any) -> str:
    if md.get("choices"):
        return " / ".join(str(c) for c in md["choices"])
    lo, hi = md.get("lo"), md.get("hi")
    if lo is None and hi is None:
        return ""
    return f"[{_value(float(lo)) if lo is not None else '-inf'}, {_value(float(hi)) if hi is not None else 'inf'}]"


def config_table(cls: type) -> str:
    """Markdown table of a config class's keys (type, unit, range, default, meaning); ``reward`` as its table."""
    rows = ["| key | type | unit | range | default | meaning |", "|---|---|---|---|---|---|"]
    for f in dataclasses.fields(cls):
        if not f.init or f.name == "reward":
            continue
        md = f.metadata
        default = f.default if f.default is not dataclasses.MISSING else f.default_factory()  # type: ignore[misc,operator]
        if isinstance(default, float) and not math.isfinite(default):
            default = str(default)
        rows.append(
            f"| `{f.name}` | {_md(_type(f))} | {md.get('unit', '-')} | {_md(_range(md))} | {_md(_value(default))} "
            f"| {_md(md.get('doc', ''))} |"
        )
    return "\n".join(rows)


def ids_table(decls: dict[str, Any] | None = None) -> str:
    """Markdown table of every registered id: its task, the preset's config values, the time limit and the
    classical pilots."""
    from vessel_gym.envs.registration import registered

    decls = registered() if decls is None else decls
    rows = ["| id | task | preset (config values over the defaults) | time limit | pilots |", "|---|---|---|---|---|"]
    for env_id, d in decls.items():
        preset = d.presets[env_id.split("/", 1)[1]]
        values = ", ".join(f"`{k}={_value(v)}`" for k, v in preset.items()) or "the defaults"
        limit = f"{d.max_episode_steps} steps" if d.max_episode_steps else "the task's own"
        pilots = ", ".join(f"`{p}`" for p in d.pilots) or "none"
        rows.append(f"| `{env_id}` | `{d.name}` | {values} | {limit} | {pilots} |")
    return "\n".join(rows)


def task_docs(cls: Any) -> str:
    """A task's generated section: config keys, then its reward, feature and ``info`` tables."""
    spec = cls.spec
    head = " ".join((cls.__doc__ or "").strip().split("\n\n")[0].split())
    return (
        f"#### {cls.__name__.removesuffix('Task')} (`{cls.__name__}`, `{cls.Config.__name__}`)\n\n"
        f"{_md(head)}\n\nConfig keys (besides the shared ones above):\n\n{config_table_task(cls)}\n\n"
        f"Reward terms (`reward` table):\n\n{spec.reward_table()}\n\nFeatures:\n\n{spec.feature_table()}\n\n"
        f"`info` entries:\n\n{spec.info_table()}\n"
    )


def config_table_task(cls: Any) -> str:
    """:func:`config_table` of a task's config, without the keys it shares unchanged with every environment."""
    from vessel_gym.envs.config import ShipEnvConfig

    shared = {f.name: f for f in dataclasses.fields(ShipEnvConfig)}
    table = config_table(cls.Config).split("\n")
    keep = table[:2]
    for f, row in zip([f for f in dataclasses.fields(cls.Config) if f.init and f.name != "reward"], table[2:]):
        base = shared.get(f.name)
        if base is not None and base.default == f.default and base.metadata == f.metadata:
            continue
        keep.append(row)
    return "\n".join(keep)


def docs_block(decls: dict[str, Any] | None = None) -> str:
    """The generated part of docs/envs.md: every task's config, reward and feature tables, between the markers."""
    return "\n".join([DOCS_BEGIN, "", *(task_docs(t) for t in tasks(decls)), DOCS_END])


def ids_block(decls: dict[str, Any] | None = None) -> str:
    """The generated ids table of docs/envs.md, between its markers."""
    return "\n".join([IDS_BEGIN, "", ids_table(decls), "", IDS_END])


def _replace(text: str, begin: str, end: str, block: str, path: Path) -> str:
    head, sep, rest = text.partition(begin)
    _old, sep2, tail = rest.partition(end)
    if not sep or not sep2:
        raise ValueError(f"{path}: no generated block (markers {begin!r} ... {end!r})")
    return head + block + tail


def render(path: str | Path) -> tuple[str, str]:
    """(current text, text with the generated blocks as the registry says) of the markdown file ``path``."""
    path = Path(path)
    text = path.read_text()
    new = _replace(text, IDS_BEGIN, IDS_END, ids_block(), path)
    return text, _replace(new, DOCS_BEGIN, DOCS_END, docs_block(), path)


def write_docs(path: str | Path) -> bool:
    """Replace the generated blocks of the markdown file ``path``; returns whether the file changed."""
    text, new = render(path)
    if new != text:
        Path(path).write_text(new)
    return new != text
