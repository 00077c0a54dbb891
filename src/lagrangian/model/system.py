"""`System`: a mechanical system as immutable data, ready for derivation."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING

import sympy

from ..budget import STAGE_SECONDS
from ..errors import ModelError
from ..symbols import Coordinate, time_symbol
from .components import ExprLike, Gravity, Particle, RigidBody, RigidBody2D, Spring

if TYPE_CHECKING:
    from ..derive import EquationsOfMotion
    from .inputs import Input

PARAMETER_SIGNS = ("positive", "nonnegative", "real", "negative")


@dataclass(frozen=True)
class Parameter:
    """A named constant of the model with an optional default value."""

    name: str
    symbol: sympy.Symbol
    default: float | None = None
    sign: str = "positive"


@dataclass(frozen=True)
class FunctionDeclaration:
    """An unspecified function, e.g. a vector potential A(x, y, z)."""

    name: str
    function: sympy.FunctionClass
    arguments: tuple[sympy.Expr, ...]

    @property
    def applied(self) -> sympy.Expr:
        return self.function(*self.arguments)


def _frozen(mapping: Mapping | None) -> Mapping:
    return MappingProxyType(dict(mapping or {}))


@dataclass(frozen=True, eq=False)
class System:
    """A mechanical system: coordinates, parameters and its Lagrangian L = T - V.

    Build one with :func:`lagrangian.load` (a model file or example name) or the
    constructors :meth:`from_lagrangian`, :meth:`from_energies` and
    :meth:`from_particles`.  ``forces`` are generalized non-conservative forces
    Q_q, ``dissipation`` is Rayleigh's function F; both enter Lagrange's equation

        d/dt (dL/dq_dot) - dL/dq = Q_q - dF/dq_dot.

    ``inputs`` (:mod:`lagrangian.model.inputs`) are named signals whose generalized
    forces are included in ``forces``; each is also a real parameter, default 0.
    """

    name: str
    coordinates: tuple[Coordinate, ...]
    parameters: tuple[Parameter, ...]
    lagrangian: sympy.Expr
    kinetic: sympy.Expr | None = None
    potential: sympy.Expr | None = None
    functions: tuple[FunctionDeclaration, ...] = ()
    forces: Mapping[str, sympy.Expr] = field(default_factory=dict)
    inputs: tuple[Input, ...] = ()
    dissipation: sympy.Expr = sympy.S.Zero
    constraints: tuple[sympy.Expr, ...] = ()
    particles: tuple[Particle, ...] = ()
    bodies: tuple[RigidBody2D | RigidBody, ...] = ()
    springs: tuple[Spring, ...] = ()
    gravity: Gravity | None = None
    initial: Mapping[str, float] = field(default_factory=dict)
    simulate_settings: Mapping[str, object] = field(default_factory=dict)
    description: str = ""
    source: str | None = None

    def __post_init__(self) -> None:
        for name in ("forces", "initial", "simulate_settings"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))

    # -- names ---------------------------------------------------------------
    @property
    def time(self) -> sympy.Symbol:
        return time_symbol()

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.coordinates)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def symbols(self) -> Mapping[str, sympy.Expr]:
        """Every name of the model -> its SymPy symbol (q, q_dot, q_ddot, parameters, t)."""
        table: dict[str, sympy.Expr] = {"t": self.time}
        for c in self.coordinates:
            table.update({c.name: c.q, c.q_dot.name: c.q_dot, c.q_ddot.name: c.q_ddot})
        table.update({p.name: p.symbol for p in self.parameters})
        return MappingProxyType(table)

    def symbol(self, name: str) -> sympy.Expr:
        try:
            return self.symbols[name]
        except KeyError:
            known = ", ".join(self.symbols)
            raise ModelError(f"unknown name '{name}' (known: {known})") from None

    @property
    def input_names(self) -> tuple[str, ...]:
        """The inputs (see :mod:`lagrangian.model.inputs`); each is also a parameter."""
        return tuple(entry.name for entry in self.inputs)

    def without_inputs(self, values: Mapping[str, float] | None = None) -> System:
        """The system with its inputs held at ``values`` (default 0): no inputs left."""
        from .inputs import without_inputs

        return without_inputs(self, values)

    @property
    def parameter_values(self) -> Mapping[str, float]:
        """Default values of the parameters that have one."""
        return MappingProxyType(
            {p.name: p.default for p in self.parameters if p.default is not None}
        )

    @property
    def state_symbols(self) -> tuple[sympy.Symbol, ...]:
        """Everything that varies along a motion: t, and each q, q', q''."""
        symbols = [self.time]
        for c in self.coordinates:
            symbols += [c.q, c.q_dot, c.q_ddot]
        return tuple(symbols)

    @property
    def is_autonomous(self) -> bool:
        """True when nothing in the model depends explicitly on time."""
        parts = [self.lagrangian, self.dissipation, *self.forces.values(), *self.constraints]
        return not any(part.has(self.time) for part in parts)

    # -- stages ----------------------------------------------------------------
    def equations_of_motion(self) -> EquationsOfMotion:
        """Lagrange's equations (see :class:`~lagrangian.derive.EquationsOfMotion`)."""
        from ..derive import derive

        return derive(self)

    # -- analysis (DESIGN section 6) ------------------------------------------------
    def conserved_quantities(self):
        """Cyclic momenta and the energy function, with reasons for what is not conserved
        (inputs held at 0)."""
        from ..analysis import conserved_quantities

        return conserved_quantities(self.without_inputs().equations_of_motion())

    def hamiltonian(self):
        """H(q, p, t) by Legendre transform, with Hamilton's equations."""
        from ..analysis import hamiltonian

        return hamiltonian(self.equations_of_motion())

    def equilibria(self):
        """Points at rest that stay at rest, each with its normal modes (inputs held at 0);
        with holonomic constraints, on the constraint surface with the multipliers."""
        from ..analysis import constrained_equilibria, equilibria

        eom = self.without_inputs().equations_of_motion()
        return constrained_equilibria(eom) if eom.constraints is not None else equilibria(eom)

    def steady_motions(self, momenta: Mapping[str, float] | None = None):
        """Steady motions (cyclic coordinates turning uniformly at the momenta p_c, given
        or symbolic; the others at rest), each with the small oscillations about it."""
        from ..analysis import steady_motions

        return steady_motions(self.without_inputs().equations_of_motion(), momenta=momenta)

    def linearize(self, at: Mapping[str, object]):
        """M0 x'' + C0 x' + K0 x = 0 about the equilibrium ``at``; ``.normal_modes()``."""
        from ..analysis import linearize

        return linearize(self.without_inputs().equations_of_motion(), at)

    def state_space(self, at: Mapping[str, object] | None = None, **options: object):
        """x' = A x + B u, y = C x + D u about an equilibrium or steady motion, x = [q, q']
        (options ``outputs``, ``inputs``: see :func:`lagrangian.analysis.state_space`)."""
        from ..analysis.state_space import state_space

        return state_space(self.equations_of_motion(), at, **options)

    def analyze(
        self,
        *,
        timeout: float | None = STAGE_SECONDS,
        momenta: Mapping[str, float] | None = None,
    ):
        """Every analysis that applies, each stage within ``timeout`` seconds (None: no limit).

        See :func:`lagrangian.analysis.analyze`; stages out of time are in ``undecided``.
        Inputs are held at 0; ``momenta`` gives cyclic momenta values for the steady motions.
        """
        from ..analysis import analyze

        eom = self.without_inputs().equations_of_motion()
        return analyze(eom, timeout=timeout, momenta=momenta)

    def simulate(self, **options: object):
        """Integrate the equations of motion -> :class:`~lagrangian.trajectory.Trajectory`.

        Options: t_end, method ("dop853", "radau", "rk4", "variational"), dt,
        rtol, atol, initial ({q: value, q_dot: value}), params, events, n_out,
        backend ("llvm", the default where SymEngine has LLVM, "numpy", or "numba"
        for generated machine code).
        """
        from ..simulation import simulate_system

        return simulate_system(self, **options)

    def ensemble(self, **options: object):
        """Many runs at once -> EnsembleTrajectory (options: lagrangian.ensemble.run_ensemble)."""
        from ..ensemble import ensemble_of_system

        return ensemble_of_system(self, **options)

    def animate(self, path=None, *, trajectory=None, **options: object):
        """The mechanism in motion (default: a run with the model's simulate settings)."""
        from ..output.animation import animate

        return animate(
            trajectory if trajectory is not None else self.simulate(), self, path, **options
        )

    def change_coordinates(
        self, coordinates: Sequence[str], substitution: Mapping[str, ExprLike], **options: object
    ) -> System:
        """The same system in new coordinates: ``substitution`` gives each old coordinate
        as a function of the new ones and t (see :mod:`lagrangian.model.transform`)."""
        from .transform import change_coordinates

        return change_coordinates(self, coordinates, substitution, **options)

    def _repr_latex_(self) -> str:
        from ..output.latex import latex_expression

        return f"$L = {latex_expression(self.lagrangian)}$"

    # -- constructors ----------------------------------------------------------
    @classmethod
    def from_lagrangian(
        cls,
        lagrangian: ExprLike,
        coordinates: Sequence[str],
        **options: object,
    ) -> System:
        """A system given by its Lagrangian. Options: see :func:`lagrangian.model.build_system`.

        >>> System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"]).parameter_names
        ('k', 'm')
        """
        from .build import ModelSpec, build_system

        return build_system(
            ModelSpec(coordinates=tuple(coordinates), lagrangian=lagrangian, **options)
        )

    @classmethod
    def from_energies(
        cls,
        kinetic: ExprLike,
        potential: ExprLike,
        coordinates: Sequence[str],
        **options: object,
    ) -> System:
        """A system given by its kinetic energy T and potential energy V (L = T - V)."""
        from .build import ModelSpec, build_system

        return build_system(
            ModelSpec(
                coordinates=tuple(coordinates), kinetic=kinetic, potential=potential, **options
            )
        )

    @classmethod
    def from_particles(
        cls,
        coordinates: Sequence[str],
        particles: Sequence[Particle] = (),
        **options: object,
    ) -> System:
        """A system of particles (and ``bodies``, ``springs``, ``gravity``) whose positions
        depend on the coordinates and time; T and V follow from the geometry."""
        from .build import ModelSpec, build_system

        return build_system(
            ModelSpec(coordinates=tuple(coordinates), particles=tuple(particles), **options)
        )
