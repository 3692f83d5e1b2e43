"""Lane drivers: the RK4 batch integrator over vessels of one ship in structure-of-arrays form, for SIMD.

The scalar drivers (:mod:`~vessel_gym.physics.integrate`) step one vessel at a time, its state a row. Here a
run of vessels of *one* ship ("lanes": one parameter row, broadcast) is transposed into columns, state
(NX, B) for a block of B vessels, and each RK4 stage is a loop over the lanes calling the per-vessel
functions the scalar step calls -- :func:`~vessel_gym.physics.vessel.derivatives_of`,
:func:`~vessel_gym.physics.steering.steering_gear_angle`, :func:`~vessel_gym.physics.integrate.stage_state`,
:func:`~vessel_gym.physics.integrate.combine_step` -- so that LLVM may evaluate several vessels at once in
vector registers. The innermost loop runs over lanes.

One source of the equations: the lane loops call those functions *recompiled* from their unchanged Python
source by :func:`recompile` (the same code object, with the names it looks up rebound), never a copy. Two
flavours of the recompilation (``math=``):

* ``"exact"``: libm's transcendental functions, as the scalar drivers. Only the compilation options differ:
  numba's error model ``numpy`` (a float division tests no zero divisor: a test and a ``ZeroDivisionError``
  exit would stop vectorisation) and the built-in ``max``/``min`` of two floats as the selects they are
  (numba's ``max`` is an out-of-line call). Every operation on every lane is the scalar one, so the results
  are the scalar drivers' to the bit; it may replace them wherever it is faster.
* ``"vector"``: ``exp``, ``sin``, ``cos`` and ``atan2`` replaced by the branch-free versions below (Cephes,
  <= 1 ulp from libm), which LLVM can vectorise; results within ~1e-13 relative of the scalar path per step,
  so never chosen automatically: opt in with ``Simulation(..., math="vector")``.

A diverged lane is flagged, not returned from: after each step a lane whose new state is not finite keeps its
last finite state and is masked dead, as the scalar driver stops such a vessel (the later lanes of its block
still compute, their results discarded). Only the alive vessels of a range are gathered into a block.

Whether LLVM actually vectorises the lane loops depends on the component sources (no loops, calls or early
exits left in a vessel's right-hand side): docs/performance.md, "Structure-of-arrays kernel", records what
``benchmarks/simd_probe.py`` finds.
"""

from __future__ import annotations

import dis
import math
import types

import numpy as np
from llvmlite import ir
from numba import njit, prange
from numba import types as nbtypes
from numba.core import cgutils
from numba.core.imputils import impl_ret_borrowed
from numba.core.registry import CPUDispatcher
from numba.extending import intrinsic

from vessel_gym.physics import layout as lo
from vessel_gym.physics.integrate import EULER, MAX_CHUNKS, combine_step, kernel_fits, stage_state
from vessel_gym.physics.steering import steering_gear_angle
from vessel_gym.physics.vessel import derivatives_of

FLAVOURS = ("exact", "vector")
# lanes per block: the block's scratch (state, stage state, four stage derivatives, inputs, environment:
# ~(6 x 12 + 2 + 15 + 5) x 8 B = 750 B per lane, 190 kB at 256 lanes) stays in the core's L2 cache through all
# steps of a call, and a block is long enough that the loop set-up is negligible
LANE_BLOCK = 256

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


@njit(inline="always")
def _select_max(a, b):  # Python's max(a, b) for two floats (b only if b > a, so NaN in a is kept), a select
    return b if b > a else a


@njit(inline="always")
def _select_min(a, b):
    return b if b < a else a


@njit(inline="always", error_model="numpy")
def vexp(x):
    """exp(x): x = n ln 2 + r, |r| <= ln 2 / 2; exp(r) = 1 + 2 r P(r^2) / (Q(r^2) - r P(r^2)); times 2^n
    built from its exponent bits. x clamped to [-708, 709] (no subnormal or infinite results; a NaN stays)."""
    x = _select_max(_select_min(x, 709.0), -708.0)
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
    s = -s if (j > 3) != (math.copysign(1.0, x) < 0.0) else s  # the sign bit: sin(-0) = -0
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
    return math.copysign(r, x)  # r >= 0; atan(-0) = -0


@njit(inline="always", error_model="numpy")
def vatan2(y, x):
    """atan2(y, x) in [-pi, pi] from :func:`vatan` and the quadrant of (x, y), signed zeros as libm's
    (atan2(+-0, -1) = +-pi, atan2(+-0, -0) = +-pi, atan2(+-0, +0) = +-0)."""
    sy = math.copysign(1.0, y)
    on_y_axis = sy * (math.pi / 2) if y != 0.0 else (sy * math.pi if math.copysign(1.0, x) < 0.0 else y)
    a = vatan(y / x) if x != 0.0 else on_y_axis
    return a + sy * math.pi if x < 0.0 else a


@njit(inline="always", error_model="numpy")
def _vsin(x):
    return vsincos(x)[0]


@njit(inline="always", error_model="numpy")
def _vcos(x):
    return vsincos(x)[1]


VECTOR_MATH = types.ModuleType("vector_math")  # the math module with vectorisable transcendentals
for _name in dir(math):
    if not _name.startswith("_"):
        setattr(VECTOR_MATH, _name, getattr(math, _name))
VECTOR_MATH.exp, VECTOR_MATH.sin, VECTOR_MATH.cos, VECTOR_MATH.atan2 = vexp, _vsin, _vcos, vatan2

# --- recompilation of the one source for lanes

_RECOMPILED: dict[tuple, CPUDispatcher] = {}
_PROXIES: dict[tuple, types.ModuleType] = {}


def _module_proxy(module: types.ModuleType, flavour: str, inline: bool) -> types.ModuleType:
    """``module`` with its compiled functions recompiled for ``flavour`` (for calls written ``module.f(...)``)."""
    key = (module.__name__, flavour, inline)
    if key not in _PROXIES:
        proxy = _PROXIES[key] = types.ModuleType(module.__name__)
        for name, value in vars(module).items():
            is_jit = isinstance(value, CPUDispatcher)
            setattr(proxy, name, recompile(value, flavour, inline) if is_jit else value)
    return _PROXIES[key]


def _has_star_call(code: types.CodeType) -> bool:
    """Whether ``code`` calls a function with ``*args`` (numba cannot inline such a call)."""
    return any(ins.opname == "CALL_FUNCTION_EX" for ins in dis.get_instructions(code))


def recompile(dispatcher: CPUDispatcher, flavour: str = "vector", inline: bool = True) -> CPUDispatcher:
    """The function of ``dispatcher`` and every compiled function it calls, recompiled from their Python source
    for a lane loop: inlined into the caller, error model ``numpy``, ``max``/``min`` as selects, no reference
    counting, and for ``flavour`` "vector" the ``math`` module replaced by :data:`VECTOR_MATH` ("exact" keeps
    libm). One source: the code object is the same, only the names it looks up differ. The callees of a
    function that calls with ``*args`` are compiled as functions of their own (``inline`` False), which numba
    cannot inline at such a call; LLVM may still inline them."""
    if flavour not in FLAVOURS:
        raise ValueError(f"math flavour must be one of {FLAVOURS}, got {flavour!r}")
    key = (dispatcher, flavour, inline)
    if key in _RECOMPILED:
        return _RECOMPILED[key]
    f = dispatcher.py_func
    names = dict(f.__globals__)
    g = types.FunctionType(f.__code__, names, f.__name__, f.__defaults__, f.__closure__)
    # registered before its callees are, so that mutual references end (numba reads ``names`` when compiling)
    options = {"inline": "always" if inline else "never", "error_model": "numpy", "_nrt": False}
    _RECOMPILED[key] = njit(**options)(g)
    inline_callees = not _has_star_call(f.__code__)
    for name in f.__code__.co_names:
        value = names.get(name)
        if isinstance(value, CPUDispatcher):
            names[name] = recompile(value, flavour, inline_callees)
        elif value is math:
            names[name] = VECTOR_MATH if flavour == "vector" else math
        elif (
            isinstance(value, types.ModuleType)
            and value.__name__.startswith("vessel_gym.")
            and any(isinstance(v, CPUDispatcher) for v in vars(value).values())
        ):
            names[name] = _module_proxy(value, flavour, inline_callees)
    names["max"], names["min"] = _select_max, _select_min
    return _RECOMPILED[key]


# --- the lane loops (plain Python here; compiled per flavour by _namespace, their callees recompiled)


# A block's columns are flat arrays, column k of lane i at [k * LANE_BLOCK + i]; a lane's row is the view
# _lane_row(A, i, n), whose stride is a compile-time constant, so LLVM sees that the lanes' elements are
# consecutive and that two columns never overlap. (A slice ``A[i::LANE_BLOCK]`` has the same elements, but numba
# derives its stride from the array's run-time stride; LLVM then finds "unsafe dependent memory operations"
# between the columns and leaves the loop scalar.)


@intrinsic
def _lane_row(typingctx, A, i, n):
    """The view of lane ``i``'s ``n`` columns in the flat block array ``A``: A[i], A[i + B], ... (B =
    LANE_BLOCK), a 1-d array of stride B elements known when compiling."""
    resty = nbtypes.Array(nbtypes.float64, 1, "A")

    def codegen(context, builder, signature, args):
        arr = context.make_array(signature.args[0])(context, builder, args[0])
        out = context.make_array(resty)(context, builder)
        intp = context.get_value_type(nbtypes.intp)
        first = builder.sext(args[1], intp) if args[1].type.width < intp.width else args[1]
        count = builder.sext(args[2], intp) if args[2].type.width < intp.width else args[2]
        context.populate_array(
            out,
            data=builder.gep(arr.data, [first]),
            shape=cgutils.pack_array(builder, [count]),
            strides=cgutils.pack_array(builder, [ir.Constant(intp, LANE_BLOCK * 8)]),
            itemsize=ir.Constant(intp, 8),
            meminfo=arr.meminfo,
            parent=arr.parent,
        )
        return impl_ret_borrowed(context, builder, resty, out._getvalue())

    return resty(A, i, n), codegen


def _lanes_angle(P, XS, US, t, out, nb):
    """Rudder angle of every lane ``t`` seconds on (steering_gear_angle), into ``out``."""
    for i in range(nb):
        out[i] = steering_gear_angle(P, XS[lo.X_DELTA * LANE_BLOCK + i], US[lo.U_DELTA_C * LANE_BLOCK + i], t)


def _lanes_stage(XS, K, h, d, XT, nb, nx):
    """The stage states XT = XS + h K of every lane, rudder angles ``d`` (stage_state)."""
    for i in range(nb):
        stage_state(_lane_row(XS, i, lo.NX), _lane_row(K, i, lo.NX), h, d[i], _lane_row(XT, i, lo.NX), nx)


def _lanes_rhs(P, XS, US, ES, FS, K, nb, shallow_env, roll, ext):
    """Right-hand side of every lane at the states XS into K (derivatives_of); ``shallow_env`` None compiles
    the deep-water equations (H the literal 0), as integrate._run_range does."""
    nf = FS.shape[0] // LANE_BLOCK
    for i in range(nb):
        if shallow_env is None:
            H = 0
        else:
            H = shallow_env[lo.E_T_OVER_H * LANE_BLOCK + i]
        x, u, e = _lane_row(XS, i, lo.NX), _lane_row(US, i, lo.NU), _lane_row(ES, i, lo.NE)
        derivatives_of(P, x, u, e, _lane_row(FS, i, nf), _lane_row(K, i, lo.NX), H, roll, ext)


def _lanes_finish(XS, K, dt, method, d, XT, live, nb, nx):
    """One step on for every lane (combine_step), committed where the lane is alive and its new state finite;
    a lane that fails keeps its last finite state and is masked dead (a select, not an exit). ``K`` holds the
    four stages' columns one after the other."""
    B = LANE_BLOCK
    S = lo.NX * LANE_BLOCK  # one stage's columns
    for i in range(nb):
        k1, k2 = _lane_row(K, i, lo.NX), _lane_row(K, S + i, lo.NX)
        k3, k4 = _lane_row(K, 2 * S + i, lo.NX), _lane_row(K, 3 * S + i, lo.NX)
        combine_step(_lane_row(XS, i, lo.NX), k1, k2, k3, k4, dt, method, d[i], _lane_row(XT, i, lo.NX), nx)
        ok = live[i]
        for k in range(nx):
            ok = ok & math.isfinite(XT[k * B + i])
        for k in range(nx):
            XS[k * B + i] = XT[k * B + i] if ok else XS[k * B + i]
        live[i] = ok


def _lanes_step(P, XS, US, ES, FS, K, XT, D, live, nb, dt, method, shallow_env, roll, ext, nx):
    """One RK4 (or Euler) step of the lanes 0..nb-1, the stages of integrate.step_vessel in its order."""
    half = 0.5 * dt
    S = lo.NX * LANE_BLOCK
    d_half, d_end = D[:LANE_BLOCK], D[LANE_BLOCK:]
    _lanes_angle(P, XS, US, dt, d_end, nb)
    _lanes_rhs(P, XS, US, ES, FS, K[:S], nb, shallow_env, roll, ext)
    if method != EULER:
        _lanes_angle(P, XS, US, half, d_half, nb)
        _lanes_stage(XS, K[:S], half, d_half, XT, nb, nx)
        _lanes_rhs(P, XT, US, ES, FS, K[S : 2 * S], nb, shallow_env, roll, ext)
        _lanes_stage(XS, K[S : 2 * S], half, d_half, XT, nb, nx)
        _lanes_rhs(P, XT, US, ES, FS, K[2 * S : 3 * S], nb, shallow_env, roll, ext)
        _lanes_stage(XS, K[2 * S : 3 * S], dt, d_end, XT, nb, nx)
        _lanes_rhs(P, XT, US, ES, FS, K[3 * S :], nb, shallow_env, roll, ext)
    _lanes_finish(XS, K, dt, method, d_end, XT, live, nb, nx)


def _scratch(nf):
    """A block's scratch, flat columns (see above): state, stage state, the four stage derivatives, inputs,
    environment, external forces (nf columns), rudder angles at t + dt/2 and t + dt, the block's vessel
    indices and alive mask."""
    B = LANE_BLOCK
    return (
        np.empty(lo.NX * B),
        np.empty(lo.NX * B),
        np.empty(4 * lo.NX * B),
        np.empty(lo.NU * B),
        np.empty(lo.NE * B),
        np.empty(nf * B),
        np.empty(2 * B),
        np.empty(B, dtype=np.int64),
        np.empty(B, dtype=np.bool_),
    )


def _run_range(P, X, U, E, F, dt, nsteps, method, alive, first, stop, S, shallow_env, roll, ext, nx):
    """Integrate the alive vessels first..stop-1 (all of parameter row P) block by block: gather up to
    LANE_BLOCK alive vessels into the columns of the scratch ``S`` (:func:`_scratch`), ``nsteps`` steps, scatter
    back with their alive flags. ``shallow_env`` is the scratch's environment columns in a kernel for shallow
    water (each lane's depth read from them) and None in a deep-water kernel (:func:`_lanes_rhs`). Returns how
    many are alive."""
    XS, XT, K, US, ES, FS, D, idx, live = S
    B = LANE_BLOCK
    nf = F.shape[1]
    count = 0
    b = first
    while b < stop:
        nb = 0
        while b < stop and nb < B:
            if alive[b]:
                idx[nb] = b
                nb += 1
            b += 1
        for j in range(nb):
            v = idx[j]
            for k in range(lo.NX):
                XS[k * B + j] = X[v, k]
                XT[k * B + j] = X[v, k]
            for k in range(lo.NU):
                US[k * B + j] = U[v, k]
            for k in range(lo.NE):
                ES[k * B + j] = E[v, k]
            for k in range(nf):
                FS[k * B + j] = F[v, k]
            live[j] = True
        for _ in range(nsteps):
            _lanes_step(P, XS, US, ES, FS, K, XT, D, live, nb, dt, method, shallow_env, roll, ext, nx)
        for j in range(nb):
            v = idx[j]
            for k in range(nx):
                X[v, k] = XS[k * B + j]
            alive[v] = live[j]
            count += live[j]
    return count


def _one_ship(ship_index):
    """Whether every vessel of the batch is of one ship (the lanes share one parameter row)."""
    for b in range(ship_index.shape[0]):
        if ship_index[b] != ship_index[0]:
            return False
    return True


# per flavour: the module's names with the lane loops compiled and their callees recompiled for it
_LANE_LOOPS = (_lanes_angle, _lanes_stage, _lanes_rhs, _lanes_finish, _lanes_step)
_NAMESPACES: dict[str, dict] = {}


def _namespace(flavour: str) -> dict:
    if flavour not in _NAMESPACES:
        g = dict(globals())
        for name in ("derivatives_of", "steering_gear_angle", "stage_state", "combine_step"):
            g[name] = recompile(g[name], flavour)
        for fn in _LANE_LOOPS:  # no reference counting: a row view taken per lane would stop vectorisation
            code = types.FunctionType(fn.__code__, g, fn.__name__)
            g[fn.__name__] = njit(error_model="numpy", _nrt=False)(code)
        for fn in (_run_range, _scratch, _one_ship):
            g[fn.__name__] = njit(error_model="numpy")(types.FunctionType(fn.__code__, g, fn.__name__))
        _NAMESPACES[flavour] = g
    return _NAMESPACES[flavour]


def _make_lane_drivers(shallow: bool, roll: bool, ext: bool, flavour: str):
    # the flags reach the compiled code as closure constants (as integrate._make_drivers); FLAVOUR is one too,
    # so that the two flavours, compiled from one code object, are cached under different keys
    SHALLOW, ROLL, EXT, FLAVOUR = shallow, roll, ext, FLAVOURS.index(flavour)
    NXK = lo.NX if roll else lo.NX_3DOF

    def run_serial(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
        if FLAVOUR < 0 or X.shape[0] == 0:
            return 0
        if not (_one_ship(ship_index) and kernel_fits(Ps, E, E if SHALLOW else None, ROLL, EXT)):
            return -1
        S = _scratch(F.shape[1])
        P = Ps[ship_index[0]]
        shallow_env = S[4] if SHALLOW else None
        return _run_range(P, X, U, E, F, dt, nsteps, method, alive, 0, X.shape[0], S, shallow_env, ROLL, EXT, NXK)

    def run_parallel(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive):
        if FLAVOUR < 0 or X.shape[0] == 0:
            return 0
        if not (_one_ship(ship_index) and kernel_fits(Ps, E, E if SHALLOW else None, ROLL, EXT)):
            return -1
        nb = X.shape[0]
        nchunks = min((nb + LANE_BLOCK - 1) // LANE_BLOCK, MAX_CHUNKS)
        P = Ps[ship_index[0]]
        count = 0
        for c in prange(nchunks):
            S = _scratch(F.shape[1])
            count += _run_range(
                P, X, U, E, F, dt, nsteps, method, alive, c * nb // nchunks, (c + 1) * nb // nchunks, S,
                S[4] if SHALLOW else None, ROLL, EXT, NXK,
            )  # fmt: skip
        return count

    g = _namespace(flavour)
    serial = types.FunctionType(run_serial.__code__, g, "run_lanes_serial", None, run_serial.__closure__)
    threaded = types.FunctionType(run_parallel.__code__, g, "run_lanes_parallel", None, run_parallel.__closure__)
    return njit(cache=True)(serial), njit(cache=True, parallel=True)(threaded)


_DRIVERS: dict[tuple, tuple] = {}


def lane_drivers(shallow: bool = True, roll: bool = True, ext: bool = True, math: str = "exact"):
    """The lane drivers (serial, threaded) for one kind of batch (as :func:`~vessel_gym.physics.integrate.drivers`)
    and math flavour ("exact": the scalar drivers' results to the bit; "vector": branch-free transcendentals),
    each ``driver(Ps, ship_index, X, U, E, F, dt, nsteps, method, alive)`` with the scalar drivers' arguments
    and result. A driver returns -1 without integrating when its kind does not hold the batch or the batch is
    not of one ship. Each combination compiles on its first use (cached on disk as the other kernels)."""
    if math not in FLAVOURS:
        raise ValueError(f"math must be one of {FLAVOURS}, got {math!r}")
    key = (bool(shallow), bool(roll), bool(ext), math)
    if key not in _DRIVERS:
        _DRIVERS[key] = _make_lane_drivers(*key)
    return _DRIVERS[key]


def lane_drivers_for(Ps: np.ndarray, ship_index: np.ndarray, E: np.ndarray, math: str = "exact"):
    """:func:`lane_drivers` of the narrowest kind that holds the batch (integrate.drivers_for), or None when
    its vessels are not all of one ship (numpy, O(N): call it when these change)."""
    if ship_index.shape[0] == 0 or not (ship_index == ship_index[0]).all():
        return None
    P = Ps[ship_index[0]]
    return lane_drivers(
        shallow=bool((E[:, lo.E_T_OVER_H] != 0.0).any()),
        roll=bool(P[lo.P_ROLL_ON] != 0.0),
        ext=bool(P[lo.P_ENGINE_EXT] != 0.0 or P[lo.P_SG_EXT] != 0.0),
        math=math,
    )
