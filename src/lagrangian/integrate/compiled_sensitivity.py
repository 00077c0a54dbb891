"""The forward sensitivity equations in the compiled DOP853 loop (numba).

The same method as :mod:`.compiled_dop853` (SciPy's DOP853, one compiled loop for every
system, taking the system's y' as a function pointer), over the state and its
sensitivities: the system's y' is :mod:`.numba_derivative` (as for the variational
equations) filled with its M, f and the generated G = d(f - M a)/d(q, q', p_wrt) (the block of
:mod:`lagrangian.codegen.sensitivity`, printed by :mod:`lagrangian.codegen.numba`).  The
steps are those SciPy's loop takes on the same vector, so both give the same answers to
rounding; here without Python per step.  Applies where :func:`.compiled_dop853.
loop_applies` (numba installed, derived equations, no constraints); None otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from .compiled_derivatives import derivative_text
from .compiled_dop853 import (
    MIN_FACTOR,
    TOO_SMALL_STEP,
    Loop,
    first_step,
    loop_applies,
    method_module,
)

if TYPE_CHECKING:
    from types import ModuleType

    from ..numeric.compiled import CompiledSystem

#: Steps per call of the loop (the watch is told the time after each call).
STEPS_PER_CALL = 256


def sensitivity_loop(compiled: CompiledSystem, parameters: Sequence[str]) -> Loop | None:
    """The loop of the state and its sensitivities, the first columns to ``parameters``
    (any number of initial-value columns after them), or None where it does not apply."""
    from ..codegen.cache import built

    if not loop_applies(compiled):
        return None
    parameters = tuple(parameters)
    return built(
        compiled.forms.fingerprint, "dop853-sensitivity", lambda: _build(compiled, parameters),
        parameters,
    )  # fmt: skip


def workspace_size(n: int, parameters: int) -> int:
    """The size m the method's workspace is made for: its G array (2 m^2 entries) holds
    the n x (2n + parameters) entries of G, and its M (m x m) and column (m) the n x n
    and n the system's code uses (it indexes them by its own N)."""
    return max(n, math.ceil(math.sqrt(n * (2 * n + parameters) / 2)))


def _build(compiled: CompiledSystem, parameters: tuple[str, ...]) -> Loop:
    from ..codegen.cache import load_text
    from ..codegen.numba import NumbaTarget

    NumbaTarget().load(compiled.program)  # the fillers' module, imported by the system's
    jacobian = _jacobian_filler(compiled, parameters).__name__
    system = load_text(*derivative_text(compiled, jacobian, len(parameters)))
    method = method_module()
    size = workspace_size(compiled.n, len(parameters))
    return Loop(method, method.y_prime(system.derivative), size, True)


def _jacobian_filler(compiled: CompiledSystem, parameters: tuple[str, ...]) -> ModuleType:
    """The generated ``jacobian(t, y, p, a, G)``: G = d(f - M a)/d(q, q', p_wrt) (row by
    row) with the accelerations a as an argument."""
    import sympy

    from ..codegen.numba import load_functions
    from ..codegen.sensitivity import sensitivity_forms

    forms = compiled.forms
    accelerations = tuple(sympy.Symbol(f"_a{i}") for i in range(forms.n))
    block = sensitivity_forms(forms, parameters).residual_jacobian
    block = block.xreplace(dict(zip(forms.accelerations, accelerations, strict=True)))
    return load_functions(
        forms, "sensitivity", [("jacobian", [("G", list(block))])],
        vectors={"jacobian": ("a", accelerations)},
    )  # fmt: skip


def solve_on_grid(
    loop: Loop,
    z0: np.ndarray,
    params: np.ndarray,
    times: np.ndarray,
    rtol: float,
    atol: float,
    watch: Callable[[float], None] | None = None,
) -> np.ndarray:
    """z at ``times`` (from times[0] to times[-1]), (len(times), len(z0)), from the dense
    output of the compiled loop."""
    z = np.array(z0, dtype=float)
    size = z.shape[0]
    flags = np.zeros(1, dtype=np.int64)

    def slope(t: float, y: np.ndarray) -> np.ndarray:
        out = np.empty_like(y)
        loop.slope(t, y, params, out, flags)
        return out

    t0, t1 = float(times[0]), float(times[-1])
    f = slope(t0, z)
    clock = np.array([t0, first_step(slope, t0, z, f, t1, rtol, atol)])
    counts = np.array([2, 0, 0, 0], dtype=np.int64)
    grid = np.ascontiguousarray(times, dtype=float)
    out = np.empty((grid.shape[0], size))
    ends, ys = np.empty(STEPS_PER_CALL), np.empty((STEPS_PER_CALL, size))
    olds, slopes = np.empty((STEPS_PER_CALL, size)), np.empty((STEPS_PER_CALL, 7, size))
    status = 0
    while status == 0:
        counts[1] = 0
        try:
            status = loop.advance(
                clock, z, f, params, t1, rtol, atol, True, grid, out, ends, ys, olds, slopes,
                counts, flags,
            )  # fmt: skip
        except ZeroDivisionError:  # NumPy's inf: rejected, as SciPy rejects a NaN error
            flags[0], counts[3] = 1, 1
            clock[1] *= MIN_FACTOR
        if watch is not None:
            watch(float(clock[0]))
    if status == 2:
        raise ModelError(f"the integration failed at t = {clock[0]:g}: {TOO_SMALL_STEP}")
    if status == 3 or counts[2] < grid.shape[0]:
        raise ModelError(f"the integration failed at t = {clock[0]:g}: the state is not finite")
    return out
