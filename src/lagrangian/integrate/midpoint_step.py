r"""The midpoint variational step of one state, from compiled fillers.

:class:`~lagrangian.integrate.variational.Variational` works on batches of states
with the NumPy functions of a compiled system: seven calls and some thirty array
operations per Newton iteration, most of a millisecond per step of a double
pendulum.  For one state (a single run) the same step is taken here from four
generated functions of (t, z = [q_m, v], p) that fill given arrays, the entries of
:mod:`lagrangian.codegen.schemes` (``momenta_force``: L_q' and L_q + Q;
``jacobian``: the Newton Jacobian J, which depends on h; ``momenta``; ``mass``),
each with its common subexpressions eliminated, by :func:`sympy.lambdify` over Python
floats (``math`` functions), whose values are copied into the arrays: the backends
``numpy`` and ``llvm``.  (On the numba backend the whole run is compiled, the step
printed from :mod:`lagrangian.codegen.steps`: :mod:`.compiled_loop`.)

The iteration, its first guess and its convergence test are the batch step's
(``Variational._midpoint``) for one element.  A filler that fails on a value (a
division by zero, a logarithm of a negative number) raises :class:`Unavailable`,
and the caller takes the step with the NumPy functions, whose inf or NaN the
driver reports.  Systems whose entries cannot be printed for ``math`` (a declared
function given as data) are not built here (:func:`midpoint_functions` returns None).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import sympy

from ..codegen.cache import built
from ..numeric.backends import solve_one
from .compiled_loop import Newton, Unavailable
from .fixed_step import StepFailure

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem
    from .base import Work


class MidpointFunctions:
    """The four fillers of one system (see the module), each ``f(t, z, p, [h], *outputs)``."""

    def __init__(self, n: int, fillers: dict):
        self.n = n
        self.momenta_force = fillers["momenta_force"]
        self.jacobian = fillers["jacobian"]
        self.momenta = fillers["momenta"]
        self.mass = fillers["mass"]


def midpoint_functions(compiled: CompiledSystem) -> MidpointFunctions | None:
    """The fillers of ``compiled`` (built on first use, then kept), or None where there are none."""
    if compiled.backend not in ("numpy", "llvm") or compiled.has_constraints:
        return None
    if compiled.forms is None:
        return None  # functions given by hand: no equations to generate code from
    # every step asks: once built, a lookup without a lock
    build = lambda: _build(compiled)  # noqa: E731
    return built(compiled.forms.fingerprint, "midpoint", build, compiled.backend)


def _build(compiled: CompiledSystem) -> MidpointFunctions | None:
    from ..codegen.schemes import SCALARS, scheme_expressions
    from ..errors import ModelError

    forms = compiled.forms
    try:
        functions = scheme_expressions(forms, "midpoint")
        fillers = {
            name: _lambdified(forms, outputs, SCALARS.get(name, ())) for name, outputs in functions
        }
    except (ModelError, NameError, TypeError, ValueError, KeyError):
        return None  # something the generated code cannot express: the NumPy step runs
    return MidpointFunctions(forms.n, fillers)


def _lambdified(forms, outputs, scalars):
    """A filler ``f(t, z, p, *scalars, *arrays)`` from lambdify over Python floats."""
    arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters, *scalars)
    entries = [entry for _, values in outputs for entry in values]
    function = sympy.lambdify(arguments, entries, modules="math", cse=True, dummify=True)
    sizes = [len(values) for _, values in outputs]
    count = len(scalars)

    def filler(t, z, p, *rest):
        try:
            values = function(t, *z.tolist(), *p.tolist(), *rest[:count])
        except (ZeroDivisionError, ValueError, OverflowError):
            raise Unavailable from None
        if len(sizes) == 1:
            rest[count].flat = values
            return
        start = 0
        for array, size in zip(rest[count:], sizes, strict=True):
            array.flat = values[start : start + size]
            start += size

    return filler


def step_one(
    functions: MidpointFunctions,
    t: float,
    h: float,
    y: np.ndarray,
    p: np.ndarray,
    last: np.ndarray | None,
    params: np.ndarray,
    work: Work,
    newton: Newton,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(y, momenta, midpoint velocity) after the midpoint step of one state y (2n,) at t.

    ``p``: the momenta at t; ``last``: the previous step's midpoint velocity (None at
    the first step).  The iterations of ``Variational._midpoint`` and ``_velocity``
    for one batch element, counted in ``work`` as there.
    """
    params = np.ascontiguousarray(params, dtype=float)
    n = functions.n
    q, w = y[:n], y[n:]
    v = w if last is None else 2 * w - last
    tm = t + h / 2
    reach = max(1.0, float(abs(q).max()))
    z, momenta, force = np.empty(2 * n), np.empty(n), np.empty(n)
    matrix = np.empty((n, n))
    previous = np.inf
    for iteration in range(newton.iterations + 1):
        z[:n] = q + (h / 2) * v
        z[n:] = v
        functions.momenta_force(tm, z, params, momenta, force)
        work.rhs_evaluations += 1
        residual = momenta - (h / 2) * force - p
        size, scale = _sizes(residual, p, momenta)
        if _converged(size, previous, scale, reach, newton):
            break
        if iteration == newton.iterations:
            raise StepFailure(
                "Newton's method for the midpoint velocity did not converge in "
                f"{newton.iterations} iterations (residual {size:.2e})"
            )
        previous = size
        functions.jacobian(tm, z, params, h, matrix)
        work.jacobian_evaluations += 1
        work.newton_iterations += 1
        v = v - _solved(matrix, residual)
    p_new = p + h * force
    q_new = q + h * v
    # the velocity from the momenta, L_q'(q, q') = p_{k+1}: Newton with M, from v
    z[:n] = q_new
    z[n:] = v
    reach = max(1.0, float(abs(q_new).max()))
    previous = np.inf
    for iteration in range(newton.iterations + 1):
        functions.momenta(t + h, z, params, momenta)
        work.rhs_evaluations += 1
        residual = momenta - p_new
        size, scale = _sizes(residual, p_new, momenta)
        if _converged(size, previous, scale, reach, newton):
            return np.concatenate([q_new, z[n:]]), p_new, v
        if iteration == newton.iterations:
            break
        previous = size
        functions.mass(t + h, z, params, matrix)
        work.jacobian_evaluations += 1
        z[n:] -= _solved(matrix, residual)
    raise StepFailure(
        f"the velocity for the momenta did not converge in {newton.iterations} iterations"
    )


def _converged(size: float, previous: float, scale: float, reach: float, newton: Newton) -> bool:
    """``variational._converged`` for one state, on Python floats."""
    if size <= newton.tol * scale or size == 0.0:
        return True
    return size >= newton.stall * previous and size <= newton.floor * scale * reach


def _sizes(residual: np.ndarray, p: np.ndarray, momenta: np.ndarray) -> tuple[float, float]:
    """max |residual| and the scale max(max |p|, max |momenta|), as Python floats
    (a NaN anywhere makes the size NaN, as numpy's max, so a NaN never converges)."""
    if residual.shape[0] > 4:
        size = float(abs(residual).max())
        return size, float(max(abs(p).max(), abs(momenta).max()))
    values = residual.tolist()  # a few numbers: Python floats are faster than NumPy calls
    size = max(map(abs, values))
    if size != size or any(value != value for value in values):
        size = math.nan  # max() keeps a NaN only where it comes first
    return size, max(map(abs, p.tolist() + momenta.tolist()))


def _solved(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    x = solve_one(matrix, rhs)
    if x is None:
        raise StepFailure("the Newton matrix (the mass matrix) is singular")
    return x
