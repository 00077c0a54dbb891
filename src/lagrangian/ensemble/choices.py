"""The names an ensemble run can be asked for: its backends, methods and precisions.

Kept apart from the runner (:mod:`.core` imports xarray and the integrators) so that
the command line reads its choices here without importing them.
"""

from __future__ import annotations

from ..codegen.c import PRECISIONS

#: How the members are integrated: NumPy arrays, a numba loop, JAX, CUDA C, a Dask cluster.
BACKENDS = ("numpy", "numba", "jax", "cuda", "dask")
#: The fixed-step methods of ensembles.
METHODS = ("rk4", "variational")

__all__ = ["BACKENDS", "METHODS", "PRECISIONS"]
