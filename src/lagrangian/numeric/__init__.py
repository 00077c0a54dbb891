"""Stage 4: EquationsOfMotion -> CompiledSystem, pure numerical functions of (t, y, params).

    compile_equations(eom, backend="numpy", definitions=None) -> CompiledSystem

Backends (``BACKENDS``): ``numpy`` and ``jax`` (JAX imported only when asked for);
``backend="numba"`` gives the NumPy functions with numba kernels for one state
(``compile.JIT_BACKENDS``; numba imported only then), ``backend="llvm"`` the
same with SymEngine's LLVM code (``default_backend()``: what a single run uses).
"""

from .backends import BACKENDS, ArrayBackend, array_backend
from .compile import DEFAULT_BAUMGARTE, compile_equations, default_backend
from .compiled import CompiledSystem

__all__ = [
    "BACKENDS",
    "DEFAULT_BAUMGARTE",
    "ArrayBackend",
    "CompiledSystem",
    "array_backend",
    "compile_equations",
    "default_backend",
]
