"""`CompiledSystem`: the equations of motion as pure numerical functions.

Conventions (everywhere in numeric/, integrate/ and ensemble/):

- the state is ``y = [q_1..q_n, q_1'..q_n']``; argument order is ``(t, y, params)``
  or ``(t, q, v, params)``; ``params`` is a 1-D array in the order of
  ``parameter_names`` (build it with :meth:`CompiledSystem.parameter_vector`);
- every function is vectorised over a trailing batch axis: ``y`` of shape
  ``(2n,)`` or ``(2n, B)`` (``params`` ``(P,)`` or ``(P, B)``) gives results
  with the same trailing axis, so an ensemble is the single run applied to
  arrays, never a second implementation;
- ``rhs`` solves M(q, t) q'' = f(q, q', t) numerically (with constraints, the
  augmented system with Baumgarte stabilisation; see ``constraint_*``).

Build one with :func:`lagrangian.numeric.compile_equations`.  With constraints,
``constraint_residual`` is position-level, c(q, t), for each holonomic
constraint (``constraint_holonomic[j]`` true) and velocity-level, A q' + a0,
for the others; ``constraint_velocity_residual`` is A q' + a0 for all;
``multipliers`` are the lambda of M q'' = f + A^T lambda from the same
stabilised solve as ``rhs`` (equal to the exact ones on the manifold);
``project`` moves a state onto the manifold (see
:mod:`lagrangian.numeric.projection`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import sympy

from ..codegen.forms import SymbolicForms
from ..codegen.program import Program
from ..derive import EquationsOfMotion
from ..errors import ModelError, setting
from ..model.values import check_parameter_value

StateFunction = Callable[[float, np.ndarray, np.ndarray], np.ndarray]  # (t, y, params)
SplitFunction = Callable[[float, np.ndarray, np.ndarray, np.ndarray], np.ndarray]  # (t, q, v, p)


@dataclass(frozen=True, eq=False)
class CompiledSystem:
    """Numerical functions of one system (see the module docstring for the conventions)."""

    equations: EquationsOfMotion
    backend: str
    coordinate_names: tuple[str, ...]
    parameter_names: tuple[str, ...]
    rhs: StateFunction  # y' = [q', q'']
    accelerations: SplitFunction  # q''
    mass_matrix: SplitFunction  # M (n, n[, B])
    forcing: SplitFunction  # f (n[, B])
    rhs_jacobian: StateFunction  # d rhs / d y, (2n, 2n) for one state
    energy: StateFunction  # the energy function h = q' . dL/dq' - L
    lagrangian: SplitFunction  # L
    momenta: SplitFunction  # p = dL/dq'
    lagrangian_gradient: SplitFunction  # dL/dq
    momenta_jacobian_q: SplitFunction  # dp/dq (n, n): d^2 L / dq' dq
    lagrangian_hessian_q: SplitFunction  # d^2 L / dq^2 (n, n)
    nonconservative_forces: SplitFunction  # Q - dF/dq'
    nonconservative_forces_jacobian_v: SplitFunction  # d(Q - dF/dq')/dq' (n, n)
    nonconservative_forces_jacobian_q: SplitFunction  # d(Q - dF/dq')/dq (n, n)
    invariants: Mapping[str, StateFunction] = field(default_factory=dict)  # conserved quantities
    not_conserved: Mapping[str, str] = field(default_factory=dict)  # name -> why (the energy)
    # not conserved in general, but where the causes vanish at a run's parameters (a momentum)
    conditional_invariants: Mapping[str, StateFunction] = field(default_factory=dict)
    # the same at given parameter values (name -> number): causes that vanish there left out
    not_conserved_at: Callable[[Mapping[str, float]], Mapping[str, str]] | None = None
    constant_mass_matrix: bool = False  # M depends on no q, q', t: Stormer-Verlet applies
    separable: bool = False  # L = q'^T M q' / 2 - V(q), M constant, no forces
    autonomous_lagrangian: bool = False  # L has no explicit t: dh/dt = q' . (Q - dF/dq')
    parameter_signs: Mapping[str, str] = field(default_factory=dict)  # name -> assumed sign
    has_constraints: bool = False
    constraint_names: tuple[str, ...] = ()  # multiplier names (lambda1, ...)
    multipliers: StateFunction | None = None  # lambda along a state
    constraint_residual: StateFunction | None = None  # f(q, t) (holonomic) / A q' + a0 (others)
    project: StateFunction | None = None  # y -> nearest state on the constraint manifold
    default_parameters: Mapping[str, float] = field(default_factory=dict)
    # -- added by compile_equations ---------------------------------------------------
    constraint_holonomic: tuple[bool, ...] = ()  # per constraint: position-level residual?
    constraint_velocity_residual: StateFunction | None = None  # A q' + a0 of every constraint
    baumgarte: float = 0.0  # stabilisation rate alpha used in rhs (1 / time; 0: none)
    definitions: Mapping[str, sympy.Lambda] = field(default_factory=dict)  # functions given
    # the model file's checks of parameter values given in place of its defaults (3-D
    # bodies' inertia): model.values.check_parameter_values of the system; None: none
    model_checks: Callable[[Mapping[str, float | np.ndarray]], None] | None = None
    # the program of the equations the functions were made from (None for functions given
    # by hand): every target that generates code for this system reads it, nobody derives
    # the forms again
    program: Program | None = field(default=None, repr=False)

    @property
    def forms(self) -> SymbolicForms | None:
        """The symbolic forms the functions were made from (None for functions given by
        hand)."""
        return None if self.program is None else self.program.forms

    @property
    def derived(self) -> bool:
        """True when the functions were compiled from derived equations (code can be
        generated from them), False for functions given by hand."""
        return isinstance(self.equations, EquationsOfMotion)

    @property
    def n(self) -> int:
        return len(self.coordinate_names)

    def parameter_vector(self, overrides: Mapping[str, float] | None = None) -> np.ndarray:
        """The params array: defaults updated by ``overrides``; a missing value is an error."""
        values = dict(self.default_parameters)
        for name, value in (overrides or {}).items():
            if name not in self.parameter_names:
                known = ", ".join(self.parameter_names) or "none"
                raise ModelError(f"unknown parameter '{name}' (parameters: {known})")
            values[name] = float(value)
        missing = [name for name in self.parameter_names if name not in values]
        if missing:
            raise ModelError(
                "no value for parameter(s) "
                + ", ".join(missing)
                + f" (give them with {setting('params=')})"
            )
        for name in self.parameter_names:
            self.check_parameter(name, values[name])
        if self.model_checks is not None:  # the model file's checks, 3-D bodies' inertia
            self.model_checks(dict(overrides or {}))
        return np.array([values[name] for name in self.parameter_names], dtype=float)

    def check_parameters(self, given: Mapping[str, float | np.ndarray]) -> None:
        """ModelError naming the first given value (a number, or an array of an ensemble's
        members) that is not finite, breaks its parameter's sign, or fails the model's
        own checks (:attr:`model_checks`)."""
        for name, values in given.items():
            self.check_parameter(name, values)
        if self.model_checks is not None:
            self.model_checks(given)

    def check_parameter(self, name: str, values: float | np.ndarray) -> None:
        """ModelError naming the first value that is not finite or breaks the parameter's sign.

        The equations were derived with the model's assumptions (a positive m makes
        sqrt(m**2) = m), so they are wrong, silently, for a value that breaks one.
        """
        check_parameter_value(name, values, self.parameter_signs.get(name, "real"))

    def state_vector(self, initial: Mapping[str, float] | None = None) -> np.ndarray:
        """y0 from ``{q: value, q_dot: value}``; missing entries are 0 (DESIGN section 2)."""
        names = list(self.coordinate_names) + [f"{c}_dot" for c in self.coordinate_names]
        values = dict(self.equations.system.initial)
        values.update(initial or {})
        unknown = set(values) - set(names)
        if unknown:
            raise ModelError(f"not a coordinate or velocity: {', '.join(sorted(unknown))}")
        for name, value in values.items():
            check_initial(name, value)
        return np.array([float(values.get(name, 0.0)) for name in names], dtype=float)


def check_initial(name: str, values: float | np.ndarray) -> None:
    """ModelError naming the first initial value of ``name`` that is not finite."""
    values = np.ravel(np.asarray(values, dtype=float))
    bad = ~np.isfinite(values)
    if bad.any():
        raise ModelError(f"initial {name} = {values[int(np.argmax(bad))]:g} is not a finite number")
