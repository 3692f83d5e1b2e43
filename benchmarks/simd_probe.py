"""How far LLVM vectorises the physics across vessels on this machine (a probe, not a timed test).

The question behind a structure-of-arrays kernel (docs/performance.md, "Structure-of-arrays kernel"): if a
loop runs over vessels ("lanes") with the state in columns and calls the *same* per-vessel functions as the
scalar drivers, does LLVM turn it into packed SIMD code (``vmulpd %ymm``) rather than one vessel at a time
(``vmulsd``)? Three probes, each printed with the packed and scalar double-precision instructions of the
compiled loop, ns per lane (median of interleaved repeats) and the largest difference from the scalar result:

1. libm: a lane loop calling ``math.exp``, ``math.sin``/``math.cos``, ``math.atan2`` (numba calls libm; no
   vector variant without Intel SVML, which needs an SVML-patched LLVM: ``numba -s`` says whether it has one),
   against branch-free double-precision versions of the same functions written in numba (Cephes' range
   reductions and rational approximations, Moshier 1989; ``vessel_gym.physics.lanes``), compiled without
   the Python error model.
2. The project's MMG hull forces (``hull.mmg_hull_forces``) in a lane loop: as compiled for the drivers, and
   recompiled from the same Python source (``vessel_gym.physics.lanes.recompile``, which the lane drivers
   use) with the error model ``numpy`` (no zero-division check), ``max``/``min`` as selects, the math
   module's transcendentals replaced by the versions above, everything inlined.
3. The same for all component forces of one vessel (``vessel.force_terms``: hull, wake, propeller, rudder,
   wind, wave drift).

Why a loop is not vectorised, LLVM says with ``llvmlite.binding.set_option("", "-pass-remarks-analysis=loop-vectorize")``
(and ``-pass-remarks-missed=``) called before the first compilation.
The serial batch driver's cost per vessel-step on kvlcc2 is printed for scale, with what the goal of 4 M
vessel-steps/s on 2 cores asks of one core.

4. The lane drivers' right-hand-side loop (``vessel_gym.physics.lanes``), both math flavours: packed and
   scalar instructions.

    python benchmarks/simd_probe.py [--repeats 7] [--lanes-only] [--remarks]
"""

from __future__ import annotations

import argparse
import math
import re
import statistics

import numpy as np
from numba import njit

from vessel_gym.physics import hull, vessel
from vessel_gym.physics import layout as lo
from vessel_gym.physics.lanes import recompile, vatan2, vexp, vsincos

TARGET_SOA = 4_000_000  # vessel-RK4-steps/s on 2 idle cores, full kvlcc2 model, N >= 1024 (issue 16)
N_LANES = 1024


def _args() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=7, help="interleaved timed repeats per figure (median)")
    ap.add_argument("--lanes-only", action="store_true", help="only the lane drivers' loops (4.)")
    ap.add_argument("--remarks", action="store_true", help="print LLVM's vectoriser remarks (stderr)")
    return ap.parse_args()


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
    from bench_physics import make_sim  # run as a script: its own folder is on the path

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


def probe_lanes() -> None:
    """The lane drivers' loops (vessel_gym.physics.lanes) of the deep-water 3-DOF kind, compiled here (the
    drivers load them from the cache with their caller): packed and scalar instructions of the right-hand-side
    lane loop (``--remarks`` says why LLVM left it scalar: any loop inside it, a call it cannot widen)."""
    from vessel_gym.physics import lanes

    _, _, _, sim = turning_batch("kvlcc2")
    B = lanes.LANE_BLOCK
    XS, K = np.ascontiguousarray(sim.state[:B].T).ravel(), np.empty(lo.NX * B)
    US, ES = np.ascontiguousarray(sim.inputs[:B].T).ravel(), np.ascontiguousarray(sim.env[:B].T).ravel()
    FS = np.zeros(3 * B)
    print("\n4. the lane drivers' loops (kvlcc2, deep water, 3 DOF), as compiled for lanes.lane_drivers")
    print(f"  {'loop':34s} {'packed':>6s} {'scalar':>6s}")
    for flavour in lanes.FLAVOURS:
        g = lanes._namespace(flavour)
        rhs = g["_lanes_rhs"]

        @njit(error_model="numpy")
        def call(P, XS, US, ES, FS, K, rhs=rhs):
            rhs(P, XS, US, ES, FS, K, B, None, False, False)

        call(sim.Ps[0], XS, US, ES, FS, K)
        p, sc = packed_ops(rhs)
        print(f"  {'right-hand side, ' + flavour + ' math':34s} {p:6d} {sc:6d}")


def main() -> None:
    args = _args()
    if args.remarks:  # LLVM's reasons, on stderr, for every loop compiled from here on
        import llvmlite.binding as llb

        llb.set_option("", "-pass-remarks-analysis=loop-vectorize")
        llb.set_option("", "-pass-remarks-missed=loop-vectorize")
        llb.set_option("", "-pass-remarks=loop-vectorize")
    import llvmlite
    import llvmlite.binding as llb
    import numba

    llvm = ".".join(map(str, llb.llvm_version_info))
    print(
        f"numba {numba.__version__}, llvmlite {llvmlite.__version__} (LLVM {llvm}), CPU {llb.get_host_cpu_name()}"
    )
    print("packed/scalar: double-precision arithmetic instructions in the compiled loop (ymm/zmm vs sd)")
    if not args.lanes_only:
        probe_libm(args.repeats)
        probe_components(args.repeats)
        probe_driver(args.repeats)
    probe_lanes()


if __name__ == "__main__":
    main()
