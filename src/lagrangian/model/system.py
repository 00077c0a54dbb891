"""`System`: a mechanical system as immutable data, ready for derivation."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import TYPE_CHECKING

import sympy

from ..errors import ModelError
from ..lazy import Later, MadeOnRead, stored
from ..symbols import Coordinate, time_symbol
from .components import ExprLike, Gravity, Particle, RigidBody, RigidBody2D, Spring
from .limits import check_plain_text

if TYPE_CHECKING:
    from .impacts import Impact
    from .inputs import Input
    from .linkages import Linkage
    from .spec import ModelSpec
    from .units import Units

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

    ``units`` (:mod:`lagrangian.model.units`) is None for a model without units; for a
    dimensioned one it holds the dimension of every name (values are in SI base units).
    ``spec`` is what the model was built from (None when it was made otherwise).

    This is the data of the model layer: it derives, analyses and simulates nothing.
    ``lagrangian.System`` (:mod:`lagrangian.facade`, above every layer) is this class
    with the convenient methods ``equations_of_motion``, ``simulate``, ``equilibria``, ...
    The constructors here return an instance of the class they are called on, and
    ``without_inputs`` and ``change_coordinates`` keep it.
    """

    name: str
    coordinates: tuple[Coordinate, ...]
    parameters: tuple[Parameter, ...]
    # L, T and V may be given as lazy.Later (a large model's, built in SymEngine): their
    # SymPy forms are made when first read, the same objects for every reader after
    lagrangian: sympy.Expr = MadeOnRead()  # type: ignore[assignment]
    kinetic: sympy.Expr | None = MadeOnRead(None)  # type: ignore[assignment]
    potential: sympy.Expr | None = MadeOnRead(None)  # type: ignore[assignment]
    functions: tuple[FunctionDeclaration, ...] = ()
    forces: Mapping[str, sympy.Expr] = field(default_factory=dict)
    inputs: tuple[Input, ...] = ()
    dissipation: sympy.Expr = sympy.S.Zero
    constraints: tuple[sympy.Expr, ...] = ()
    impacts: tuple[Impact, ...] = ()  # unilateral contacts, see .impacts
    particles: tuple[Particle, ...] = ()
    bodies: tuple[RigidBody2D | RigidBody, ...] = ()
    springs: tuple[Spring, ...] = ()
    gravity: Gravity | None = None
    initial: Mapping[str, float] = field(default_factory=dict)
    simulate_settings: Mapping[str, object] = field(default_factory=dict)
    description: str = ""
    source: str | None = None
    units: Units | None = None
    spec: ModelSpec | None = field(default=None, repr=False)
    linkage: Linkage | None = field(default=None, repr=False)  # links and joints, if any
    # (L as given to ``lagrangian``, a Later or not; L in SymEngine) as the build assembled
    # them from SymEngine parts (large models): see ``built_lagrangian``
    symengine_lagrangian: tuple | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        for name in ("forces", "initial", "simulate_settings"):
            object.__setattr__(self, name, _frozen(getattr(self, name)))
        # what the model file refuses, refused however the system is made: the name and
        # the description reach pages, exported code and CSV headers, which must encode
        check_plain_text(self.name, "name")
        check_plain_text(self.description, "description", breaks="\n\t")
        for kind in ("particles", "bodies", "springs"):
            for i, component in enumerate(getattr(self, kind)):
                check_plain_text(component.name, f"{kind}[{i}].name")

    @property
    def built_lagrangian(self) -> object | None:
        """L in SymEngine as the build assembled it, while ``lagrangian`` is still that L
        (None otherwise: no such form, or L replaced since): told by the identity of what
        the field holds, so that its SymPy form is not made (the large route of derive
        starts from this one)."""
        built = self.symengine_lagrangian
        if built is None:
            return None
        given, form = built
        held = stored(self, "lagrangian")
        if held is given or (isinstance(given, Later) and given.holds(held)):
            return form
        return None

    def __repr__(self) -> str:  # the REPL shows the model, not every field of it
        values = ", ".join(
            f"{p.name} = {p.default:g}" if p.default is not None else p.name
            for p in self.parameters
        )
        return (
            f"<System {self.name!r}: coordinates {', '.join(self.coordinate_names)}; "
            f"parameters {values or 'none'}; L = {self.lagrangian}>"
        )

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

    def change_coordinates(
        self, coordinates: Sequence[str], substitution: Mapping[str, ExprLike], **options: object
    ) -> System:
        """The same system in new coordinates: ``substitution`` gives each old coordinate
        as a function of the new ones and t (see :mod:`lagrangian.model.transform`)."""
        from .transform import change_coordinates

        return change_coordinates(self, coordinates, substitution, **options)

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

        return cls.adopt(
            build_system(
                ModelSpec(coordinates=tuple(coordinates), lagrangian=lagrangian, **options)
            )
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

        return cls.adopt(
            build_system(
                ModelSpec(
                    coordinates=tuple(coordinates), kinetic=kinetic, potential=potential, **options
                )
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

        return cls.adopt(
            build_system(
                ModelSpec(coordinates=tuple(coordinates), particles=tuple(particles), **options)
            )
        )

    @classmethod
    def adopt(cls, system: System) -> System:
        """``system`` as an instance of ``cls`` (the same fields): how ``lagrangian.System``
        takes over a system built by the model layer."""
        if type(system) is cls:
            return system
        # the stored values: a Later is handed over, not made
        return cls(**{f.name: stored(system, f.name) for f in fields(system)})
