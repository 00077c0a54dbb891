"""Linearization about an equilibrium and the normal modes of the small oscillations.

With M(q, t) q'' = f(q, q', t) (see :class:`~lagrangian.derive.EquationsOfMotion`)
and an equilibrium q0 (f(q0, 0, t) = 0), a small displacement x = q - q0 obeys

    M0 x'' + C0 x' + K0 x = 0,   M0 = M(q0),  K0 = -df/dq |0,  C0 = -df/dq' |0.

C0 = D + G splits into damping D (symmetric part) and gyroscopic terms G
(antisymmetric part, from magnetic fields or rotating frames).  Solutions
x = X exp(i w t) need det(K0 - w^2 M0 + i w C0) = 0.  Without damping that
polynomial is even in w (transpose the matrix), so it is a polynomial of degree
n in s = w^2 whose n roots, with multiplicity, are the ``omega_squared``: s > 0
an oscillation of angular frequency sqrt(s), s = 0 a neutral direction, s < 0
or s not real an instability.  With damping, ``omega_squared`` are those of the
undamped system (M0, G, K0) and stability is decided from the characteristic
exponents lambda, det(M0 lambda^2 + C0 lambda + K0) = 0 (Routh-Hurwitz).  A
gyroscopic system can be stable with K0 not positive definite (a charge on a
potential hill in a strong magnetic field) [Goldstein, Classical Mechanics, ch. 6;
Merkin, Introduction to the Theory of Stability, ch. 6].

Closed forms: the polynomial in s comes from a division-free (Berkowitz)
determinant and is solved exactly when its factors have degree <= 2; otherwise
everything is computed numerically at the default parameter values.  Signs of
symbolic roots are decided by the parameters' assumptions for generic values (a
real parameter is taken non-zero), else at the default values.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import sympy
from sympy.core.function import AppliedUndef

from ..algebra import tidy
from ..derive import EquationsOfMotion
from ..errors import ModelError
from ..model import System
from ..model.values import check_parameter_expressions
from .modes import ModeAnalysis, NormalModes, Stability, vanishes  # noqa: F401  (re-exported)


@dataclass(frozen=True, eq=False)
class LinearizedSystem:
    """M0 x'' + C0 x' + K0 x = 0 about ``point`` (x = q - q0, written with the names q).

    >>> import lagrangian as lg
    >>> eom = lg.load("simple_pendulum").equations_of_motion()
    >>> linearize(eom, at={"theta": 0}).normal_modes().omega_squared
    (g/l,)
    """

    system: System
    point: Mapping[str, sympy.Expr]
    mass: sympy.ImmutableMatrix
    damping: sympy.ImmutableMatrix
    stiffness: sympy.ImmutableMatrix
    values: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", MappingProxyType(dict(self.point)))
        object.__setattr__(self, "values", MappingProxyType(dict(self.values)))

    @property
    def gyroscopic(self) -> sympy.ImmutableMatrix:
        """G = (C0 - C0^T)/2."""
        return _tidy_matrix((self.damping - self.damping.T) / 2)

    @property
    def dissipative(self) -> sympy.ImmutableMatrix:
        """D = (C0 + C0^T)/2."""
        return _tidy_matrix((self.damping + self.damping.T) / 2)

    @property
    def equations(self) -> tuple[sympy.Expr, ...]:
        """(M0 x'' + C0 x' + K0 x)_i, each = 0."""
        coordinates = self.system.coordinates
        x = sympy.Matrix([c.q for c in coordinates])
        v = sympy.Matrix([c.q_dot for c in coordinates])
        a = sympy.Matrix([c.q_ddot for c in coordinates])
        rows = self.mass * a + self.damping * v + self.stiffness * x
        return tuple(tidy(row, self.system.state_symbols) for row in rows)

    def normal_modes(self) -> NormalModes:
        """Frequencies, mode shapes and stability (see the module docstring)."""
        if any(m.has(AppliedUndef) for m in (self.mass, self.stiffness, self.damping)):
            return NormalModes.undetermined("the linearization involves unspecified functions")
        if tidy(self.mass.det(method="berkowitz"), trig=True) == 0:
            return NormalModes.undetermined(
                "the mass matrix is singular at this point (a coordinate singularity)"
            )
        return ModeAnalysis(self).compute()


def linearize(
    eom: EquationsOfMotion, at: Mapping[str, object], *, check: bool = True
) -> LinearizedSystem:
    """Linearize M q'' = f about the rest point ``at`` (q = q0, q' = 0).

    ``at`` maps coordinate names to numbers or SymPy expressions; it may also fix
    parameters (``{"theta": 0.3, "p_phi": 1.2}``).  A coordinate left out must
    not appear in M or f (a cyclic one).  Raises ModelError when it does, when
    f(q0, 0) != 0 (not an equilibrium, up to rounding; ``check=False`` skips this
    test for points known to be equilibria), when the equations depend on t
    there, or when they are singular at the point.
    """
    system = eom.system
    if system.constraints:
        raise ModelError("linearization with constraints is not supported", field="constraints")
    values = {
        c.name: _value(at[c.name], c.name, system) for c in system.coordinates if c.name in at
    }
    parameters = {p.name: p for p in system.parameters}
    fixed = {}
    for name, value in at.items():
        if name in parameters:
            fixed[name] = _value(value, name, system)
        elif name not in values:
            known = ", ".join((*system.coordinate_names, *parameters))
            raise ModelError(f"'{name}' is not a coordinate or parameter (known: {known})")
    check_parameter_expressions(system, fixed)  # the model's checks of the values given
    q = [c.q for c in system.coordinates]
    qdot = [c.q_dot for c in system.coordinates]
    missing = [
        c.name
        for c in system.coordinates
        if c.name not in values and (eom.mass_matrix.has(c.q) or eom.forcing.has(c.q))
    ]
    if missing:
        raise ModelError(
            "the point must give " + ", ".join(missing) + " (they appear in the equations)"
        )
    substitution = {c.q: values[c.name] for c in system.coordinates if c.name in values}
    substitution |= dict.fromkeys(qdot, sympy.Integer(0))
    substitution |= {parameters[name].symbol: value for name, value in fixed.items()}
    forcing = eom.forcing
    rest = forcing.xreplace(substitution)
    mass = eom.mass_matrix.xreplace(substitution)
    stiffness = -forcing.jacobian(q).xreplace(substitution)
    damping = -forcing.jacobian(qdot).xreplace(substitution)
    parts = (rest, mass, stiffness, damping)
    if any(entry.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo) for p in parts for entry in p):
        raise ModelError("the equations of motion are singular at this point")
    if any(p.has(system.time) for p in parts):
        raise ModelError(
            "the equations depend explicitly on t at this point: no fixed linearization"
        )
    defaults = dict(system.parameter_values) | {
        name: float(v) for name, v in fixed.items() if v.is_number and v.is_real
    }
    residual = [r for r in rest if check and not vanishes(r, system, defaults)]
    if residual:
        raise ModelError(
            "not an equilibrium: f(q0, 0) = " + ", ".join(str(tidy(r)) for r in residual) + " != 0"
        )

    clean = _tidy_matrix
    point = values | fixed
    return LinearizedSystem(system, point, clean(mass), clean(damping), clean(stiffness), defaults)


def _tidy_matrix(matrix: sympy.Matrix) -> sympy.ImmutableMatrix:
    return sympy.ImmutableMatrix(matrix.applyfunc(lambda e: tidy(e, trig=True)))


def _value(value: object, name: str, system: System) -> sympy.Expr:
    if isinstance(value, bool) or not isinstance(value, int | float | sympy.Basic):
        raise ModelError(f"expected a number or SymPy expression, got {value!r}", field=name)
    if isinstance(value, int):
        return sympy.Integer(value)
    if isinstance(value, float):
        return sympy.Float(value)
    table = {p.name: p.symbol for p in system.parameters}
    unknown = sorted(s.name for s in value.free_symbols if s.name not in table)
    if unknown:
        raise ModelError(f"unknown symbols {unknown} in the value", field=name)
    return value.xreplace({s: table[s.name] for s in value.free_symbols})
