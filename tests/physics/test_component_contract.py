"""The component contract: the built-ins declared in one table, checked replacement, components from a ship
file reaching the simulation, the IMO trials and the environments (docs/components.md)."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from vessel_gym.physics import layout as lo
from vessel_gym.physics.components import SLOTS
from vessel_gym.physics.components.compose import builtin_slots, delta_monomials
from vessel_gym.physics.components.registry import BUILTINS
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.integrate import forces_batch
from vessel_gym.physics.kinematics import coriolis_forces
from vessel_gym.physics.params import BODY, HULL, WAVE_DRIFT, WINDAGE
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import load_ship
from vessel_gym.physics.simulation import Simulation
from vessel_gym.physics.vessel import FORCE_NAMES, N_OUT, derivatives

DOC = Path(__file__).resolve().parents[2] / "docs" / "components.md"


def _doc_module(name: str) -> str:
    """The source of the module ``name`` shown in docs/components.md (``<!-- file: name -->``)."""
    m = re.search(rf"<!-- file: {re.escape(name)} -->\n```python\n(.*?)\n```", DOC.read_text(), re.S)
    assert m, f"docs/components.md shows no {name}"
    return m.group(1) + "\n"


@pytest.fixture
def user_models(tmp_path, monkeypatch):
    """The docs' user modules (my_hull, my_thruster, my_rudder) importable from tmp_path."""
    for name in ("my_hull.py", "my_thruster.py", "my_rudder.py"):
        (tmp_path / name).write_text(_doc_module(name))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("VESSEL_GYM_ALLOW_CODE", "1")  # these ship files name the test's own modules
    yield tmp_path
    for name in ("my_hull", "my_thruster", "my_rudder"):
        sys.modules.pop(name, None)


LINEAR_HULL = """[hull]
model = "my_hull:LinearHull"
m_x = 0.022
m_y = 0.223
J_z = 0.011
R_0 = 0.022
Y_v = -0.315
Y_r = 0.083
N_v = -0.137
N_r = -0.049
"""


def _replace_hull(text: str, table: str = LINEAR_HULL) -> str:
    start = text.index("[hull]")
    end = text.index("\n[", start + 1)
    return text[:start] + table + text[end:]


# --- 1. the registry ----------------------------------------------------------------------------------------
def test_registry_declares_every_builtin_force_once():
    for spec in BUILTINS:
        assert spec.slot in SLOTS
        assert len(spec.forces) == 3 and all(f == "" or f in FORCE_NAMES for f in spec.forces)
        assert all(s in lo.STATE_NAMES for s in spec.states)
        assert callable(spec.function) and spec.citation
    summed = {"X_H", "Y_H", "N_H", "X_P", "X_R", "Y_R", "N_R", "X_W", "Y_W", "N_W", "X_D", "Y_D", "N_D"}
    declared = {f for s in BUILTINS if s.name != "derivative_rudder" for f in s.forces if f}
    assert declared == summed
    owned = [
        st for s in BUILTINS for st in s.states
    ]  # every integrated state but the rigid body's has one owner
    assert sorted(owned) == sorted(set(owned)) == ["delta", "governor", "n", "reversing_gear"]


@pytest.mark.parametrize("ship", ["kvlcc2", "mariner", "dtc"])
def test_named_forces_sum_to_the_equations_of_motion(ship):
    """Sum of the named force records + the Coriolis terms = M nu' from the kernel (surge: m11 u')."""
    env = Environment(wind_speed_m_s=15.0, wind_from_deg=40.0, Hs_m=2.0, Tp_s=9.0, wave_from_deg=60.0)
    sim = Simulation(ship)
    sim.reset()
    sim.set_environment(env)
    sim.set_helm(rudder_order_rad=0.3)
    sim.advance(30.0)
    rec = sim.named_forces()
    X = sum(f.X for f in rec.values())[0]
    P, x = sim.Ps[0], sim.state[0]
    xd = np.zeros(lo.NX)
    derivatives(P, x, sim.inputs[0], sim.env[0], np.zeros(3), xd)
    Xc = coriolis_forces(P, x[lo.X_U], x[lo.X_V], x[lo.X_R])[0]
    assert P[BODY.m11] * xd[lo.X_U] == pytest.approx(X + Xc, rel=1e-9, abs=1e-6 * abs(X))


# --- 2. replacement is checked ----------------------------------------------------------------------------
def test_replace_rudder_removes_the_hull_delta_terms():
    sim = Simulation("mariner", replace=["rudder"])
    assert len(delta_monomials(Simulation("mariner").Ps[0])) > 0
    assert len(delta_monomials(sim.Ps[0])) == 0
    assert "rudder" not in builtin_slots(sim.Ps[0])
    out = np.zeros((2, N_OUT))
    x = np.zeros((2, lo.NX))
    x[:, lo.X_U] = 7.7
    x[1, lo.X_DELTA] = 0.3
    forces_batch(sim.Ps, np.zeros(2, dtype=np.int64), x, np.zeros((2, lo.NU)), np.zeros((2, lo.NE)), out)
    assert np.array_equal(out[0, :3], out[1, :3])  # hull forces no longer see the rudder angle


def test_user_rudder_replacing_the_delta_terms_reproduces_the_builtin_turn(user_models):
    from my_rudder import DerivativeRudder

    def turn(sim):
        sim.reset()
        sim.set_helm(rudder_order_rad=np.radians(20.0))
        sim.advance(120.0)
        return sim.state.copy()

    built_in = turn(Simulation("mariner", dt=0.1))
    user = turn(
        Simulation("mariner", dt=0.1, components=[DerivativeRudder(load_ship("mariner"))], replace=["rudder"])
    )
    # the same terms in numpy: round-off (terms summed in another order) over 1200 RK4 steps
    np.testing.assert_allclose(user, built_in, rtol=1e-8, atol=1e-6)
    assert abs(built_in[0, lo.X_PSI]) > 0.5  # it did turn


def test_rudder_in_an_occupied_slot_raises(user_models):
    from my_rudder import DerivativeRudder

    rudder = DerivativeRudder(load_ship("mariner"))
    with pytest.raises(ValueError, match=r"slot 'rudder', which the ship's derivative_rudder fills.*replace"):
        Simulation("mariner", components=[rudder])
    with pytest.raises(ValueError, match=r"slot 'rudder', which the ship's mmg_rudder fills"):
        Simulation("kvlcc2", components=[rudder])
    with pytest.raises(ValueError, match="filled twice"):
        Simulation("mariner", components=[rudder, rudder], replace=["rudder"])


class _Hull:
    slot = "hull"

    def forces(self, sim, x):
        return np.zeros((x.shape[0], 3))


def test_hull_replacement_needs_added_mass_and_removes_the_builtin_one():
    with pytest.raises(ValueError, match=r"added_mass\(\)"):
        Simulation("kvlcc2", components=[_Hull()], replace=["hull"])
    with pytest.raises(ValueError, match=r"replace=\['hull'\] needs a component with slot = 'hull'"):
        Simulation("kvlcc2", replace=["hull"])
    with pytest.raises(ValueError, match=r"slot 'hull', which the ship's mmg_hull fills"):
        Simulation("kvlcc2", components=[_Hull()])

    class Bare(_Hull):
        def added_mass(self):
            return np.zeros((3, 3))

    sim = Simulation("kvlcc2", components=[Bare()], replace=["hull"])
    s = load_ship("kvlcc2")
    m = s.mass_kg
    assert sim.Ps[0, BODY.m11] == m  # the MMG hull's m_x left with it
    assert sim.Ps[0, BODY.CY_ur] == m and sim.Ps[0, BODY.CX_vr] == m  # rigid-body Coriolis only
    assert sim.Ps[0, HULL.kind] == lo.HULL_NONE


@pytest.mark.parametrize("slot", ["governor", "shaft", "transmission", "propeller", "current"])
def test_slots_not_replaceable_are_refused_with_a_reason(slot):
    with pytest.raises(ValueError, match=rf"replace: '{slot}' is not yet supported: .*(state|kinematics|engine)"):
        Simulation("kvlcc2", replace=[slot])

    class Comp:
        def forces(self, sim, x):
            return np.zeros((x.shape[0], 3))

    Comp.slot = slot
    with pytest.raises(ValueError, match=rf"slot '{slot}' is not yet supported"):
        Simulation("kvlcc2", components=[Comp()])


def test_old_replace_names_still_work():
    sim = Simulation("kvlcc2", replace=["wind", "waves"])
    assert sim.Ps[0, WINDAGE.on] == 0.0 and sim.Ps[0, WAVE_DRIFT.on] == 0.0


# --- 3. components from a ship file --------------------------------------------------------------------------
def test_ship_file_hull_is_used_and_matches_the_linear_mmg_terms(user_models, ship_file):
    path = ship_file("kvlcc2_l7", _replace_hull)
    sim = Simulation(path)
    builtin = Simulation("kvlcc2_l7")
    assert [type(c).__name__ for c in sim.components] == ["LinearHull"]
    x = np.zeros((1, lo.NX))
    U = builtin.ship().test_speed_m_s
    x[0, lo.X_U], x[0, lo.X_V] = U, 0.01 * U  # v' = 0.01: the cubic terms are 1e-4 of the linear ones
    F = sim.component_forces(x)[0][1][0]
    out = np.zeros((1, N_OUT))
    forces_batch(builtin.Ps, builtin.ship_index, x, builtin.inputs, builtin.env, out)
    assert F[1] == pytest.approx(out[0, 1], rel=1e-3)
    assert F[2] == pytest.approx(out[0, 2], rel=1e-3)
    # added mass as the built-in MMG hull's (Yasukawa & Yoshimura 2015 eq. 4)
    np.testing.assert_allclose(
        sim.Ps[0, BODY.m11 : BODY.Minv33 + 1], builtin.Ps[0, BODY.m11 : BODY.Minv33 + 1], rtol=1e-12
    )
    sim.reset()
    sim.set_helm(rudder_order_rad=np.radians(10.0))
    sim.advance(10.0)
    assert sim.r[0] > 0.0 and "LinearHull" in sim.named_forces()


def test_ship_file_component_acts_on_its_ship_only(user_models, ship_file):
    table = '[[components]]\nslot = "extra"\nmodel = "my_thruster:TunnelThruster"\nparams = { thrust_kN = 50.0, x_m = 100.0, order = 1.0 }\n'
    path = ship_file("kvlcc2", lambda t: t + "\n" + table)
    sim = Simulation([path, "kvlcc2"], n=2)
    sim.reset()
    Y = sim.named_forces()["TunnelThruster"].Y
    assert Y.tolist() == [50e3, 0.0]


@pytest.mark.parametrize(
    "table, message",
    [
        (
            '[hull]\nmodel = "no_such_module_xyz:Hull"\n',
            r"\[hull\] model: cannot import module 'no_such_module_xyz'",
        ),
        ('[hull]\nmodel = "my_hull:NoSuchHull"\n', r"\[hull\] model: module 'my_hull' has no 'NoSuchHull'"),
        ('[hull]\nmodel = "my hull:X"\n', r"\[hull\] model: 'my hull:X' is not an import path"),
        (LINEAR_HULL.replace("Y_v = -0.315", "Y_v = 0.3"), r"\[hull\] params Y_v"),
        (LINEAR_HULL + "X_vv = 1.0\n", r"\[hull\] params.*X_vv"),
    ],
)
def test_bad_ship_file_component_is_a_one_line_error(user_models, ship_file, table, message):
    path = ship_file("kvlcc2_l7", lambda t: _replace_hull(t, table))
    with pytest.raises(ShipFileError, match=message) as err:
        load_ship(path)
    assert "\n" not in str(err.value) and str(path) in str(err.value)


def test_bad_components_entry(user_models, ship_file):
    path = ship_file(
        "kvlcc2", lambda t: t + '\n[[components]]\nslot = "bow"\nmodel = "my_thruster:TunnelThruster"\n'
    )
    with pytest.raises(ShipFileError, match=r"\[\[components\]\]\[0\] slot: 'bow' is not one of"):
        load_ship(path)


def test_cli_manoeuvre_runs_a_ship_file_component(user_models, ship_file, capsys):
    from vessel_gym.cli import main

    free = ship_file("kvlcc2_l7", filename="free.toml")
    pushed = ship_file(
        "kvlcc2_l7",
        lambda t: (
            t + '\n[[components]]\nmodel = "my_thruster:TunnelThruster"\n'
            "params = { thrust_kN = 0.02, x_m = 3.0, order = -1.0 }\n"
        ),
        filename="pushed.toml",
    )
    results = []
    for path in (free, pushed):
        assert main(["manoeuvre", "turning-circle", str(path), "--json"]) == 0
        results.append(json.loads(capsys.readouterr().out))
    assert results[0] != results[1]  # the thruster (pushing the bow to port) changed the turn


@pytest.mark.slow
def test_cli_imo_runs_a_ship_file_hull(user_models, ship_file, capsys):
    from vessel_gym.cli import main

    path = ship_file("kvlcc2_l7", _replace_hull)
    assert main(["imo", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)


def test_env_uses_a_ship_file_component(user_models, ship_file):
    import gymnasium as gym

    import vessel_gym  # noqa: F401  (registers the environments)

    path = ship_file("kvlcc2_l7", _replace_hull)
    env = gym.make("vessel_gym/ZigZag-v1", ship=str(path))
    env.reset(seed=0)
    sim = env.unwrapped.task.sim if hasattr(env.unwrapped, "task") else env.unwrapped.sim
    assert [type(c).__name__ for c in sim.components] == ["LinearHull"]
    for _ in range(3):
        obs, *_ = env.step(env.action_space.sample())
    assert np.all(np.isfinite(obs))
    env.close()
