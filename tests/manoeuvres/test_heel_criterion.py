"""The optional heel-in-turn criterion (2008 IS Code Part A §3.1.3 guidance) and the roll plot of the IMO report:
off by default, refused for a 3-DOF ship, the largest |heel| of the 35 deg turn held to the limit asked for."""

from __future__ import annotations

import contextlib
import io
import json

import pytest

from vessel_gym.cli import main
from vessel_gym.manoeuvres import imo, trials
from vessel_gym.physics.shipfile import load_ship

pytest.importorskip("matplotlib")

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def run(*argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def container_turn():
    """The container ship's 35 deg turn to starboard to 360 deg, as the IMO report runs it."""
    return trials.turning_circle("container", 35.0, until_deg=360.0)


def test_heel_criterion_is_the_largest_heel_of_the_turn(container_turn):
    tc = container_turn
    phi_deg = abs(tc.track.phi) * 180.0 / 3.141592653589793
    (c,) = imo.heel_criteria(tc, imo.IS_CODE_PASSENGER_HEEL_LIMIT_DEG)
    assert c.name == "heel_in_turn" and c.side == "starboard" and c.unit == "deg"
    assert c.value == pytest.approx(phi_deg.max(), rel=1e-12) == abs(tc.max_heel_deg)
    assert "3.1.3" in c.note and c.limit == 10.0
    # the verdict follows the limit: the container ship heels between 5 and 10 deg in this turn (docs/manoeuvres.md)
    assert 5.0 < c.value < 10.0
    assert c.passed and not imo.heel_criteria(tc, 5.0)[0].passed
    assert c.to_dict()["verdict"] == "pass"


def test_a_3dof_turn_has_no_heel_criterion():
    tc = trials.turning_circle("kvlcc2", 35.0, until_deg=180.0)
    assert tc.max_heel_deg is None and imo.heel_criteria(tc, 10.0) == []


def test_heel_limit_refused_for_a_3dof_ship():
    with pytest.raises(ValueError, match="no roll"):
        imo.imo_report("kvlcc2", heel_limit_deg=10.0)
    code, out, err = run("imo", "kvlcc2", "--heel-limit", "10")
    assert code == 2 and out == "" and "--heel-limit" in err and "kvlcc2" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    code, _, err = run("imo", "container", "--heel-limit", "95")
    assert code == 2 and "--heel-limit" in err and "Traceback" not in err


def test_roll_plot_renders_both_sides(container_turn):
    from vessel_gym.manoeuvres import plots

    port = trials.turning_circle("container", -35.0, until_deg=360.0)
    crit = imo.heel_criteria(container_turn, 10.0) + imo.heel_criteria(port, 10.0)
    fig = plots.figure_roll([("35 deg turning test", [container_turn, port])], crit, "heel")
    ax = fig.axes[0]
    assert len(ax.lines) >= 4  # two sides, two limit lines
    png = plots.figure_bytes(fig)
    assert png[:8] == PNG_MAGIC and len(png) > 10_000
    assert plots.report_plot_names(load_ship("container"))["roll"] == "Heel"
    assert "roll" not in plots.report_plot_names(load_ship("kvlcc2"))


@pytest.mark.slow
def test_imo_report_with_heel_limit(tmp_path):
    """The full report of the container ship with --heel-limit 10: the verdict in JSON and HTML, the roll plot."""
    code, out, err = run(
        "imo", "container", "--heel-limit", "10", "--json", "--report", tmp_path / "r", "--plot", tmp_path / "p"
    )
    assert code == 0, err
    data = json.loads(out)
    heel = [c for c in data["criteria"] if c["name"] == "heel_in_turn"]
    assert [c["side"] for c in heel] == ["starboard", "port"]
    assert all(c["limit"] == 10.0 and c["verdict"] == "pass" and 5.0 < c["value"] < 10.0 for c in heel)
    # the MSC.137(76) criteria come first and are the 13 of a report without the option
    assert len(data["criteria"]) == 15 and data["criteria"][13]["name"] == "heel_in_turn"
    html = (tmp_path / "r" / "imo_container.html").read_text(encoding="utf-8")
    assert "§3.1.3" in html and "<b>Heel.</b>" in html
    assert (tmp_path / "p" / "roll.png").read_bytes()[:8] == PNG_MAGIC
