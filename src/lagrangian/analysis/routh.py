"""Routhian reduction: eliminate the cyclic coordinates, keep their momenta as constants.

A coordinate c is cyclic when dL/dq_c = 0, Q_c = 0 and dF/dq_c' = 0; then
p_c = dL/dq_c' is constant.  Solving p_c = dL/dq_c' for the cyclic velocities
(linear in them when L is quadratic in the velocities) and forming Routh's function

    R(q, q', p, t) = L - sum_c p_c q_c'

gives, for the remaining coordinates j, Lagrange's equations with R in place
of L: d/dt (dR/dq_j') - dR/dq_j = Q_j - dF/dq_j'.  The reduced system has the
p_c as (real) parameters; its equilibria are the *steady motions* of the full
system (q_j constant, q_c turning uniformly): circular Kepler orbits, the conical
pendulum.  At rest in the reduced coordinates R reduces to minus the effective
potential,

    V_eff(q, p) = -R(q, q_j' = 0, p),

e.g. p_theta^2/(2 r^2) - mu/r for the central force and
p_phi^2/(2 m l^2 sin^2 theta) - m g l cos(theta) for the spherical pendulum
[Landau & Lifshitz, Mechanics, section 41; Goldstein, Classical Mechanics, 8.3].

R is formed as L0 - (p - b) . q_c' / 2, with L0 = L at q_c' = 0 and b = p at q_c' = 0
(L = q_c'^T A q_c' / 2 + q_c'^T b + L0 and q_c' = A^-1 (p - b)): the same function as
L - p . q_c' with q_c' substituted, written as a few terms over one denominator instead of
a sum of fractions over A's determinant (the heavy top's R: 190 characters, not 1,900).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import sympy

from ..algebra import is_zero, squares_combined, tidy, tidy_fraction
from ..derive import EquationsOfMotion, derive
from ..derive.solve import solve_linear
from ..errors import ModelError
from ..model import System
from ..pointwise import surely_nonzero
from .equilibria import Equilibrium, equilibria


@dataclass(frozen=True, eq=False)
class Reduction:
    """The result of :func:`reduce`.

    ``cyclic``: the eliminated coordinates; ``momenta``: their constant momenta
    p_c (parameters of ``system``); ``velocities``: q_c' in terms of the rest and
    the p_c; ``routhian`` R; ``effective_potential`` V_eff; ``system``: the
    reduced :class:`~lagrangian.model.System` with Lagrangian R.
    """

    cyclic: tuple[str, ...]
    momenta: Mapping[str, sympy.Symbol]
    velocities: Mapping[str, sympy.Expr]
    routhian: sympy.Expr
    effective_potential: sympy.Expr
    system: System

    def __post_init__(self) -> None:
        for name in ("momenta", "velocities"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))


def cyclic_coordinates(eom: EquationsOfMotion) -> tuple[str, ...]:
    """Coordinates with dL/dq = 0, Q_q = 0, dF/dq' = 0 that appear nowhere else
    (forces, dissipation, constraints), so that they can be eliminated."""
    system = eom.system
    others = [*system.forces.values(), system.dissipation, *system.constraints]
    return tuple(
        step.coordinate.name
        for step in eom.steps
        if not surely_nonzero(step.force_gradient)  # seconds faster than is_zero alone
        and is_zero(step.force_gradient)
        and step.generalized_force == 0
        and is_zero(step.dissipation_force)
        and not any(part.has(step.coordinate.q) for part in others)
    )


def reduce(eom: EquationsOfMotion, *, momenta: Mapping[str, float] | None = None) -> Reduction:
    """Routh's reduction of every cyclic coordinate of ``eom`` (see the module docstring).

    ``momenta`` optionally gives default values to the p_c (the reduced system's
    parameters), so that numerical steps (equilibria, modes) can use them.

    >>> import lagrangian as lg
    >>> reduce(lg.load("central_force").equations_of_motion()).effective_potential
    -mu/r + p_theta**2/(2*r**2)
    """
    system = eom.system
    momenta = dict(momenta or {})
    cyclic = cyclic_coordinates(eom)
    if not cyclic:
        raise ModelError("no cyclic coordinate: nothing to reduce")
    if len(cyclic) == len(system.coordinates):
        raise ModelError("every coordinate is cyclic: nothing would remain after reduction")
    if eom.mass_matrix.has(*(c.q_dot for c in system.coordinates)):
        raise ModelError("Routh's reduction needs a Lagrangian quadratic in the velocities")
    coordinates = system.coordinates
    index = {c.name: i for i, c in enumerate(coordinates)}
    kept = [c for c in coordinates if c.name not in cyclic]
    eliminated = [coordinates[index[name]] for name in cyclic]
    clash = {c.momentum_name for c in eliminated} & set(system.parameter_names)
    if clash:
        raise ModelError(f"parameter names {sorted(clash)} are needed for the momenta")
    unknown = set(momenta) - {c.momentum_name for c in eliminated}
    if unknown:
        raise ModelError(f"not momenta of cyclic coordinates: {sorted(unknown)}", field="momenta")

    # p_c = A q_c' + b with b the momentum at q_c' = 0: solve A q_c' = p_c - b.
    no_cyclic_velocity = {c.q_dot: 0 for c in eliminated}
    rows = [index[c.name] for c in eliminated]
    block = eom.mass_matrix.extract(rows, rows)
    rhs = sympy.Matrix(
        [
            c.p - eom.steps[i].momentum.xreplace(no_cyclic_velocity)
            for c, i in zip(eliminated, rows, strict=True)
        ]
    )
    state = (system.time, *(x for c in kept for x in (c.q, c.q_dot)), *(c.p for c in eliminated))
    solved = solve_linear(block, rhs, state)
    if solved is None:
        raise ModelError("too many coupled cyclic coordinates for a symbolic reduction")
    # A's determinant is a sum of squares of sines and cosines: (I1 + M l^2) sin^2 of a top
    solved = [tidy_fraction(squares_combined(v), state, trig=True) for v in solved]
    velocities = {c.q_dot: v for c, v in zip(eliminated, solved, strict=True)}
    positions = {c.q: 0 for c in eliminated}  # L does not depend on them (checked above)

    def reduced(expr: sympy.Expr) -> sympy.Expr:
        return tidy(expr.xreplace(velocities).xreplace(positions), state, trig=True)

    # R = L0 - (p - b) . q_c' / 2 (the module docstring): one fraction, not a sum of them
    at_rest_cyclic = tidy(system.lagrangian.xreplace(no_cyclic_velocity), state, trig=True)
    quadratic = sympy.Add(*(u * v for u, v in zip(rhs, solved, strict=True))) / 2
    quadratic = squares_combined(tidy_fraction(quadratic, state, trig=True))
    routhian = at_rest_cyclic - quadratic
    at_rest = {c.q_dot: 0 for c in kept}
    effective = tidy(-at_rest_cyclic.xreplace(at_rest), state, trig=True) + squares_combined(
        tidy_fraction(quadratic.xreplace(at_rest), state, trig=True)
    )
    parameters: dict[str, object] = {
        p.name: {"value": p.default, "sign": p.sign} for p in system.parameters
    }
    for c in eliminated:
        parameters[c.momentum_name] = {"value": momenta.get(c.momentum_name), "sign": "real"}
    functions = {
        f.name: [str(a) for a in f.arguments]
        for f in system.functions
        if not any(a in {*positions, *velocities} for a in f.arguments)
    }
    reduced_system = type(system).from_lagrangian(  # the caller's class: lagrangian.System
        routhian,
        coordinates=[c.name for c in kept],
        parameters=parameters,
        forces={name: reduced(q) for name, q in system.forces.items() if name not in cyclic},
        dissipation=reduced(system.dissipation),
        functions=functions,
        name=f"{system.name} (reduced)",
        description=f"Routh's reduction of {', '.join(cyclic)}",
    )
    return Reduction(
        cyclic=cyclic,
        momenta={c.name: c.p for c in eliminated},
        velocities={c.name: velocities[c.q_dot] for c in eliminated},
        routhian=routhian,
        effective_potential=effective,
        system=reduced_system,
    )


@dataclass(frozen=True)
class SteadyMotion(Equilibrium):
    """A steady motion: the non-cyclic coordinates at rest (``point``), the cyclic ones
    turning uniformly at ``velocities`` (q_c' for the momenta ``momenta``).

    Everything else is the :class:`Equilibrium` of the reduced system: ``modes``
    are the small oscillations of the non-cyclic coordinates about the steady
    motion, with the p_c held (conical pendulum: omega^2 = Omega^2 (1 + 3 cos^2
    theta0) with Omega^2 = g/(l cos theta0); circular Kepler orbit: omega^2 =
    mu^4/p^6, the orbital frequency squared).
    """

    velocities: Mapping[str, sympy.Expr] = field(default_factory=dict)
    momenta: Mapping[str, sympy.Expr] = field(default_factory=dict)

    def __post_init__(self) -> None:
        super().__post_init__()
        for name in ("velocities", "momenta"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))


def steady_motions(
    eom: EquationsOfMotion,
    *,
    momenta: Mapping[str, float] | None = None,
    timeout: float = 10.0,
) -> tuple[SteadyMotion, ...]:
    """The equilibria of the reduced system: motions with constant non-cyclic coordinates.

    ``momenta`` gives values to the cyclic momenta p_c (then the steady motions are
    found numerically where SymPy cannot solve); without, they stay symbols.

    >>> import lagrangian as lg
    >>> [dict(e.point) for e in steady_motions(lg.load("central_force").equations_of_motion())]
    [{'r': p_theta**2/mu}]
    """
    return steady_motions_of(reduce(eom, momenta=momenta), timeout=timeout)


def steady_motions_of(reduction: Reduction, *, timeout: float = 10.0) -> tuple[SteadyMotion, ...]:
    """The steady motions of a reduction (see :func:`steady_motions`)."""
    given = {
        p: sympy.Float(reduction.system.parameter_values[str(p)])
        for p in reduction.momenta.values()
        if str(p) in reduction.system.parameter_values
    }
    found = []
    for e in equilibria(derive(reduction.system), timeout=timeout):
        at = {reduction.system.symbol(name): value for name, value in e.point.items()}
        numbers = {}  # a numerical point holds at the default values: so do its velocities
        if e.numeric:
            numbers = {
                p.symbol: sympy.Float(p.default)
                for p in reduction.system.parameters
                if p.default is not None
            }
        velocities = {
            name: tidy(v.xreplace(at).xreplace(numbers), trig=True)
            for name, v in reduction.velocities.items()
        }
        parts = {f.name: getattr(e, f.name) for f in dataclasses.fields(Equilibrium)}
        momenta = {str(p): given.get(p, p) for p in reduction.momenta.values()}
        found.append(SteadyMotion(**parts, velocities=velocities, momenta=momenta))
    return tuple(found)
