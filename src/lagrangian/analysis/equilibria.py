"""Equilibria: configurations at rest that stay at rest, with their small oscillations.

With M(q, t) q'' = f(q, q', t) (see :class:`~lagrangian.derive.EquationsOfMotion`),
q(t) = q0 is a motion exactly when

    G(q0) = f(q0, 0, t) = 0,

since M is invertible.  G holds the generalized forces at rest: -dV/dq and, for
moving constraints whose Lagrangian has no explicit t, the centrifugal terms
(a bead on a hoop turning at omega also rests at cos theta = g/(R omega^2)).
When G depends explicitly on t, no point stays at rest for all t in general and
none is reported; when G vanishes identically, every configuration is an
equilibrium (one :class:`Equilibrium` with an empty point).  A coordinate that
does not appear in G (a cyclic or free one) is left out of the point.

G = 0 is solved by SymPy first (each equation split into its factors, so that
sin(theta) (R omega^2 cos(theta) - g) = 0 keeps theta = pi), in a forked child
process killed after ``timeout`` seconds, keeping the solutions that may be real
(at the default parameter values, when every parameter has one).  The answer is
cross-checked by a numerical multi-start search (at the defaults, or at random
parameter values); when SymPy fails, times out, or misses a root, the numerical
roots at the default values are reported instead (``numeric=True``).  A
coordinate on which G depends 2 pi-periodically is an angle: numerical roots of
it are reduced to (-pi, pi] and compared modulo 2 pi.

What a physicist needs beyond the points (each in its own module):

- V = 0 with nothing acting at rest is seen from L alone: every configuration
  (a torque-free body), without a search;
- continua: a solution that leaves coordinates free is a family, linearized at
  one member (:mod:`.neutral`); numerical roots on one are grouped
  (:mod:`.continua`); every omega^2 = 0 is named (translation, rotation, along
  the family, neutral);
- singular coordinates (M0 singular, theta = 0 of spherical coordinates): the
  modes of the regular directions, the degenerate coordinates named
  (:mod:`.singular`);
- symbolic omega^2 whose signs the assumptions do not decide: the verdict is
  said to hold at the default values, with the condition for stability
  (:mod:`.conditions`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import sympy
from sympy.core.function import AppliedUndef

from ..algebra import is_zero, tidy
from ..budget import checked_seconds, remaining
from ..derive import EquationsOfMotion
from ..errors import ModelError
from ..model import System
from .conditions import stability_verdict
from .continua import grouped
from .linear import NormalModes, Stability, linearize
from .neutral import free_coordinates, representative, zero_mode_names
from .search import RootSearch
from .singular import Reduced, at_rest_under_every_name, regular_modes

#: Share of a stage's remaining time for SymPy's solve (the numerical search gets the rest).
SYMBOLIC_SHARE = 0.5


class PointWithModes:
    """What an equilibrium (constrained or not) tells from the normal modes about it."""

    modes: NormalModes

    @property
    def stable(self) -> bool:
        """Linearly stable (``STABLE`` or ``ASYMPTOTICALLY_STABLE``)."""
        return self.modes.stable

    @property
    def omega_squared(self) -> tuple[sympy.Expr, ...]:
        return self.modes.omega_squared


@dataclass(frozen=True)
class Equilibrium(PointWithModes):
    """A point at rest (coordinate name -> value) with the normal modes about it.

    ``free``: for a continuum of equilibria, the coordinates that parametrize it
    (the point gives the others in terms of them); the modes are those at
    ``representative`` (a member with the free coordinates set).  ``degenerate``:
    coordinates that are singular at the point (their row of M vanishes); the
    modes are then those of the regular directions (:mod:`.singular`).
    ``zero_modes``: what each direction with omega^2 = 0 is (:mod:`.neutral`).
    ``family_dimension``: for a numerical root on a continuum (:mod:`.continua`),
    the dimension of the family through it (the point is one member).
    ``at_defaults``: the stability verdict holds at the default parameter values;
    ``stability_condition``: the condition on the parameters for stability
    (:mod:`.conditions`), when found.
    """

    point: Mapping[str, sympy.Expr]
    numeric: bool
    modes: NormalModes
    free: tuple[str, ...] = ()
    representative: Mapping[str, sympy.Expr] = field(default_factory=dict)
    degenerate: tuple[str, ...] = ()
    zero_modes: tuple[str, ...] = ()
    at_defaults: bool = False
    stability_condition: sympy.Basic | None = None
    family_dimension: int = 0  # free directions of a family found numerically (.continua)
    # G = 0 only under these names of a configuration the coordinates are singular at:
    # not an equilibrium (a gimbal lock; see .singular.at_rest_under_every_name)
    coordinate_singularity: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", MappingProxyType(dict(self.point)))
        object.__setattr__(self, "representative", MappingProxyType(dict(self.representative)))

    @property
    def everywhere(self) -> bool:
        """Every configuration is an equilibrium (an empty point, no free coordinates)."""
        return not self.point and not self.free and not self.degenerate

    def __repr__(self) -> str:  # the REPL shows the point and its verdict, as analyze does
        point = ", ".join(f"{k} = {v}" for k, v in self.point.items()) or "every configuration"
        free = f" (free: {', '.join(self.free)})" if self.free else ""
        numeric = ", numeric" if self.numeric else ""
        squares = ", ".join(map(str, self.modes.omega_squared)) or "none"
        return (
            f"<Equilibrium {point}{free}: {self.modes.stability.value}{numeric}; "
            f"omega^2 = {squares}>"
        )


def equilibria(eom: EquationsOfMotion, *, timeout: float = 10.0) -> tuple[Equilibrium, ...]:
    """Every rest point G(q0) = f(q0, 0, t) = 0 of ``eom`` (see the module docstring).

    >>> import lagrangian as lg
    >>> [dict(e.point) for e in equilibria(lg.load("simple_pendulum").equations_of_motion())]
    [{'theta': 0}, {'theta': pi}]
    """
    found = (with_modes(eom, rest) for rest in rest_points(eom, timeout=timeout))
    return tuple(e for e in found if not e.coordinate_singularity)


@dataclass(frozen=True)
class RestPoint:
    """An equilibrium before its modes: ``everywhere`` when every configuration is one."""

    point: Mapping[str, sympy.Expr]
    numeric: bool
    everywhere: bool = False
    dimension: int = 0  # of a family found numerically through the point (see .continua)
    found: int = 1  # numerical roots found on that family


def with_modes(eom: EquationsOfMotion, rest: RestPoint) -> Equilibrium:
    """The :class:`Equilibrium` at ``rest``, with the normal modes about it.

    A continuum (free coordinates) is linearized at a representative member; a
    point where coordinates are singular, in its regular directions.
    """
    if rest.everywhere:
        modes = _modes_everywhere(eom)
        names = _everywhere_names(eom, modes)
        return Equilibrium({}, rest.numeric, modes, zero_modes=names)
    free = free_coordinates(eom, rest.point)
    member = representative(eom, rest.point, free) if free else dict(rest.point)
    modes, degenerate, linear, singularity = _modes(eom, member, rest.numeric)
    zero = ()
    if linear is not None and any(_is_zero_root(w) for w in modes.omega_squared):
        family = len(free) or rest.dimension
        zero = zero_mode_names(eom, linear.stiffness, linear.basis, member, family)
    verdict = stability_verdict(modes, damped=linear is not None and linear.damped)
    return Equilibrium(
        rest.point,
        rest.numeric,
        modes,
        free=free,
        representative=member if free else {},
        degenerate=degenerate,
        zero_modes=zero,
        at_defaults=verdict.at_defaults,
        stability_condition=verdict.condition,
        family_dimension=rest.dimension,
        coordinate_singularity=singularity,
    )


def _is_zero_root(w: sympy.Expr) -> bool:
    return w == 0 or (w.is_number and abs(complex(w)) == 0)


def _everywhere_names(eom: EquationsOfMotion, modes: NormalModes) -> tuple[str, ...]:
    if modes.omega_squared and all(w == 0 for w in modes.omega_squared):
        return ("every direction: every configuration is at rest",) * len(modes.omega_squared)
    return ()


def rest_points(eom: EquationsOfMotion, *, timeout: float = 10.0) -> tuple[RestPoint, ...]:
    """The points of :func:`equilibria`, without their modes.

    ``timeout`` bounds SymPy's solve (and less when a deadline of
    :mod:`lagrangian.budget` ends sooner); past it, the numerical roots.
    """
    timeout = checked_seconds(timeout, "timeout")
    system = eom.system
    if system.constraints:
        raise ModelError("equilibria with constraints are not supported", field="constraints")
    rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}
    if _flat(system, rest):
        return (RestPoint({}, False, everywhere=True),)
    forces = [tidy(g, trig=True) for g in eom.forcing.xreplace(rest)]
    if any(g.has(system.time) for g in forces):
        return ()
    unspecified = sorted({str(a.func) for g in forces for a in g.atoms(AppliedUndef)})
    if unspecified:
        raise ModelError(
            "cannot locate equilibria: the forces at rest involve the unspecified "
            "function(s) " + ", ".join(unspecified)
        )
    equations = [g for g in forces if not is_zero(g)]
    if not equations:
        return (RestPoint({}, False, everywhere=True),)
    equations, at_values = _balanced(system, equations)
    if equations is None:
        return ()  # a force at rest that no configuration cancels
    if not equations:  # balanced at the values: every configuration (Atwood, m1 = m2)
        return (RestPoint({}, True, everywhere=True),)
    symbols = set().union(*(g.free_symbols for g in equations))
    unknowns = [c for c in system.coordinates if c.q in symbols]
    search = RootSearch(system, equations, unknowns)
    left = remaining()  # SymPy gets a share of a stage's time: the numerical route the rest
    points = search.symbolic(timeout if left is None else min(timeout, SYMBOLIC_SHARE * left))
    numeric = points is None or not search.confirms(points)
    if not numeric:
        return tuple(RestPoint(p, at_values) for p in points)
    members = grouped(system, equations, unknowns, search.numeric())
    return tuple(RestPoint(m.point, True, dimension=m.dimension, found=m.found) for m in members)


def _balanced(system: System, equations: list) -> tuple[list | None, bool]:
    """The equations that depend on the configuration, and whether some were dropped as
    zero at the parameter values; None where a force at rest depends on no coordinate and
    is not zero there.

    A generalized force at rest that no coordinate enters, (m1 - m2) g for the Atwood
    machine, never vanishes for generic values: no equilibrium.  At values that balance
    it (--set m1=1 --set m2=1) it is 0 for every configuration, and the equilibria are
    those of the other equations there (for the Atwood machine, its whole line: 'none
    found' said the opposite)."""
    coordinates = {c.q for c in system.coordinates}
    constant = [g for g in equations if not g.free_symbols & coordinates]
    if not constant:
        return equations, False
    values = system.parameter_values
    at = {p.symbol: sympy.Float(values[p.name]) for p in system.parameters if p.name in values}
    for g in constant:
        number = g.xreplace(at)
        if not number.is_number or abs(complex(number)) > 0:
            return None, False
    return [g for g in equations if g.free_symbols & coordinates], True


def _flat(system: System, rest: Mapping) -> bool:
    """Every configuration at rest is an equilibrium, seen from L alone (no search):
    L(q, 0) does not depend on q (V = 0, no moving constraints), L has no t, and
    no generalized or dissipative force acts at rest (a torque-free rigid body)."""
    q = [c.q for c in system.coordinates]
    at_rest = system.lagrangian.xreplace(rest)
    if at_rest.has(*q) or system.lagrangian.has(system.time):
        return False
    forces = [*system.forces.values()] + [
        sympy.diff(system.dissipation, c.q_dot) for c in system.coordinates
    ]
    return all(is_zero(f.xreplace(rest)) for f in forces)


def _modes(
    eom: EquationsOfMotion, point: Mapping[str, sympy.Expr], numeric: bool
) -> tuple[NormalModes, tuple[str, ...], Reduced | None, bool]:
    """(modes, degenerate coordinates, the linearization in the directions used, whether
    the point is only a coordinate singularity) about ``point``."""
    at = dict(point)
    if numeric:
        at |= {name: sympy.Float(v) for name, v in eom.system.parameter_values.items()}
    try:
        linear = linearize(eom, at, check=not numeric)
    except ModelError as error:
        return NormalModes.undetermined(str(error)), (), None, False
    modes = linear.normal_modes()
    if modes.stability is Stability.UNDETERMINED and "singular" in modes.note:
        regular = regular_modes(linear)
        if regular is not None:
            return (*regular, not at_rest_under_every_name(eom, linear))
    damped = not linear.dissipative.is_zero_matrix
    identity = sympy.eye(len(eom.system.coordinates))
    return modes, (), Reduced(linear.stiffness, identity, damped), False


def _modes_everywhere(eom: EquationsOfMotion) -> NormalModes:
    """Modes when every point is at rest: no restoring or velocity forces -> all omega^2 = 0."""
    coordinates = eom.system.coordinates
    rest = {c.q_dot: 0 for c in coordinates}
    for variables in ([c.q for c in coordinates], [c.q_dot for c in coordinates]):
        if any(not is_zero(e) for e in eom.forcing.jacobian(variables).xreplace(rest)):
            return _modes(eom, {}, False)[0]
    n = len(coordinates)
    return NormalModes(
        omega_squared=(sympy.Integer(0),) * n,
        stability=Stability.MARGINAL,
        closed_form=True,
        shapes=tuple(sympy.ImmutableMatrix(n, 1, lambda i, _, k=k: int(i == k)) for k in range(n)),
    )
