"""The model's geometry as numbers along a motion: where to draw what, frame by frame.

A :class:`Geometry` turns the particles, rigid bodies and springs of a
:class:`~lagrangian.model.System` into NumPy functions of (t, q) at fixed
parameter values; :meth:`Geometry.at` evaluates them at many times at once and
returns a :class:`Positions`.  :func:`rods` decides which pairs of points are
joined by a rigid rod: a rod is drawn between consecutive particles, or from the
pivot, when the distance between them is constant along the motion (checked
numerically, relative variation below :data:`ROD_TOLERANCE`).  The pivot is the
origin, or a moving support: the part of a particle's position that depends on t
alone (``a*cos(w*t)`` of a pendulum whose support is shaken), see :func:`support_of`.

A planar rigid body is drawn as a uniform rod through its centre along its angle,
with the length L = sqrt(12 I / m) of the uniform rod of the same mass and moment
of inertia; a 3-D body as the box (or disc) of the same mass and principal
moments, turned by its rotation R(q, t) (:mod:`lagrangian.output.solids`).
3-D models are shown in two orthographic views: the side view (horizontal axis,
vertical axis; vertical = against gravity, else z) and the top view.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy

from ..algebra import as_expression
from ..errors import ModelError, setting
from ..model import RigidBody, System
from .solids import SolidShape, solid_points, solid_shape

#: Relative variation (max - min) / max of a distance below which it is a rigid rod.
ROD_TOLERANCE = 1e-4
#: Name of the fixed point a pendulum hangs from.
ORIGIN = -1
AXIS_NAMES = ("x", "y", "z")


@dataclass(frozen=True, eq=False)
class Positions:
    """Everything drawable at the times ``t`` (T,), as arrays with a trailing time axis.

    ``particles`` (P, D, T); ``centers`` (B, 2, T) and ``angles`` (B, T) of the
    planar bodies; ``springs`` (S, 2, D, T): both ends of every spring;
    ``solid_centers`` (S3, 3, T) and ``rotations`` (S3, 3, 3, T) of the 3-D bodies.
    """

    t: np.ndarray
    particles: np.ndarray
    centers: np.ndarray
    angles: np.ndarray
    springs: np.ndarray
    solid_centers: np.ndarray | None = None
    rotations: np.ndarray | None = None
    support: np.ndarray | None = None  # (D, T) of a moving support; None: the origin

    def point(self, index: int) -> np.ndarray:
        """(D, T) of a particle, or of the pivot (the origin or the moving support) for
        :data:`ORIGIN`."""
        if index == ORIGIN:
            if self.support is not None:
                return self.support
            return np.zeros((self.particles.shape[1], self.t.shape[0]))
        return self.particles[index]


@dataclass(frozen=True, eq=False)
class Geometry:
    """Numerical geometry of one system at fixed parameter values (see the module docstring)."""

    system: System
    parameters: Mapping[str, float]
    dimension: int
    masses: np.ndarray  # (P,)
    body_lengths: np.ndarray  # (B,)
    vertical: int  # index of the axis that points up (against gravity)
    solid_shapes: tuple[SolidShape, ...]  # the outline of each 3-D body, body frame
    _particle_functions: tuple
    _center_functions: tuple
    _angle_functions: tuple
    _spring_functions: tuple
    _solid_center_functions: tuple = ()
    _rotation_functions: tuple = ()
    _support_functions: tuple = ()  # of the moving support (see support_of); () for none
    coordinates_only: bool = False  # stand-in dots for the coordinates: no rods between them

    @property
    def planar_bodies(self) -> tuple:
        return tuple(b for b in self.system.bodies if not isinstance(b, RigidBody))

    @property
    def solids(self) -> tuple[RigidBody, ...]:
        return tuple(b for b in self.system.bodies if isinstance(b, RigidBody))

    @property
    def particle_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.system.particles)

    @property
    def views(self) -> tuple[tuple[int, int], ...]:
        """Pairs of axes to draw: one view in 2-D; side and top view in 3-D."""
        if self.dimension == 2:
            return ((0, 1),)
        horizontal = [k for k in range(3) if k != self.vertical]
        return ((horizontal[0], self.vertical), (horizontal[0], horizontal[1]))

    def at(self, t: np.ndarray, q: np.ndarray) -> Positions:
        """The positions at the times ``t`` (T,) for the coordinates ``q`` (n, T)."""
        t = np.asarray(t, dtype=float)
        q = np.asarray(q, dtype=float).reshape(len(self.system.coordinates), t.shape[0])
        values = [self.parameters[p.name] for p in self.system.parameters]

        def evaluate(functions: Sequence, width: int) -> np.ndarray:
            result = np.empty((len(functions), width, t.shape[0]))
            for i, point in enumerate(functions):
                for k, f in enumerate(point):
                    result[i, k] = np.broadcast_to(np.asarray(f(t, *q, *values), float), t.shape)
            return result

        particles = evaluate(self._particle_functions, self.dimension)
        centers = evaluate(self._center_functions, 2)
        angles = evaluate([[f] for f in self._angle_functions], 1)[:, 0]
        ends = [end for spring in self._spring_functions for end in spring]
        springs = evaluate(ends, self.dimension).reshape(-1, 2, self.dimension, t.shape[0])
        solid_centers = evaluate(self._solid_center_functions, 3)
        rotations = evaluate(self._rotation_functions, 9).reshape(-1, 3, 3, t.shape[0])
        support = None
        if self._support_functions:
            support = evaluate([self._support_functions], self.dimension)[0]
        return Positions(t, particles, centers, angles, springs, solid_centers, rotations, support)

    def solid_outlines(self, positions: Positions) -> list[np.ndarray]:
        """The outline of each 3-D body in space, (K, 3, T) each: r_c + R p for the
        body-frame points p of its :class:`~lagrangian.output.solids.SolidShape`."""
        return [
            solid_points(shape, positions.solid_centers[i], positions.rotations[i])
            for i, shape in enumerate(self.solid_shapes)
        ]

    def body_ends(self, positions: Positions) -> np.ndarray:
        """(B, 2 ends, 2, T): the ends of the rods that stand for the bodies."""
        direction = np.stack([np.cos(positions.angles), np.sin(positions.angles)], axis=1)
        half = (self.body_lengths / 2)[:, None, None] * direction
        return np.stack([positions.centers - half, positions.centers + half], axis=1)

    def extent(self, positions: Positions, rods: Sequence[tuple[int, int]]) -> np.ndarray:
        """(D, 2): the smallest and largest coordinate of everything drawn, over all times."""
        pieces = [positions.particles.transpose(1, 0, 2).reshape(self.dimension, -1)]
        if self.planar_bodies:
            ends = self.body_ends(positions)  # (B, 2, 2, T)
            pieces.append(ends.transpose(2, 0, 1, 3).reshape(2, -1))
        for outline in self.solid_outlines(positions):
            pieces.append(outline.transpose(1, 0, 2).reshape(3, -1))
        if self.system.springs:
            pieces.append(positions.springs.transpose(2, 0, 1, 3).reshape(self.dimension, -1))
        if any(ORIGIN in rod for rod in rods):
            pieces.append(positions.point(ORIGIN))
        points = np.concatenate(pieces, axis=1)
        points = points[:, np.all(np.isfinite(points), axis=0)]
        if points.size == 0:
            return np.zeros((self.dimension, 2))
        return np.stack([points.min(axis=1), points.max(axis=1)], axis=1)


def geometry(system: System, parameters: Mapping[str, float] | None = None) -> Geometry:
    """The :class:`Geometry` of ``system`` at ``parameters`` (default: the model's values).

    A model without particles or bodies (given by its Lagrangian or energies) is
    drawn as its coordinates: one dot per coordinate q_i at (q_i, -i), moving
    along its own line.  Raises :class:`ModelError` when a parameter has no value.
    """
    coordinates_only = not system.particles and not system.bodies
    if coordinates_only:
        system = coordinates_drawn(system)
    values = dict(system.parameter_values)
    values.update({k: float(v) for k, v in (parameters or {}).items()})
    missing = [p.name for p in system.parameters if p.name not in values]
    if missing:
        raise ModelError(
            f"no value for parameter(s) {', '.join(missing)} (give them with {setting('params=')})"
        )
    arguments = (system.time, *(c.q for c in system.coordinates))
    arguments += tuple(p.symbol for p in system.parameters)
    substitution = {p.symbol: values[p.name] for p in system.parameters}

    def compile_point(point: Sequence[sympy.Expr], where: str) -> tuple:
        try:
            return tuple(sympy.lambdify(arguments, as_expression(x), "numpy") for x in point)
        except Exception as error:  # an unspecified function, an unsupported call
            raise ModelError(f"cannot evaluate the geometry of {where}: {error}") from None

    def number(expr: sympy.Expr, where: str) -> float:
        try:
            return float(as_expression(expr).subs(substitution))
        except (TypeError, ValueError):
            raise ModelError(f"{where} must be a number at the parameter values") from None

    solids = [b for b in system.bodies if isinstance(b, RigidBody)]
    planar = [b for b in system.bodies if not isinstance(b, RigidBody)]
    support = support_of(system)
    dimension = len(system.particles[0].position) if system.particles else (3 if solids else 2)
    masses = np.array([number(p.mass, f"the mass of {p.name}") for p in system.particles])
    shapes = tuple(
        solid_shape(
            number(b.mass, f"the mass of {b.name}"),
            np.array([[number(x, f"the inertia of {b.name}") for x in row] for row in b.inertia]),
        )
        for b in solids
    )
    body_lengths = []
    links = {link.name for link in system.linkage.links} if system.linkage else set()
    for body in planar:
        mass, inertia = number(body.mass, body.name), number(body.inertia, body.name)
        if body.name in links:  # drawn from its start to its end (output.linkage_drawing)
            body_lengths.append(0.0)
            continue
        body_lengths.append(np.sqrt(12 * inertia / mass) if mass > 0 and inertia > 0 else 0.0)
    vertical = dimension - 1
    if system.gravity is not None and system.gravity.direction is not None:
        direction = [abs(number(x, "the gravity direction")) for x in system.gravity.direction]
        vertical = int(np.argmax(direction))
    return Geometry(
        system=system,
        parameters=values,
        dimension=dimension,
        masses=masses,
        body_lengths=np.array(body_lengths, dtype=float),
        vertical=vertical,
        solid_shapes=shapes,
        _particle_functions=tuple(compile_point(p.position, p.name) for p in system.particles),
        _center_functions=tuple(compile_point(b.center, b.name) for b in planar),
        _angle_functions=tuple(compile_point([b.angle], b.name)[0] for b in planar),
        _spring_functions=tuple(
            tuple(compile_point(end, s.name) for end in s.ends) for s in system.springs
        ),
        _solid_center_functions=tuple(compile_point(b.position, b.name) for b in solids),
        _rotation_functions=tuple(
            compile_point([x for row in b.rotation for x in row], b.name) for b in solids
        ),
        _support_functions=compile_point(support, "the support") if support else (),
        coordinates_only=coordinates_only,
    )


def support_of(system: System) -> tuple[sympy.Expr, ...] | None:
    """The moving point the mechanism hangs from, or None when it hangs from a fixed one.

    The support is the part of a particle's position that depends on t and the
    parameters alone, the terms without a coordinate: (a cos(w t), 0) of a pendulum
    at (a cos(w t) + l sin θ, -l cos θ).  The first particle that has one that moves
    gives it (the later links of a chain carry the same terms).
    """
    q = [c.q for c in system.coordinates]
    for particle in system.particles:
        support = tuple(
            as_expression(x).as_independent(*q, as_Add=True)[0] for x in particle.position
        )
        if any(x.has(system.time) for x in support):
            return support
    return None


def coordinates_drawn(system: System) -> System:
    """``system`` with a stand-in particle per coordinate: q_i drawn at (q_i, -i)."""
    import dataclasses

    from ..model import Particle

    dots = tuple(
        Particle(c.name, sympy.Integer(1), (c.q, sympy.Integer(-i)))
        for i, c in enumerate(system.coordinates)
    )
    return dataclasses.replace(system, particles=dots, gravity=None, springs=())


def rods(positions: Positions, *, tolerance: float = ROD_TOLERANCE) -> tuple[tuple[int, int], ...]:
    """The rigid links (a, b) between particles (indices; :data:`ORIGIN` for the pivot).

    Particle i is joined to particle i - 1 when their distance stays constant,
    else to the origin when its distance from the origin stays constant, else
    to nothing: a rod stands for a holonomic constraint the model already has,
    never for one the picture would invent.
    """
    links = []
    for i in range(positions.particles.shape[0]):
        for other in (i - 1, ORIGIN) if i > 0 else (ORIGIN,):
            if _constant_distance(positions.point(i), positions.point(other), tolerance):
                links.append((other, i))
                break
    return tuple(links)


def solid_pivots(positions: Positions, *, tolerance: float = ROD_TOLERANCE) -> tuple[int, ...]:
    """The 3-D bodies (indices) whose centre stays at a constant distance from the origin:
    a body turning about a fixed point there (a top), drawn with a stem from it."""
    if positions.solid_centers is None:
        return ()
    origin = np.zeros((3, positions.t.shape[0]))
    return tuple(
        i
        for i, center in enumerate(positions.solid_centers)
        if _constant_distance(center, origin, tolerance)
    )


def _constant_distance(a: np.ndarray, b: np.ndarray, tolerance: float) -> bool:
    distance = np.linalg.norm(a - b, axis=0)
    if distance.size == 0 or not np.all(np.isfinite(distance)):
        return False
    largest = float(distance.max())
    return largest > 0 and float(distance.max() - distance.min()) <= tolerance * largest


def zigzag(a: np.ndarray, b: np.ndarray, *, coils: int = 8, width: float = 0.05) -> np.ndarray:
    """(2, 2 coils + 4) points of a spring drawn as a zigzag from ``a`` to ``b`` (2-D points).

    Straight leads take the first and last 15 % of the length; ``width`` is the
    half-width of the zigzag in data units.
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    along = b - a
    length = float(np.hypot(*along))
    if length == 0:
        return np.stack([a, b], axis=1)
    unit = along / length
    normal = np.array([-unit[1], unit[0]])
    s = np.linspace(0.15, 0.85, 2 * coils + 1)[1:-1]
    offsets = width * np.where(np.arange(s.size) % 2 == 0, 1.0, -1.0)
    middle = a[:, None] + np.outer(along, s) + np.outer(normal, offsets)
    return np.column_stack([a, a + 0.15 * along, middle, a + 0.85 * along, b])


def axis_label(axis: int) -> str:
    return f"${AXIS_NAMES[axis]}$"
