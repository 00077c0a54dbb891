"""`EquationsOfMotion`: the one object every later stage reads."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import sympy

from ..lazy import MadeOnRead
from ..symbols import Coordinate
from .constraints import ConstraintForms

if TYPE_CHECKING:
    from ..model import System


@dataclass(frozen=True)
class CoordinateDerivation:
    """Lagrange's equation for one coordinate q, term by term, as done by hand.

    d/dt (dL/dq_dot) - dL/dq = Q_q - dF/dq_dot
    """

    coordinate: Coordinate
    momentum: sympy.Expr  # dL/dq_dot
    momentum_rate: sympy.Expr  # d/dt (dL/dq_dot), contains accelerations
    force_gradient: sympy.Expr  # dL/dq
    generalized_force: sympy.Expr  # Q_q
    dissipation_force: sympy.Expr  # dF/dq_dot
    constraint_force: sympy.Expr  # sum_j lambda_j A_jq (zero without constraints)
    equation: sympy.Expr  # the left side minus the right side, = 0
    # the positive constant factor the equation was divided by (1: none), said with it
    divided_by: sympy.Expr = sympy.S.One


class Deferred(Sequence):
    """A tuple made on first use, for parts of the equations that most callers never read."""

    def __init__(self, make: Callable[[], tuple]):
        self._make: Callable[[], tuple] | None = make
        self._items: tuple = ()

    def _made(self) -> tuple:
        if self._make is not None:
            self._items, self._make = tuple(self._make()), None
        return self._items

    def __getitem__(self, index):
        return self._made()[index]

    def __len__(self) -> int:
        return len(self._made())

    def __repr__(self) -> str:
        return repr(self._made())


@dataclass(frozen=True)
class SymEngineForms:
    """L, the equations, M (rows) and f as SymEngine expressions: the same expressions as
    the SymPy ones of :class:`EquationsOfMotion`, kept by the SymEngine route
    (:mod:`lagrangian.derive.fast`) so that large systems print without converting back."""

    lagrangian: object
    equations: tuple
    mass_matrix: tuple
    forcing: tuple


@dataclass(frozen=True, eq=False)
class EquationsOfMotion:
    """Lagrange's equations of a :class:`~lagrangian.model.System`.

    The canonical form, referred to everywhere else, is

        M(q, t) q'' = f(q, q', t),

    with the mass matrix M_ij = d^2 L / (dq_i' dq_j') and the forcing
    f_i = dL/dq_i - sum_j d^2 L/(dq_i' dq_j) q_j' - d^2 L/(dq_i' dt) + Q_i - dF/dq_i'.
    ``equations[i]`` is the i-th Euler-Lagrange equation written as
    ``expr = 0`` (equal to ``(M q'' - f)[i]`` up to rearrangement).
    With constraints (see :mod:`lagrangian.derive.constraints`) the equations
    read M q'' = f + A^T lambda with A q'' = beta; ``equations`` then contain the
    multiplier symbols lambda_j, and ``accelerations`` and ``multipliers`` are
    solved with lambda eliminated.
    ``mass_matrix`` and ``forcing`` may be given as :class:`~lagrangian.lazy.Later` (made on
    first read).
    ``accelerations`` holds q'' solved explicitly (``None`` where that would
    not stay readable; the numeric stages solve M q'' = f instead).  M depends
    on the velocities only for Lagrangians that are not quadratic in them (a
    relativistic particle).
    """

    system: System
    equations: Sequence[sympy.Expr]
    mass_matrix: sympy.ImmutableMatrix = MadeOnRead()  # type: ignore[assignment]
    forcing: sympy.ImmutableMatrix = MadeOnRead()  # type: ignore[assignment]
    accelerations: Mapping[str, sympy.Expr] | None
    steps: Sequence[CoordinateDerivation]
    constraints: ConstraintForms | None = None
    multipliers: Mapping[str, sympy.Expr] | None = None
    symengine: SymEngineForms | None = field(default=None, repr=False)

    @property
    def coordinates(self) -> tuple[Coordinate, ...]:
        return self.system.coordinates

    @property
    def lagrangian(self) -> sympy.Expr:
        return self.system.lagrangian

    def acceleration(self, coordinate: str) -> sympy.Expr:
        """q'' of ``coordinate`` as an expression of (q, q', t)."""
        if self.accelerations is None:
            raise ValueError("accelerations were not solved symbolically for this system")
        return self.accelerations[coordinate]
