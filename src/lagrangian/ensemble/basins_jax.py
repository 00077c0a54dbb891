"""The basin walk's iterations on the JAX ensemble's loop (``backend="jax"``).

The starts of a pool step the same rk4 steps on the same grid of times as on numba
(:class:`lagrangian.ensemble.basins._Walk`), through the jitted loop of
:mod:`lagrangian.ensemble.jax_backend` in float64 (its state saved after every
``steps`` steps: once per iteration of the map), on JAX's default device (a GPU where
JAX has one).  The loop is traced once per compiled system and pool size, and the pool
is padded (its last start repeated) to one of a few sizes, FIRST_POOL times a power of
four, so that a walk whose pool grows and shrinks compiles it a few times at most.  The
labeller stays on the host: each call returns numpy arrays.  JAX is imported here only.
"""

from __future__ import annotations

import numpy as np

#: The pool is padded to the least of FIRST_POOL * GROWTH**k that holds it.
GROWTH = 4


def padded_size(count: int, first: int) -> int:
    """The least ``first * GROWTH**k`` >= ``count`` (a few sizes: a few compiles)."""
    size = first
    while size < count:
        size *= GROWTH
    return size


class JaxIterations:
    """``iterations(states)``: the states (B, m) after each of the ``chunk`` iterations of
    ``steps`` rk4 steps on ``grid`` (``chunk * steps + 1`` times), (B, m, chunk)."""

    def __init__(self, compiled, p: np.ndarray, grid: np.ndarray, steps: int, first: int):
        from ..integrate.explicit_rk import RK4
        from .jax_backend import _jax, _loop

        self.jax = _jax()  # without JAX: one line naming the extra, before any work
        self.p, self.grid, self.first = np.asarray(p, dtype=float), grid, first
        # the loop (cached per compiled system and settings) saves every ``steps`` steps;
        # dt is not part of its key: the grid gives the times
        self.loop = _loop(compiled, RK4(dt=float(grid[1] - grid[0])), "float64", steps,
                          False, False)  # fmt: skip

    def __call__(self, states: np.ndarray) -> np.ndarray:
        from .jax_backend import _padded

        count = states.shape[0]
        y0, _ = _padded(np.ascontiguousarray(states.T), self.p, padded_size(count, self.first))
        with self.jax.enable_x64(True):
            results = self.loop(y0, self.p, self.grid)
            paths = np.asarray(self.jax.device_get(results[3]), dtype=float)
        # (iterations + 1, m, size) -> (count, m, iterations), the first (the start) dropped
        return np.ascontiguousarray(np.transpose(paths[1:, :, :count], (2, 1, 0)))
