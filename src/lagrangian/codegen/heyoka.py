"""The heyoka target: the explicit ODE y' = [q', M^{-1} f] as heyoka's expressions.

M and f of M q'' = f (declared functions replaced by their definitions) are converted
with ``heyoka.from_sympy``: time as ``heyoka.time``, q and q' as variables ``q<i>``,
``v<i>``, the parameters as heyoka's runtime parameters ``par[j]``; q'' = M^{-1} f is
written out as Gaussian elimination in those expressions (the one elimination,
:func:`lagrangian.codegen.steps.elimination`, walked over them without pivoting by
:func:`lagrangian.codegen.arrays.eliminated`; why no pivoting is needed where M is
definite: :mod:`lagrangian.integrate.taylor`, which builds heyoka's integrator from
``load``).  ``render`` gives the ODE as heyoka prints it.
"""

from __future__ import annotations

import sympy

from ..errors import MissingDependencyError, ModelError
from .arrays import eliminated
from .program import Program
from .target import AbstractLoadedTarget


class HeyokaTarget(
    AbstractLoadedTarget, name="heyoka", language="heyoka expressions", suffix=".txt", base=0
):
    """The ODE of a program (see the module docstring)."""

    def check(self) -> None:
        try:
            import heyoka  # noqa: F401
        except ImportError:
            raise MissingDependencyError("method 'taylor'", "heyoka", "taylor") from None

    def render(self, program: Program, name: str) -> str:
        return "".join(f"d{variable}/dt = {rate}\n" for variable, rate in self.load(program))

    def load(self, program: Program) -> list:
        """[(variable, its rate)] for q<i>' = v<i> and v<i>' = q''_i, over ``par[j]``."""
        import heyoka as hy

        forms = program.forms
        n = forms.n
        q = [hy.make_vars(f"q{i}") for i in range(n)]
        v = [hy.make_vars(f"v{i}") for i in range(n)]
        replace = {forms.time: hy.time}
        replace |= dict(zip(forms.coordinates, q, strict=True))
        replace |= dict(zip(forms.velocities, v, strict=True))
        replace |= {symbol: hy.par[j] for j, symbol in enumerate(forms.parameters)}
        mass, forcing = forms.mass_matrix, forms.forcing
        try:
            matrix = [[_from_sympy(mass[i, j], replace) for j in range(n)] for i in range(n)]
            force = [_from_sympy(forcing[i, 0], replace) for i in range(n)]
        except (TypeError, ValueError) as error:
            raise ModelError(f"method 'taylor' cannot express the equations: {error}") from None
        accelerations = eliminated(matrix, force)
        return [(q[i], v[i]) for i in range(n)] + [(v[i], accelerations[i]) for i in range(n)]


def _from_sympy(expression, replace: dict):
    """heyoka's expression of a SymPy one; a rational heyoka cannot hold exactly (a
    denominator that is not a power of 2, as in x/10) becomes the nearest double, as in
    every other compiled form."""
    import heyoka as hy

    inexact = {
        number: sympy.Float(number, precision=53)
        for number in expression.atoms(sympy.Rational)
        if number.q & (number.q - 1)
    }
    return hy.from_sympy(expression.xreplace(inexact) if inexact else expression, replace)
