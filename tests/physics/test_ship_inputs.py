"""Bad input never crashes: unreadable ship files and implausible ships are one line on stderr naming the
file (and the key and allowed range) with exit code 2; Environment checks its ranges at construction."""

from __future__ import annotations

import math
import os
import re
import sys
import time
from pathlib import Path

import pytest

from vessel_gym.cli import main
from vessel_gym.physics.environment import Environment
from vessel_gym.physics.schema import SpecError
from vessel_gym.physics.shipchecks import ShipFileError
from vessel_gym.physics.shipfile import MAX_SHIP_FILE_BYTES, SHIP_DIR, builtin_ships, load_ship

BUILTIN_TEXT = {name: (SHIP_DIR / f"{name}.toml").read_text() for name in builtin_ships()}


def _imo(path: Path | str, capsys) -> tuple[int, str]:
    """``vessel-gym imo PATH`` in-process: (exit code, stderr). Every case here fails while loading."""
    t0 = time.monotonic()
    code = main(["imo", str(path)])
    assert time.monotonic() - t0 < 10.0, "a bad file must fail at once, not hang"
    err = capsys.readouterr().err
    return code, err


def _one_line(err: str) -> str:
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def _variant(tmp_path: Path, name: str, old: str, new: str, filename: str = "my_ship.toml") -> Path:
    text = BUILTIN_TEXT[name]
    assert old in text, old
    p = tmp_path / filename
    p.write_text(text.replace(old, new, 1))
    return p


# ------------------------------------------------------------------------------------------- unreadable files
def test_400_digit_integer_is_one_line_naming_file_and_key(tmp_path, capsys):
    path = _variant(tmp_path, "kvlcc2", "L_m = 320.0", "L_m = " + "9" * 400)
    code, err = _imo(path, capsys)
    line = _one_line(err)
    assert code == 2 and str(path) in line and "L_m" in line and "too large" in line


@pytest.mark.parametrize(
    ("old", "key"),
    [
        ("Y_vvv = -8.078000e-02", "Y_vvv"),  # a free-form derivative table
        ("torque_map_fuel = [0.0, 0.2,", "torque_map_fuel"),  # inside a list, 400 digits
    ],
)
def test_huge_integer_anywhere(tmp_path, old, key):
    new = old.replace("-8.078000e-02", "1" + "0" * 400).replace("[0.0, 0.2,", "[0.0, " + "7" * 400 + ",")
    path = _variant(tmp_path, "mariner", old, new)
    with pytest.raises(ShipFileError, match=rf"^{re.escape(str(path))} .*{key}.*too large"):
        load_ship(path)


def test_100000_deep_array_is_one_line(tmp_path, capsys):
    path = _variant(tmp_path, "kvlcc2", "L_m = 320.0", "L_m = " + "[" * 100_000 + "]" * 100_000)
    code, err = _imo(path, capsys)
    line = _one_line(err)
    assert code == 2 and str(path) in line and "nested too deeply" in line


def test_moderately_deep_array_names_the_key(tmp_path):
    """Nesting the TOML parser still accepts is a type error on the key, printed short."""
    path = _variant(tmp_path, "kvlcc2", "L_m = 320.0", "L_m = " + "[" * 200 + "1" + "]" * 200)
    with pytest.raises(ShipFileError) as info:
        load_ship(path)
    msg = str(info.value)
    assert "L_m: expected a number" in msg and len(msg) < len(str(path)) + 200


def test_directory_as_ship_file(tmp_path, capsys):
    d = tmp_path / "ships.toml"
    d.mkdir()
    code, err = _imo(d, capsys)
    line = _one_line(err)
    assert code == 2 and str(d) in line and "is a directory" in line


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_device_as_ship_file_is_not_read(capsys):
    code, err = _imo("/dev/zero", capsys)
    line = _one_line(err)
    assert code == 2 and "/dev/zero" in line and "not a regular file" in line


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_pipe_as_ship_file_does_not_hang(tmp_path, capsys):
    """A FIFO with no writer (like /dev/stdin on a terminal) would block open(); it is refused unread."""
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    code, err = _imo(fifo, capsys)
    line = _one_line(err)
    assert code == 2 and str(fifo) in line and "not a regular file" in line


def test_file_above_the_size_bound(tmp_path, capsys):
    path = tmp_path / "big.toml"
    path.write_text(BUILTIN_TEXT["kvlcc2"] + "#" * MAX_SHIP_FILE_BYTES + "\n")
    code, err = _imo(path, capsys)
    line = _one_line(err)
    assert code == 2 and str(path) in line and "larger than the limit of 1 MiB" in line


def test_invalid_utf8_names_the_file(tmp_path, capsys):
    path = tmp_path / "latin1.toml"
    path.write_bytes(BUILTIN_TEXT["kvlcc2"].replace('name = "kvlcc2"', 'name = "K\xf8ge"').encode("latin-1"))
    code, err = _imo(path, capsys)
    line = _one_line(err)
    assert code == 2 and str(path) in line and "not UTF-8" in line


@pytest.mark.skipif(sys.platform == "win32" or os.geteuid() == 0, reason="root reads everything")
def test_unreadable_file(tmp_path, capsys):
    path = _variant(tmp_path, "kvlcc2", "L_m", "L_m")
    path.chmod(0)
    code, err = _imo(path, capsys)
    line = _one_line(err)
    assert code == 2 and str(path) in line and "cannot read" in line


# ------------------------------------------------------------------------------------------- plausibility
@pytest.mark.parametrize("name", builtin_ships())
def test_builtin_ships_pass_the_plausibility_checks(name):
    load_ship(name)


# (case, built-in, old text, new text, key the message must name, phrase)
IMPLAUSIBLE = [
    ("1 kg for a 161 m ship", "mariner", "mass_kg = 17045423.0", "mass_kg = 1.0", "mass_kg", "outside ["),
    ("mass 1e30", "mariner", "mass_kg = 17045423.0", "mass_kg = 1e30", "mass_kg", "outside the allowed"),
    (
        "displacement ten times rho L B T C_b",
        "kvlcc2",
        "displacement_m3 = 312600.0",
        "displacement_m3 = 512600.0",
        "displacement_m3",
        "factor 1.2",
    ),
    (
        "k_zz 0.05 L",
        "kvlcc2",
        "k_zz_m = 80.0 ",
        "k_zz_m = 16.0 ",
        "k_zz_m",
        "0.05 L is outside [0.15, 0.35] L",
    ),
    (
        "I_zG a hundred times too large",
        "mariner",
        "I_zG_kgm2 = 2.14517507e10",
        "I_zG_kgm2 = 2.14517507e12",
        "I_zG_kgm2",
        "radius of gyration",
    ),
    (
        "shaft inertia 1e300",
        "kvlcc2",
        "shaft_inertia_kgm2 = 5.0e5",
        "shaft_inertia_kgm2 = 1e300",
        "shaft_inertia_kgm2",
        "outside the allowed",
    ),
    (
        "shaft inertia of a toy propeller on a 9.86 m propeller",
        "kvlcc2",
        "shaft_inertia_kgm2 = 5.0e5",
        "shaft_inertia_kgm2 = 0.1",
        "shaft_inertia_kgm2",
        "rho D^5",
    ),
    ("engine inertia", "dtc", "inertia_kgm2 = 2.5e6", "inertia_kgm2 = 100.0", "inertia_kgm2", "run-up time"),
    (
        "negative torque with fuel",
        "kvlcc2",
        "[-0.060, 0.164, 0.388, 0.550, 0.550, 0.550],",
        "[-0.060, -0.164, 0.388, 0.550, 0.550, 0.550],",
        "torque_map[0][1]",
        "outside [0, inf]",
    ),
    (
        "positive torque without fuel",
        "kvlcc2",
        "[-0.060, 0.164, 0.388, 0.550, 0.550, 0.550],",
        "[0.060, 0.164, 0.388, 0.550, 0.550, 0.550],",
        "torque_map[0][0]",
        "without fuel",
    ),
    (
        "torque falling with fuel",
        "kvlcc2",
        "[-0.060, 0.164, 0.388, 0.550, 0.550, 0.550],",
        "[-0.060, 0.164, 0.388, 0.550, 0.450, 0.550],",
        "torque_map[0]",
        "must not decrease",
    ),
    ("resistance 1e30 N", "dtc", "resistance_N = 3.29e6", "resistance_N = 1e30", "resistance_N", "outside"),
]


@pytest.mark.parametrize(
    ("case", "name", "old", "new", "key", "phrase"), IMPLAUSIBLE, ids=[c[0] for c in IMPLAUSIBLE]
)
def test_implausible_ship_is_one_line_with_key_and_range(tmp_path, capsys, case, name, old, new, key, phrase):
    path = _variant(tmp_path, name, old, new)
    code, err = _imo(path, capsys)
    line = _one_line(err)
    assert code == 2, case
    assert str(path) in line and key in line and phrase in line, line


def test_mass_check_without_block_coefficient(tmp_path):
    """Without C_b the implied block coefficient must lie in [0.35, 1.0] (Mariner: 0.54)."""
    path = _variant(tmp_path, "mariner", "mass_kg = 17045423.0", "mass_kg = 34000000.0")  # C_B 1.08
    with pytest.raises(ShipFileError, match=r"mass_kg: .*\[0.35, 1\] \(give C_b"):
        load_ship(path)
    ok = _variant(tmp_path, "mariner", "mass_kg = 17045423.0", "mass_kg = 30000000.0", "ok.toml")  # C_B 0.95
    assert load_ship(ok).mass_kg == 3.0e7


# ------------------------------------------------------------------------------------------- environment
@pytest.mark.parametrize(
    ("kwargs", "phrase"),
    [
        ({"wind_speed_m_s": 200.0}, "wind_speed_m_s: 200 m/s is outside the allowed range [0, 60]"),
        ({"wind_speed_m_s": math.nan}, "wind_speed_m_s: value must be finite"),
        ({"current_speed_m_s": -1.0}, "current_speed_m_s: -1 m/s is outside the allowed range [0, 6]"),
        ({"Hs_m": 30.0}, "Hs_m: 30 m is outside the allowed range [0, 16]"),
        ({"Tp_s": math.inf}, "Tp_s: value must be finite"),
        ({"air_temperature_k": 20.0}, "air_temperature_k: 20 K is outside"),
        ({"wave_from_deg": "north"}, "wave_from_deg: expected a number"),
    ],
)
def test_environment_checks_ranges_at_construction(kwargs, phrase):
    with pytest.raises(SpecError, match=re.escape(phrase)) as info:
        Environment(**kwargs)
    assert isinstance(info.value, ValueError)
    assert str(info.value).startswith("Environment ")


def test_environment_in_range_constructs():
    e = Environment(wind_speed_m_s=60.0, current_speed_m_s=6.0, Hs_m=16.0, Tp_s=25.0, wind_from_deg=-360.0)
    assert e.wind_speed_m_s == 60.0


def test_integer_beyond_the_parser_digit_limit(tmp_path):
    path = _variant(tmp_path, "kvlcc2", "L_m = 320.0", "L_m = " + "7" * 5000)
    with pytest.raises(ShipFileError, match=rf"^{re.escape(str(path))}: a number is too long"):
        load_ship(path)


@pytest.mark.parametrize(
    "name",
    ["x" * 5000, "kv\x00lcc2", "kv\x00lcc2.toml", "/" + "x" * 5000 + ".toml"],
    ids=["long", "nul", "nul-path", "long-path"],
)
def test_unusable_names_and_paths(name, capsys):
    """Names the file system refuses (too long, a NUL byte) are one line, not an OSError traceback."""
    code, err = _imo(name, capsys)
    line = _one_line(err)
    assert code == 2 and ("unknown ship" in line or "cannot read" in line)
    assert len(line) < 300 or "cannot read" in line
