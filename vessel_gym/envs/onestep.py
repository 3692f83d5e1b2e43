"""The one-ship environment's control step in one compiled call: helm, physics, runaway check and task update.

A one-ship ``env.step`` runs four compiled functions: the helm's order into the simulation's inputs, the physics
steps (:meth:`Simulation.step <vessel_gym.physics.simulation.Simulation.step>`'s serial driver), the runaway check
(:func:`~vessel_gym.physics.runaway.flag_runaway`) and the task update (its kernel, and in HarbourApproach-v2 the
chart's depth under the ship). Each crossing from Python into compiled code unboxes every array it is given,
about 60 ns an array (5-26 arrays a call), so the crossings cost more than a ZigZag ship's physics step. Here the
same functions are called from one compiled function, composed for the environment's helm, driver and task, with
their arguments bound once into one object (a numba ``StructRef``: one unboxing per call, ~0.2 us, instead of
one per array). No equation or rule is written again: the composed function only calls the functions the
separate calls run, in the same order, so the results are the same to the bit.

How the composition is made: one template (:func:`_template`) calls its stages by global names (``HELM``,
``DRIVER``, ``RUNAWAY``, ``STAGE1``, ``STAGE2``); :func:`compose` makes a function of the template's code with
those names bound to the environment's compiled functions, and its cache key (a closure value, which numba's
cache index hashes with the code) names them: their module, name and closure values. So
each composition compiles once (a few seconds: the stages' code is linked in and optimised together) and is then
loaded from numba's cache like any kernel. A stage function made by a factory whose closure holds other compiled
functions gets no stable key and is compiled again in every process.

What stays in Python, in :meth:`ShipEnv.step <vessel_gym.envs.env.ShipEnv.step>`: the action's check and its two
numbers (:meth:`Helm.step_values <vessel_gym.envs.helm.Helm.step_values>`), the simulation's clock, a task's
Python after its kernel (ZigZagRandom-v1's next course change), the returns. A step takes the separate calls
instead while a helm is overridden (a panel on the link holds it), and an environment never binds one when the
simulation has Python components (a user's engine), its task update runs Python before its kernel (ZigZag-v0's
random schedule) or numba's JIT is disabled.
"""

from __future__ import annotations

import builtins
import types as pytypes
from typing import Any

import numba
from numba import njit, types
from numba.experimental import structref

KIND_CHANGED = -1  # the driver no longer fits the batch (Ps or env written directly): nothing integrated
BAD_ACTION = -2  # the helm stage refused the action (NaN): nothing written, nothing integrated


@structref.register
class StepBindingType(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class StepBinding(structref.StructRefProxy):
    """The arguments of a composed step's stages (tuples: the helm's after the action, the driver's, the runaway
    check's, and of up to two task update stages), bound once: a call unboxes this one object."""


structref.define_proxy(StepBinding, StepBindingType, ["helm", "driver", "runaway", "stage1", "stage2"])


@njit(cache=True)
def _bind(helm, driver, runaway, stage1, stage2):
    return StepBinding(helm, driver, runaway, stage1, stage2)


@njit(cache=True)
def no_stage():
    """An update stage that does nothing (a task update of one compiled call)."""
    return 0


def _template(KEY: str) -> Any:
    def one_step(binding, a0, a1):
        """One control step of vessel 0: orders from the action's numbers ``a0``, ``a1``, the physics steps, the
        runaway check, the task update. Returns the number of vessels alive, or KIND_CHANGED / BAD_ACTION."""
        KEY  # noqa: B018  (the composition's cache key: numba's cache index hashes the closure's values)
        if not HELM(a0, a1, *binding.helm):  # noqa: F821  (HELM and the other stages: bound by compose)
            return BAD_ACTION
        if DRIVER(*binding.driver) < 0:  # noqa: F821
            return KIND_CHANGED
        alive = RUNAWAY(*binding.runaway)  # noqa: F821
        STAGE1(*binding.stage1)  # noqa: F821
        STAGE2(*binding.stage2)  # noqa: F821
        return alive

    return one_step


_TEMPLATE = _template("")
_COMPOSED: dict[str, Any] = {}


def _identity(fn: Any) -> str:
    """A compiled function's name in a composition's cache key: module, qualified name and closure values (the
    kind flags of a driver made by a factory). Its code needs no stamp: the package's kernels are cached in a
    directory named by a hash of all the sources they can read (:mod:`vessel_gym.physics.jitcache`)."""
    py = fn.py_func
    cells = tuple(c.cell_contents for c in py.__closure__ or ())
    return f"{py.__module__}.{py.__qualname__}{cells!r}"


def compose(helm: Any, driver: Any, runaway: Any, stages: tuple) -> Any:
    """The compiled (numba dispatcher) one-step function calling ``helm``, ``driver``, ``runaway`` and the one
    or two update ``stages`` (compiled functions) in that order; one per composition in a process."""
    fns = (helm, driver, runaway, *stages, *(no_stage,) * (2 - len(stages)))
    key = "|".join(_identity(f) for f in fns)
    fn = _COMPOSED.get(key)
    if fn is None:
        names = {"HELM": fns[0], "DRIVER": fns[1], "RUNAWAY": fns[2], "STAGE1": fns[3], "STAGE2": fns[4]}
        scope = {"__name__": __name__, "__builtins__": builtins, "BAD_ACTION": BAD_ACTION}
        scope.update(KIND_CHANGED=KIND_CHANGED, **names)
        code = _TEMPLATE.__code__
        py = pytypes.FunctionType(code, scope, code.co_name, None, (pytypes.CellType(key),))
        py.__qualname__, py.__doc__ = _TEMPLATE.__qualname__, _TEMPLATE.__doc__
        fn = _COMPOSED[key] = njit(cache=True)(py)
    return fn


def bind_one_step(helm: Any, sim: Any, nsteps: int, task: Any, phase: Any) -> tuple | None:
    """``(call, binding, after)`` for one control step of a one-ship environment: ``call(binding, *values)``
    runs the helm's stage on ``values = helm.step_values(action)``, ``nsteps`` physics steps, the runaway check
    and the task update of ``phase``, and returns :func:`_template`'s code; ``after`` is None or the task's
    Python to run next. None if the step cannot be one compiled call (see the module docstring). Compiles the
    composition, or loads it from the cache."""
    if numba.config.DISABLE_JIT:
        return None
    physics = sim.compiled_step(nsteps)
    update = task.one_step_update(phase)
    if physics is None or update is None or len(update[0]) > 2:
        return None
    stages, after = update
    driver, driver_args, runaway, runaway_args = physics
    helm_fn, helm_args = helm.compiled_stage()
    stage_args = [args for _fn, args in stages] + [()] * (2 - len(stages))
    binding = _bind(helm_args, driver_args, runaway_args, *stage_args)
    fn = compose(helm_fn, driver, runaway, tuple(f for f, _args in stages))
    sig = (numba.typeof(binding), types.float64, types.float64)
    fn.compile(sig)
    return fn.overloads[sig].entry_point, binding, after
