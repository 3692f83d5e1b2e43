"""The CollisionAvoidance results table: Wilson intervals, the command and its page block."""

from __future__ import annotations

import pytest

from agents import colreg_results


def test_wilson_interval_matches_the_published_formula():
    # Wilson (1927); e.g. Newcombe (1998), Stat. Med. 17, 857-872, Table I: 0/20 -> 0 to 0.1611, 10/20 -> 0.2993 to 0.7007
    lo, hi = colreg_results.wilson(0, 20)
    assert lo == 0.0 and hi == pytest.approx(0.1611, abs=1e-4)
    lo, hi = colreg_results.wilson(10, 20)
    assert lo == pytest.approx(0.2993, abs=1e-4) and hi == pytest.approx(0.7007, abs=1e-4)
    lo, hi = colreg_results.wilson(20, 20)
    assert lo == pytest.approx(0.8389, abs=1e-4) and hi == 1.0


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--agents", "nope"], "no pilot"),
        (["--cases", "23"], "no Imazu case"),
        (["--set", "dnv", "--cases", "56"], "no DNV baseline case"),
        (["--write", "nope.md"], "no such"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(argv, needle, capsys):
    assert colreg_results.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0]


def test_one_case_writes_the_block_of_the_page(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(f"# x\n\n{colreg_results.BEGIN}\nold\n{colreg_results.END}\ntail\n")
    assert colreg_results.main(["--episodes", "1", "--cases", "1", "--write", str(page)]) == 0
    text = page.read_text()
    assert "old" not in text and text.endswith(f"{colreg_results.END}\ntail\n")
    assert "| 1 | `scripted` | 0.0 [0.0, 79.3] | 100.0 [20.7, 100.0] |" in text
    assert "| 1 | `pid` | 100.0 [20.7, 100.0] | 0.0 [0.0, 79.3] |" in text


def test_a_dnv_situation_writes_its_own_block(tmp_path):
    page = tmp_path / "page.md"
    dnv = colreg_results.SETS["dnv"][2]
    page.write_text(
        f"{colreg_results.BEGIN}\nimazu\n{colreg_results.END}\n{dnv}\nold\n{colreg_results.END}\n"
    )
    argv = ["--set", "dnv", "--episodes", "1", "--cases", "7", "--write", str(page)]
    assert colreg_results.main(argv) == 0
    text = page.read_text()
    assert "imazu" in text and "old" not in text and "1 dnv cases" in text
    # situation 7 (head-on and crossing give-way): the route follower collides, the velocity obstacles pass
    assert "| 7 (HO, CR-GW) | `scripted` | 0.0 [0.0, 79.3] | 100.0 [20.7, 100.0] |" in text
    assert "| 7 (HO, CR-GW) | `pid` | 100.0 [20.7, 100.0] | 0.0 [0.0, 79.3] |" in text
