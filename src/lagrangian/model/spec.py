"""`ModelSpec`: a model as the user wrote it, its expression fields, and its size check."""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field

from .components import ExprLike, Gravity, Particle, RigidBody, RigidBody2D, Spring
from .impacts import Impact, impact_fields
from .inputs import input_fields
from .limits import check_counts, check_expression_text
from .linkages import Joint, Link, link_fields

# What an expression field may depend on.
COORDINATES, VELOCITIES, TIME, PARAMETERS = "coordinates", "velocities", "t", "parameters"
STATE_AND_TIME = frozenset({COORDINATES, VELOCITIES, TIME, PARAMETERS})
CONFIGURATION = frozenset({COORDINATES, TIME, PARAMETERS})
CONSTANT = frozenset({PARAMETERS})
CONSTANT_OR_TIME = frozenset({PARAMETERS, TIME})


@dataclass(frozen=True)
class ModelSpec:
    """A model as the user wrote it: names, and expressions as text, SymPy or numbers.

    ``parameters`` maps a name to its default value (``None`` for none) or to
    ``{"value": v, "sign": "real"}``; a plain sequence of names declares
    parameters without values; a value may be text with a unit (``"50 cm"``, see
    :mod:`.units`; ``units`` maps names to units); ``None`` takes every undeclared name used in the
    expressions as a positive parameter (Python API only; model files must
    declare their parameters).  ``inputs`` maps an input's name to a coordinate
    name or to {coordinate: generalized force} (see :mod:`.inputs`).
    """

    coordinates: tuple[str, ...]
    parameters: Mapping[str, object] | Sequence[str] | None = None
    lagrangian: ExprLike | None = None
    kinetic: ExprLike | None = None
    potential: ExprLike | None = None
    particles: tuple[Particle, ...] = ()
    bodies: tuple[RigidBody2D | RigidBody, ...] = ()
    springs: tuple[Spring, ...] = ()
    links: tuple[Link, ...] = ()  # planar linkages (:mod:`.linkages`)
    joints: tuple[Joint, ...] = ()
    gravity: Gravity | None = None
    forces: Mapping[str, ExprLike] = field(default_factory=dict)
    conservative_forces: Mapping[str, ExprLike] = field(default_factory=dict)
    dissipation: ExprLike | None = None
    constraints: tuple[ExprLike, ...] = ()
    impacts: tuple[Impact, ...] = ()  # see .impacts
    functions: Mapping[str, Sequence[str]] = field(default_factory=dict)
    inputs: Mapping[str, object] = field(default_factory=dict)  # see .inputs
    initial: Mapping[str, float] = field(default_factory=dict)
    simulate: Mapping[str, object] = field(default_factory=dict)
    units: Mapping[str, str] = field(default_factory=dict)  # see .units
    name: str = ""
    description: str = ""
    source: str | None = None


def check_size(spec: ModelSpec) -> None:
    """Refuse a model with too many entries or too much expression text (:mod:`.limits`)."""
    counted = {
        "coordinates": spec.coordinates,
        "parameters": spec.parameters,
        "particles": spec.particles,
        "bodies": spec.bodies,
        "springs": spec.springs,
        "links": spec.links,
        "joints": spec.joints,
        "constraints": spec.constraints,
        "impacts": spec.impacts,
        "functions": spec.functions,
        "forces": spec.forces,
        "conservative_forces": spec.conservative_forces,
        "initial": spec.initial,
        "inputs": spec.inputs,
        "units": spec.units,
    }
    check_counts(
        {
            kind: len(entries)
            for kind, entries in counted.items()
            if isinstance(entries, Sequence | Mapping) and not isinstance(entries, str)
        }
    )
    check_expression_text(
        {where: len(value) for where, value, _ in expression_fields(spec) if isinstance(value, str)}
    )


def expression_fields(spec: ModelSpec) -> Iterator[tuple[str, object, frozenset[str]]]:
    """Every expression of ``spec`` with its field name and what it may depend on."""
    for key in ("lagrangian", "kinetic", "potential", "dissipation"):
        value = getattr(spec, key)
        if value is not None:
            yield key, value, STATE_AND_TIME
    for i, particle in enumerate(spec.particles):
        yield f"particles[{i}].mass", particle.mass, CONSTANT
        for k, x in enumerate(particle.position):
            yield f"particles[{i}].position[{k}]", x, CONFIGURATION
    for i, body in enumerate(spec.bodies):
        if isinstance(body, RigidBody):
            from .rigid_body import body_fields

            yield from body_fields(body, f"bodies[{i}]", CONSTANT, CONFIGURATION)
            continue
        yield f"bodies[{i}].mass", body.mass, CONSTANT
        yield f"bodies[{i}].inertia", body.inertia, CONSTANT
        for k, x in enumerate(body.center):
            yield f"bodies[{i}].center[{k}]", x, CONFIGURATION
        yield f"bodies[{i}].angle", body.angle, CONFIGURATION
    for i, spring in enumerate(spec.springs):
        yield f"springs[{i}].stiffness", spring.stiffness, CONSTANT_OR_TIME
        yield f"springs[{i}].rest_length", spring.rest_length, CONSTANT_OR_TIME
        for e, end in enumerate(spring.ends):
            if not isinstance(end, str):
                for k, x in enumerate(end):
                    yield f"springs[{i}].ends[{e}][{k}]", x, CONSTANT_OR_TIME
    yield from link_fields(spec.links, spec.joints, CONSTANT, CONSTANT_OR_TIME)
    if spec.gravity is not None:
        yield "gravity.g", spec.gravity.g, CONSTANT
        for k, x in enumerate(spec.gravity.direction or ()):
            yield f"gravity.direction[{k}]", x, CONSTANT
    for name, value in spec.forces.items():
        yield f"forces.{name}", value, STATE_AND_TIME
    for name, value in spec.conservative_forces.items():
        yield f"conservative_forces.{name}", value, CONFIGURATION
    for i, value in enumerate(spec.constraints):
        yield f"constraints[{i}]", value, STATE_AND_TIME
    for where, value in input_fields(spec.inputs):
        yield where, value, STATE_AND_TIME
    yield from impact_fields(spec.impacts, CONFIGURATION, CONSTANT)
