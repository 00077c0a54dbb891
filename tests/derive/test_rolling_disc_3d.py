"""A disc rolling without slipping on a plane, as a 3-D body with its contact constraints.

The oracle is SymPy's mechanics (the rolling disc of its documentation): the
disc is a ``RigidBody`` in frames oriented by axis rotations (yaw q1 about z,
lean q2 about the yawed x, spin q3 about the disc's axis y), its kinetic energy
is SymPy's own, and ``LagrangesMethod`` with the nonholonomic rolling
constraints (the material point at the contact has zero velocity) gives q''
and the multipliers.  Our model takes the same disc as ``[[bodies]]`` with
Euler angles in the "zxy" convention; the constraints are SymPy's, written out
as text.
"""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy
from sympy.physics.mechanics import (
    LagrangesMethod,
    Point,
    ReferenceFrame,
    RigidBody,
    dynamicsymbols,
    inertia,
    msubs,
)

import lagrangian as lg

NAMES = ["x", "y", "q1", "q2", "q3"]
VALUES = {"m": 1.3, "r": 0.4, "g": 9.81}


def sympy_disc():
    """(LagrangesMethod, coordinates, constraint expressions) of SymPy's rolling disc."""
    x, y, q1, q2, q3 = dynamicsymbols(NAMES)
    m, r, g = sympy.symbols("m r g")
    t = dynamicsymbols._t
    frame = ReferenceFrame("N")
    yawed = frame.orientnew("Y", "Axis", [q1, frame.z])
    leaned = yawed.orientnew("L", "Axis", [q2, yawed.x])
    disc = leaned.orientnew("R", "Axis", [q3, leaned.y])
    origin = Point("O")
    origin.set_vel(frame, 0)
    contact = origin.locatenew("C", x * frame.x + y * frame.y)
    centre = contact.locatenew("D", r * leaned.z)
    centre.set_vel(frame, centre.pos_from(origin).dt(frame))
    body = RigidBody(
        "disc", centre, disc, m, (inertia(leaned, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4), centre)
    )
    body.potential_energy = m * g * centre.pos_from(origin).dot(frame.z)
    lagrangian = sympy.physics.mechanics.Lagrangian(frame, body)
    # the material point of the disc at the contact has zero velocity
    rolling = centre.vel(frame) + disc.ang_vel_in(frame).cross(-r * leaned.z)
    constraints = [rolling.dot(frame.x), rolling.dot(frame.y)]
    coordinates = [x, y, q1, q2, q3]
    method = LagrangesMethod(lagrangian, coordinates, nonhol_coneqs=constraints, frame=frame)
    method.form_lagranges_equations()
    speeds = [c.diff(t) for c in coordinates]
    return method, coordinates, speeds, constraints


@pytest.fixture(scope="module")
def disc():
    method, coordinates, speeds, constraints = sympy_disc()
    names = {c: sympy.Symbol(n) for c, n in zip(coordinates, NAMES, strict=True)}
    names.update({v: sympy.Symbol(f"{n}_dot") for v, n in zip(speeds, NAMES, strict=True)})
    text = [str(sympy.expand(c.subs(names))) for c in constraints]  # speeds before coordinates
    system = lg.System.from_particles(
        NAMES,
        bodies=[
            lg.RigidBody(
                "disc",
                "m",
                ("x + r*sin(q1)*sin(q2)", "y - r*cos(q1)*sin(q2)", "r*cos(q2)"),
                ("m*r^2/4", "m*r^2/2", "m*r^2/4"),
                euler=("q1", "q2", "q3"),
                convention="zxy",
            )
        ],
        gravity=lg.Gravity("g"),
        constraints=text,
        parameters=VALUES,
    )
    compiled = lg.compile_equations(system.equations_of_motion())
    return compiled, method, coordinates, speeds, constraints


def rolling_state(disc, q, yaw, lean, spin) -> dict:
    """{coordinate or speed: value} with x', y' from the rolling constraints."""
    _, _, coordinates, speeds, constraints = disc
    point = dict(zip(coordinates, q, strict=True))
    point.update({speeds[2]: yaw, speeds[3]: lean, speeds[4]: spin})
    unknown = sympy.symbols("u v")
    m, r, g = sympy.symbols("m r g")
    numbers = {m: VALUES["m"], r: VALUES["r"], g: VALUES["g"]}
    equations = [
        c.subs({speeds[0]: unknown[0], speeds[1]: unknown[1]}).subs(point).subs(numbers)
        for c in constraints
    ]
    solved = sympy.solve(equations, unknown, dict=True)[0]
    point.update({speeds[0]: float(solved[unknown[0]]), speeds[1]: float(solved[unknown[1]])})
    return point


@pytest.mark.slow
def test_rolling_disc_accelerations_equal_sympy_mechanics(disc):
    compiled, method, _, speeds, constraints = disc
    m, r, g = sympy.symbols("m r g")
    numbers = {m: VALUES["m"], r: VALUES["r"], g: VALUES["g"]}
    t = dynamicsymbols._t
    multipliers = list(method.lam_vec)
    accelerations = [v.diff(t) for v in speeds]
    symbols = [*accelerations, *multipliers]
    placeholders = sympy.symbols(f"z0:{len(symbols)}")
    swap = dict(zip(symbols, placeholders, strict=True))
    # M q'' = f + A^T lambda (SymPy's rows, lambda columns included), and the rolling
    # constraints differentiated once: A q'' + (dA/dt) q' = 0; formed once, for every point
    rates = [c.diff(t).subs(swap) for c in constraints]
    rows = [[rate.diff(z) for z in placeholders] for rate in rates]
    rest = [rate.subs(dict.fromkeys(placeholders, 0)) for rate in rates]
    full_matrix = sympy.Matrix([*method.mass_matrix.subs(swap).tolist(), *rows])
    full_forcing = sympy.Matrix([*method.forcing.subs(swap), *(-x for x in rest)])
    rng = random.Random(8)
    for _ in range(4):
        q = [rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-3, 3), rng.uniform(-1, 1)]
        q.append(rng.uniform(-3, 3))
        yaw, lean, spin = rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-5, 5)
        point = rolling_state(disc, q, yaw, lean, spin)
        # msubs: the same values as .subs(point).subs(numbers) (to 3e-17), ten times faster
        full = msubs(full_matrix, point, numbers)
        forcing = msubs(full_forcing, point, numbers)
        expected = np.linalg.solve(np.array(full, float), np.array(forcing, float).ravel())
        y = np.array(q + [float(point[v]) for v in speeds])
        ours = compiled.rhs(0.0, y, compiled.parameter_vector())
        assert np.allclose(ours[5:], expected[:5], rtol=1e-8, atol=1e-9)
        assert np.max(np.abs(expected[:5])) > 0.1  # a real test: the disc accelerates


@pytest.mark.slow
def test_a_rolling_disc_keeps_rolling_and_conserves_energy(disc):
    compiled, _, coordinates, speeds, _ = disc
    from lagrangian.integrate import simulate

    point = rolling_state(disc, [0, 0, 0, 0.2, 0], yaw=0.5, lean=0.0, spin=-8.0)
    initial = {n: float(point[c]) for n, c in zip(NAMES, coordinates, strict=True)}
    initial |= {f"{n}_dot": float(point[v]) for n, v in zip(NAMES, speeds, strict=True)}
    run = simulate(compiled, t_end=1.0, initial=initial, n_out=101)
    residual = compiled.constraint_velocity_residual
    params = compiled.parameter_vector()
    for k in range(0, 101, 25):
        y = np.array([run[n][k] for n in NAMES] + [run[f"{n}_dot"][k] for n in NAMES])
        assert np.allclose(residual(run.t[k], y, params), 0, atol=1e-6)
    assert run.drift("energy") < 1e-6
