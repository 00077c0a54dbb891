"""Derived accelerations against an independent oracle: sympy.physics.mechanics.

Each system is built twice: with ``lagrangian`` (text or SymPy, particles,
bodies, springs, gravity) and with ``LagrangesMethod`` over dynamicsymbols
(points, frames, particles, rigid bodies, force lists).  The oracle's mass
matrix and forcing are mapped to plain symbols (q(t) -> q, q'(t) -> q_dot),
evaluated at seeded random points and solved numerically; the toolkit's
solved accelerations must agree to a relative 1e-9.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Mapping, Sequence

import pytest
import sympy
from sympy.physics.mechanics import (
    LagrangesMethod,
    Lagrangian,
    Point,
    ReferenceFrame,
    RigidBody,
    dynamicsymbols,
    inertia,
)
from sympy.physics.mechanics import Particle as OracleParticle

import lagrangian as lg
from helpers import assert_close, evaluate, random_point, solve_linear

N_POINTS = 5
T = dynamicsymbols._t
sin, cos, sqrt = sympy.sin, sympy.cos, sympy.sqrt


def plain_state(expr: sympy.Expr, coordinates: Sequence[sympy.Function]) -> sympy.Expr:
    """q(t) -> q, q'(t) -> q_dot, q''(t) -> q_ddot (plain symbols named like the toolkit's)."""
    mapping = {}
    for q in coordinates:
        name = q.func.__name__
        mapping[q.diff(T, 2)] = sympy.Symbol(f"{name}_ddot")
        mapping[q.diff(T)] = sympy.Symbol(f"{name}_dot")
        mapping[q] = sympy.Symbol(name)
    return expr.xreplace(mapping)


def oracle_forms(
    method: LagrangesMethod, coordinates: Sequence[sympy.Function]
) -> tuple[sympy.Matrix, sympy.Matrix]:
    """The oracle's M and f in plain symbols, formed once for all the points compared."""
    method.form_lagranges_equations()
    return plain_state(method.mass_matrix, coordinates), plain_state(method.forcing, coordinates)


def oracle_accelerations(
    forms: tuple[sympy.Matrix, sympy.Matrix],
    coordinates: Sequence[sympy.Function],
    point: Mapping[str, float],
) -> dict[str, float]:
    mass, forcing = forms
    n = len(coordinates)
    matrix = [[evaluate(mass[i, j], point) for j in range(n)] for i in range(n)]
    rhs = [evaluate(forcing[i], point) for i in range(n)]
    solution = solve_linear(matrix, rhs)
    return {q.func.__name__: value for q, value in zip(coordinates, solution, strict=True)}


def toolkit_accelerations(eom, point: Mapping[str, float]) -> dict[str, float]:
    names = [c.name for c in eom.coordinates]
    if eom.accelerations is not None:
        return {name: evaluate(eom.accelerations[name], point) for name in names}
    n = len(names)
    matrix = [[evaluate(eom.mass_matrix[i, j], point) for j in range(n)] for i in range(n)]
    rhs = [evaluate(eom.forcing[i], point) for i in range(n)]
    return dict(zip(names, solve_linear(matrix, rhs), strict=True))


def compare(
    system,
    method: LagrangesMethod,
    coordinates: Sequence[sympy.Function],
    rng: random.Random,
    *,
    ranges: Mapping[str, tuple[float, float]] | None = None,
    avoid: Callable[[Mapping[str, float]], bool] | None = None,
    count: int = N_POINTS,
) -> list[dict[str, float]]:
    """Assert equal accelerations at ``count`` random points; returns the points."""
    eom = system.equations_of_motion()
    assert [c.name for c in system.coordinates] == [q.func.__name__ for q in coordinates]
    forms = oracle_forms(method, coordinates)
    points = []
    for _ in range(count):
        point = random_point(system, rng, ranges, avoid=avoid)
        ours = toolkit_accelerations(eom, point)
        theirs = oracle_accelerations(forms, coordinates, point)
        for name in ours:
            assert_close(ours[name], theirs[name], what=f"{name}_ddot at {point}")
        points.append(point)
    return points


def velocity_of(point: Point, frame: ReferenceFrame, origin: Point) -> None:
    point.set_vel(frame, point.pos_from(origin).dt(frame))


def height(point: Point, origin: Point, up) -> sympy.Expr:
    return point.pos_from(origin).dot(up)


# -- explicit time: a pendulum whose pivot oscillates vertically ----------------------
def test_pendulum_with_vertically_oscillating_pivot(rng):
    system = lg.System.from_particles(
        coordinates=["theta"],
        particles=[
            lg.Particle("bob", mass="m", position=["l*sin(theta)", "a*cos(w*t) - l*cos(theta)"])
        ],
        gravity=lg.Gravity(g="g", direction=(0, -1)),
    )
    assert not system.is_autonomous
    theta = dynamicsymbols("theta")
    m, l, g, a, w = sympy.symbols("m l g a w")
    frame, origin = ReferenceFrame("N"), Point("O")
    bob = Point("P")
    bob.set_pos(origin, l * sin(theta) * frame.x + (a * cos(w * T) - l * cos(theta)) * frame.y)
    velocity_of(bob, frame, origin)
    particle = OracleParticle("bob", bob, m)
    particle.potential_energy = m * g * height(bob, origin, frame.y)
    method = LagrangesMethod(Lagrangian(frame, particle), [theta])
    points = compare(system, method, [theta], rng, ranges={"t": (0.0, 10.0)})

    # and the textbook form: theta'' = -(g - a w^2 cos(w t)) sin(theta) / l
    eom = system.equations_of_motion()
    for point in points:
        expected = (
            -(point["g"] - point["a"] * point["w"] ** 2 * math.cos(point["w"] * point["t"]))
            * math.sin(point["theta"])
            / point["l"]
        )
        assert_close(evaluate(eom.accelerations["theta"], point), expected, scale=1.0)


def test_bead_on_a_rotating_hoop_3d(rng):
    """Rheonomic and 3-D: a bead on a hoop of radius R turning about the vertical at rate w."""
    system = lg.System.from_particles(
        coordinates=["theta"],
        particles=[
            lg.Particle(
                "bead",
                mass="m",
                position=["R*sin(theta)*cos(w*t)", "R*sin(theta)*sin(w*t)", "-R*cos(theta)"],
            )
        ],
        gravity=lg.Gravity(g="g", direction=(0, 0, -1)),
    )
    theta = dynamicsymbols("theta")
    m, R, g, w = sympy.symbols("m R g w")
    frame, origin = ReferenceFrame("N"), Point("O")
    hoop = frame.orientnew("H", "Axis", [w * T, frame.z])
    bead = origin.locatenew("P", R * sin(theta) * hoop.x - R * cos(theta) * hoop.z)
    velocity_of(bead, frame, origin)
    particle = OracleParticle("bead", bead, m)
    particle.potential_energy = m * g * height(bead, origin, frame.z)
    method = LagrangesMethod(Lagrangian(frame, particle), [theta])
    compare(system, method, [theta], rng)


# -- velocity-dependent potential: a charge in a uniform magnetic field B z -------------
@pytest.mark.parametrize("as_text", [True, False], ids=["text", "sympy"])
def test_charged_particle_in_uniform_magnetic_field(rng, as_text):
    text = "m*(x_dot**2 + y_dot**2 + z_dot**2)/2 + q*B*(x*y_dot - y*x_dot)/2 - q*E0*z"
    lagrangian = text if as_text else sympy.sympify(text)
    system = lg.System.from_lagrangian(
        lagrangian,
        coordinates=["x", "y", "z"],
        parameters={"m": 1.0, "B": 2.0, "E0": 0.5, "q": {"value": -1.0, "sign": "real"}},
    )
    assert system.symbol("q").is_positive is None
    assert system.symbol("q").is_real
    x, y, z = dynamicsymbols("x y z")
    m, q, B, E0 = sympy.symbols("m q B E0")
    velocity = [s.diff(T) for s in (x, y, z)]
    oracle_lagrangian = (
        m * sum(v**2 for v in velocity) / 2 + q * B * (x * velocity[1] - y * velocity[0]) / 2
    ) - q * E0 * z
    method = LagrangesMethod(oracle_lagrangian, [x, y, z])
    points = compare(system, method, [x, y, z], rng)

    # Lorentz force: m a = q v x B + q E
    eom = system.equations_of_motion()
    for point in points:
        qb_m = point["q"] * point["B"] / point["m"]
        assert_close(evaluate(eom.accelerations["x"], point), qb_m * point["y_dot"], scale=1.0)
        assert_close(evaluate(eom.accelerations["y"], point), -qb_m * point["x_dot"], scale=1.0)
        expected_z = -point["q"] * point["E0"] / point["m"]
        assert_close(evaluate(eom.accelerations["z"], point), expected_z, scale=1.0)
    # the charge took a negative value somewhere: the sign assumption matters
    assert any(point["q"] < 0 for point in points) or len(points) < 3


# -- generalized forces and Rayleigh dissipation ------------------------------------
def test_forced_damped_particle_in_polar_coordinates(rng):
    """Drag -b v (as Rayleigh's F = b v^2/2) and a tangential driving force F0 cos(w t)."""
    system = lg.System.from_particles(
        coordinates=["r", "theta"],
        particles=[lg.Particle("p", mass="m", position=["r*cos(theta)", "r*sin(theta)"])],
        potential="k*(r - L0)**2/2",
        dissipation="b*(r_dot**2 + r**2*theta_dot**2)/2",
        forces={"theta": "F0*r*cos(w*t)"},
    )
    r, theta = dynamicsymbols("r theta")
    m, k, L0, b, F0, w = sympy.symbols("m k L0 b F0 w")
    frame, origin = ReferenceFrame("N"), Point("O")
    radial = frame.orientnew("A", "Axis", [theta, frame.z])
    p = origin.locatenew("P", r * radial.x)
    velocity_of(p, frame, origin)
    particle = OracleParticle("p", p, m)
    particle.potential_energy = k * (r - L0) ** 2 / 2
    forces = [(p, -b * p.vel(frame) + F0 * cos(w * T) * radial.y)]
    method = LagrangesMethod(Lagrangian(frame, particle), [r, theta], forcelist=forces, frame=frame)
    compare(system, method, [r, theta], rng, ranges={"r": (0.5, 2.0)})


def test_damped_pendulum_with_pivot_torque(rng):
    """Viscous friction at the pivot as a generalized force, a driving torque on the rod."""
    system = lg.System.from_particles(
        coordinates=["theta"],
        particles=[lg.Particle("bob", mass="m", position=["l*sin(theta)", "-l*cos(theta)"])],
        gravity=lg.Gravity(g="g"),
        forces={"theta": "-c*theta_dot + tau*sin(w*t)"},
    )
    theta = dynamicsymbols("theta")
    m, l, g, c, tau, w = sympy.symbols("m l g c tau w")
    frame, origin = ReferenceFrame("N"), Point("O")
    rod = frame.orientnew("A", "Axis", [theta, frame.z])
    rod.set_ang_vel(frame, theta.diff(T) * frame.z)
    bob = origin.locatenew("P", -l * rod.y)
    velocity_of(bob, frame, origin)
    particle = OracleParticle("bob", bob, m)
    particle.potential_energy = m * g * height(bob, origin, frame.y)
    loads = [(rod, (-c * theta.diff(T) + tau * sin(w * T)) * frame.z)]
    method = LagrangesMethod(Lagrangian(frame, particle), [theta], forcelist=loads, frame=frame)
    compare(system, method, [theta], rng)


# -- springs with a non-zero rest length ---------------------------------------------
def _far_apart(point: Mapping[str, float]) -> bool:
    return (
        math.hypot(point["x1"], point["y1"]) < 0.3
        or math.hypot(point["x2"] - point["x1"], point["y2"] - point["y1"]) < 0.3
    )


def test_two_masses_on_springs_with_rest_length_in_a_plane(rng):
    system = lg.System.from_particles(
        coordinates=["x1", "y1", "x2", "y2"],
        particles=[
            lg.Particle("a", mass="m1", position=["x1", "y1"]),
            lg.Particle("b", mass="m2", position=["x2", "y2"]),
        ],
        springs=[
            lg.Spring(stiffness="k1", ends=((0, 0), "a"), rest_length="L1"),
            lg.Spring(stiffness="k2", ends=("a", "b"), rest_length="L2"),
        ],
        gravity=lg.Gravity(g="g", direction=(0, -1)),
    )
    x1, y1, x2, y2 = coordinates = dynamicsymbols("x1 y1 x2 y2")
    m1, m2, k1, k2, L1, L2, g = sympy.symbols("m1 m2 k1 k2 L1 L2 g")
    frame, origin = ReferenceFrame("N"), Point("O")
    a = origin.locatenew("A", x1 * frame.x + y1 * frame.y)
    b = origin.locatenew("B", x2 * frame.x + y2 * frame.y)
    velocity_of(a, frame, origin)
    velocity_of(b, frame, origin)
    pa, pb = OracleParticle("a", a, m1), OracleParticle("b", b, m2)
    stretch1 = a.pos_from(origin).magnitude() - L1
    stretch2 = b.pos_from(a).magnitude() - L2
    pa.potential_energy = k1 * stretch1**2 / 2 + m1 * g * height(a, origin, frame.y)
    pb.potential_energy = k2 * stretch2**2 / 2 + m2 * g * height(b, origin, frame.y)
    method = LagrangesMethod(Lagrangian(frame, pa, pb), coordinates)
    compare(system, method, coordinates, rng, avoid=_far_apart)


def test_two_masses_between_walls_on_a_line(rng):
    """1-D chain wall-a-b-wall: the spring lengths are |x1|, |x2 - x1|, |D - x2|."""
    system = lg.System.from_particles(
        coordinates=["x1", "x2"],
        particles=[
            lg.Particle("a", mass="m1", position=["x1", 0]),
            lg.Particle("b", mass="m2", position=["x2", 0]),
        ],
        springs=[
            lg.Spring(stiffness="k1", ends=((0, 0), "a"), rest_length="L1"),
            lg.Spring(stiffness="k2", ends=("a", "b"), rest_length="L2"),
            lg.Spring(stiffness="k3", ends=("b", ("D", 0)), rest_length="L3"),
        ],
    )
    x1, x2 = coordinates = dynamicsymbols("x1 x2")
    m1, m2, k1, k2, k3, L1, L2, L3, D = sympy.symbols("m1 m2 k1 k2 k3 L1 L2 L3 D")
    velocity = [s.diff(T) for s in coordinates]
    kinetic = (m1 * velocity[0] ** 2 + m2 * velocity[1] ** 2) / 2
    lengths = [sqrt(x1**2), sqrt((x2 - x1) ** 2), sqrt((D - x2) ** 2)]
    potential = sum(
        stiffness * (length - rest) ** 2 / 2
        for stiffness, length, rest in zip((k1, k2, k3), lengths, (L1, L2, L3), strict=True)
    )
    method = LagrangesMethod(kinetic - potential, coordinates)

    def degenerate(point):
        return (
            min(abs(point["x1"]), abs(point["x2"] - point["x1"]), abs(point["D"] - point["x2"]))
            < 0.2
        )

    compare(system, method, coordinates, rng, avoid=degenerate)


# -- planar rigid bodies ----------------------------------------------------------------
def _rod_oracle(frame, origin, angle, center, m, l):
    """A uniform rod of mass m, length l (I = m l^2/12 about its centre) turning with `angle`."""
    body_frame = frame.orientnew("A", "Axis", [angle, frame.z])
    body_frame.set_ang_vel(frame, angle.diff(T) * frame.z)
    mass_center = origin.locatenew("G", center(body_frame))
    velocity_of(mass_center, frame, origin)
    return RigidBody(
        "rod", mass_center, body_frame, m, (inertia(body_frame, 0, 0, m * l**2 / 12), mass_center)
    )


def test_physical_pendulum_rod_pivoted_at_one_end(rng):
    system = lg.System.from_particles(
        coordinates=["theta"],
        bodies=[
            lg.RigidBody2D(
                "rod",
                mass="m",
                inertia="m*l**2/12",
                center=("l/2*sin(theta)", "-l/2*cos(theta)"),
                angle="theta",
            )
        ],
        gravity=lg.Gravity(g="g", direction=(0, -1)),
    )
    theta = dynamicsymbols("theta")
    m, l, g = sympy.symbols("m l g")
    frame, origin = ReferenceFrame("N"), Point("O")
    rod = _rod_oracle(frame, origin, theta, lambda a: -l / 2 * a.y, m, l)
    rod.potential_energy = m * g * height(rod.masscenter, origin, frame.y)
    method = LagrangesMethod(Lagrangian(frame, rod), [theta])
    points = compare(system, method, [theta], rng)

    # I_pivot = m l^2/3: theta'' = -3 g sin(theta) / (2 l)
    eom = system.equations_of_motion()
    for point in points:
        expected = -3 * point["g"] * math.sin(point["theta"]) / (2 * point["l"])
        assert_close(evaluate(eom.accelerations["theta"], point), expected, scale=1.0)


def test_rod_hanging_from_a_cart_on_a_spring(rng):
    system = lg.System.from_particles(
        coordinates=["x", "theta"],
        particles=[lg.Particle("cart", mass="M", position=["x", 0])],
        bodies=[
            lg.RigidBody2D(
                "rod",
                mass="m",
                inertia="m*l**2/12",
                center=("x + l/2*sin(theta)", "-l/2*cos(theta)"),
                angle="theta",
            )
        ],
        springs=[lg.Spring(stiffness="k", ends=("cart", (0, 0)))],
        gravity=lg.Gravity(g="g", direction=(0, -1)),
    )
    x, theta = coordinates = dynamicsymbols("x theta")
    M, m, l, g, k = sympy.symbols("M m l g k")
    frame, origin = ReferenceFrame("N"), Point("O")
    cart_point = origin.locatenew("C", x * frame.x)
    velocity_of(cart_point, frame, origin)
    cart = OracleParticle("cart", cart_point, M)
    cart.potential_energy = k * x**2 / 2
    rod = _rod_oracle(frame, origin, theta, lambda a: x * frame.x - l / 2 * a.y, m, l)
    rod.potential_energy = m * g * height(rod.masscenter, origin, frame.y)
    method = LagrangesMethod(Lagrangian(frame, cart, rod), coordinates)
    compare(system, method, coordinates, rng)


# -- 3-D -----------------------------------------------------------------------------------
def test_particle_on_a_cone(rng):
    """A particle on the cone z = c r (vertex down) under gravity, in (r, phi)."""
    system = lg.System.from_particles(
        coordinates=["r", "phi"],
        particles=[lg.Particle("p", mass="m", position=["r*cos(phi)", "r*sin(phi)", "c*r"])],
        gravity=lg.Gravity(g="g", direction=(0, 0, -1)),
    )
    r, phi = coordinates = dynamicsymbols("r phi")
    m, c, g = sympy.symbols("m c g")
    frame, origin = ReferenceFrame("N"), Point("O")
    p = origin.locatenew("P", r * cos(phi) * frame.x + r * sin(phi) * frame.y + c * r * frame.z)
    velocity_of(p, frame, origin)
    particle = OracleParticle("p", p, m)
    particle.potential_energy = m * g * height(p, origin, frame.z)
    method = LagrangesMethod(Lagrangian(frame, particle), coordinates)
    compare(system, method, coordinates, rng, ranges={"r": (0.5, 2.0)})


def test_spherical_pendulum_in_3d_from_particles(rng):
    system = lg.System.from_particles(
        coordinates=["theta", "phi"],
        particles=[
            lg.Particle(
                "bob",
                mass="m",
                position=["l*sin(theta)*cos(phi)", "l*sin(theta)*sin(phi)", "-l*cos(theta)"],
            )
        ],
        gravity=lg.Gravity(g="g", direction=(0, 0, -1)),
    )
    theta, phi = coordinates = dynamicsymbols("theta phi")
    m, l, g = sympy.symbols("m l g")
    frame, origin = ReferenceFrame("N"), Point("O")
    azimuth = frame.orientnew("B", "Axis", [phi, frame.z])
    polar = azimuth.orientnew("C", "Axis", [-theta, azimuth.y])  # tilts -z towards +x of B
    bob = origin.locatenew("P", -l * polar.z)
    velocity_of(bob, frame, origin)
    particle = OracleParticle("bob", bob, m)
    particle.potential_energy = m * g * height(bob, origin, frame.z)
    method = LagrangesMethod(Lagrangian(frame, particle), coordinates)

    def near_pole(point):
        return abs(math.sin(point["theta"])) < 0.2

    compare(system, method, coordinates, rng, avoid=near_pole)


# -- a 3-link pendulum ----------------------------------------------------------------------
@pytest.mark.slow
def test_three_link_pendulum_from_particles(rng):
    particles = []
    x_text, y_text = "0", "0"
    for i in (1, 2, 3):
        x_text += f" + l{i}*sin(theta{i})"
        y_text += f" - l{i}*cos(theta{i})"
        particles.append(lg.Particle(f"bob{i}", mass=f"m{i}", position=[x_text, y_text]))
    system = lg.System.from_particles(
        coordinates=["theta1", "theta2", "theta3"],
        particles=particles,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
    )
    angles = dynamicsymbols("theta1:4")
    masses = sympy.symbols("m1:4")
    lengths = sympy.symbols("l1:4")
    g = sympy.Symbol("g")
    frame, origin = ReferenceFrame("N"), Point("O")
    previous, bodies = origin, []
    for i, (angle, mass, length) in enumerate(zip(angles, masses, lengths, strict=True)):
        link = frame.orientnew(f"A{i}", "Axis", [angle, frame.z])
        bob = previous.locatenew(f"P{i}", -length * link.y)
        velocity_of(bob, frame, origin)
        particle = OracleParticle(f"bob{i}", bob, mass)
        particle.potential_energy = mass * g * height(bob, origin, frame.y)
        bodies.append(particle)
        previous = bob
    method = LagrangesMethod(Lagrangian(frame, *bodies), angles)
    compare(system, method, angles, rng)
