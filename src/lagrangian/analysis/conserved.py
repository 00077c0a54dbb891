"""Conserved quantities: cyclic momenta, the energy function (Jacobi integral), Noether charges.

With p_i = dL/dq_i' and Lagrange's equations d/dt p_i = dL/dq_i + Q_i - dF/dq_i',

- a coordinate is *cyclic* when dL/dq = 0, Q_q = 0 and dF/dq' = 0: then p_q is constant;
- the energy function h = sum_i q_i' p_i - L changes at the rate
  dh/dt = -dL/dt + sum_i q_i' (Q_i - dF/dq_i'): it is conserved when L has no
  explicit t and neither the forces nor dissipation do work.  h = T + V when T is
  a quadratic form in the velocities and V is velocity-free; otherwise (moving
  constraints, as the bead on a rotating wire) h is only the Jacobi integral and
  T + V is not conserved.  Terms of L in t alone (and the parameters), f(t) =
  dF/dt, change no equation of motion; h is that of L - f(t) (else ``x_dot^2/2 + 1/t``
  would have an energy that is infinite at t = 0 and never conserved, for a free
  particle).
- Noether: if L is invariant under q -> q + eps xi(q, t) (dL = 0 to first order),
  then sum_i p_i xi_i is conserved.  Such symmetries (translations, rotations,
  any linear combination of coordinates, Galilean boosts) are searched for
  automatically (:mod:`lagrangian.analysis.symmetries`), within
  :data:`SYMMETRY_SECONDS`.

Every quantity reported conserved is also checked numerically (its time
derivative along the motion vanishes at random states), and every quantity not
conserved carries the reason.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy

from ..algebra import is_zero, tidy
from ..budget import attempt, remaining
from ..derive import EquationsOfMotion
from ..derive.constraints import constraint_velocity_form
from ..errors import ModelError
from ..model import System
from .motion import contradicted_along_motion, total_derivative
from .symmetries import point_symmetries

#: Seconds for the automatic search of point symmetries within ``analyze``'s stage (past
#: it: cyclic momenta only, and a note), and when conserved_quantities is called alone.
SYMMETRY_SECONDS = 3.0
SYMMETRY_SECONDS_ALONE = 30.0


@dataclass(frozen=True)
class ConservedQuantity:
    """A function of (q, q', t) constant along every motion."""

    name: str
    expression: sympy.Expr
    description: str = ""

    def __repr__(self) -> str:  # the REPL shows the quantity, not the dataclass fields
        why = f"   ({self.description})" if self.description else ""
        return f"<conserved {self.name} = {self.expression}{why}>"


@dataclass(frozen=True)
class NotConserved:
    """A quantity one might expect to be conserved, with why it is not.

    ``rates``: each cause (its words in ``reason``) with the rate of change it gives the
    quantity, a function of (q, q', t) and the parameters, or None where the cause acts
    whatever the values (moving constraints).  A rate that vanishes at the parameter
    values of a run (an input F = 0, an amplitude 0) is no cause in that run
    (:meth:`reasons_at`).
    """

    name: str
    expression: sympy.Expr
    reason: str
    rates: tuple[tuple[str, sympy.Expr | None], ...] = ()

    def __repr__(self) -> str:
        return f"<not conserved {self.name} = {self.expression}   because {self.reason}>"

    def reasons_at(self, values: Mapping[sympy.Symbol, sympy.Expr]) -> tuple[str, ...]:
        """The causes that still act with the parameters set to ``values`` (their rate is
        not identically zero in q, q' and t then); the whole reason when none is known."""
        if not self.rates:
            return (self.reason,)
        return tuple(
            cause
            for cause, rate in self.rates
            if rate is None or not is_zero(rate.xreplace(values))
        )


@dataclass(frozen=True)
class Conservation:
    """The result of :func:`conserved_quantities`."""

    cyclic_coordinates: tuple[str, ...]
    conserved: tuple[ConservedQuantity, ...]
    not_conserved: tuple[NotConserved, ...]
    notes: tuple[str, ...] = ()  # e.g. the symmetry search ran out of time

    def __getitem__(self, name: str) -> ConservedQuantity:
        for quantity in self.conserved:
            if quantity.name == name:
                return quantity
        raise KeyError(f"'{name}' is not conserved (conserved: {self.names})")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(q.name for q in self.conserved)

    def __repr__(self) -> str:
        """One line per quantity, as ``analyze`` lists them (REPL and Jupyter)."""
        lines = [
            f"Conservation (cyclic coordinates: {', '.join(self.cyclic_coordinates) or 'none'})"
        ]
        lines += [f"  {q.name} = {q.expression}   ({q.description})" for q in self.conserved]
        lines += [
            f"  not {q.name} = {q.expression}   because {q.reason}" for q in self.not_conserved
        ]
        lines += [f"  note: {note}" for note in self.notes]
        return "\n".join(lines)


def conserved_quantities(
    eom: EquationsOfMotion, *, symmetry_seconds: float | None = None
) -> Conservation:
    """Cyclic momenta, Noether charges of point symmetries and the energy function of a
    system, with reasons for what is not conserved.

    ``symmetry_seconds``: the time for the symmetry search (default: 3 s inside
    ``analyze``'s stage, 30 s when called alone); past it, a note says so.
    """
    system = eom.system
    state = system.state_symbols
    cyclic, conserved, not_conserved = [], [], []
    for step in eom.steps:
        c = step.coordinate
        if not is_zero(step.force_gradient):
            continue
        if step.generalized_force != 0:
            rate = (f"the generalized force Q_{c.name} acts on it", step.generalized_force)
        elif step.dissipation_force != 0:
            rate = (f"dissipation acts on {c.name}", step.dissipation_force)
        elif step.constraint_force != 0:
            rate = (f"a constraint force acts on {c.name}", None)
        else:
            rate = None
        if rate is not None:
            not_conserved.append(NotConserved(c.momentum_name, step.momentum, rate[0], (rate,)))
            continue
        cyclic.append(c.name)
        conserved.append(
            ConservedQuantity(
                c.momentum_name,
                step.momentum,
                f"{c.name} is cyclic: the Lagrangian does not depend on it",
            )
        )

    energy = energy_function(system)
    rates = _energy_leaks(system) + _constraint_work(eom)
    kinetic_plus_potential = _mechanical_energy(system)
    equals_t_plus_v = kinetic_plus_potential is not None and is_zero(
        energy - kinetic_plus_potential
    )
    if rates:
        reason = "; ".join(cause for cause, _ in rates)
        not_conserved.append(NotConserved("energy", energy, reason, tuple(rates)))
    else:
        if equals_t_plus_v:
            description = "h = T + V, the total energy"
        elif kinetic_plus_potential is not None:
            description = "the Jacobi integral h = Σ q̇ ∂L/∂q̇ - L, not T + V"
        else:
            description = "the energy function h = Σ q̇ ∂L/∂q̇ - L (T + V when L = T - V)"
        gauge = time_only_terms(system)
        if gauge != 0:
            description += f"; the terms of L in t alone ({gauge}) left out: they move nothing"
        conserved.append(ConservedQuantity("energy", tidy(energy, state), description))
    if kinetic_plus_potential is not None and not equals_t_plus_v:
        not_conserved.append(
            NotConserved(
                "mechanical_energy",
                tidy(kinetic_plus_potential, state),
                "T + V differs from the energy function h: the constraints move "
                "(positions depend on t), so their forces do work",
            )
        )
    notes = []
    # coordinates L does not contain: their momenta are listed above, conserved or not
    ignorable = [s.coordinate.name for s in eom.steps if is_zero(s.force_gradient)]
    # within analyze's stage a short budget; called alone, a generous one (nothing hangs)
    seconds = symmetry_seconds
    if seconds is None:
        seconds = SYMMETRY_SECONDS if remaining() is not None else SYMMETRY_SECONDS_ALONE
    found, undecided = attempt(
        "symmetry search",
        seconds,
        lambda: point_symmetries(eom, tuple(cyclic), tuple(ignorable)),
    )
    if undecided is not None:
        notes.append(f"{undecided}: Noether charges other than cyclic momenta may be missing")
    for symmetry in found or ():
        if symmetry.broken:
            not_conserved.append(NotConserved(symmetry.name, symmetry.charge, symmetry.broken))
        else:
            conserved.append(ConservedQuantity(symmetry.name, symmetry.charge, symmetry.reason))
    for quantity in conserved:
        if contradicted_along_motion(quantity.expression, eom):
            raise AssertionError(f"bug: {quantity.name} reported conserved but is not")
    return Conservation(tuple(cyclic), tuple(conserved), tuple(not_conserved), tuple(notes))


def time_only_terms(system: System) -> sympy.Expr:
    """The terms of L in t alone (and the parameters): f(t), a total derivative dF/dt that
    changes no equation of motion (0 when there are none).

    >>> time_only_terms(System.from_lagrangian("x_dot**2/2 + log(t) - k*x**2", ["x"]))
    log(t)
    """
    state = [symbol for c in system.coordinates for symbol in (c.q, c.q_dot)]
    return sympy.Add(
        *(
            term
            for term in sympy.Add.make_args(system.lagrangian)
            if term.has(system.time) and not term.has(*state)
        )
    )


def motion_lagrangian(system: System) -> sympy.Expr:
    """L without :func:`time_only_terms`: the same motion, and the energy function h of
    ``x_dot**2/2 + 1/t`` is the free particle's (finite at t = 0, and conserved)."""
    return system.lagrangian - time_only_terms(system)


def energy_function(system: System) -> sympy.Expr:
    """h = sum_i q_i' dL/dq_i' - L, of L without its terms in t alone (see the module)."""
    lagrangian = motion_lagrangian(system)
    return tidy(
        sum((c.q_dot * sympy.diff(lagrangian, c.q_dot) for c in system.coordinates), -lagrangian),
        system.state_symbols,
    )


def _energy_leaks(system: System) -> list[tuple[str, sympy.Expr]]:
    """Why h is not conserved (empty when it is): the terms of dh/dt, each with its cause."""
    leaks = []
    explicit = sympy.diff(motion_lagrangian(system), system.time)
    if not is_zero(explicit):
        leaks.append(("L depends on t", -explicit))
    power = sum(
        (c.q_dot * system.forces.get(c.name, 0) for c in system.coordinates), sympy.Integer(0)
    )
    if not is_zero(power):
        doing_work = [name for name, q in system.forces.items() if q != 0]
        verb = "does" if len(doing_work) == 1 else "do"
        leaks.append((", ".join(f"Q_{name}" for name in doing_work) + f" {verb} work", power))
    dissipated = sum(
        (c.q_dot * sympy.diff(system.dissipation, c.q_dot) for c in system.coordinates),
        sympy.Integer(0),
    )
    if not is_zero(dissipated):
        leaks.append(("dissipation", -dissipated))
    return leaks


def _constraint_work(eom: EquationsOfMotion) -> list[tuple[str, None]]:
    """Constraint forces A^T lambda do work -lambda . a0 when A q' + a0 = 0 has a0 != 0."""
    system = eom.system
    at_rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}  # a bare q' -> 0 stays SymPy
    for constraint in system.constraints:
        if not is_zero(constraint_velocity_form(constraint, system).xreplace(at_rest)):
            return [("the constraints move, so their forces do work", None)]
    return []


def _mechanical_energy(system: System) -> sympy.Expr | None:
    if system.kinetic is None or system.potential is None:
        return None
    return system.kinetic + system.potential


def noether_charge(
    eom: EquationsOfMotion, generator: Mapping[str, sympy.Expr], name: str = "noether"
) -> ConservedQuantity:
    """The conserved charge sum_i p_i xi_i of an infinitesimal point symmetry q -> q + eps xi.

    ``generator`` maps coordinate names to xi_i(q, t) (SymPy expressions in the
    system's symbols; missing coordinates have xi = 0).  Raises ModelError when
    L is not invariant: dL = sum_i (dL/dq_i xi_i + dL/dq_i' dxi_i/dt) must vanish
    and the generalized forces must do no work along xi.
    """
    system = eom.system
    unknown = set(generator) - set(system.coordinate_names)
    if unknown:
        raise ModelError(f"not coordinates: {sorted(unknown)}", field="generator")
    xi = {c.name: generator.get(c.name, sympy.Integer(0)) for c in system.coordinates}
    variation = sum(
        (
            sympy.diff(system.lagrangian, c.q) * xi[c.name]
            + sympy.diff(system.lagrangian, c.q_dot) * total_derivative(xi[c.name], eom)
            for c in system.coordinates
        ),
        sympy.Integer(0),
    )
    if not is_zero(variation):
        raise ModelError(
            "not a symmetry: the Lagrangian changes by " + str(tidy(variation)), field="generator"
        )
    virtual_work = sum(
        (
            (system.forces.get(c.name, 0) - sympy.diff(system.dissipation, c.q_dot)) * xi[c.name]
            for c in system.coordinates
        ),
        sympy.Integer(0),
    )
    if not is_zero(virtual_work):
        raise ModelError("not a symmetry of the forces: they do work along it", field="generator")
    charge = tidy(
        sum(
            (step.momentum * xi[step.coordinate.name] for step in eom.steps),
            sympy.Integer(0),
        ),
        system.state_symbols,
    )
    return ConservedQuantity(name, charge, "Noether charge of the symmetry " + str(generator))
