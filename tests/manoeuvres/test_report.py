"""The IMO report a student hands in (HTML, plots with limits and verdicts), output files that are never
replaced without --force, and JSON numbers rounded by their unit."""

from __future__ import annotations

import base64
import contextlib
import io
import json
import re

import pytest

from vessel_gym.cli import main
from vessel_gym.manoeuvres import imo, plots, trials
from vessel_gym.outputs import OutputExistsError, output_target, rounded
from vessel_gym.physics.shipfile import load_ship

pytest.importorskip("matplotlib")

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
SHIP = "kvlcc2"  # the fastest full IMO run among the built-ins (about 1 s warm)


def run(*argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def imo_run(tmp_path_factory):
    """One full IMO run writing the report and the plots (shared by the tests below)."""
    root = tmp_path_factory.mktemp("imo")
    code, out, err = run("imo", SHIP, "--json", "--report", root / "report", "--plot", root / "plots")
    assert code == 0, err
    return root, json.loads(out)


def test_report_is_one_self_contained_html(imo_run):
    root, data = imo_run
    files = list((root / "report").iterdir())
    assert [f.name for f in files] == [f"imo_{SHIP}.html"]
    html = files[0].read_text(encoding="utf-8")
    # no external resources: every src/href is inline data
    refs = re.findall(r'(?:src|href)\s*=\s*"([^"]*)"', html)
    assert refs and all(r.startswith("data:image/png;base64,") for r in refs)
    assert "<link" not in html and "<script" not in html and "url(" not in html
    # every plot embedded as a decodable PNG
    images = re.findall(r'src="data:image/png;base64,([^"]+)"', html)
    assert len(images) == len(plots.REPORT_PLOTS)
    assert all(base64.b64decode(b)[:8] == PNG_MAGIC for b in images)
    # particulars and the citation of the ship file's [source] table
    ship = load_ship(SHIP)
    assert ship.source.citation in html
    assert f"{ship.particulars.B_m:.2f} m" in html and "15.50 kn" in html
    # the criteria table: one row per criterion, with value, limit and verdict
    rows = re.findall(r"<tr><td>.*?</tr>", html)
    assert len(rows) == len(data["criteria"]) == 13
    for row, c in zip(rows, data["criteria"]):
        assert f"{c['limit']:.2f}" in row
        assert (">PASS<" if c["pass"] else ">FAIL<") in row
    assert 'class="overall PASS"' in html


def test_report_plots_exist_with_limits(imo_run):
    root, _ = imo_run
    names = sorted(p.name for p in (root / "plots").iterdir())
    assert names == sorted(f"{stem}.png" for stem in plots.REPORT_PLOTS)
    for p in (root / "plots").iterdir():
        data = p.read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 20_000, p.name


def test_report_and_plots_are_not_replaced(imo_run, tmp_path):
    root, _ = imo_run
    report = root / "report" / f"imo_{SHIP}.html"
    before = report.read_bytes(), (root / "plots" / "stopping.png").read_bytes()
    for argv in (("--report", root / "report"), ("--plot", root / "plots"), ("--report", report)):
        code, out, err = run("imo", SHIP, *argv)
        assert code == 2 and out == ""
        assert len(err.strip().splitlines()) == 1 and "--force" in err, err
    assert (report.read_bytes(), (root / "plots" / "stopping.png").read_bytes()) == before
    # a regular file where a plot directory is meant, and a single-image format for several plots
    afile = tmp_path / "notes"
    afile.write_text("mine")
    for target in (afile, tmp_path / "one.png"):
        code, _, err = run("imo", SHIP, "--plot", target)
        assert code == 2 and len(err.strip().splitlines()) == 1 and "--plot" in err
    assert afile.read_text() == "mine" and not (tmp_path / "one.png").exists()


def test_imo_json_numbers_are_rounded(imo_run):
    _, data = imo_run
    assert data["L_over_V_s"] == 40.1  # 320 m at 15.5 kn; times to 0.1 s
    for c in data["criteria"]:
        decimals = {"L": 3, "deg": 2}[c["unit"]]
        assert c["value"] == round(c["value"], decimals)
    po = data["pull_out"]
    assert all(x == round(x, 4) for x in po["steady_rate_deg_s"] + po["residual_rate_deg_s"])


def test_rounding_rule():
    d = {
        "head_reach_m": 117.59999999999759,
        "advance_L": 3.0723456,
        "overshoot_deg": [5.0234, 13.9149],
        "time_s": 71.4589,
        "final_speed_kn": 6.1234,
        "steady_rate_deg_s": [0.408176338],
        "criteria": [{"value": 3.07234, "limit": 4.5, "unit": "L"}, {"value": 5.01789, "unit": "deg"}],
        "pass": True,
        "n": 3,
        "other": 1.23456789,
        "none": None,
    }
    assert rounded(d) == {
        "head_reach_m": 117.6,
        "advance_L": 3.072,
        "overshoot_deg": [5.02, 13.91],
        "time_s": 71.5,
        "final_speed_kn": 6.12,
        "steady_rate_deg_s": [0.4082],
        "criteria": [{"value": 3.072, "limit": 4.5, "unit": "L"}, {"value": 5.02, "unit": "deg"}],
        "pass": True,
        "n": 3,
        "other": 1.23457,
        "none": None,
    }
    assert json.dumps(rounded({"x_m": 117.59999999999759})) == '{"x_m": 117.6}'


def test_manoeuvre_json_is_rounded():
    code, out, _ = run("manoeuvre", "stopping", "--ship", SHIP, "--json")
    assert code == 0
    d = json.loads(out)
    for k in ("track_reach_m", "head_reach_m", "lateral_deviation_m"):
        assert d[k] == round(d[k], 2)
    assert d["time_s"] == round(d["time_s"], 1) and d["track_reach_L"] == round(d["track_reach_L"], 3)


KINDS = {
    "turning-circle": (),
    "zigzag": ("--overshoots", "2"),
    "initial-turning": (),
    "stopping": (),
    "pull-out": (),
}


@pytest.mark.parametrize(
    "kind",
    # stopping and pull-out plots were the broken ones; the other three run in the slow set
    [k if k in ("stopping", "pull-out") else pytest.param(k, marks=pytest.mark.slow) for k in KINDS],
)
def test_every_manoeuvre_plot_writes_or_refuses(kind, tmp_path):
    # an existing directory (with or without a trailing slash): the plot goes inside it, named by ship and kind
    code, out, err = run("manoeuvre", kind, "--ship", SHIP, *KINDS[kind], "--plot", tmp_path)
    assert code == 0, err
    written = tmp_path / f"{SHIP}_{kind}.png"
    assert sorted(tmp_path.iterdir()) == [written]
    assert written.read_bytes()[:8] == PNG_MAGIC and not (tmp_path.parent / f"{tmp_path.name}.png").exists()
    # a second run refuses and leaves the file as it was
    before = written.read_bytes()
    code, out, err = run("manoeuvre", kind, "--ship", SHIP, *KINDS[kind], "--plot", f"{tmp_path}/")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and "--force" in err
    assert written.read_bytes() == before
    # a named file is written as it is named
    named = tmp_path / "sub" / "mine.svg"
    code, _, err = run("manoeuvre", kind, "--ship", SHIP, *KINDS[kind], "--plot", named)
    assert code == 0, err
    assert named.read_bytes().lstrip().startswith(b"<?xml")


def test_force_replaces_and_bad_suffix_refuses(tmp_path):
    target = tmp_path / "it.png"
    target.write_bytes(b"user data")
    code, _, err = run("manoeuvre", "initial-turning", "--ship", SHIP, "--plot", target)
    assert code == 2 and target.read_bytes() == b"user data"
    code, _, err = run("manoeuvre", "initial-turning", "--ship", SHIP, "--plot", target, "--force")
    assert code == 0 and target.read_bytes()[:8] == PNG_MAGIC
    code, _, err = run("manoeuvre", "initial-turning", "--ship", SHIP, "--plot", tmp_path / "x.txt")
    assert code == 2 and len(err.strip().splitlines()) == 1 and ".txt" in err
    code, _, err = run("manoeuvre", "initial-turning", "--ship", SHIP, "--plot", target / "inside.png")
    assert code == 2 and "not a directory" in err


def test_output_target_rule(tmp_path):
    assert output_target(tmp_path / "a.png", (".png",), "--plot") == (tmp_path / "a.png", False)
    assert output_target(tmp_path / "new", (".png",), "--plot") == (tmp_path / "new", True)
    assert output_target(f"{tmp_path}/x.png/", (".png",), "--plot")[1] is True
    assert output_target(tmp_path, (".png",), "--plot") == (tmp_path, True)
    with pytest.raises(OutputExistsError, match="--plot"):
        output_target(tmp_path / "a.gif", (".png",), "--plot")


# figures: the fixes a user saw, checked on the figure objects


@pytest.fixture(scope="module")
def stop():
    return trials.stopping(SHIP)


def test_stopping_figure_track_axis_and_speed_rpm(stop):
    fig = plots.figure_for(stop, "t", SHIP)
    track, speed, rpm = fig.axes
    lo, hi = track.get_xlim()
    assert hi - lo >= 2.0  # a straight track keeps a +-1 L lateral axis, not a 1e-16 one
    assert track.get_ylim()[1] > imo.STOPPING_LARGE_SHIP_LIMIT_L  # both limits visible
    assert "speed" in speed.get_ylabel() and "rpm" in rpm.get_ylabel()
    texts = " ".join(t.get_text() for ax in fig.axes for t in ax.texts)
    assert "limit 15 L" in texts and "PASS" in texts and "head reach" in texts
    plots.figure_bytes(fig)


def test_zigzag_figure_draws_limits_and_overshoots():
    z = trials.zigzag(SHIP, 10.0, 10.0, n_overshoots=2)
    fig = plots.figure_for(z, "t", SHIP)
    texts = " ".join(t.get_text() for ax in fig.axes for t in ax.texts)
    LV = 320.0 / (15.5 * 1852 / 3600)
    first, second = imo.zigzag10_limits(LV)
    assert f"1st overshoot limit {first:.1f} deg" in texts
    assert f"2nd overshoot limit {second:.1f} deg" in texts
    assert f"1st overshoot {z.overshoot_deg[0]:.2f} deg" in texts and "PASS" in texts
    plots.figure_bytes(fig)


def test_initial_turning_figure_is_not_a_sliver():
    it = trials.initial_turning(SHIP, 10.0)
    fig = plots.figure_for(it, "t", SHIP)
    for ax in fig.axes:
        bb = ax.get_position()
        w, h = bb.width * fig.get_figwidth(), bb.height * fig.get_figheight()
        assert 0.5 < w / h < 2.5
    assert len(fig.axes[0].get_xticks()) <= 10
    plots.figure_bytes(fig)


def test_limits_only_in_the_imo_condition():
    tc = trials.turning_circle(SHIP, 20.0, until_deg=360.0)
    assert imo.criteria_for(tc, SHIP) == []
    fig = plots.figure_for(tc, "t", SHIP)
    texts = " ".join(t.get_text() for t in fig.axes[0].texts)
    assert "no IMO limit" in texts and "PASS" not in texts
    plots.figure_bytes(fig)
    ship = load_ship(SHIP)
    assert [c.name for c in imo.criteria_for(trials.turning_circle(ship, -35.0, until_deg=360.0), ship)] == [
        "advance",
        "tactical_diameter",
    ]


def test_html_names_a_missing_trial():
    from vessel_gym.manoeuvres.report import report_html

    ship = load_ship(SHIP)
    tc = trials.turning_circle(ship, 35.0, until_deg=360.0)
    rep = imo.ImoReport(SHIP, 320.0, 15.5, imo.turning_criteria(tc), {"turning_starboard": tc}, ship)
    html = report_html(rep)
    assert html.count("data:image/png;base64,") == 1 and "Not completed" in html and "Pull-out" in html


def test_pdf_report_has_a_summary_page_and_the_plots(tmp_path):
    from vessel_gym.manoeuvres.report import summary_text, write_report

    ship = load_ship(SHIP)
    tc = trials.turning_circle(ship, 35.0, until_deg=360.0)
    rep = imo.ImoReport(SHIP, 320.0, 15.5, imo.turning_criteria(tc), {"turning_starboard": tc}, ship)
    text = summary_text(rep)
    assert "Yasukawa" in text and "tactical_diameter" in text and "PASS" in text
    out = write_report(rep, tmp_path / "r.pdf")
    data = out.read_bytes()
    assert data[:5] == b"%PDF-" and len(re.findall(rb"/Type /Page[^s]", data)) == 2  # summary + turning
    with pytest.raises(OutputExistsError):
        write_report(rep, out)


def test_report_names_documentation_pages_not_repository_paths(imo_run):
    """The report's reader has the file, not the repository: the ship file's notes name pages of the
    documentation ("physics"), never a path such as docs/physics.md."""
    from vessel_gym.manoeuvres.report import readable_refs

    root, _ = imo_run
    html = (root / "report" / f"imo_{SHIP}.html").read_text(encoding="utf-8")
    assert "docs/" in load_ship(SHIP).source.notes  # what the notes say in the ship file
    assert "docs/" not in html and ".md" not in html
    assert "the vessel-gym documentation, page &quot;physics&quot;" in html
    assert readable_refs('see docs/cfd-dtc-study.md, "Results"') == (
        'see the vessel-gym documentation, page "cfd-dtc-study", "Results"'
    )
