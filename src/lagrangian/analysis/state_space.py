"""State-space linearization: x' = A x + B u, y = C x + D u about an operating point.

With M(q, t) q'' = f(q, q', t, u) (see :class:`~lagrangian.derive.EquationsOfMotion`;
the inputs u are those of :mod:`lagrangian.model.inputs`) and the state
x = [q, q'], the first-order system is

    x' = F(x, u) = [q',  M(q)^-1 f(q, q', u)].

About an operating point (q0, q0', u0) where q'' = M^-1 f = 0 (an equilibrium,
q0' = 0, or a steady motion: only cyclic coordinates move, at constant rates),
small deviations obey x' = A x + B u, with

    A = [[0, I], [M0^-1 df/dq, M0^-1 df/dq']],   B = [[0], [M0^-1 df/du]],

everything at the point.  d(M^-1 f)/dx = M^-1 (df/dx - dM/dx q'') and the last
term vanishes there because q'' = 0, so M is never inverted symbolically: only
M0 = M(q0), by LU, at the point.  Outputs y = h(q, q', u) give C = dh/dx and
D = dh/du at the point (default: the whole state, C = I, D = 0).

The matrices are SymPy expressions in the parameters; :meth:`StateSpace.numeric`
evaluates them (default parameter values), :meth:`StateSpace.to_control` makes a
``control.ss`` of python-control when it is installed.  Constrained systems
and points where the equations depend on t are refused.  The state ordering is
always [q_1 .. q_n, q_1' .. q_n'] in the order of the coordinates.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..algebra import tidy
from ..derive import EquationsOfMotion
from ..errors import MissingDependencyError, ModelError
from ..model import System
from ..provided import Provided
from .modes import vanishes
from .operating_point import OperatingPoint, chosen_inputs, chosen_outputs, first_equilibrium

#: Entries longer than this (SymPy operation count) are only tidied, not factored.
SIMPLIFY_MAX_OPS = 400


@dataclass(frozen=True)
class NumericStateSpace:
    """A, B, C, D as float arrays with the names of the states, inputs and outputs."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class StateSpace:
    """x' = A x + B u, y = C x + D u about ``point`` (x, u, y deviations from it).

    ``point``: the values that define it (coordinates, velocities of steady
    motions, nominal inputs, parameters fixed there); ``values``: the default
    parameter values used by :meth:`numeric`.

    >>> import lagrangian as lg
    >>> ss = lg.load("simple_pendulum").state_space(at={"theta": 0})
    >>> ss.A
    Matrix([
    [   0, 1],
    [-g/l, 0]])
    """

    # the LaTeX of output/, given by the facade (see lagrangian.provided)
    _repr_latex_ = Provided()

    system: System
    point: Mapping[str, sympy.Expr]
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    A: sympy.ImmutableMatrix
    B: sympy.ImmutableMatrix
    C: sympy.ImmutableMatrix
    D: sympy.ImmutableMatrix
    values: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", MappingProxyType(dict(self.point)))
        object.__setattr__(self, "values", MappingProxyType(dict(self.values)))

    @property
    def parameters(self) -> tuple[str, ...]:
        """The parameters the matrices depend on, sorted."""
        matrices = (self.A, self.B, self.C, self.D)
        return tuple(sorted({s.name for m in matrices for s in m.free_symbols}))

    def numeric(self, params: Mapping[str, float] | None = None) -> NumericStateSpace:
        """The matrices at the default parameter values, overridden by ``params``.

        A parameter without a value is a ModelError naming it.
        """
        matrices = (self.A, self.B, self.C, self.D)
        if any(m.has(AppliedUndef, sympy.Derivative) for m in matrices):
            raise ModelError(
                "the matrices involve the model's unspecified functions: no numbers without "
                "their definitions"
            )
        values = dict(self.values) | dict(params or {})
        missing = [name for name in self.parameters if name not in values]
        if missing:
            raise ModelError(
                "no value for " + ", ".join(missing) + " (give params={name: value})",
                field="parameters",
            )
        symbols = {s.name: s for m in (self.A, self.B, self.C, self.D) for s in m.free_symbols}
        table = {symbols[name]: sympy.Float(values[name]) for name in symbols}
        arrays = []
        for matrix in (self.A, self.B, self.C, self.D):
            numbers = matrix.xreplace(table).evalf()
            try:
                arrays.append(np.array(numbers.tolist(), dtype=float).reshape(matrix.shape))
            except TypeError:
                raise ModelError(
                    "the state-space matrices are not real numbers at these parameter values"
                ) from None
        return NumericStateSpace(*arrays, self.states, self.inputs, self.outputs)

    def to_control(self, params: Mapping[str, float] | None = None):
        """``control.ss(A, B, C, D)`` of python-control (numbers: :meth:`numeric`)."""
        try:
            import control
        except ImportError:
            raise MissingDependencyError("to_control()", "python-control", "control") from None
        numbers = self.numeric(params)
        return control.ss(
            numbers.A,
            numbers.B,
            numbers.C,
            numbers.D,
            states=list(self.states),
            inputs=list(self.inputs),
            outputs=list(self.outputs),
        )


def state_space(
    eom: EquationsOfMotion,
    at: Mapping[str, object] | None = None,
    *,
    inputs: Sequence[str] | None = None,
    outputs: Mapping[str, object] | Sequence[str] | None = None,
) -> StateSpace:
    """Linearize x' = F(x, u) about ``at`` (see the module docstring).

    ``at`` maps coordinate names to values, velocity names (``phi_dot``) to the
    constant rates of a steady motion (cyclic coordinates only), input names to
    their nominal values and parameter names to fixed values; a value is a number
    or a SymPy expression in the parameters.  A coordinate left out must not
    appear in M or f; velocities and inputs left out are 0.  ``at=None`` takes
    the first equilibrium that :func:`~lagrangian.analysis.equilibria` finds
    with the inputs at 0.  ``inputs`` chooses and orders the inputs (default:
    all of the model's).  ``outputs`` maps names to expressions of q, q', the
    inputs and the parameters (text for the safe parser, or SymPy), or lists
    names of coordinates and velocities; default: the whole state.
    """
    system = eom.system
    if system.constraints:
        raise ModelError(
            "state-space linearization with constraints is not supported", field="constraints"
        )
    if at is None:
        at = first_equilibrium(system)
    chosen = chosen_inputs(system, inputs)
    point = OperatingPoint(system, at)
    q = [c.q for c in system.coordinates]
    v = [c.q_dot for c in system.coordinates]
    u = [system.symbol(name) for name in chosen]
    mass, forcing = eom.mass_matrix, eom.forcing
    point.check_steady(mass, forcing)
    M0 = point.at(mass)
    f0 = point.at(forcing)
    if any(entry.has(system.time) for entry in (*M0, *f0)):
        raise ModelError("the equations depend explicitly on t at this point: no fixed A, B")
    if _singular(M0):
        raise ModelError("the mass matrix is singular at this point (a coordinate singularity)")
    rest = _solve(M0, f0)
    moving = [r for r in rest if not vanishes(r, system, point.defaults)]
    if moving:
        raise ModelError(
            "not an equilibrium or steady motion: q'' = "
            + ", ".join(str(_simplified(r)) for r in rest)
            + " != 0 at this point"
        )
    n = len(q)
    lower = _solve(M0, point.at(forcing.jacobian(q + v)))
    upper = sympy.zeros(n, n).row_join(sympy.eye(n))
    A = upper.col_join(lower)
    B = sympy.zeros(2 * n, 0)
    if u:
        B = sympy.zeros(n, len(u)).col_join(_solve(M0, point.at(forcing.jacobian(u))))
    names, expressions = chosen_outputs(system, outputs)
    h = sympy.Matrix(expressions)
    C = point.at(h.jacobian(q + v)) if expressions else sympy.zeros(0, 2 * n)
    D = point.at(h.jacobian(u)) if expressions and u else sympy.zeros(len(expressions), len(u))
    states = (*system.coordinate_names, *(c.q_dot.name for c in system.coordinates))
    return StateSpace(
        system=system,
        point=point.given,
        states=states,
        inputs=tuple(chosen),
        outputs=names,
        A=_tidy(A),
        B=_tidy(B),
        C=_tidy(C),
        D=_tidy(D),
        values=point.defaults,
    )


def _solve(mass: sympy.Matrix, right: sympy.Matrix) -> sympy.Matrix:
    """M0^-1 right, exactly: over the field of rational functions of the parameters where
    the entries are such (every entry comes out cancelled, in milliseconds), else by
    SymPy's LU with the entries tidied (nested fractions that take long to simplify)."""
    from sympy.polys.matrices import DomainMatrix

    try:
        left, rhs = DomainMatrix.from_Matrix(mass).unify(DomainMatrix.from_Matrix(right))
        if not left.domain.is_EX:
            return left.to_field().lu_solve(rhs.to_field()).to_Matrix()
    except (sympy.polys.polyerrors.PolynomialError, ZeroDivisionError, ValueError):
        pass
    return mass.LUsolve(right)


def _singular(mass: sympy.Matrix) -> bool:
    from sympy.polys.matrices import DomainMatrix

    try:
        exact = DomainMatrix.from_Matrix(mass)
        if not exact.domain.is_EX:
            return exact.det() == exact.domain.zero
    except (sympy.polys.polyerrors.PolynomialError, ValueError):
        pass
    return tidy(mass.det(method="berkowitz"), trig=True) == 0


def _tidy(matrix: sympy.MatrixBase) -> sympy.ImmutableMatrix:
    return sympy.ImmutableMatrix(matrix.applyfunc(_simplified))


def _simplified(entry: sympy.Expr) -> sympy.Expr:
    """A short equal form: the LU solve leaves nested fractions of the parameters."""
    entry = tidy(entry, trig=True)
    if entry.is_Number or sympy.count_ops(entry) > SIMPLIFY_MAX_OPS:
        return entry
    candidate = sympy.factor(sympy.cancel(sympy.together(entry)))
    return candidate if sympy.count_ops(candidate) <= sympy.count_ops(entry) else entry
