"""The task registry: every environment id comes from a task's own declaration, nowhere else.

A task declares itself in its own file with :func:`register_task`: its ids, each a named *preset* of the task's
configuration (a version is config values, not a subclass), its ``max_episode_steps``, its classical pilots and
its episode metrics (capabilities the agents read), and its default training hyperparameters. From that one
declaration come the Gymnasium registration (ids, entry points, time limits), the lazy names of
:mod:`vessel_gym.envs`, the docs tables (``python -m vessel_gym.envs.tasks docs/envs.md``), the API tests
(parametrised over :func:`registered`), the agents' baselines and metrics and their training defaults.

Registration stays cheap: ``import vessel_gym`` registers the built-in tasks of :mod:`vessel_gym.envs.tasks` by
reading their declarations from the source (:func:`builtin_declarations`, the ``register_task(...)`` call's
literal ``presets`` and ``max_episode_steps``), without importing them (importing a task loads numba and the
physics: seconds). A task defined anywhere else registers when its module is imported (the decorator does it).
Both are idempotent.
"""

from __future__ import annotations

import ast
import dataclasses
import functools
import importlib
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

NAMESPACE = "vessel_gym"
TASKS_DIR = Path(__file__).resolve().parent / "tasks"


@dataclass(frozen=True)
class Declaration:
    """What a task declares about itself (:func:`register_task`).

    ``presets``: id (without the namespace) -> config values over the config class's defaults, in the order of
    the docs. ``env``: ``"module:Class"`` of its environment class (its vector twin is ``<Class>`` with
    ``VectorEnv`` for ``Env``), or None for the classes :func:`register_task` makes. ``pilots``: baseline
    name -> callable ``pilot(env)`` giving a policy (``policy(obs) -> action`` with ``reset(mask=None)``).
    ``metrics``: callable ``metrics(infos, terminated) -> dict`` of an episode's task metrics from its step
    ``info`` dicts. ``train``: default training hyperparameters (meta keys and algorithm arguments, see
    docs/agents.md), ``{"common": {...}, "<algo>": {...}}``.
    """

    module: str
    name: str  # the task class
    presets: Mapping[str, Mapping[str, Any]]
    max_episode_steps: int | None
    env: str | None = None
    pilots: Mapping[str, Any] = field(default_factory=dict)
    metrics: Any = None
    train: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    namespace: str = NAMESPACE

    @property
    def ids(self) -> list[str]:
        return [f"{self.namespace}/{p}" for p in self.presets]

    def entry_points(self) -> tuple[str, str]:
        env = self.env or f"{self.module}:{env_class_name(self.name)}"
        return env, env[: -len("Env")] + "VectorEnv" if env.endswith("Env") else env + "VectorEnv"


def env_class_name(task_name: str) -> str:
    """The environment class :func:`register_task` makes for the task class ``task_name`` (``BerthingTask`` ->
    ``BerthingEnv``)."""
    return task_name.removesuffix("Task") + "Env"


# id -> declaration, of every registered task (built-in ones as read from source until imported)
_REGISTRY: dict[str, Declaration] = {}


def register_task(
    *,
    presets: Mapping[str, Mapping[str, Any]],
    max_episode_steps: int | None,
    env: str | None = None,
    pilots: Mapping[str, Any] | None = None,
    metrics: Callable[..., dict[str, Any]] | None = None,
    train: Mapping[str, Mapping[str, Any]] | None = None,
    namespace: str = NAMESPACE,
) -> Callable[[type], type]:
    """Class decorator of a :class:`~vessel_gym.envs.task.Task`: declare its ids (presets of its config) and
    capabilities, register the ids with Gymnasium, and (``env`` None) make its environment classes
    ``<Name>Env`` and ``<Name>VectorEnv`` in the task's module.

    Every id names a preset: ``{"Berthing-v0": {}, "BerthingWindy-v0": {"wind_speed_m_s": [5, 10]}}``, registered
    as ``<namespace>/<preset>`` (a task of your own: your own namespace). A later version of an id's name
    (``-v2`` after ``-v1``) makes Gymnasium raise ``DeprecatedEnv`` for a version no longer declared.
    """

    def decorate(cls: Any) -> Any:  # a Task subclass (its Config, spec and declaration are class attributes)
        for pid, values in presets.items():
            unknown = set(values) - {f.name for f in dataclasses.fields(cls.Config) if f.init}
            if unknown:
                raise ValueError(f"{cls.__name__} preset {pid}: no config keys {sorted(unknown)}")
        decl = Declaration(
            module=cls.__module__,
            name=cls.__name__,
            presets={k: dict(v) for k, v in presets.items()},
            max_episode_steps=max_episode_steps,
            env=env,
            pilots=dict(pilots or {}),
            metrics=metrics,
            train={k: dict(v) for k, v in (train or {}).items()},
            namespace=namespace,
        )
        cls.declaration = decl
        if env is None:
            _make_env_classes(cls)
        _register(decl, replace=True)
        return cls

    return decorate


def _make_env_classes(task_cls: type) -> None:
    """``<Name>Env`` and ``<Name>VectorEnv`` over ``task_cls``, placed in its module (so that they pickle)."""
    from vessel_gym.envs.env import ShipEnv, ShipVectorEnv

    module = sys.modules[task_cls.__module__]
    name = env_class_name(task_cls.__name__)
    doc = task_cls.__doc__ or f"The environment of :class:`{task_cls.__name__}`."
    env_cls = type(name, (ShipEnv,), {"Task": task_cls, "env_name": name[:-3], "__doc__": doc})
    vec_name = name[:-3] + "VectorEnv"
    vec_cls = type(vec_name, (ShipVectorEnv,), {"Env": env_cls, "__doc__": f"Native vector version of {name}."})
    for c in (env_cls, vec_cls):
        c.__module__ = module.__name__
        c.__qualname__ = c.__name__
        setattr(module, c.__name__, c)


def _register(decl: Declaration, replace: bool = False) -> None:
    from gymnasium.envs.registration import register, registry

    env_entry, vec_entry = decl.entry_points()
    for preset, env_id in zip(decl.presets, decl.ids):
        old = _REGISTRY.get(env_id)
        if old is not None and (old.module, old.name) != (decl.module, decl.name):
            raise ValueError(f"{env_id} is declared by {old.module}.{old.name} and {decl.module}.{decl.name}")
        _REGISTRY[env_id] = decl
        if env_id in registry:
            if not replace:
                continue
            del registry[env_id]
        register(
            id=env_id,
            entry_point=env_entry,
            vector_entry_point=vec_entry,
            max_episode_steps=decl.max_episode_steps,
            kwargs={"preset": preset},
        )


@functools.cache
def builtin_declarations() -> tuple[Declaration, ...]:
    """The declarations of the tasks in :mod:`vessel_gym.envs.tasks`, read from their source (no import):
    each module's ``@register_task(...)`` (at the start of a line, before its class) with literal ``presets``,
    ``max_episode_steps``, ``env`` and ``namespace``."""
    out = []
    for path in sorted(TASKS_DIR.glob("*.py")):
        text = path.read_text()
        start = text.find("\n@register_task(")
        while start >= 0:
            # the decorator and its class line only: parsing the whole module would cost 10x more
            line = text.index("\nclass ", start)
            end = text.index("\n", line + 1)
            node = ast.parse(text[start + 1 : end] + "\n    pass\n").body[0]
            assert isinstance(node, ast.ClassDef)
            kw = {k.arg: k.value for k in node.decorator_list[0].keywords}  # type: ignore[attr-defined]
            out.append(
                Declaration(
                    module=f"vessel_gym.envs.tasks.{path.stem}",
                    name=node.name,
                    presets=ast.literal_eval(kw["presets"]),
                    max_episode_steps=ast.literal_eval(kw["max_episode_steps"]),
                    env=ast.literal_eval(kw["env"]) if "env" in kw else None,
                    namespace=ast.literal_eval(kw["namespace"]) if "namespace" in kw else NAMESPACE,
                )
            )
            start = text.find("\n@register_task(", end)
    return tuple(out)


def register_envs() -> list[str]:
    """Register every built-in task's ids with Gymnasium (from source: nothing heavy is imported); safe to call
    any number of times. Returns the registered ids."""
    ids = []
    for decl in builtin_declarations():
        if decl.ids[0] not in _REGISTRY:
            _register(decl)
        ids += decl.ids
    return ids


def known_ids() -> list[str]:
    """Every registered id, built-in (from source, cheap) and of any task module imported since."""
    register_envs()
    return list(_REGISTRY)


def import_builtin_tasks() -> None:
    """Import every built-in task module (its decorator then holds the full declaration)."""
    for decl in builtin_declarations():
        importlib.import_module(decl.module)


def registered(namespace: str | None = NAMESPACE) -> dict[str, Declaration]:
    """id -> declaration of every registered task of ``namespace`` (None: of every namespace), the built-in
    ones imported (so complete), in registration order."""
    import_builtin_tasks()
    return {i: d for i, d in _REGISTRY.items() if namespace is None or d.namespace == namespace}


def task_class(env_id: str) -> type:
    """The task class of a registered id (``vessel_gym/`` may be left out)."""
    decl = declaration(env_id)
    return getattr(importlib.import_module(decl.module), decl.name)


def declaration(env_id: str) -> Declaration:
    """The declaration of a registered id (``vessel_gym/`` may be left out); KeyError names the known ids."""
    env_id = env_id if "/" in env_id else f"{NAMESPACE}/{env_id}"
    decl = _REGISTRY.get(env_id)
    if decl is None:
        register_envs()
        decl = _REGISTRY.get(env_id)
    if decl is None:
        raise KeyError(f"{env_id} is no registered task id (have: {', '.join(_REGISTRY)})")
    if decl.metrics is None and not decl.pilots and not decl.train:  # read from source: import for the rest
        importlib.import_module(decl.module)
        decl = _REGISTRY[env_id]
    return decl


def preset_of(env: Any) -> str | None:
    """The preset (id without namespace) an environment was made with, if any."""
    return getattr(getattr(env, "unwrapped", env).task, "preset", None)
