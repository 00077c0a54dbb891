"""The llvm target: M and f of one state as SymEngine's LLVM-compiled code.

``load`` gives one :class:`symengine.Lambdify` (``backend="llvm"``, common
subexpressions eliminated) of [t, q, q', params] -> [M row by row, f] of M q'' = f,
made in milliseconds (a 10-link chain: about 0.05 s, where numba compiles for
seconds), or None where SymEngine cannot hold the equations (declared functions,
floating-point numbers: see :func:`lagrangian.algebra.to_symengine`);
:mod:`lagrangian.numeric.llvm_functions` solves M q'' = f with it.  ``render`` gives
the entries as SymEngine reads them: LLVM's own code is not text.

:func:`load_jacobian` gives the Jacobian of the same equations for the variational
equations and implicit methods: G = d(f - M a)/d(q, q') over [t, q, q', a, params],
a the accelerations as symbols, so that dq''/d(q, q') = M^-1 G at a = q'' (see
:mod:`lagrangian.numeric.dynamics`): no solved accelerations are differentiated.
"""

from __future__ import annotations

import functools

from ..algebra import to_symengine
from ..distributions import without_distributions
from ..errors import MissingDependencyError
from .program import Program
from .target import AbstractLoadedTarget


@functools.cache
def llvm_available() -> bool:
    """Whether SymEngine's Lambdify can compile with LLVM here."""
    try:
        import symengine as se

        x = se.Symbol("x")
        se.Lambdify([x], [x + 1], backend="llvm")
    except (ImportError, RuntimeError, ValueError, TypeError):
        return False
    return True


class LLVMTarget(
    AbstractLoadedTarget, name="llvm", language="LLVM (SymEngine)", suffix=".txt", base=0
):
    """M and f of one state (see the module docstring)."""

    def check(self) -> None:
        if not llvm_available():
            raise MissingDependencyError(
                "backend 'llvm'", "SymEngine built with LLVM (the symengine wheels are)"
            )

    def render(self, program: Program, name: str) -> str:
        converted = _converted(program)
        if converted is None:
            return ""
        symbols, entries = converted
        lines = ["arguments: " + ", ".join(str(s) for s in symbols)]
        return "\n".join([*lines, *(str(entry) for entry in entries), ""])

    def load(self, program: Program):
        """symengine.Lambdify of [M row by row, f] over [t, q, q', params], or None."""
        # None where SymEngine cannot hold the equations: the NumPy functions answer
        return _lambdified(_converted(program))


def llvm_blocks(program: Program):
    """:meth:`LLVMTarget.load` of ``program``, made once per process for its equations:
    shared by the llvm backend's functions and DOP853's loop over them
    (:func:`lagrangian.integrate.compiled_dop853.linked_loop`)."""
    from .cache import built

    return built(program.forms.fingerprint, "llvm", lambda: LLVMTarget().load(program))


def load_jacobian(program: Program):
    """symengine.Lambdify of G = d(f - M a)/d(q, q') row by row (n x 2n) over
    [t, q, q', a, params], or None where SymEngine (or its LLVM) cannot hold it."""
    import sympy

    forms = program.forms
    accelerations = sympy.Matrix(forms.accelerations)
    residual = sympy.Matrix(forms.forcing) - forms.mass_matrix * accelerations
    jacobian = residual.jacobian([*forms.coordinates, *forms.velocities])
    arguments = (
        forms.time, *forms.coordinates, *forms.velocities, *forms.accelerations, *forms.parameters
    )  # fmt: skip
    return _lambdified(_symengine(list(jacobian), arguments))


def _lambdified(converted):
    """symengine.Lambdify (LLVM) of (arguments, entries), or None where it cannot be made."""
    if converted is None or not llvm_available():
        return None
    import symengine as se

    symbols, entries = converted
    try:
        return se.Lambdify(symbols, entries, backend="llvm", cse=True)
    except (RuntimeError, ValueError, TypeError, NotImplementedError):
        return None


def _converted(program: Program):
    """(arguments, [M row by row, f]) as SymEngine objects, or None where it cannot hold them."""
    forms = program.forms
    n = forms.n
    entries = [forms.mass_matrix[i, j] for i in range(n) for j in range(n)]
    entries += [forms.forcing[i, 0] for i in range(n)]
    arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters)
    return _symengine(entries, arguments)


def _symengine(entries, arguments):
    """(arguments, entries) as SymEngine objects, or None where it cannot hold them."""
    cache: dict = {}
    converted = [to_symengine(without_distributions(entry), cache) for entry in entries]
    symbols = [to_symengine(symbol, cache) for symbol in arguments]
    if any(x is None for x in converted):
        return None
    known = set(symbols)
    if any(not (x.free_symbols <= known) for x in converted):
        return None
    return symbols, converted
