"""Array backends of the compiled functions: NumPy (always there) and JAX (optional).

A backend is what the generic numerical code needs from an array library: the
``modules`` argument of :func:`sympy.lambdify`, the array namespace ``xp``
(``numpy`` or ``jax.numpy``, which share the functions used here), and a way
to stack the entries a lambdified function returns (Python numbers for the
constant ones) into one array with the batch shape.  Backends are found by
name in :data:`BACKENDS`; JAX is imported only when its backend is built, so
``lagrangian`` works (and starts fast) without it.

Linear algebra is written batch-first, ``(*batch, rows, cols)``, the layout of
the stacked solvers (``numpy.linalg.solve`` on a stack of matrices).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType, ModuleType
from typing import Any

import numpy as np

from ..errors import MissingDependencyError, ModelError

Array = Any  # numpy.ndarray or jax.Array


@dataclass(frozen=True)
class ArrayBackend:
    """What the compiled functions need from an array library.

    ``eager`` is a capability: True when array values can be read in Python
    while computing (NumPy), so iterations may stop once converged; False when
    the functions may be traced (``jax.jit``), so iterations run a fixed count.
    ``iterate(step, x, count, tolerance)`` applies ``x, size = step(x)`` up to
    ``count`` times, stopping early (where it can) once ``size <= tolerance``.
    """

    name: str
    modules: str  # the ``modules`` argument of sympy.lambdify
    xp: ModuleType  # numpy or jax.numpy
    eager: bool
    stack: Callable[[Sequence[Any], tuple[int, ...]], Array]  # entries -> (*batch, k)
    stack_leading: Callable[[Sequence[Any], tuple[int, ...]], Array]  # entries -> (k, *batch)
    asarray: Callable[[Any], Array]
    iterate: Callable[[Callable[[Array], tuple[Array, Array]], Array, int, float], Array]

    def solve(self, matrix: Array, rhs: Array) -> Array:
        """x with ``matrix x = rhs`` for (*batch, n, n) and (*batch, n)."""
        if self.eager and matrix.shape[-1] <= 2:
            return _small_solve(matrix, rhs)
        if matrix.ndim == 2:
            return self.xp.linalg.solve(matrix, rhs)
        return self.xp.linalg.solve(matrix, rhs[..., None])[..., 0]

    def solve_matrix(self, matrix: Array, rhs: Array) -> Array:
        """X with ``matrix X = rhs`` for (*batch, n, n) and (*batch, n, k)."""
        return self.xp.linalg.solve(matrix, rhs)

    def transpose(self, matrix: Array) -> Array:
        """Swap the last two axes (the matrix axes of a batch-first stack)."""
        return self.xp.swapaxes(matrix, -1, -2)


def solve_one(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
    """x with ``matrix x = rhs`` for one system, (n, n) and (n,) or (n, k); None where it is
    singular.

    The one solve of a single system in Python (the compiled midpoint step of one state,
    the llvm right-hand sides and their Jacobians, the numpy backend's single state):
    LAPACK's LU solve (``dgesv``) called without numpy's wrapper, whose overhead is most
    of a small solve.
    """
    _, _, result, info = _gesv()(matrix, rhs)
    return None if info != 0 else result


@functools.cache
def _gesv():
    from scipy.linalg.lapack import dgesv

    return dgesv


def _small_solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``numpy.linalg.solve`` for n <= 2 by the closed forms, several times faster.

    LAPACK's call overhead is most of an rhs evaluation of a one- or two-coordinate
    model; Cramer's rule is as accurate as LU at n = 2 (Higham, *Accuracy and
    Stability of Numerical Algorithms*, 2nd ed., section 1.10.1).  One system is
    solved by :func:`solve_one`.
    """
    n = matrix.shape[-1]
    if matrix.ndim == 2:
        solution = solve_one(matrix, rhs)
        if solution is None:
            raise np.linalg.LinAlgError("Singular matrix")
        return solution
    a = matrix[..., 0, 0]
    if n == 1:
        determinant = a
    else:
        b, c, d = matrix[..., 0, 1], matrix[..., 1, 0], matrix[..., 1, 1]
        determinant = a * d - b * c
    if np.any(determinant == 0):
        raise np.linalg.LinAlgError("Singular matrix")
    if n == 1:
        return rhs / determinant[..., None]
    solution = np.empty(rhs.shape, dtype=np.result_type(matrix, rhs))
    solution[..., 0] = (d * rhs[..., 0] - b * rhs[..., 1]) / determinant
    solution[..., 1] = (a * rhs[..., 1] - c * rhs[..., 0]) / determinant
    return solution


# -- NumPy ---------------------------------------------------------------------
def _numpy_stack(values: Sequence[Any], batch_shape: tuple[int, ...]) -> np.ndarray:
    if not batch_shape:
        return np.array(values, dtype=float)
    out = np.empty((*batch_shape, len(values)))
    for index, value in enumerate(values):
        out[..., index] = value  # a constant entry broadcasts to the batch
    return out


def _numpy_stack_leading(values: Sequence[Any], batch_shape: tuple[int, ...]) -> np.ndarray:
    if not batch_shape:
        return np.array(values, dtype=float)
    out = np.empty((len(values), *batch_shape))
    for index, value in enumerate(values):
        out[index] = value  # contiguous rows: cheaper than the strided batch-first writes
    return out


def _numpy_asarray(value: Any) -> np.ndarray:
    return np.asarray(value, dtype=float)


def _numpy_iterate(step, x, count: int, tolerance: float):
    for _ in range(count):
        x, size = step(x)
        if float(size) <= tolerance:
            break
    return x


def numpy_backend() -> ArrayBackend:
    """The NumPy backend (the default)."""
    return ArrayBackend(
        name="numpy",
        modules="numpy",
        xp=np,
        eager=True,
        stack=_numpy_stack,
        stack_leading=_numpy_stack_leading,
        asarray=_numpy_asarray,
        iterate=_numpy_iterate,
    )


# -- JAX -------------------------------------------------------------------------
def jax_backend() -> ArrayBackend:
    """The JAX backend: the same functions, traceable by ``jax.jit`` and ``jax.vmap``.

    Arrays follow JAX's precision setting (float32 unless ``jax_enable_x64``).
    """
    try:
        import jax
        import jax.numpy as jnp
    except ImportError:
        raise MissingDependencyError("backend 'jax'", "JAX", "jax") from None

    def stack(values: Sequence[Any], batch_shape: tuple[int, ...], axis: int = -1):
        dtype = jnp.result_type(float)  # float64 with x64 enabled, else float32
        entries = [jnp.broadcast_to(jnp.asarray(v, dtype=dtype), batch_shape) for v in values]
        return jnp.stack(entries, axis=axis)

    def iterate(step, x, count: int, tolerance: float):
        """A fixed number of steps (traceable), compiled once as a loop."""
        return jax.lax.fori_loop(0, count, lambda _, value: step(value)[0], x)

    return ArrayBackend(
        name="jax",
        modules="jax",
        xp=jnp,
        eager=False,
        stack=stack,
        stack_leading=functools.partial(stack, axis=0),
        asarray=jnp.asarray,
        iterate=iterate,
    )


#: Backend name -> builder.  An unknown name is an error that lists these.
BACKENDS: Mapping[str, Callable[[], ArrayBackend]] = MappingProxyType(
    {"numpy": numpy_backend, "jax": jax_backend}
)


def array_backend(name: str) -> ArrayBackend:
    """The backend called ``name`` (see :data:`BACKENDS`)."""
    try:
        builder = BACKENDS[name]
    except (KeyError, TypeError):
        valid = ", ".join(sorted(BACKENDS))
        raise ModelError(f"unknown backend '{name}' (backends: {valid})") from None
    return builder()
