"""Turn a raw model description (text, numbers, SymPy) into a checked, frozen `System`.

The TOML loader and the Python constructors both produce a :class:`ModelSpec`
(:mod:`.spec`); :func:`build_system` checks its size, validates names, parses
every expression with the safe parser, checks what each field may depend on
and that its numbers are doubles (``10**400`` or ``1e-400`` cannot be simulated,
and SymPy factors such integers in the simplifications that follow), and
assembles L = T - V, within :data:`BUILD_SECONDS` (a deadline, as derive's).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping, Sequence
from dataclasses import replace

import sympy
from sympy.core.function import AppliedUndef

from ..budget import attempt
from ..errors import ModelError, ParseError
from ..parsing import (
    DeclaredFunction,
    Namespace,
    parse_expression,
    referenced_names,
)
from ..parsing.constants import NotRealError, RealConstants
from ..symbols import (
    TIME_NAME,
    is_identifier,
    parameter_symbol,
    time_symbol,
)
from .components import Gravity, RigidBody, Spring
from .energy import conservative_potential, gravity_potential, kinetic_energy, spring_potential
from .impacts import check_initial_gaps, check_restitutions, resolve_impacts
from .inputs import assemble_inputs, input_entries, input_parameters, with_input_forces
from .limits import check_kinetic_work
from .linkage_reactions import with_reactions
from .linkages import build_linkage, link_bodies
from .naming import RESERVED, coordinates_named, parameter_entry, warn_of_likely_typos
from .rigid_body import moving_with, resolve_body
from .spec import (
    COORDINATES,
    PARAMETERS,
    TIME,
    VELOCITIES,
    ModelSpec,
    check_size,
    expression_fields,
)
from .system import FunctionDeclaration, Parameter, System
from .units import dimensioned, has_units, read_units
from .values import check_masses

__all__ = ["ModelSpec", "build_system"]

#: Seconds the model may take to build (the kinetic energy of bodies is simplified as it
#: is assembled): the same bound as derive's, so that no model build runs unbounded.
BUILD_SECONDS = 60.0
#: log10 of the largest double and of the smallest (subnormal) one.
_LARGEST_DIGITS = math.log10(sys.float_info.max)
_SMALLEST_DIGITS = math.log10(math.ulp(0.0))


def build_system(spec: ModelSpec) -> System:
    """Validate ``spec`` and build the frozen :class:`System` it describes.

    Its size is checked first (:mod:`.limits`), before any symbol is made.
    """
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
        return replace(system, spec=given)
    except ModelError as error:
        raise error.located(source=spec.source) from None


class _Builder:
    def __init__(self, spec: ModelSpec, trees: dict | None = None):
        self.spec = spec
        self.trees = trees  # the syntax trees, kept for the dimension check (with units)
        self.coordinates = coordinates_named(spec.coordinates)
        self.names = self._base_names()
        self.functions = self._functions()
        self.parameters = self._parameters()
        self.parameters += input_parameters(
            spec.inputs, self._check_new_name, {p.name for p in self.parameters}
        )
        self.namespace = self._namespace()

    # -- names ---------------------------------------------------------------
    def _base_names(self) -> dict[str, tuple[sympy.Expr, str]]:
        names: dict[str, tuple[sympy.Expr, str]] = {TIME_NAME: (time_symbol(), TIME)}
        for c in self.coordinates:
            names[c.name] = (c.q, COORDINATES)
            names[c.q_dot.name] = (c.q_dot, VELOCITIES)
            names[c.q_ddot.name] = (c.q_ddot, "accelerations")
        return names

    def _functions(self) -> dict[str, FunctionDeclaration]:
        declared = {}
        if not isinstance(self.spec.functions, Mapping):
            raise ModelError("expected a table of name = [arguments]", field="functions")
        for name, arguments in self.spec.functions.items():
            where = f"functions.{name}"
            self._check_new_name(name, where)
            if isinstance(arguments, str) or not isinstance(arguments, Sequence):
                raise ModelError("expected a list of argument names", field=where)
            symbols = []
            for argument in arguments:
                if argument not in self.names or self.names[argument][1] == "accelerations":
                    raise ModelError(
                        f"argument '{argument}' is not a coordinate, velocity or t", field=where
                    )
                symbols.append(self.names[argument][0])
            declared[name] = FunctionDeclaration(
                name, sympy.Function(name, real=True), tuple(symbols)
            )
        return declared

    def _parameters(self) -> tuple[Parameter, ...]:
        given = self.spec.parameters
        if given is None:
            entries: dict[str, object] = dict.fromkeys(sorted(self._undeclared_names()))
        elif isinstance(given, Mapping):
            entries = dict(given)
        elif isinstance(given, Sequence) and not isinstance(given, str):
            entries = dict.fromkeys(given)
        else:
            raise ModelError("expected a table of name = value", field="parameters")
        parameters = []
        for name, entry in entries.items():
            where = f"parameters.{name}"
            self._check_new_name(name, where)
            value, sign = parameter_entry(entry, where)
            symbol = parameter_symbol(name, positive=(sign == "positive"))
            if sign == "nonnegative":
                symbol = sympy.Symbol(name, nonnegative=True)
            elif sign == "negative":
                symbol = sympy.Symbol(name, negative=True)
            parameters.append(Parameter(name, symbol, value, sign))
        warn_of_likely_typos(
            entries, self.coordinates, declared=given is not None, source=self.spec.source
        )
        return tuple(parameters)

    def _check_new_name(self, name: object, where: str) -> None:
        if not isinstance(name, str) or not is_identifier(name):
            raise ModelError(f"invalid name {name!r}", field=where)
        if name in RESERVED:
            raise ModelError(f"'{name}' is reserved and cannot be declared", field=where)
        if name in self.names or name in getattr(self, "functions", {}):
            raise ModelError(f"'{name}' is declared twice", field=where)

    def _undeclared_names(self) -> set[str]:
        found: set[str] = set()
        for where, value, _ in expression_fields(self.spec):
            if isinstance(value, str):
                try:
                    referenced = referenced_names(value)
                except ParseError as error:
                    raise ModelError(str(error), field=where, text=value) from None
                found |= referenced.symbols
            elif isinstance(value, sympy.Basic):
                found |= {s.name for s in value.free_symbols if isinstance(s, sympy.Symbol)}
        inputs = {name for name, _, _ in input_entries(self.spec.inputs)}
        return found - set(self.names) - set(self.functions) - inputs - RESERVED

    def _namespace(self) -> Namespace:
        symbols = {name: symbol for name, (symbol, _) in self.names.items()}
        symbols.update({p.name: p.symbol for p in self.parameters})
        symbols.update({f.name: f.applied for f in self.functions.values()})
        functions = {
            f.name: DeclaredFunction(f.function, f.arguments) for f in self.functions.values()
        }
        return Namespace(symbols=symbols, functions=functions)

    def _category(self, symbol: sympy.Symbol) -> str:
        entry = self.names.get(symbol.name)
        return entry[1] if entry else PARAMETERS

    # -- expressions -----------------------------------------------------------
    def expr(self, value: object, where: str, allowed: frozenset[str]) -> sympy.Expr:
        """Parse or adopt one expression and check what it depends on."""
        if isinstance(value, bool) or value is None:
            raise ModelError(f"expected an expression, got {value!r}", field=where)
        if isinstance(value, str):
            try:
                result = parse_expression(value, self.namespace, trees=self.trees)
            except ParseError as error:
                raise ModelError(str(error), field=where, text=value) from None
        elif isinstance(value, int):
            result = sympy.Integer(value)
        elif isinstance(value, float):
            if not math.isfinite(value):
                raise ModelError(f"expected a finite number, got {value!r}", field=where)
            result = sympy.Rational(repr(value))
        elif isinstance(value, sympy.Expr):
            result = self._adopt(value, where)
        else:
            raise ModelError(
                f"expected an expression, got {type(value).__name__}", field=where, text=str(value)
            )
        beyond = _beyond_double(result)
        if beyond is not None:
            raise ModelError(
                f"the number {beyond} is beyond double precision",
                field=where,
                text=value if isinstance(value, str) else str(value),
            )
        for symbol in result.free_symbols:
            category = self._category(symbol)
            if category not in allowed:
                raise ModelError(
                    f"'{symbol}' ({category}) is not allowed here; this field may depend on "
                    + ", ".join(sorted(allowed)),
                    field=where,
                    text=value if isinstance(value, str) else str(value),
                )
        return result

    def _adopt(self, value: sympy.Expr, where: str) -> sympy.Expr:
        """Rebind the symbols of a user's SymPy expression to the model's, by name."""
        table = self.namespace.symbols
        mapping = {}
        for symbol in value.free_symbols:
            if symbol.name not in table:
                raise ModelError(f"unknown symbol '{symbol.name}'", field=where, text=str(value))
            mapping[symbol] = table[symbol.name]
        adopted = value.xreplace(mapping)
        for applied in adopted.atoms(AppliedUndef):
            declared = self.functions.get(applied.func.__name__)
            if declared is None:
                raise ModelError(
                    f"undeclared function '{applied.func.__name__}'", field=where, text=str(value)
                )
            adopted = adopted.xreplace({applied: declared.function(*applied.args)})
        try:  # the parser checks this as it builds; a SymPy expression is checked whole
            RealConstants().check(adopted)
        except NotRealError as error:
            raise ModelError(
                f"{error.subexpression} {error.reason}", field=where, text=str(value)
            ) from None
        return adopted

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
        kinetic = (
            kinetic_energy(self.coordinates, time, particles, bodies)
            if (particles or bodies)
            else None
        )
        if spec.kinetic is not None:
            kinetic = resolved["kinetic"] + (kinetic or 0)
        potential_terms = []
        if spec.potential is not None:
            potential_terms.append(resolved["potential"])
        if gravity is not None:
            potential_terms.append(gravity_potential(gravity, particles, bodies))
        potential_terms += [spring_potential(s) for s in springs]
        conservative = self._by_coordinate(
            spec.conservative_forces, "conservative_forces", resolved
        )
        if conservative:
            potential_terms.append(
                conservative_potential(self.coordinates, conservative, "conservative_forces")
            )
        potential = sympy.Add(*potential_terms) if potential_terms else None

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
            lagrangian = kinetic - (potential if potential is not None else 0)

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
        check_kinetic_work(
            len(q & set().union(*(x.free_symbols for x in point))) for point in points
        )

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


def _beyond_double(expr: sympy.Expr) -> str | None:
    """A number of ``expr`` outside the range of doubles (shown short), or None."""
    for number in expr.atoms(sympy.Number):
        if number == 0 or not number.is_finite:
            continue
        if number.is_Rational:
            digits = math.log10(abs(number.p)) - math.log10(number.q)
        else:
            digits = float(sympy.log(abs(number), 10).evalf(15))
        if digits > _LARGEST_DIGITS or digits < _SMALLEST_DIGITS:
            shown = str(number)
            return shown if len(shown) <= 24 else f"{shown[:12]}... (about 10^{digits:.4g})"
    return None
