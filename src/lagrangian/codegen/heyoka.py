"""The heyoka target: the explicit ODE y' = [q', M^{-1} f] as heyoka's expressions.

M and f of M q'' = f (declared functions replaced by their definitions) are converted
with ``heyoka.from_sympy``: time as ``heyoka.time``, q and q' as variables ``q<i>``,
``v<i>``, the parameters as heyoka's runtime parameters ``par[j]``; q'' = M^{-1} f is
written out as Gaussian elimination in those expressions (the one elimination,
:func:`lagrangian.codegen.steps.elimination`, walked over them without pivoting by
:func:`lagrangian.codegen.arrays.eliminated`; why no pivoting is needed where M is
definite: :mod:`lagrangian.integrate.taylor`, which builds heyoka's integrator from
``load``).  ``render`` gives the ODE as heyoka prints it.

Each largest subexpression of M and f made of parameters alone (``l1*l2*m2`` of
``l1*l2*m2*cos(theta1 - theta2)``, ``m1 + m2``) becomes one more runtime parameter,
computed from the parameters before a run (:attr:`HeyokaOde.constants`): heyoka
computes a product of parameters again at every order of every step, and the double
pendulum's ODE took 50 elementary operations against the 32 of the same equations
with the values written in (1.3-1.5x the time of a step); hoisted, it takes 36.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import sympy

from ..errors import MissingDependencyError, ModelError
from .arrays import eliminated
from .program import Program
from .subtrees import hoisted
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
        ode = self.load(program)
        lines = [f"d{variable}/dt = {rate}" for variable, rate in ode.equations]
        names = [str(symbol) for symbol in program.forms.parameters]
        lines += [f"par[{j}] = {symbol}" for j, symbol in enumerate(names)]
        start = len(names)
        lines += [f"par[{start + j}] = {value}" for j, value in enumerate(ode.hoisted)]
        return "".join(line + "\n" for line in lines)

    def load(self, program: Program) -> HeyokaOde:
        """The ODE q<i>' = v<i>, v<i>' = q''_i over ``par[j]`` (see :class:`HeyokaOde`)."""
        import heyoka as hy

        forms = program.forms
        n = forms.n
        parameters = tuple(forms.parameters)
        table: dict[sympy.Expr, sympy.Symbol] = {}
        mass = [[_hoisted(forms.mass_matrix[i, j], parameters, table) for j in range(n)]
                for i in range(n)]  # fmt: skip
        forcing = [_hoisted(forms.forcing[i, 0], parameters, table) for i in range(n)]
        q = [hy.make_vars(f"q{i}") for i in range(n)]
        v = [hy.make_vars(f"v{i}") for i in range(n)]
        replace = {forms.time: hy.time}
        replace |= dict(zip(forms.coordinates, q, strict=True))
        replace |= dict(zip(forms.velocities, v, strict=True))
        replace |= {symbol: hy.par[j] for j, symbol in enumerate((*parameters, *table.values()))}
        try:
            matrix = [[_from_sympy(mass[i][j], replace) for j in range(n)] for i in range(n)]
            force = [_from_sympy(forcing[i], replace) for i in range(n)]
        except (TypeError, ValueError) as error:
            raise ModelError(f"method 'taylor' cannot express the equations: {error}") from None
        accelerations = eliminated(matrix, force)
        equations = [(q[i], v[i]) for i in range(n)] + [(v[i], accelerations[i]) for i in range(n)]
        hoisted = tuple(table)
        function = sympy.lambdify(parameters, list(hoisted), "numpy") if hoisted else None
        return HeyokaOde(equations, hoisted, _constants(function))


@dataclass(frozen=True)
class HeyokaOde:
    """heyoka's [(variable, its rate)] over ``par[j]``: the program's parameters first, in
    their order, then the ``hoisted`` subexpressions of them; ``constants(params)`` gives
    all of these values from the parameters'."""

    equations: list
    hoisted: tuple[sympy.Expr, ...]
    constants: Callable[[np.ndarray], np.ndarray]


def _constants(function) -> Callable[[np.ndarray], np.ndarray]:
    def constants(params: np.ndarray) -> np.ndarray:
        params = np.asarray(params, dtype=float)
        if function is None:
            return params
        with np.errstate(all="ignore"):  # 1/(m1 - m2) at m1 = m2: inf, reported by the run
            values = function(*(np.float64(value) for value in params))
        return np.concatenate([params, np.asarray(values, dtype=float).ravel()])

    return constants


def _hoisted(
    expression: sympy.Expr, parameters: tuple, table: dict[sympy.Expr, sympy.Symbol]
) -> sympy.Expr:
    """``expression`` with each largest subexpression of ``parameters`` alone (a number
    or one parameter aside) replaced by a symbol that ``table`` keeps for it."""
    known = set(parameters)

    def entry(part: sympy.Expr) -> sympy.Expr | None:  # numbers stay as they are
        if part.is_Atom or not part.free_symbols:
            return None
        if part not in table:
            table[part] = sympy.Dummy(f"c{len(table)}")
        return table[part]

    return hoisted(expression, lambda part: part.free_symbols <= known, entry)


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
