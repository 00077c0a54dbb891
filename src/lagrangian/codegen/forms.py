"""The symbolic expressions that are compiled, read from an EquationsOfMotion.

Everything here is SymPy: the mass matrix and forcing of M(q, t) q'' = f(q, q', t)
(see :class:`~lagrangian.derive.EquationsOfMotion`), the Lagrangian and its
derivatives, the non-conservative forces, the energy function, the conserved
quantities and the constraints, with the model's unspecified functions
replaced by their definitions.  The numerical stages lambdify these; nothing is
inverted symbolically.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

import sympy
from sympy.core.function import AppliedUndef

from ..algebra import is_zero
from ..analysis.conserved import (
    SYMMETRY_SECONDS,
    Conservation,
    conserved_quantities,
    motion_lagrangian,
)
from ..derive import EquationsOfMotion
from ..errors import ModelError
from .definitions import (
    Definitions,
    check_specified,
    substitute,
    substitute_matrix,
    unspecified_error,
)

#: Baumgarte's rate alpha (1 / time unit) for constrained systems: residuals decay
#: like exp(-alpha t).  About 10 / (the shortest time scale of the motion) keeps
#: the drift small without making the equations stiff; 0 turns it off.
DEFAULT_BAUMGARTE = 10.0

#: The largest rate accepted: alpha^2 enters the equations, and a residual that decays in
#: a microsecond of model time already makes them as stiff as any solver can follow.
MAX_BAUMGARTE = 1e6


def checked_baumgarte(alpha: float) -> float:
    """``alpha`` as a float when it is a usable stabilisation rate: finite, from 0 (none)
    to :data:`MAX_BAUMGARTE`; a :class:`~lagrangian.errors.ModelError` otherwise."""
    try:
        value = float(alpha)
        shown = repr(value)
    except (TypeError, ValueError):
        value, shown = math.nan, repr(alpha)[:40]
    if not 0.0 <= value <= MAX_BAUMGARTE:  # NaN fails this too
        raise ModelError(
            f"the Baumgarte stabilisation rate alpha must be a number from 0 (none) to "
            f"{MAX_BAUMGARTE:g} (1 / time unit), not {shown}",
            field="baumgarte",
        )
    return value


@dataclass(frozen=True)
class ConstraintExpressions:
    """The constraints c_j = 0 in the forms the numerical code needs.

    ``matrix`` A and ``bias`` beta give the differentiated constraints
    A q'' = beta (see :mod:`lagrangian.derive.constraints`); ``velocity`` is the
    velocity-level residual A q' + a0 of every constraint (for a holonomic one
    the time derivative of c(q, t)); ``position`` the residual c(q, t) of each
    holonomic constraint (``None`` for the others).
    """

    multipliers: tuple[sympy.Symbol, ...]
    holonomic: tuple[bool, ...]
    matrix: sympy.ImmutableMatrix
    bias: sympy.ImmutableMatrix
    velocity: sympy.ImmutableMatrix
    position: tuple[sympy.Expr | None, ...]

    @property
    def count(self) -> int:
        return len(self.multipliers)

    @property
    def residual(self) -> list[sympy.Expr]:
        """c_j(q, t) for a holonomic constraint, A_j q' + a0_j for the others."""
        return [
            self.position[j] if self.holonomic[j] else self.velocity[j] for j in range(self.count)
        ]

    def stabilised_bias(self, alpha: float) -> sympy.ImmutableMatrix:
        """beta - 2 alpha (A q' + a0) - alpha^2 c (the last term for holonomic constraints only).

        Baumgarte's stabilisation: with A q'' equal to this, a residual obeys
        c'' + 2 alpha c' + alpha^2 c = 0 (critically damped, rate alpha), and a
        velocity-level residual r obeys r' + 2 alpha r = 0, instead of drifting.
        """
        alpha = sympy.Float(alpha)
        rows = []
        for j in range(self.count):
            row = self.bias[j] - 2 * alpha * self.velocity[j]
            if self.holonomic[j]:
                row -= alpha**2 * self.position[j]
            rows.append(row)
        return sympy.ImmutableMatrix(self.count, 1, rows)


@dataclass(frozen=True)
class SymbolicForms:
    """What :func:`~lagrangian.numeric.compile_equations` compiles (defined functions in)."""

    equations: EquationsOfMotion
    definitions: Definitions
    time: sympy.Symbol
    coordinates: tuple[sympy.Symbol, ...]
    velocities: tuple[sympy.Symbol, ...]
    accelerations: tuple[sympy.Symbol, ...]
    parameters: tuple[sympy.Symbol, ...]
    mass_matrix: sympy.ImmutableMatrix
    forcing: sympy.ImmutableMatrix  # n x 1
    lagrangian: sympy.Expr
    momenta: sympy.ImmutableMatrix  # dL/dq', n x 1
    nonconservative_forces: sympy.ImmutableMatrix  # Q - dF/dq', n x 1
    energy: sympy.Expr  # sum q' dL/dq' - L
    constraints: ConstraintExpressions | None
    conservative: bool  # Q - dF/dq' = 0: no generalized forces, no dissipation

    @property
    def n(self) -> int:
        return len(self.coordinates)

    @cached_property
    def fingerprint(self) -> str:
        """The sha256 every cache of generated code keys on
        (:func:`~lagrangian.codegen.program.forms_fingerprint`), made once."""
        from .program import forms_fingerprint  # program is built on these forms

        return forms_fingerprint(self)

    @cached_property
    def conservation(self) -> Conservation:
        """:func:`~lagrangian.analysis.conserved_quantities` of the equations: found on first
        use, the analysis simplifies, which takes seconds for a large system that a run may
        never need."""
        # a run reports drifts, it does not wait on a long search for more charges
        return conserved_quantities(self.equations, symmetry_seconds=SYMMETRY_SECONDS)

    @property
    def invariants(self) -> Mapping[str, sympy.Expr]:
        """The conserved quantities (:attr:`conservation`), the definitions substituted."""
        return self._defined(self.conservation.conserved)

    @property
    def conditional_invariants(self) -> Mapping[str, sympy.Expr]:
        """The quantities other than the energy that are not conserved in general but are at
        parameter values where every cause of their change vanishes (a momentum whose force
        is an input that a run sets to 0), the definitions substituted."""
        return self._defined(
            quantity
            for quantity in self.conservation.not_conserved
            if quantity.name != "energy"
            and quantity.rates
            and all(rate is not None for _, rate in quantity.rates)
        )

    def _defined(self, quantities) -> dict[str, sympy.Expr]:
        """Name -> expression of ``quantities``, the definitions substituted (none left)."""
        found = {q.name: substitute(q.expression, self.definitions) for q in quantities}
        _check_no_functions_left(list(found.values()))
        return found

    @property
    def not_conserved(self) -> Mapping[str, str]:
        """Name -> why, of the quantities that are not conserved (the energy when L depends
        on t, forces or inputs do work, or dissipation acts)."""
        return {quantity.name: quantity.reason for quantity in self.conservation.not_conserved}

    def not_conserved_at(self, values: Mapping[str, float]) -> Mapping[str, str]:
        """:attr:`not_conserved` with the parameters at ``values`` (name -> number): the
        causes whose rate vanishes there are left out (the energy of a cart-pole whose input
        F is 0), and so is a quantity that none is left for: it is conserved in such a run."""
        numbers = {p: sympy.Float(values[p.name]) for p in self.parameters if p.name in values}
        found = {}
        for quantity in self.conservation.not_conserved:
            defined = dataclasses.replace(
                quantity,
                rates=tuple(
                    (cause, None if rate is None else substitute(rate, self.definitions))
                    for cause, rate in quantity.rates
                ),
            )
            reasons = defined.reasons_at(numbers)
            if reasons:
                found[quantity.name] = "; ".join(reasons)
        return found

    @property
    def constant_mass_matrix(self) -> bool:
        """M depends on none of q, q', t."""
        moving = (self.time, *self.coordinates, *self.velocities)
        return not any(entry.has(*moving) for entry in self.mass_matrix)

    @property
    def separable(self) -> bool:
        """L = q'^T M q' / 2 - V(q) with M constant, no forces, dissipation or constraints."""
        if not self.constant_mass_matrix or self.constraints is not None:
            return False
        if not self.conservative or not is_zero(sympy.diff(self.lagrangian, self.time)):
            return False
        linear_part = self.momenta - self.mass_matrix * sympy.Matrix(self.velocities)
        return all(is_zero(entry) for entry in linear_part)


def symbolic_forms(eom: EquationsOfMotion, definitions: Definitions) -> SymbolicForms:
    """The expressions to compile; raises ModelError for a function nobody defined."""
    system = eom.system
    check_specified(system, definitions)

    def sub(expr: sympy.Expr) -> sympy.Expr:
        return substitute(expr, definitions)

    coordinates = tuple(c.q for c in system.coordinates)
    velocities = tuple(c.q_dot for c in system.coordinates)
    lagrangian = sub(motion_lagrangian(system))  # its energy is the analysis's h
    momenta = sympy.ImmutableMatrix([sub(step.momentum) for step in eom.steps])
    nonconservative = sympy.ImmutableMatrix(
        [
            sub(system.forces.get(c.name, sympy.Integer(0)) - sympy.diff(system.dissipation, v))
            for c, v in zip(system.coordinates, velocities, strict=True)
        ]
    )
    energy = sum((v * p for v, p in zip(velocities, momenta, strict=True)), -lagrangian)
    forms = SymbolicForms(
        equations=eom,
        time=system.time,
        coordinates=coordinates,
        velocities=velocities,
        accelerations=tuple(c.q_ddot for c in system.coordinates),
        parameters=tuple(p.symbol for p in system.parameters),
        mass_matrix=substitute_matrix(eom.mass_matrix, definitions),
        forcing=substitute_matrix(eom.forcing, definitions),
        lagrangian=lagrangian,
        momenta=momenta,
        nonconservative_forces=nonconservative,
        energy=energy,
        definitions=definitions,
        constraints=_constraint_expressions(eom, sub),
        conservative=all(entry == 0 for entry in nonconservative),
    )
    parts = [
        forms.mass_matrix,
        forms.forcing,
        forms.lagrangian,
        forms.momenta,
        forms.nonconservative_forces,
    ]
    if forms.constraints is not None:
        constraints = forms.constraints
        parts += [constraints.matrix, constraints.bias, constraints.velocity]
    _check_no_functions_left(parts)
    return forms


def _constraint_expressions(eom: EquationsOfMotion, sub) -> ConstraintExpressions | None:
    forms = eom.constraints
    if forms is None:
        return None
    system = eom.system
    velocity, position = [], []
    for j, (constraint, holonomic) in enumerate(
        zip(system.constraints, forms.holonomic, strict=True)
    ):
        constraint = sub(constraint)
        if holonomic:
            rate = sympy.diff(constraint, system.time) + sum(
                (forms.matrix[j, k] * c.q_dot for k, c in enumerate(system.coordinates)),
                sympy.Integer(0),
            )
            velocity.append(sub(rate))
            position.append(constraint)
        else:
            velocity.append(constraint)
            position.append(None)
    return ConstraintExpressions(
        multipliers=forms.multipliers,
        holonomic=forms.holonomic,
        matrix=sympy.ImmutableMatrix(forms.matrix.applyfunc(sub)),
        bias=sympy.ImmutableMatrix(forms.bias.applyfunc(sub)),
        velocity=sympy.ImmutableMatrix(len(velocity), 1, velocity),
        position=tuple(position),
    )


def _check_no_functions_left(parts: list[sympy.Basic]) -> None:
    """A guard: after substitution no unspecified function may remain anywhere."""
    left = {applied for part in parts for applied in part.atoms(AppliedUndef)}
    if left:
        raise unspecified_error(sorted(str(applied) for applied in left))
