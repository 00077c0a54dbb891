"""Turn a raw model description (text, numbers, SymPy) into a checked, frozen `System`.

The TOML loader and the Python constructors both produce a :class:`ModelSpec`
(:mod:`.spec`); :func:`build_system` checks its size, validates names, parses
every expression with the safe parser, checks what each field may depend on
and that its numbers are doubles (``10**400`` or ``1e-400`` cannot be simulated,
and SymPy factors such integers in the simplifications that follow), and
assembles L = T - V, within :data:`BUILD_SECONDS` (a deadline, as derive's).  The names
and the expressions are :mod:`.build_names`'s, this module the assembly.
"""

from __future__ import annotations

from dataclasses import replace

import sympy

from ..algebra import to_symengine
from ..budget import attempt
from ..collector import cycle_collector_paused
from ..errors import ModelError
from ..lazy import stored, value_of
from ..symbols import time_symbol
from .build_names import ModelNames
from .components import Gravity, RigidBody, Spring
from .energy import conservative_potential, gravity_potential, kinetic_energy, spring_potential
from .energy_large import Converted, difference_in_symengine
from .impacts import check_initial_gaps, check_restitutions, resolve_impacts
from .inputs import assemble_inputs, with_input_forces
from .limits import check_kinetic_work
from .linkage_reactions import with_reactions
from .linkages import build_linkage, link_bodies
from .rigid_body import moving_with, resolve_body
from .spec import ModelSpec, check_size, expression_fields
from .system import System
from .units import dimensioned, has_units, read_units
from .values import check_masses

__all__ = ["ModelSpec", "build_system"]

#: Seconds the model may take to build (the kinetic energy of bodies is simplified as it
#: is assembled): the same bound as derive's, so that no model build runs unbounded.
BUILD_SECONDS = 60.0


def build_system(spec: ModelSpec) -> System:
    """Validate ``spec`` and build the frozen :class:`System` it describes.

    Its size is checked first (:mod:`.limits`), before any symbol is made.  The cycle
    collector is paused meanwhile (:mod:`lagrangian.collector`): the expressions and T's
    pieces of a large model set off full collections that walk the whole heap.
    """
    with cycle_collector_paused():
        return _built(spec)


def _built(spec: ModelSpec) -> System:
    try:
        check_size(spec)
        given, declared, initial, trees = spec, None, None, None
        if has_units(spec):  # a model without units reads none (and imports no pint)
            spec, declared, initial = read_units(spec)
            trees = {}
        system, undecided = attempt("model", BUILD_SECONDS, _Builder(spec, trees).build)
        if undecided is not None:
            raise ModelError(
                f"the model was not built within {BUILD_SECONDS:g} s: its expressions are "
                "too costly to assemble"
            )
        check_masses(system)
        check_restitutions(system)
        check_initial_gaps(system, {}, {})
        if declared is not None:
            system = dimensioned(system, spec, declared, initial, trees)
        # L, T and V handed over as stored: a large model's are made in SymPy on first read
        return replace(system, spec=given, **{name: stored(system, name) for name in _ENERGIES})
    except ModelError as error:
        raise error.located(source=spec.source) from None


_ENERGIES = ("lagrangian", "kinetic", "potential")


class _Builder(ModelNames):
    """The System of a ModelSpec: its energies assembled from the expressions resolved."""

    # -- assembly --------------------------------------------------------------
    def build(self) -> System:
        spec = self.spec
        resolved = {where: self.expr(v, where, ok) for where, v, ok in expression_fields(spec)}
        particles = tuple(
            replace(
                p,
                name=p.name or f"particle{i + 1}",
                mass=resolved[f"particles[{i}].mass"],
                position=tuple(
                    resolved[f"particles[{i}].position[{k}]"] for k in range(len(p.position))
                ),
            )
            for i, p in enumerate(spec.particles)
        )
        bodies = tuple(
            self._body_3d(i, b, resolved)
            if isinstance(b, RigidBody)
            else replace(
                b,
                name=b.name or f"body{i + 1}",
                mass=resolved[f"bodies[{i}].mass"],
                inertia=resolved[f"bodies[{i}].inertia"],
                center=tuple(resolved[f"bodies[{i}].center[{k}]"] for k in range(len(b.center))),
                angle=resolved[f"bodies[{i}].angle"],
            )
            for i, b in enumerate(spec.bodies)
        )
        linkage = None
        if spec.links or spec.joints:
            coordinates = {c.name: c.q for c in self.coordinates}
            linkage = build_linkage(spec.links, spec.joints, resolved, coordinates)
            bodies += link_bodies(linkage)
        dimension = self._dimension(particles, bodies)
        points = {p.name: p.position for p in particles} | {b.name: b.center for b in bodies}
        if len(points) != len(particles) + len(bodies):
            raise ModelError("two particles or bodies share a name", field="particles")
        springs = tuple(
            self._spring(i, s, resolved, points, dimension) for i, s in enumerate(spec.springs)
        )
        gravity = self._gravity(resolved, dimension)
        constraints = tuple(resolved[f"constraints[{i}]"] for i in range(len(spec.constraints)))
        if linkage is not None:
            linkage = with_reactions(
                linkage, len(constraints), self.coordinates, gravity, particles, bodies, springs
            )
            constraints += linkage.constraints

        time = time_symbol()
        self._check_kinetic_work(particles, bodies)
        known: dict = {}  # SymPy -> SymEngine of what the large route assembled in SymEngine
        converted: dict = {}  # the positions' SymEngine forms, made by T's large route for V
        kinetic = (
            kinetic_energy(self.coordinates, time, particles, bodies, known, converted)
            if (particles or bodies)
            else None
        )
        if spec.kinetic is not None:
            kinetic = resolved["kinetic"] + (value_of(kinetic) or 0)
        potential_terms = []
        if spec.potential is not None:
            potential_terms.append(resolved["potential"])
        if gravity is not None:
            potential_terms.append(gravity_potential(gravity, particles, bodies, known, converted))
        potential_terms += [spring_potential(s) for s in springs]
        conservative = self._by_coordinate(
            spec.conservative_forces, "conservative_forces", resolved
        )
        if conservative:
            potential_terms.append(
                conservative_potential(self.coordinates, conservative, "conservative_forces")
            )
        potential = None  # V alone may stay a Later (see energy_large.Converted)
        if len(potential_terms) == 1:
            potential = potential_terms[0]
        elif potential_terms:
            potential = sympy.Add(*map(value_of, potential_terms))
        converted = None  # L in SymEngine, where T was assembled there

        if spec.lagrangian is not None:
            if kinetic is not None or potential is not None:
                raise ModelError(
                    "give either 'lagrangian' or the energies (kinetic, potential, particles, "
                    "bodies, springs, gravity), not both",
                    field="lagrangian",
                )
            lagrangian = resolved["lagrangian"]
        elif kinetic is None:
            raise ModelError(
                "no kinetic energy: give 'lagrangian', 'kinetic' or particles/bodies",
                field="kinetic",
            )
        else:
            lagrangian = None
            # T (and V) made in SymEngine: so is L, T - V (SymPy would sort it); a T still
            # to be converted (Converted) has not filled ``known`` yet
            if known or isinstance(kinetic, Converted):
                lagrangian, converted = difference_in_symengine(kinetic, potential, known)
            if lagrangian is None:
                lagrangian = value_of(kinetic) - (
                    value_of(potential) if potential is not None else 0
                )
        # where T (and V) were made in SymEngine, so is L: its SymPy form converts back
        # at the cost of its top level, and the large route of derive starts from it
        if converted is None and known:
            converted = to_symengine(lagrangian, known)

        self._check_initial()
        inputs = assemble_inputs(
            spec.inputs,
            resolved,
            {p.name: p.symbol for p in self.parameters},
            {c.name for c in self.coordinates},
        )
        return System(
            name=spec.name or "system",
            description=spec.description,
            coordinates=self.coordinates,
            parameters=self.parameters,
            functions=tuple(self.functions.values()),
            lagrangian=lagrangian,
            kinetic=kinetic,
            potential=potential
            if potential is not None
            else (sympy.Integer(0) if kinetic is not None else None),
            forces=with_input_forces(self._by_coordinate(spec.forces, "forces", resolved), inputs),
            inputs=inputs,
            dissipation=resolved.get("dissipation", sympy.Integer(0)),
            constraints=constraints,
            linkage=linkage,
            impacts=resolve_impacts(
                spec.impacts,
                resolved,
                tuple(c.q for c in self.coordinates),
                set(self.names) | {p.name for p in self.parameters},
            ),
            particles=particles,
            bodies=bodies,
            springs=springs,
            gravity=gravity,
            initial={k: float(v) for k, v in spec.initial.items()},
            simulate_settings=dict(spec.simulate),
            source=spec.source,
            symengine_lagrangian=None if converted is None else (lagrangian, converted),
        )

    def _body_3d(self, i, body, resolved) -> RigidBody:
        """A 3-D body resolved and checked (:func:`~.rigid_body.resolve_body`)."""
        values = {p.symbol: p.default for p in self.parameters if p.default is not None}
        symbols = [time_symbol(), *(c.q for c in self.coordinates)]
        symbols += [p.symbol for p in self.parameters]
        built = resolve_body(body, f"bodies[{i}]", resolved, values, symbols)
        return replace(built, name=body.name or f"body{i + 1}")

    def _check_kinetic_work(self, particles, bodies) -> None:
        """Refuse geometry whose kinetic energy is too costly to assemble (:mod:`.limits`)."""
        q = {c.q for c in self.coordinates}
        points = [p.position for p in particles] + [
            moving_with(b) if isinstance(b, RigidBody) else (*b.center, b.angle) for b in bodies
        ]
        check_kinetic_work(len(q & set().union(*map(self.free_symbols, point))) for point in points)

    def _by_coordinate(self, table, where, resolved) -> dict[str, sympy.Expr]:
        names = {c.name for c in self.coordinates}
        for name in table:
            if name not in names:
                raise ModelError(f"'{name}' is not a coordinate", field=f"{where}.{name}")
        return {name: resolved[f"{where}.{name}"] for name in table}

    def _dimension(self, particles, bodies) -> int | None:
        dimensions = {len(p.position) for p in particles}
        dimensions |= {3 if isinstance(b, RigidBody) else 2 for b in bodies}
        for i, p in enumerate(particles):
            if len(p.position) not in (2, 3):
                raise ModelError(
                    f"a position has 2 or 3 components, got {len(p.position)}",
                    field=f"particles[{i}].position",
                )
        if len(dimensions) > 1:
            raise ModelError("particles and bodies mix 2-D and 3-D positions", field="particles")
        return dimensions.pop() if dimensions else None

    def _spring(self, i, spring, resolved, points, dimension) -> Spring:
        ends = []
        for e, end in enumerate(spring.ends):
            where = f"springs[{i}].ends[{e}]"
            if isinstance(end, str):
                if end not in points:
                    raise ModelError(f"no particle or body named '{end}'", field=where, text=end)
                ends.append(points[end])
            else:
                point = tuple(resolved[f"{where}[{k}]"] for k in range(len(end)))
                if dimension is not None and len(point) != dimension:
                    raise ModelError(f"expected a point with {dimension} components", field=where)
                ends.append(point)
        if len(ends) != 2:
            raise ModelError("a spring has exactly two ends", field=f"springs[{i}].ends")
        return replace(
            spring,
            name=spring.name or f"spring{i + 1}",
            stiffness=resolved[f"springs[{i}].stiffness"],
            rest_length=resolved[f"springs[{i}].rest_length"],
            ends=tuple(ends),
        )

    def _gravity(self, resolved, dimension) -> Gravity | None:
        if self.spec.gravity is None:
            return None
        given = self.spec.gravity.direction
        if given is None:
            direction = (0,) * ((dimension or 2) - 1) + (-1,)
        else:
            direction = tuple(resolved[f"gravity.direction[{k}]"] for k in range(len(given)))
        if dimension is not None and len(direction) != dimension:
            raise ModelError(
                f"direction has {len(direction)} components, positions have {dimension}",
                field="gravity.direction",
            )
        norm = sympy.sqrt(sum(d**2 for d in direction))
        if norm == 0:
            raise ModelError("direction is the zero vector", field="gravity.direction")
        return Gravity(g=resolved["gravity.g"], direction=tuple(d / norm for d in direction))

    def _check_initial(self) -> None:
        allowed = {c.name for c in self.coordinates} | {c.q_dot.name for c in self.coordinates}
        for name, value in self.spec.initial.items():
            if name not in allowed:
                raise ModelError(
                    f"'{name}' is not a coordinate or velocity", field=f"initial.{name}"
                )
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ModelError(f"expected a number, got {value!r}", field=f"initial.{name}")
