"""How far LLVM vectorises the physics across vessels on this machine (a probe, not a timed test).

The question behind a structure-of-arrays kernel (docs/performance.md, "Structure-of-arrays kernel"): if a
loop runs over vessels ("lanes") with the state in columns and calls the *same* per-vessel functions as the
scalar drivers, does LLVM turn it into packed SIMD code (``vmulpd %ymm``) rather than one vessel at a time
(``vmulsd``)? Three probes, each printed with the packed and scalar double-precision instructions of the
compiled loop, ns per lane (median of interleaved repeats) and the largest difference from the scalar result:

1. libm: a lane loop calling ``math.exp``, ``math.sin``/``math.cos``, ``math.atan2`` (numba calls libm; no
   vector variant without Intel SVML, which needs an SVML-patched LLVM: ``numba -s`` says whether it has one),
   against branch-free double-precision versions of the same functions written in numba (Cephes' range
   reductions and rational approximations, Moshier 1989), compiled without the Python error model.
2. The project's MMG hull forces (``hull.mmg_hull_forces``) in a lane loop: as compiled for the drivers, and
   recompiled from the same Python source (:func:`recompile`) with the error model ``numpy`` (no
   zero-division check), ``max``/``min`` as selects, the math module's transcendentals replaced by the
   versions above, everything inlined.
3. The same for all component forces of one vessel (``vessel.force_terms``: hull, wake, propeller, rudder,
   wind, wave drift).

Why a loop is not vectorised, LLVM says with ``llvmlite.binding.set_option("", "-pass-remarks-analysis=loop-vectorize")``
(and ``-pass-remarks-missed=``) called before the first compilation.
The serial batch driver's cost per vessel-step on kvlcc2 is printed for scale, with what the goal of 4 M
vessel-steps/s on 2 cores asks of one core.

    python benchmarks/simd_probe.py [--repeats 7]
"""

from __future__ import annotations

import argparse
import math
import re
import statistics
import sys
import types

import numpy as np
from llvmlite import ir
from numba import njit
from numba import types as nbtypes
from numba.core.registry import CPUDispatcher
from numba.extending import intrinsic

from vessel_gym.physics import hull, vessel
from vessel_gym.physics import layout as lo

TARGET_SOA = 4_000_000  # vessel-RK4-steps/s on 2 idle cores, full kvlcc2 model, N >= 1024 (issue 16)
N_LANES = 1024


def _args() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=7, help="interleaved timed repeats per figure (median)")
    return ap.parse_args()


# --- branch-free exp, sin/cos, atan2 (Cephes: S. L. Moshier, Methods and Programs for Mathematical Functions,
# 1989; double-precision coefficients of exp.c, sin.c, atan.c). Every branch is a select LLVM can if-convert.


@intrinsic
def _int64_bits_as_float64(typingctx, x):
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return nbtypes.float64(nbtypes.int64), codegen


LOG2E = 1.4426950408889634
LN2_HI = 6.93145751953125e-1  # ln 2 in two parts, so that n ln 2 is exact in the reduction
LN2_LO = 1.42860682030941723212e-6


@njit(inline="always", error_model="numpy")
def vexp(x):
    """exp(x): x = n ln 2 + r, |r| <= ln 2 / 2; exp(r) = 1 + 2 r P(r^2) / (Q(r^2) - r P(r^2)); times 2^n
    built from its exponent bits. Clamped to [-708, 709] (no subnormal or infinite results)."""
    x = max(min(x, 709.0), -708.0)
    n = math.floor(LOG2E * x + 0.5)
    r = (x - n * LN2_HI) - n * LN2_LO
    rr = r * r
    p = r * ((1.26177193074810590878e-4 * rr + 3.02994407707441961300e-2) * rr + 9.99999999999999999910e-1)
    q = ((3.00198505138664455042e-6 * rr + 2.52448340349684104192e-3) * rr + 2.27265548208155028766e-1) * rr
    q = q + 2.00000000000000000009e0
    return (1.0 + 2.0 * (p / (q - p))) * _int64_bits_as_float64((np.int64(n) + 1023) << 52)


PIO4_1 = 7.85398125648498535156e-1  # pi/4 in three parts (Cody-Waite reduction)
PIO4_2 = 3.77489470793079817668e-8
PIO4_3 = 2.69515142907905952645e-15
FOUR_OVER_PI = 1.27323954473516268615


@njit(inline="always", error_model="numpy")
def vsincos(x):
    """(sin x, cos x): octant j of |x|, z = |x| - j pi/4, both polynomials, the octant's signs and swap as
    selects. Accurate while j pi/4 is exact in the three-part reduction (|x| < ~1e8 rad)."""
    ax = abs(x)
    j = np.int64(ax * FOUR_OVER_PI)
    j = j + (j & 1)
    y = float(j)
    z = ((ax - y * PIO4_1) - y * PIO4_2) - y * PIO4_3
    zz = z * z
    ps = (1.58962301576546568060e-10 * zz - 2.50507477628578072866e-8) * zz + 2.75573136213857245213e-6
    ps = (
        (ps * zz - 1.98412698295895385996e-4) * zz + 8.33333333332211858878e-3
    ) * zz - 1.66666666666666307295e-1
    ps = z + z * zz * ps
    pc = (-1.13585365213876817300e-11 * zz + 2.08757008419747316778e-9) * zz - 2.75573141792967388112e-7
    pc = (
        (pc * zz + 2.48015872888517045348e-5) * zz - 1.38888888888730564116e-3
    ) * zz + 4.16666666666665929218e-2
    pc = 1.0 - 0.5 * zz + zz * zz * pc
    j = j & 7
    swap = (j == 2) | (j == 6)
    s = pc if swap else ps
    c = ps if swap else pc
    s = -s if (j > 3) != (x < 0.0) else s
    c = -c if (j == 2) | (j == 4) else c
    return s, c


TAN_3PI_8 = 2.41421356237309504880
MOREBITS = 6.123233995736765886130e-17  # pi/2 - (pi/2 rounded to double)


@njit(inline="always", error_model="numpy")
def vatan(x):
    """atan(x): |x| reduced to [0, 0.66] by tan(3 pi/8) and 0.66 (selects), then a rational P/Q in x^2."""
    ax = abs(x)
    big = ax > TAN_3PI_8
    mid = (ax > 0.66) & (not big)
    y0 = math.pi / 2 if big else (math.pi / 4 if mid else 0.0)
    extra = MOREBITS if big else (0.5 * MOREBITS if mid else 0.0)
    t = (-1.0 if big else (ax - 1.0 if mid else ax)) / (ax if big else (ax + 1.0 if mid else 1.0))
    z = t * t
    p = (-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z - 7.500855792314704667340e1
    p = (p * z - 1.228866684490136173410e2) * z - 6.485021904942025371773e1
    q = (
        ((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z + 4.328810604912902668951e2
    ) * z
    q = (q + 4.853903996359136964868e2) * z + 1.945506571482613964425e2
    r = y0 + (t * z * p / q + t + extra)
    return -r if x < 0.0 else r


@njit(inline="always", error_model="numpy")
def vatan2(y, x):
    """atan2(y, x) in (-pi, pi] from :func:`vatan` and the quadrant of (x, y)."""
    half_pi = math.pi / 2 if y > 0.0 else (-math.pi / 2 if y < 0.0 else 0.0)
    a = vatan(y / x) if x != 0.0 else half_pi
    if x < 0.0:
        a = a + math.pi if y >= 0.0 else a - math.pi
    return a


@njit(inline="always", error_model="numpy")
def _vsin(x):
    return vsincos(x)[0]


@njit(inline="always", error_model="numpy")
def _vcos(x):
    return vsincos(x)[1]


@njit(inline="always")
def _select_max(a, b):  # Python's max(a, b) for two floats (b only if b > a), as a select
    return b if b > a else a


@njit(inline="always")
def _select_min(a, b):
    return b if b < a else a


VECTOR_MATH = types.ModuleType("vector_math")  # the math module with vectorisable transcendentals
for _name in dir(math):
    if not _name.startswith("_"):
        setattr(VECTOR_MATH, _name, getattr(math, _name))
VECTOR_MATH.exp, VECTOR_MATH.sin, VECTOR_MATH.cos, VECTOR_MATH.atan2 = vexp, _vsin, _vcos, vatan2

_RECOMPILED: dict = {}


def recompile(dispatcher: CPUDispatcher) -> CPUDispatcher:
    """The function of ``dispatcher`` and every compiled function it calls, recompiled from their Python
    source for a lane loop: inlined, error model ``numpy``, ``max``/``min`` as selects, ``math`` replaced by
    :data:`VECTOR_MATH`. One source: the code object is the same, only the names it looks up differ."""
    if dispatcher in _RECOMPILED:
        return _RECOMPILED[dispatcher]
    f = dispatcher.py_func
    names = dict(f.__globals__)
    for name in f.__code__.co_names:
        value = names.get(name)
        if isinstance(value, CPUDispatcher):
            names[name] = recompile(value)
        elif value is math:
            names[name] = VECTOR_MATH
    names["max"], names["min"] = _select_max, _select_min
    g = types.FunctionType(f.__code__, names, f.__name__, f.__defaults__, f.__closure__)
    _RECOMPILED[dispatcher] = njit(inline="always", error_model="numpy", _nrt=False)(g)
    return _RECOMPILED[dispatcher]


# --- lane loops


@njit(error_model="numpy")
def lanes_vexp(a, out):
    for i in range(a.shape[0]):
        out[i] = vexp(a[i])


@njit
def lanes_exp(a, out):
    for i in range(a.shape[0]):
        out[i] = math.exp(a[i])


@njit(error_model="numpy")
def lanes_vsincos(a, out):
    for i in range(a.shape[0]):
        out[0, i], out[1, i] = vsincos(a[i])


@njit
def lanes_sincos(a, out):
    for i in range(a.shape[0]):
        out[0, i] = math.sin(a[i])
        out[1, i] = math.cos(a[i])


@njit(error_model="numpy")
def lanes_vatan2(a, b, out):
    for i in range(a.shape[0]):
        out[i] = vatan2(a[i], b[i])


@njit
def lanes_atan2(a, b, out):
    for i in range(a.shape[0]):
        out[i] = math.atan2(a[i], b[i])


mmg_hull_lanes = recompile(hull.mmg_hull_forces)
force_terms_lanes = recompile(vessel.force_terms)


@njit
def lanes_hull(P, X, out):  # structure of arrays: X (NX, N); the drivers' compiled function
    for i in range(X.shape[1]):
        out[0, i], out[1, i], out[2, i] = hull.mmg_hull_forces(P, X[lo.X_U, i], X[lo.X_V, i], X[lo.X_R, i], 0)


@njit(error_model="numpy")
def lanes_hull_soa(P, X, out):
    for i in range(X.shape[1]):
        out[0, i], out[1, i], out[2, i] = mmg_hull_lanes(P, X[lo.X_U, i], X[lo.X_V, i], X[lo.X_R, i], 0)


@njit
def lanes_force_terms(P, X, env, out):  # array of structs, as the drivers: X (N, NX)
    for i in range(X.shape[0]):
        f = vessel.force_terms(P, X[i], env, 0)
        for k in range(vessel.N_OUT):
            out[k, i] = f[k]


@njit(error_model="numpy")
def lanes_force_terms_soa(P, X, env, out):
    for i in range(X.shape[1]):
        f = force_terms_lanes(P, X[:, i], env, 0)
        for k in range(vessel.N_OUT):
            out[k, i] = f[k]


# --- measurement


def packed_ops(fn) -> tuple[int, int]:
    """(packed, scalar) double-precision arithmetic instructions in ``fn``'s machine code: ``v...pd`` on
    ymm/zmm registers against ``v...sd``."""
    asm = fn.inspect_asm(fn.signatures[0])
    arith = r"v(?:add|sub|mul|div|sqrt|max|min|fmadd\d*|fmsub\d*|fnmadd\d*)"
    return len(re.findall(arith + r"pd\s[^\n]*%[yz]mm", asm)), len(re.findall(arith + r"sd\s", asm))


def interleaved(calls: dict, repeats: int, lanes: int) -> dict:
    """Median ns per lane of each call, the calls timed in turn within each repeat (a busy machine slows
    them alike)."""
    from bench_physics import seconds_per_call

    for call in calls.values():
        call()
    samples: dict = {name: [] for name in calls}
    for _ in range(repeats):
        for name, call in calls.items():
            samples[name].append(seconds_per_call(call, 0.05) / lanes * 1e9)
    return {name: statistics.median(s) for name, s in samples.items()}


def ulp_error(got: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.abs(got - ref) / np.spacing(np.maximum(np.abs(ref), 1e-300))))


def rel_diff(got: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.abs(got - ref) / np.maximum(np.abs(ref), 1e-300)))


def row(name: str, fn, ns: float, diff: str) -> None:
    p, s = packed_ops(fn)
    print(f"  {name:34s} {p:6d} {s:6d} {ns:9.2f}  {diff}")


def probe_libm(repeats: int) -> None:
    print("\n1. transcendental functions in a lane loop (N = 1024)")
    print(f"  {'loop':34s} {'packed':>6s} {'scalar':>6s} {'ns/lane':>9s}  error")
    rng = np.random.default_rng(1)
    xe, xs = rng.uniform(-30.0, 5.0, N_LANES), rng.uniform(-100.0, 100.0, N_LANES)
    ya, xa = rng.normal(0.0, 3.0, N_LANES), rng.normal(0.0, 3.0, N_LANES)
    o1, r1 = np.empty(N_LANES), np.empty(N_LANES)
    o2, r2 = np.empty((2, N_LANES)), np.empty((2, N_LANES))
    t = interleaved(
        {
            "exp": lambda: lanes_exp(xe, r1),
            "vexp": lambda: lanes_vexp(xe, o1),
            "sincos": lambda: lanes_sincos(xs, r2),
            "vsincos": lambda: lanes_vsincos(xs, o2),
            "atan2": lambda: lanes_atan2(ya, xa, r1),
            "vatan2": lambda: lanes_vatan2(ya, xa, o1),
        },
        repeats,
        N_LANES,
    )
    lanes_exp(xe, r1)
    lanes_vexp(xe, o1)
    row("math.exp (libm)", lanes_exp, t["exp"], "-")
    row("exp, branch-free numba", lanes_vexp, t["vexp"], f"{ulp_error(o1, r1):.0f} ulp")
    row("math.sin + math.cos (libm)", lanes_sincos, t["sincos"], "-")
    lanes_sincos(xs, r2)
    lanes_vsincos(xs, o2)
    row("sincos, branch-free numba", lanes_vsincos, t["vsincos"], f"{ulp_error(o2, r2):.0f} ulp")
    lanes_atan2(ya, xa, r1)
    lanes_vatan2(ya, xa, o1)
    row("math.atan2 (libm)", lanes_atan2, t["atan2"], "-")
    row("atan2, branch-free numba", lanes_vatan2, t["vatan2"], f"{ulp_error(o1, r1):.0f} ulp")


def turning_batch(ship: str):
    """(P, X (N, NX), env row) of N_LANES ``ship``s turning in wind, a minute into the turn."""
    sys.path.insert(0, __file__.rsplit("/", 1)[0])
    from bench_physics import make_sim

    sim = make_sim(ship, N_LANES)
    sim.step(600)
    return sim.Ps[0], np.ascontiguousarray(sim.state), sim.env[0].copy(), sim


def probe_components(repeats: int) -> None:
    print("\n2-3. the project's component functions in a lane loop (kvlcc2 turning in wind, N = 1024)")
    print(f"  {'loop':34s} {'packed':>6s} {'scalar':>6s} {'ns/lane':>9s}  largest relative difference")
    P, X, env, _ = turning_batch("kvlcc2")
    Xs = np.ascontiguousarray(X.T)
    h_ref, h_soa = np.empty((3, N_LANES)), np.empty((3, N_LANES))
    f_ref, f_soa = np.empty((vessel.N_OUT, N_LANES)), np.empty((vessel.N_OUT, N_LANES))
    t = interleaved(
        {
            "hull": lambda: lanes_hull(P, Xs, h_ref),
            "hull_soa": lambda: lanes_hull_soa(P, Xs, h_soa),
            "ft": lambda: lanes_force_terms(P, X, env, f_ref),
            "ft_soa": lambda: lanes_force_terms_soa(P, Xs, env, f_soa),
        },
        repeats,
        N_LANES,
    )
    same = "bitwise equal" if np.array_equal(h_ref, h_soa) else f"{rel_diff(h_soa, h_ref):.1e}"
    row("mmg_hull_forces (drivers' build)", lanes_hull, t["hull"], "-")
    row("mmg_hull_forces, recompiled", lanes_hull_soa, t["hull_soa"], same)
    row("force_terms (drivers' build)", lanes_force_terms, t["ft"], "-")
    nz = np.abs(f_ref) > 1e-6 * np.abs(f_ref).max(axis=1, keepdims=True)  # entries that are not ~0 by sign
    same = "bitwise equal" if np.array_equal(f_ref, f_soa) else f"{rel_diff(f_soa[nz], f_ref[nz]):.1e}"
    row("force_terms, recompiled", lanes_force_terms_soa, t["ft_soa"], same)


def probe_driver(repeats: int) -> None:
    from bench_physics import driver_args, sim_drivers

    _, _, _, sim = turning_batch("kvlcc2")
    args = driver_args(sim, 10)
    run_serial, _ = sim_drivers(sim)
    ns = interleaved({"serial": lambda: run_serial(*args)}, repeats, N_LANES * 10)["serial"]
    need = 2 * 1e9 / TARGET_SOA
    print(
        f"\nserial driver, kvlcc2, N = {N_LANES}: {ns:.0f} ns per vessel-RK4-step ({1e3 / ns:.2f} M/s on one core);"
        f" {TARGET_SOA / 1e6:g} M/s on 2 cores needs {need:.0f} ns per vessel-step per core (x{ns / need:.1f})"
    )


def main() -> None:
    args = _args()
    import llvmlite
    import llvmlite.binding as llb
    import numba

    llvm = ".".join(map(str, llb.llvm_version_info))
    print(
        f"numba {numba.__version__}, llvmlite {llvmlite.__version__} (LLVM {llvm}), CPU {llb.get_host_cpu_name()}"
    )
    print("packed/scalar: double-precision arithmetic instructions in the compiled loop (ymm/zmm vs sd)")
    probe_libm(args.repeats)
    probe_components(args.repeats)
    probe_driver(args.repeats)


if __name__ == "__main__":
    main()
