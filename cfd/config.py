"""Study settings: one validated, frozen :class:`Study` built from CLI arguments or a study TOML file.

Every key has a stated range; :func:`build_study` raises :class:`~cfd.errors.InputError` naming the
key and the allowed range. The same keys are used on the command line (``--pmm-speed``) and in
study files (``pmm_speed``).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib


from .case.common import TIME_SCHEMES
from .errors import InputError
from .regression import CHOICES as DRIFT_FORMS
from .regression import DEFAULT as DRIFT_FORM_DEFAULT

TESTS = ("tow", "drift", "sway", "yaw")
#: tests run only when named: "heel" (static heel, for the roll derivatives of a 4-DOF ship; cfd.heel)
OPTIONAL_TESTS = ("heel",)
GRADINGS = {1: "ULTRA COARSE", 2: "COARSE", 3: "MEDIUM", 4: "FINE", 5: "ULTRA FINE"}
SIMULATION_TYPES = {
    1: ("Steady Straight Ahead Towing", ("tow",)),
    2: ("Steady Oblique Towing", ("drift",)),
    3: ("Pure Sway Motion", ("sway",)),
    4: ("Pure Yaw Motion", ("yaw",)),
    5: ("Full Automated Setup of PMM Motion", TESTS),
}
NORMALISATIONS = ("rho_L2_U2", "half_rho_L2_U2")


@dataclass(frozen=True)
class Study:
    """All settings of one CFD study (SI units; angles in degrees as entered)."""

    hull: str  # path of an STL file, or "wigley"
    lpp: float
    bwl: float
    tm: float
    out: Path
    grading: int = 1
    tests: tuple[str, ...] = TESTS
    name: str = ""
    x_ap: float | None = None
    z_keel: float | None = None
    procs: int = 1
    mesh_procs: int = 1
    template: Path | None = None
    speeds: tuple[float, ...] = ()  # tow speeds (m/s)
    pmm_speed: float = 0.0  # speed of drift, sway and yaw tests (m/s)
    drift_deg: tuple[float, ...] = (2.0, 4.0, 6.0, 8.0, 10.0)
    sway_period: float = 0.0  # s; 0 -> pi * L / U (omega' = 2)
    sway_amplitude: tuple[float, ...] = ()  # m; () -> 0.025 L
    yaw_period: float = 0.0
    yaw_deg: tuple[float, ...] = (4.0,)
    sweep_omega_prime: tuple[float, ...] = ()  # frequency sweep: extra sway/yaw runs at these ω' = ωL/U
    cycles: float = 3.0  # PMM periods simulated after the start ramp
    fit_cycles: int = 2  # last whole periods used in the fits
    rho: float = 999.1  # ITTC 7.5-02-01-03, fresh water 15 °C
    nu: float = 1.1386e-6
    layers: bool = True  # prism layers on the hull, first layer sized for ``yplus``
    yplus: float = 150.0
    wake: bool = True  # a refinement cylinder along the wake of each inflow angle (drift and PMM)
    courant: float = 1.0  # PMM time step: Courant number U dt / h on the hull surface cells
    time_scheme: str = "backward"  # PMM time discretisation: backward (second order) or Euler
    sizing: str = "grading"  # "grading" or "yplus" (seed: background cell = wall distance x 2^levels)
    free_surface: bool = False
    max_iterations: int = 0  # steady SIMPLE iterations; 0 -> by grading
    normalisation: str = "rho_L2_U2"
    scale_to: str = "template"  # "template" or "cfd"
    k_zz: float = 0.0  # m; 0 -> from the template's k_zz/L, else 0.25 L
    form_factor: float = -1.0  # k of (1+k) for full-scale resistance; < 0 -> from the CFD (double body)
    drift_form: str = DRIFT_FORM_DEFAULT  # static-drift regression written to the ship file (cfd.regression)
    heel_deg: tuple[float, ...] = (10.0,)  # static-heel angles (deg, starboard down); one mesh each
    heel_drift_deg: float = 6.0  # drift angle of the heeled drift runs, at + and - this angle (0: none)
    z_G: float = 0.0  # m, model scale: height of G above the still waterline (the roll axis of K)
    GM: float = 0.0  # m, model scale: GM for a new [roll] table (the template has none); scaled with the hull
    k_xx: float = 0.0  # m, model scale: roll radius of gyration for a new [roll] table; scaled with the hull

    @property
    def U_ref(self) -> float:
        return self.pmm_speed

    @property
    def steady_iterations(self) -> int:
        return self.max_iterations or {1: 500, 2: 800, 3: 1200, 4: 2000, 5: 3000}[self.grading]

    def sway_omega(self) -> float:
        return 2.0 * math.pi / self.sway_period

    def yaw_omega(self) -> float:
        return 2.0 * math.pi / self.yaw_period

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["out"] = str(self.out)
        d["template"] = str(self.template) if self.template else None
        return d


# ---------------------------------------------------------------------------------- parsing helpers
def parse_number(
    key: str, value: Any, lo: float, hi: float, *, lo_open: bool = False, integer: bool = False
) -> Any:
    """A number (or integer) in [lo, hi] (or (lo, hi]) from a string or TOML value; InputError names ``key``."""
    rng = f"{'(' if lo_open else '['}{lo:g}, {hi:g}]"
    if isinstance(value, bool):
        raise InputError(key, f"must be a number in {rng} (got {value!r})")
    try:
        x = int(value) if integer and float(value) == int(float(value)) else float(value)
    except (TypeError, ValueError):
        raise InputError(
            key, f"must be {'an integer' if integer else 'a number'} in {rng} (got {value!r})"
        ) from None
    if integer and not isinstance(x, int):
        raise InputError(key, f"must be an integer in {rng} (got {value!r})")
    if not math.isfinite(x) or x < lo or x > hi or (lo_open and x == lo):
        raise InputError(key, f"must be in {rng} (got {value!r})")
    return x


def parse_list(
    key: str, value: Any, lo: float, hi: float, *, lo_open: bool = True, max_count: int = 20
) -> tuple:
    """Numbers from a TOML array, ``"a,b,c"`` or ``"MIN:MAX:COUNT"`` (COUNT values, ends included)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        items: list[Any] = [value]
    elif isinstance(value, str):
        text = value.strip()
        if text.count(":") == 2:
            a, b, n = text.split(":")
            lo_v = parse_number(key, a, lo, hi, lo_open=lo_open)
            hi_v = parse_number(key, b, lo, hi, lo_open=lo_open)
            count = parse_number(key + " count", n, 1, max_count, integer=True)
            if hi_v < lo_v:
                raise InputError(key, f"range {text!r}: MAX must be >= MIN")
            if count == 1:
                items = [lo_v]
            else:
                items = [lo_v + (hi_v - lo_v) * i / (count - 1) for i in range(count)]
        else:
            items = [s for s in text.replace(";", ",").split(",") if s.strip()]
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        raise InputError(key, f"must be a list of numbers in [{lo:g}, {hi:g}] (got {value!r})")
    if not items:
        raise InputError(key, f"needs at least one value in [{lo:g}, {hi:g}]")
    if len(items) > max_count:
        raise InputError(key, f"at most {max_count} values (got {len(items)})")
    vals = tuple(round(parse_number(key, v, lo, hi, lo_open=lo_open), 10) for v in items)
    return tuple(sorted(set(vals)))


def _bool(key: str, value: Any) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.lower() in {"1", "true", "yes", "on", "0", "false", "no", "off"}:
        return value.lower() in {"1", "true", "yes", "on"}
    raise InputError(key, f"must be true or false (got {value!r})")


def _choice(key: str, value: Any, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise InputError(key, f"must be one of {', '.join(choices)} (got {value!r})")
    return value


def parse_tests(value: Any) -> tuple[str, ...]:
    """``"all"``, ``"tow,drift"`` or a list -> ordered tuple of test names."""
    if isinstance(value, str):
        items = [s.strip() for s in value.split(",") if s.strip()]
    elif isinstance(value, (list, tuple)):
        items = [str(s).strip() for s in value]
    else:
        raise InputError("tests", f"must be 'all' or a comma-separated subset of {','.join(TESTS)}")
    if items and items[0] == "all" and set(items[1:]) <= set(OPTIONAL_TESTS):
        return TESTS + tuple(t for t in OPTIONAL_TESTS if t in items)
    known = TESTS + OPTIONAL_TESTS
    bad = [s for s in items if s not in known]
    if bad or not items:
        raise InputError("tests", f"must be 'all' or a subset of {','.join(known)} (got {value!r})")
    return tuple(t for t in known if t in items)


KEYS = (
    "hull",
    "lpp",
    "bwl",
    "tm",
    "out",
    "grading",
    "tests",
    "name",
    "x_ap",
    "z_keel",
    "procs",
    "mesh_procs",
    "template",
    "speeds",
    "pmm_speed",
    "drift_deg",
    "sway_period",
    "sway_amplitude",
    "yaw_period",
    "yaw_deg",
    "sweep_omega_prime",
    "cycles",
    "fit_cycles",
    "rho",
    "nu",
    "layers",
    "yplus",
    "wake",
    "courant",
    "time_scheme",
    "sizing",
    "free_surface",
    "max_iterations",
    "normalisation",
    "scale_to",
    "k_zz",
    "form_factor",
    "drift_form",
    "heel_deg",
    "heel_drift_deg",
    "z_G",
    "GM",
    "k_xx",
)


def build_study(raw: Mapping[str, Any], base_dir: Path | None = None) -> Study:
    """Validate raw settings (strings or TOML values) and fill the defaults that depend on L and U.

    Relative paths in ``raw`` are taken relative to ``base_dir`` (the study file's folder).
    """
    unknown = sorted(set(raw) - set(KEYS))
    if unknown:
        raise InputError(unknown[0], f"unknown key (allowed: {', '.join(KEYS)})")
    for req in ("hull", "lpp", "bwl", "tm", "out"):
        if raw.get(req) in (None, ""):
            raise InputError(req, "is required")
    base = base_dir or Path.cwd()

    def path(v: Any) -> Path:
        p = Path(str(v)).expanduser()
        return p if p.is_absolute() else base / p

    hull = str(raw["hull"])
    if hull.lower() != "wigley":
        hp = path(hull)
        if not (hp.name.lower().endswith(".stl") or hp.name.lower().endswith(".stl.gz")):
            raise InputError("hull", f"must be 'wigley' or a .stl / .stl.gz file (got {hull!r})")
        if not hp.is_file():
            raise InputError("hull", f"file {hp} does not exist")
        hull = str(hp)
    else:
        hull = "wigley"
    lpp = parse_number("lpp", raw["lpp"], 0.0, 500.0, lo_open=True)
    bwl = parse_number("bwl", raw["bwl"], 0.0, 0.5 * lpp, lo_open=True)
    tm = parse_number("tm", raw["tm"], 0.0, 0.5 * lpp, lo_open=True)
    kw: dict[str, Any] = {"hull": hull, "lpp": lpp, "bwl": bwl, "tm": tm, "out": path(raw["out"])}
    if "grading" in raw:
        kw["grading"] = parse_number("grading", raw["grading"], 1, 5, integer=True)
    if "tests" in raw:
        kw["tests"] = parse_tests(raw["tests"])
    if "name" in raw:
        kw["name"] = str(raw["name"])
    for k in ("x_ap", "z_keel"):
        if raw.get(k) not in (None, ""):
            kw[k] = parse_number(k, raw[k], -1e4, 1e4)
    ncpu = max(os.cpu_count() or 1, 1)
    for k in ("procs", "mesh_procs"):
        if k in raw:
            kw[k] = parse_number(k, raw[k], 1, 4 * ncpu, integer=True)
    if raw.get("template") not in (None, ""):
        tp = path(raw["template"])
        if not tp.is_file():
            raise InputError("template", f"ship file {tp} does not exist")
        try:
            tomllib.loads(tp.read_text())
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise InputError("template", f"{tp} is not valid TOML: {exc}") from None
        kw["template"] = tp
    vmax = 20.0
    speeds = parse_list("speeds", raw["speeds"], 0.0, vmax) if "speeds" in raw else ()
    pmm = (
        parse_number("pmm_speed", raw["pmm_speed"], 0.0, vmax, lo_open=True) if raw.get("pmm_speed") else 0.0
    )
    if not speeds and not pmm:
        speeds = (round(0.2 * math.sqrt(9.81 * lpp), 6),)  # Fn = 0.2
    pmm = pmm or max(speeds)
    if not speeds:
        speeds = (pmm,)
    kw["speeds"], kw["pmm_speed"] = speeds, pmm
    if "drift_deg" in raw:
        # 0 is allowed in the list: it is the straight tow at the same speed, run anyway
        kw["drift_deg"] = tuple(
            b for b in parse_list("drift_deg", raw["drift_deg"], 0.0, 30.0, lo_open=False) if b
        )
        if not kw["drift_deg"]:
            raise InputError("drift_deg", "needs at least one angle in (0, 30] deg")
    for k in ("sway_period", "yaw_period"):
        default = math.pi * lpp / pmm  # omega' = omega L / U = 2
        kw[k] = parse_number(k, raw[k], 0.0, 1e4, lo_open=True) if raw.get(k) else round(default, 6)
    amp_default = (round(0.025 * lpp, 6),)
    kw["sway_amplitude"] = (
        parse_list("sway_amplitude", raw["sway_amplitude"], 0.0, 0.5 * lpp)
        if "sway_amplitude" in raw
        else amp_default
    )
    if "yaw_deg" in raw:
        kw["yaw_deg"] = parse_list("yaw_deg", raw["yaw_deg"], 0.0, 30.0)
    if "sweep_omega_prime" in raw:
        # omega' 0.2-5 spans the quasi-steady range to the seed's omega' = 2 and beyond (memory effects)
        kw["sweep_omega_prime"] = parse_list(
            "sweep_omega_prime", raw["sweep_omega_prime"], 0.2, 5.0, max_count=6
        )
    periods = [kw["sway_period"]] + [2 * math.pi * lpp / (w * pmm) for w in kw.get("sweep_omega_prime", ())]
    for a in kw["sway_amplitude"]:
        for period in periods:
            v0 = a * 2 * math.pi / period
            if v0 > math.tan(math.radians(30.0)) * pmm:
                raise InputError(
                    "sway_amplitude",
                    f"{a:g} m at period {period:.4g} s gives a sway "
                    f"velocity of {v0 / pmm:.2f} U; allowed up to tan(30 deg) U",
                )
    if "cycles" in raw:
        kw["cycles"] = parse_number("cycles", raw["cycles"], 1.5, 50.0)
    if "fit_cycles" in raw:
        kw["fit_cycles"] = parse_number("fit_cycles", raw["fit_cycles"], 1, 49, integer=True)
    if kw.get("fit_cycles", 2) > kw.get("cycles", 3.0) - 0.5:
        raise InputError(
            "fit_cycles",
            f"must be <= cycles - 0.5 = {kw.get('cycles', 3.0) - 0.5:g} "
            "(the first half period is the start ramp)",
        )
    if "rho" in raw:
        kw["rho"] = parse_number("rho", raw["rho"], 500.0, 2000.0)
    if "nu" in raw:
        kw["nu"] = parse_number("nu", raw["nu"], 1e-8, 1e-3)
    for k in ("layers", "free_surface", "wake"):
        if k in raw:
            kw[k] = _bool(k, raw[k])
    if "yplus" in raw:
        kw["yplus"] = parse_number("yplus", raw["yplus"], 1.0, 1000.0)
    if "courant" in raw:
        # above ~2.5 on the hull cells the field maximum passes the gate's limit (cfd.verification)
        kw["courant"] = parse_number("courant", raw["courant"], 0.1, 2.5)
    if "time_scheme" in raw:
        kw["time_scheme"] = _choice("time_scheme", raw["time_scheme"], TIME_SCHEMES)
    if "sizing" in raw:
        kw["sizing"] = _choice("sizing", raw["sizing"], ("grading", "yplus"))
    if "max_iterations" in raw:
        kw["max_iterations"] = parse_number("max_iterations", raw["max_iterations"], 10, 100000, integer=True)
    if "normalisation" in raw:
        kw["normalisation"] = _choice("normalisation", raw["normalisation"], NORMALISATIONS)
    if "scale_to" in raw:
        kw["scale_to"] = _choice("scale_to", raw["scale_to"], ("template", "cfd"))
    if raw.get("k_zz") not in (None, ""):
        kw["k_zz"] = parse_number("k_zz", raw["k_zz"], 0.0, lpp, lo_open=True)
    if "drift_form" in raw:
        kw["drift_form"] = _choice("drift_form", raw["drift_form"], DRIFT_FORMS)
    if raw.get("form_factor") not in (None, ""):
        kw["form_factor"] = parse_number("form_factor", raw["form_factor"], 0.0, 1.0)
    _heel_keys(raw, kw, lpp, tm)
    re_l = pmm * lpp / kw.get("nu", Study.nu)
    if re_l < 1e4:
        raise InputError(
            "pmm_speed",
            f"Reynolds number {re_l:.3g} is below 1e4; the k-omega SST set-up needs "
            "a turbulent flow (raise the speed or the length)",
        )
    return Study(**kw)


def _heel_keys(raw: Mapping[str, Any], kw: dict[str, Any], lpp: float, tm: float) -> None:
    """The static-heel settings; with tests "heel" the ship file needs a [roll] table: the template's or
    one made from GM and k_xx."""
    if "heel_deg" in raw:
        # 30 deg: a double-body hull heeled further has lost the wall-sided waterline the mirror assumes
        kw["heel_deg"] = parse_list("heel_deg", raw["heel_deg"], 0.0, 30.0, max_count=4)
    if "heel_drift_deg" in raw:
        kw["heel_drift_deg"] = parse_number("heel_drift_deg", raw["heel_drift_deg"], 0.0, 20.0)
    if raw.get("z_G") not in (None, ""):
        kw["z_G"] = parse_number("z_G", raw["z_G"], -tm, lpp)
    for k in ("GM", "k_xx"):
        if raw.get(k) not in (None, ""):
            kw[k] = parse_number(k, raw[k], 0.0, lpp, lo_open=True)
    if "heel" not in kw.get("tests", TESTS):
        return
    if "drift" not in kw.get("tests", TESTS):
        raise InputError("tests", "'heel' needs 'drift' too: K_v and the drift part of the heeled drift fit")
    template = kw.get("template")
    has_roll = template is not None and "roll" in tomllib.loads(Path(template).read_text())
    if not has_roll and not (kw.get("GM") and kw.get("k_xx")):
        raise InputError(
            "GM", "with tests 'heel' and a template without [roll], GM and k_xx (m, model scale) are required"
        )


def load_study_file(path: str | Path, overrides: Mapping[str, Any] | None = None) -> Study:
    """Read a study TOML file (keys as in :data:`KEYS`); ``overrides`` win over the file."""
    p = Path(path)
    if not p.is_file():
        raise InputError("study", f"file {p} does not exist")
    try:
        raw = tomllib.loads(p.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError("study", f"{p} is not valid TOML: {exc}") from None
    raw.update({k: v for k, v in (overrides or {}).items() if v is not None})
    return build_study(raw, base_dir=p.parent.resolve())
