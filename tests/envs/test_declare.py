"""The task declarations: every positional thing (kernel columns, weights, ``info`` keys, observation layout, the
docs tables) is derived from one declaration of names per task, and a reordered declaration relabels nothing.

The failure these tests guard against: reward terms written by column index in a kernel and named by the field
order of a weights dataclass, with nothing tying the two (reordering ZigZag's weights once reported the heading
error as ``speed_loss``, weighted 0.5).
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import math
import re
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from tests.envs.helpers import ENV_IDS
from vessel_gym.envs import tasks
from vessel_gym.envs.declare import FeatureSpec, TaskSpec, Term, columns
from vessel_gym.envs.registration import builtin_declarations
from vessel_gym.envs.tasks import zigzag
from vessel_gym.envs.tasks.zigzag import ZigZagTask, zigzag_update

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs" / "envs.md"


def _make(env_id: str, **kw):
    return gym.make(env_id, disable_env_checker=True, **kw)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_everything_positional_comes_from_the_declaration(env_id):
    """Per registered id: weights class fields, weight vector, kernel columns, ``info["reward_terms"]`` keys
    (single and vector environment) and the observation layout all follow the task's declaration."""
    env = _make(env_id, observation_type="physical")
    task = env.unwrapped.task
    spec = task.spec
    names = spec.term_names
    assert names == tuple(t.name for t in spec.terms)
    # kernel columns: term j of the declaration is column j of the reward-term rows, feature likewise
    assert tuple(spec.TERM) == tuple(range(len(names))) and spec.TERM._fields == names
    assert spec.FEAT._fields == spec.feature_names
    # the weights config class has the terms as fields in declaration order; the weight vector is read by name
    reward = task.config.reward
    assert tuple(f.name for f in dataclasses.fields(reward)) == names
    assert task.term_names == names
    assert task.weights.shape == (len(names),)
    for j, t in enumerate(spec.terms):
        assert getattr(type(reward)(), t.name) == t.weight  # default weight declared once
        harbour_time = "HarbourApproach-v" in env_id and t.name == "time"
        if not harbour_time:  # the harbour task (v1 on) charges time per L / U_T
            assert task.weights[j] == getattr(reward, t.name)
    # info keys, single and vector
    _obs, info = env.reset(seed=0)
    assert tuple(info["reward_terms"]) == names
    obs, r, _te, _tr, info = env.step(env.action_space.sample())
    assert tuple(info["reward_terms"]) == names
    assert math.isclose(sum(info["reward_terms"].values()), r, rel_tol=1e-12, abs_tol=1e-12)
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    _vobs, vinfo = venv.reset(seed=0)
    assert tuple(vinfo["reward_terms"]) == names
    # observation layout: declared features in the observed order, each at its declared column
    layout = env.unwrapped.observation_layout
    for feat in layout.features:
        base = re.sub(r"_\d+$", "", feat.name) if feat.name not in spec.feature_names else feat.name
        assert feat.column >= getattr(spec.FEAT, base)
        if base == feat.name:
            assert feat.column == getattr(spec.FEAT, base)
            value = np.clip(task.feat[0, feat.column], -feat.scale, feat.scale)
            assert np.isclose(layout.value(obs, feat.name), value, rtol=1e-6, atol=1e-6)
    env.close()
    venv.close()


def _rollout_terms(env, steps: int = 60) -> list[dict[str, float]]:
    env.reset(seed=3)
    out = []
    for i in range(steps):
        a = np.array([0.8 if (i // 15) % 2 == 0 else -0.6], dtype=np.float32)
        _o, _r, _te, _tr, info = env.step(a)
        out.append(info["reward_terms"])
    return out


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_reordered_declaration_relabels_nothing(monkeypatch):
    """Reverse ZigZag-v1's reward terms in the declaration: the kernel's columns, the weights and the info keys
    move with it, and every term keeps its value under its own name (the kernel runs un-jitted so that it reads
    the reordered columns)."""
    reference = _rollout_terms(_make("vessel_gym/ZigZag-v1", observation_type="physical"))
    spec = zigzag.SPEC
    reordered = TaskSpec(spec.title, tuple(reversed(spec.terms)), spec.features, info=spec.info)
    assert reordered.TERM.heading_error == len(spec.terms) - 1  # the heading error moved to the last column
    monkeypatch.setattr(zigzag, "TERM", reordered.TERM)
    monkeypatch.setattr(ZigZagTask, "spec", reordered)
    monkeypatch.setattr(ZigZagTask, "kernel", staticmethod(zigzag_update.py_func))
    env = _make("vessel_gym/ZigZag-v1", observation_type="physical")
    assert env.unwrapped.task.term_names == tuple(reversed(spec.term_names))
    moved = _rollout_terms(env)
    assert [tuple(t) for t in moved] == [tuple(reversed(tuple(t))) for t in reference]
    for a, b in zip(reference, moved):
        assert a == pytest.approx(b, rel=0, abs=0)
    assert any(t["heading_error"] < 0.0 for t in moved) and any(t["speed_loss"] < 0.0 for t in moved)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_terms_mean_what_their_names_say():
    """ZigZag-v1's named terms against the named features they are made of (a column mix-up fails here)."""
    env = _make("vessel_gym/ZigZag-v1", observation_type="physical", first_change_s=[0.0, 0.0])
    task = env.unwrapped.task
    layout = env.unwrapped.observation_layout
    w = task.config.reward
    obs, _info = env.reset(seed=1)
    prev_order = layout.value(obs, "rudder_order")
    U0 = task.ts[0, zigzag.S.U0]
    for i in range(40):
        a = np.array([0.5 if i < 20 else -0.5], dtype=np.float32)
        obs, _r, _te, _tr, info = env.step(a)
        terms = info["reward_terms"]
        err = layout.value(obs, "heading_error")
        assert terms["heading_error"] == pytest.approx(-w.heading_error * abs(err) / math.pi, rel=1e-6)
        order = layout.value(obs, "rudder_order")
        limit = task.rudder_scale()
        assert terms["rudder_activity"] == pytest.approx(
            -w.rudder_activity * abs(order - prev_order) / (2.0 * limit), rel=1e-6, abs=1e-12
        )
        U = math.hypot(layout.value(obs, "u"), layout.value(obs, "v"))
        assert terms["speed_loss"] == pytest.approx(
            -w.speed_loss * max(0.0, U0 - U) / U0, rel=1e-5, abs=1e-7
        )  # float32 u, v
        prev_order = order


def test_docs_carry_the_generated_tables():
    """docs/envs.md holds the tables generated from the registered tasks (ids and presets, config keys, reward
    terms, features), exactly: ``python -m vessel_gym.envs.tasks --check docs/envs.md`` exits 0 (regenerate
    with ``python -m vessel_gym.envs.tasks docs/envs.md``)."""
    assert tasks.docs_block() in DOCS.read_text() and tasks.ids_block() in DOCS.read_text()
    from vessel_gym.envs.tasks.__main__ import main

    assert main(["--check", str(DOCS)]) == 0


def test_docs_check_fails_on_a_stale_page(tmp_path, capsys):
    from vessel_gym.envs.tasks.__main__ import main

    stale = tmp_path / "envs.md"
    stale.write_text(DOCS.read_text().replace("| `vessel_gym/ZigZag-v1` |", "| `vessel_gym/ZigZag-v9` |"))
    assert main(["--check", str(stale)]) == 1
    assert "stale" in capsys.readouterr().out


def test_a_reordered_declaration_no_longer_matches_the_docs():
    """The docs check can fail: a declaration with two terms swapped gives a table the docs do not carry."""
    doc = DOCS.read_text()
    spec = zigzag.SPEC
    t = spec.terms
    swapped = TaskSpec(spec.title, (t[1], t[0], *t[2:]), spec.features)
    assert spec.reward_table() in doc
    assert swapped.reward_table() not in doc


def test_declarations_refuse_what_would_be_ambiguous():
    with pytest.raises(ValueError, match="duplicate"):
        columns("a", "b", "a")
    with pytest.raises(ValueError, match="duplicate"):
        TaskSpec("x", (Term("a", 1.0, ""), Term("a", 1.0, "")), ())
    with pytest.raises(ValueError, match="only the last"):
        TaskSpec("x", (), (FeatureSpec("b", "m", (1.0, "L"), "", "n"), FeatureSpec("c", "m", (1.0, "L"), "")))
    spec = zigzag.SPEC
    other = TaskSpec("y", tuple(reversed(spec.terms)), spec.features)
    with pytest.raises(ValueError, match="differ"):
        other.weights_class("Other", __name__, "", base=zigzag.ZigZagReward)
    with pytest.raises(ValueError, match="replaces no term"):
        spec.variant("z", nope=Term("nope", 1.0, ""))


def test_tasks_ask_the_physics_by_name():
    """No task module reads the simulation's state, input or environment rows by column: they import no layout
    constants and call the named accessors of physics.kinematics."""
    for path in sorted((ROOT / "vessel_gym" / "envs" / "tasks").glob("*.py")):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                assert node.module != "vessel_gym.physics.layout", path.name
                assert not (
                    node.module == "vessel_gym.physics" and any(a.name == "layout" for a in node.names)
                )
        assert not re.search(r"\blo\.[XUE]_", path.read_text()), path.name


def _docstring_table(doc: str, section: str) -> list[list[str]]:
    """The rows (cells) of the first table under ``## section`` of a spec sheet, header and rule excluded."""
    part = doc.split(f"## {section}", 1)[1].split("\n    ## ", 1)[0]
    rows = [line.strip() for line in part.splitlines() if line.strip().startswith("|")]
    return [[c.strip() for c in row.strip("|").split("|")] for row in rows[2:]]


@pytest.mark.parametrize("entry", sorted({d.entry_points()[0] for d in builtin_declarations()}))
def test_spec_sheets_follow_the_declarations(entry):
    """Each environment's spec sheet (its class docstring) lists the declared reward terms in declaration order
    with their default weights, and observes only declared features."""
    import importlib

    module, name = entry.split(":")
    cls = getattr(importlib.import_module(module), name)
    spec = cls.Task.spec
    terms = _docstring_table(cls.__doc__, "Rewards")
    assert [row[0] for row in terms] == list(spec.term_names)
    assert [float(row[1]) for row in terms] == [t.weight for t in spec.terms]
    if "| Num | Name |" in cls.__doc__:
        names = [row[1] for row in _docstring_table(cls.__doc__, "Observation Space")]
        for name in names:
            base = name.split("_j")[0] if name.startswith("beam") else name
            assert base in spec.feature_names or name.startswith(("wind_angle_sin", "current_x")), name


def test_envs_shim_modules_are_gone():
    """Every name has one home: the old envs.core and envs.kernels re-exports, the one-call step and the lazy
    info are not importable."""
    for name in ("core", "kernels", "onestep", "info", "zigzag", "turning", "harbour"):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(f"vessel_gym.envs.{name}")
