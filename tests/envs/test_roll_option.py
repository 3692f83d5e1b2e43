"""The roll options of the open-water tasks (docs/envs.md "Roll options"): on the 4-DOF `container` ship the
observation can end with roll angle and roll rate, and the reward can carry a heel term; on a 3-DOF ship both
are refused at construction; with the defaults nothing about an environment changes (the reference tests of
tests/envs check that bit for bit; here: no roll column and no ``heel`` key).

The observed roll is compared with the simulation's bridge reading (its own path from the state to heel and roll
rate, in degrees), the heel term with its definition -(phi / heel_ref)^2 x weight.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

from tests.envs import test_api as api
from tests.physics.test_roll import _effective_roll_inertia
from vessel_gym.envs import tasks
from vessel_gym.envs.declare import TaskSpec, Term
from vessel_gym.envs.tasks import turning, zigzag
from vessel_gym.physics.roll import G_M_S2, free_roll_frequency
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.vessel import pack

ROLL_IDS = ("vessel_gym/ZigZag-v1", "vessel_gym/ZigZagRandom-v1", "vessel_gym/TurningCircle-v0")
HEEL_WEIGHT = 2.0
HEEL_REF_DEG = 5.0


def _make(env_id: str, **kw):
    return gym.make(env_id, disable_env_checker=True, **kw)


def _roll_env(env_id: str, **kw):
    return _make(
        env_id,
        ship="container",
        observe_roll=True,
        heel_weight=HEEL_WEIGHT,
        heel_ref_deg=HEEL_REF_DEG,
        **kw,
    )


def test_the_roll_rate_scale_is_the_free_roll_frequency_of_container_m():
    """omega_phi of the packed container ship against sqrt(m g GM / I_eff) with I_eff from container.m's prime
    masses (the independent transcription of tests/physics/test_roll.py); 0.5 %, that test's tolerance on the
    free-roll period it gives."""
    ship = load_ship("container")
    expected = math.sqrt(ship.mass_kg * G_M_S2 * ship.roll.GM_m / _effective_roll_inertia())
    assert free_roll_frequency(pack(ship)) == pytest.approx(expected, rel=0.005)
    assert free_roll_frequency(pack(load_ship("kvlcc2_l7"))) == 0.0


@pytest.mark.parametrize("env_id", ROLL_IDS)
def test_observed_roll_and_heel_term_on_container(env_id):
    """Single environment, physical observation: the last two entries are the bridge's heel and roll rate, the
    heel term is -weight (phi / heel_ref)^2 and the terms still sum to the reward."""
    env = _roll_env(env_id, observation_type="physical")
    task = env.unwrapped.task
    layout = env.unwrapped.observation_layout
    names = [f.name for f in layout.features]
    assert names[-2:] == ["phi", "p"]
    assert tuple(task.spec.term_names_with(True))[-1] == "heel"
    obs, info = env.reset(seed=2)
    assert tuple(info["reward_terms"]) == task.spec.term_names_with(True)
    ref = math.radians(HEEL_REF_DEG)
    sphi, sp = layout.scale[-2:]
    peak, unclipped = 0.0, 0
    for _ in range(120):  # hard to starboard: the container ship heels (to port, outward) in the turn
        obs, r, _te, _tr, info = env.step(np.array([1.0], dtype=np.float32))
        reading = task.sim.bridge(0)
        phi, p = math.radians(reading.roll_deg), math.radians(reading.roll_rate_dps)
        # physical observations are clipped to +-scale (docs/envs.md "Observations")
        assert layout.value(obs, "phi") == pytest.approx(np.clip(phi, -sphi, sphi), rel=1e-6, abs=1e-9)
        assert layout.value(obs, "p") == pytest.approx(np.clip(p, -sp, sp), rel=1e-6, abs=1e-9)  # float32
        assert info["reward_terms"]["heel"] == pytest.approx(-HEEL_WEIGHT * (phi / ref) ** 2, rel=1e-12)
        assert math.isclose(sum(info["reward_terms"].values()), r, rel_tol=1e-12, abs_tol=1e-12)
        peak = max(peak, abs(phi))
        unclipped += abs(phi) < sphi and abs(p) < sp
    assert peak > math.radians(0.5)  # the test saw a heel, not a ship held upright
    assert unclipped > 20  # and compared unclipped values
    env.close()


@pytest.mark.parametrize("env_id", ROLL_IDS)
def test_normalized_roll_uses_the_documented_scales(env_id):
    """Normalized: phi / heel_ref and p / (heel_ref omega_phi)."""
    env = _roll_env(env_id)
    task = env.unwrapped.task
    layout = env.unwrapped.observation_layout
    omega = free_roll_frequency(task.sim.Ps[0])
    ref = math.radians(HEEL_REF_DEG)
    assert layout.scale[-2:] == pytest.approx([ref, ref * omega], rel=1e-15)
    env.reset(seed=0)
    for _ in range(80):
        obs, *_ = env.step(np.array([1.0], dtype=np.float32))
    phi, p = task.sim.state[0, -2:]  # X_PHI, X_P: the last two columns of the state row (docs/physics.md)
    assert obs[-2] == pytest.approx(np.clip(phi / ref, -1, 1), rel=1e-6, abs=1e-7)
    assert obs[-1] == pytest.approx(np.clip(p / (ref * omega), -1, 1), rel=1e-6, abs=1e-7)
    env.close()


@pytest.mark.parametrize("env_id", ROLL_IDS)
def test_vector_environment_observes_roll_per_vessel(env_id):
    """Vector environment of 3: each row's last two entries and heel term are that vessel's."""
    venv = gym.make_vec(
        env_id,
        num_envs=3,
        vectorization_mode="vector_entry_point",
        ship="container",
        observe_roll=True,
        heel_weight=HEEL_WEIGHT,
        heel_ref_deg=HEEL_REF_DEG,
        observation_type="physical",
    )
    task = venv.unwrapped.task
    obs, info = venv.reset(seed=5)
    assert tuple(info["reward_terms"]) == task.spec.term_names_with(True)
    actions = np.array([[1.0], [-1.0], [0.3]], dtype=np.float32)
    sphi, sp = task.layout.scale[-2:]
    ref = math.radians(HEEL_REF_DEG)
    for _ in range(60):
        obs, r, _te, _tr, info = venv.step(actions)
        for k in range(3):
            reading = task.sim.bridge(k)
            phi, p = math.radians(reading.roll_deg), math.radians(reading.roll_rate_dps)
            assert obs[k, -2] == pytest.approx(np.clip(phi, -sphi, sphi), rel=1e-6, abs=1e-9)
            assert obs[k, -1] == pytest.approx(np.clip(p, -sp, sp), rel=1e-6, abs=1e-9)
            assert info["reward_terms"]["heel"][k] == pytest.approx(-HEEL_WEIGHT * (phi / ref) ** 2, rel=1e-12)
        total = sum(info["reward_terms"].values())
        assert np.allclose(total, r, rtol=1e-12, atol=1e-12)
    # the two hard-over vessels heel, to opposite sides
    assert np.all(np.abs(obs[:2, -2]) > math.radians(0.25)) and obs[0, -2] * obs[1, -2] < 0.0
    venv.close()


@pytest.mark.parametrize("env_id", ROLL_IDS)
def test_defaults_on_container_add_no_roll(env_id):
    """Options off (the defaults), even on a ship with roll: the observation and info keys of any ship."""
    env = _make(env_id, ship="container")
    base = _make(env_id)
    names = [f.name for f in env.unwrapped.observation_layout.features]
    assert names == [f.name for f in base.unwrapped.observation_layout.features]
    _obs, info = env.reset(seed=0)
    _obs, _r, _te, _tr, info = env.step(env.action_space.sample())
    assert "heel" not in info["reward_terms"]
    assert tuple(info["reward_terms"]) == env.unwrapped.task.spec.term_names
    env.close()
    base.close()


@pytest.mark.parametrize("env_id", ROLL_IDS)
@pytest.mark.parametrize("option", [{"observe_roll": True}, {"heel_weight": 1.0}])
def test_roll_options_are_refused_on_a_3dof_ship(env_id, option):
    """kvlcc2_l7 (the default ship) has no roll: a one-line SpecError naming the option, at construction, for
    the single and the vector environment."""
    (key,) = option
    with pytest.raises(SpecError, match=rf"^\w+Config: {key} needs a ship with roll[^\n]*'kvlcc2_l7' is 3-DOF$"):
        _make(env_id, **option)
    with pytest.raises(SpecError, match=key):
        gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point", **option)


def test_the_optional_term_is_declared_once():
    """The heel term is the declaration's optional block: its column follows the terms, it is not a field of the
    weights class, the generated docs table lists it marked as an option and the features table the roll
    features; an option may not reuse a term's name."""
    for spec in (zigzag.SPEC, turning.SPEC):
        assert spec.option_names == ("heel",)
        assert spec.OPT.heel == len(spec.term_names)
        assert spec.term_names_with(False) == spec.term_names
        assert "heel" not in spec.term_names
        assert "| `heel` (option) | 0 | heel_weight != 0: -(phi / heel ref)^2 |" in spec.reward_table()
        assert "| `phi` | rad | heel ref |" in spec.feature_table()
        assert "| `p` | rad/s | heel ref x omega_phi |" in spec.feature_table()
    assert zigzag.SPEC.reward_table() in tasks.docs_block()
    env = _roll_env("vessel_gym/ZigZag-v1")
    task = env.unwrapped.task
    assert task.weights[task.spec.OPT.heel] == HEEL_WEIGHT
    assert task.terms.shape[1] == len(task.spec.term_names) + 1
    env.close()
    with pytest.raises(ValueError, match="duplicate"):
        TaskSpec("x", (Term("heel", 1.0, ""),), (), options=(Term("heel", 0.0, ""),))


ROLL_VARIANTS = [
    ("vessel_gym/ZigZag-v1", {"ship": "container", "observe_roll": True, "heel_weight": 1.0}),
    ("vessel_gym/ZigZagRandom-v1", {"ship": "container", "observe_roll": True, "leg_time_s": [2.0, 4.0]}),
    (
        "vessel_gym/TurningCircle-v0",
        {"ship": "container", "observe_roll": True, "heel_weight": 0.5, "mode": "reverse"},
    ),
]
API_CHECKS = (
    "test_gymnasium_check_env_no_warnings",
    "test_sb3_check_env_no_warnings",
    "test_same_seed_same_rollout",
    "test_observations_inside_space_and_finite",
    "test_vector_equals_n_single_envs",
)


@pytest.mark.parametrize("check", API_CHECKS)
@pytest.mark.parametrize("env_id,kw", ROLL_VARIANTS, ids=lambda v: v if isinstance(v, str) else "")
def test_the_api_checks_hold_with_the_roll_options(check, env_id, kw):
    """tests/envs/test_api.py's checks (gymnasium and SB3 env checkers, seeding, observation space, the vector
    environment equal to N single ones) with the roll options on."""
    getattr(api, check)(env_id, kw)
