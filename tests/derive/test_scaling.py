"""The large-system route (SymEngine term tables) against the readable route and the closed form.

Above ``FAST_MIN_COORDINATES`` coordinates, T is assembled and Lagrange's equations
are derived by :mod:`lagrangian.derive.fast`.  Its M and f must equal the readable
route's at random points (forced onto small systems, every worked example among
them) and the closed-form n-link pendulum's; its size must grow like n^2.
"""

from __future__ import annotations

import importlib
import math

import pytest
import sympy

import lagrangian as lg
from helpers import assert_close, evaluate, random_point
from lagrangian.examples import example_names, example_path

from .test_chain_pendulum import chain_pendulum, check_chain


def _derive(build, monkeypatch, threshold):
    euler_lagrange = importlib.import_module("lagrangian.derive.euler_lagrange")
    energy = importlib.import_module("lagrangian.model.energy")
    with monkeypatch.context() as patch:
        patch.setattr(euler_lagrange, "FAST_MIN_COORDINATES", threshold)
        patch.setattr(energy, "FAST_MIN_COORDINATES", threshold)
        system = build()
        return system, system.equations_of_motion()


def _assert_same(readable, fast, rng, count=3):
    (system, slow_eom), (_, fast_eom) = readable, fast
    n = len(system.coordinates)
    multipliers = fast_eom.constraints.multipliers if fast_eom.constraints else ()
    for _ in range(count):
        point = random_point(system, rng) | {lam.name: rng.uniform(-2, 2) for lam in multipliers}
        for i in range(n):
            for j in range(n):
                assert_close(
                    evaluate(fast_eom.mass_matrix[i, j], point),
                    evaluate(slow_eom.mass_matrix[i, j], point),
                    what=f"M[{i},{j}]",
                )
            assert_close(
                evaluate(fast_eom.forcing[i], point),
                evaluate(slow_eom.forcing[i], point),
                what=f"f[{i}]",
            )
            inertia = sum(
                evaluate(fast_eom.mass_matrix[i, j], point) * point[c.q_ddot.name]
                for j, c in enumerate(system.coordinates)
            )
            constraint_force = evaluate(fast_eom.steps[i].constraint_force, point)
            assert_close(
                evaluate(fast_eom.equations[i], point),
                inertia - evaluate(fast_eom.forcing[i], point) - constraint_force,
                scale=1.0,
                what=f"equation {i} = (M q'' - f - A^T lambda)[{i}]",
            )
            for name in (
                "momentum",
                "momentum_rate",
                "force_gradient",
                "dissipation_force",
                "constraint_force",
            ):
                assert_close(
                    evaluate(getattr(fast_eom.steps[i], name), point),
                    evaluate(getattr(slow_eom.steps[i], name), point),
                    what=f"{name} {i}",
                )
            assert fast_eom.steps[i].equation == fast_eom.equations[i]


@pytest.mark.parametrize("name", [n for n in example_names()])
def test_the_large_route_gives_the_worked_examples_equations(name, rng, monkeypatch):
    def build():
        return lg.load(example_path(name))

    readable = _derive(build, monkeypatch, threshold=10_000)
    if readable[0].functions:
        pytest.skip("unspecified functions keep the readable route")
    _assert_same(readable, _derive(build, monkeypatch, threshold=1), rng)


@pytest.mark.parametrize("n", [2, 3, 4])
def test_the_large_route_gives_the_readable_chain(n, rng, monkeypatch):
    def build():
        return chain_pendulum(n)

    readable = _derive(build, monkeypatch, threshold=10_000)
    fast = _derive(build, monkeypatch, threshold=1)
    _assert_same(readable, fast, rng)


@pytest.mark.parametrize("n", [8, 12, 20])
def test_chain_matches_the_closed_form(n, rng):
    check_chain(n, rng, count=2)


def test_the_mass_matrix_of_a_chain_is_grouped():
    """M_ij = (m_j + ... + m_n) l_i l_j cos(theta_i - theta_j): one term per entry."""
    system = chain_pendulum(8)
    entry = system.equations_of_motion().mass_matrix[2, 5]
    assert any(factor.func is sympy.cos for factor in sympy.Mul.make_args(entry))
    assert len(sympy.Add.make_args(sympy.expand(entry))) == 3  # m6 + m7 + m8


def _cse_size(n: int) -> int:
    eom = chain_pendulum(n).equations_of_motion()
    replacements, reduced = sympy.cse([*eom.mass_matrix, *eom.forcing], order="none")
    return sum(sympy.count_ops(e) for _, e in replacements) + sum(
        sympy.count_ops(e) for e in reduced
    )


def test_size_grows_like_n_squared():
    """Doubling the links multiplies the operation count after CSE by about 4, not 8."""
    ratio = _cse_size(16) / _cse_size(8)
    assert ratio < 5.5


def _spring_chain_3d():
    """Three beads in space on rest-length springs, the first driven along x (sqrt, t)."""
    names = [f"{axis}{k}" for k in range(1, 4) for axis in "xyz"]
    beads = [
        lg.Particle(f"bead{k}", mass=f"m{k}", position=[f"x{k}", f"y{k}", f"z{k}"])
        for k in range(1, 4)
    ]
    anchor = ("a*cos(w*t)", "0", "0")
    ends = [anchor, "bead1", "bead2", "bead3"]
    springs = [
        lg.Spring(stiffness=f"k{k}", ends=(ends[k - 1], ends[k]), rest_length="r0")
        for k in range(1, 4)
    ]
    return lg.System.from_particles(
        coordinates=names,
        particles=beads,
        springs=springs,
        gravity=lg.Gravity(g="g"),
        dissipation="b*(" + " + ".join(f"{n}_dot^2" for n in names) + ")/2",
    )


def _charged_chain():
    """Seven charges in a plane, a magnetic field (velocity-dependent L), exp coupling, forces."""
    n = 7
    kinetic = " + ".join(f"m*(x{k}_dot^2 + y{k}_dot^2)/2" for k in range(1, n + 1))
    magnetic = " + ".join(f"B*(x{k}*y{k}_dot - y{k}*x{k}_dot)/2" for k in range(1, n + 1))
    coupling = " + ".join(
        f"c*exp(-((x{k} - x{k + 1})^2 + (y{k} - y{k + 1})^2))" for k in range(1, n)
    )
    coordinates = [f"{axis}{k}" for k in range(1, n + 1) for axis in "xy"]
    return lg.System.from_lagrangian(
        f"{kinetic} + q*({magnetic}) - {coupling} - E0*x1*sin(w*t)",
        coordinates=coordinates,
        forces={"x3": "-b*x3_dot + F*cos(w*t)", "y7": "-b*y7_dot*x7^2"},
    )


def _rotating_frame_chain():
    """A 5-link chain seen from a frame turning at rate W (moving constraint, Coriolis)."""
    return chain_pendulum(5, length="l", angle="theta{i} + W*t")


def _friction_chain():
    """A 7-link chain with Coulomb friction, drag |v|^3, a V-shaped potential and atan2."""
    return chain_pendulum(
        7,
        length="l",
        mass="m",
        potential="k*Abs(theta1 - theta2) + c*atan2(theta3, 2 + theta4^2) + E*theta5^2",
        forces={f"theta{i}": f"-mu*sign(theta{i}_dot)" for i in range(1, 8)},
        dissipation="b*Abs(theta6_dot)^3/3 + d*Abs(theta6_dot - theta7_dot)",
    )


def _rod_chain():
    """Five uniform rods hinged end to end (a chain of physical pendulums), with a torsion
    spring at the top hinge: rigid bodies on the large route."""
    n = 5
    bodies, x_end, y_end = [], "0", "0"
    for i in range(1, n + 1):
        center = [f"{x_end} + a{i}*sin(theta{i})/2", f"{y_end} - a{i}*cos(theta{i})/2"]
        inertia = f"m{i}*a{i}^2/12"
        bodies.append(lg.RigidBody2D(f"rod{i}", mass=f"m{i}", inertia=inertia, center=center,
                                     angle=f"theta{i}"))  # fmt: skip
        x_end += f" + a{i}*sin(theta{i})"
        y_end += f" - a{i}*cos(theta{i})"
    return lg.System.from_particles(
        coordinates=[f"theta{i}" for i in range(1, n + 1)],
        bodies=bodies,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        potential="kappa*theta1^2/2",
    )


OTHER_SYSTEMS = [
    _spring_chain_3d, _charged_chain, _rotating_frame_chain, _friction_chain, _rod_chain
]  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize("build", OTHER_SYSTEMS)
def test_the_large_route_gives_the_readable_equations_of_other_systems(build, rng, monkeypatch):
    """Systems that are not examples: 3-D springs with rest length, time, damping, charges,
    friction (sign, |u|, atan2): each takes the large route and gives the readable equations."""
    readable = _derive(build, monkeypatch, threshold=10_000)
    fast = _derive(build, monkeypatch, threshold=1)
    assert fast[1].symengine is not None  # the large route's own forms: it did not fall back
    _assert_same(readable, fast, rng, count=2)


def test_a_derivative_symengine_leaves_undone_keeps_the_readable_route():
    """d sign(u)/dx is a Dirac delta in SymPy and undone in SymEngine: the readable route."""
    fast = importlib.import_module("lagrangian.derive.fast")
    coordinates = [f"x{i}" for i in range(1, 8)]
    kinetic = " + ".join(f"{x}_dot^2/2" for x in coordinates)
    system = lg.System.from_lagrangian(f"{kinetic} - sign(x1)*x2^2", coordinates=coordinates)
    assert fast.derive_large(system) is None
    assert system.equations_of_motion().forcing[0].has(sympy.DiracDelta)


def test_symengine_functions_come_back_as_sympy_builds_them():
    import symengine as se

    from lagrangian.algebra import to_sympy

    x = sympy.Symbol("x", real=True)
    for name in ["sin", "cos", "tan", "exp", "log", "sinh", "cosh", "tanh", "asin", "atan"]:
        converted = to_sympy(getattr(se, name)(se.Symbol("x") + 1), {"x": x})
        expected = getattr(sympy, name)(x + 1, evaluate=False)
        assert converted == expected and hash(converted) == hash(expected), name
        assert converted.func is expected.func and converted.nargs == expected.nargs
        assert sympy.diff(converted, x) == sympy.diff(expected, x)


def _cartesian_chain(n: int):
    """n particles in the plane held at distance l from each other (and the first from the
    origin) by n holonomic constraints: the n-link pendulum in 2n Cartesian coordinates."""
    particles = [
        lg.Particle(f"p{i}", mass="m", position=[f"x{i}", f"y{i}"]) for i in range(1, n + 1)
    ]
    links = ["x1^2 + y1^2 - l^2"]
    links += [f"(x{i} - x{i - 1})^2 + (y{i} - y{i - 1})^2 - l^2" for i in range(2, n + 1)]
    return lg.System.from_particles(
        coordinates=[f"{axis}{i}" for i in range(1, n + 1) for axis in "xy"],
        particles=particles,
        gravity=lg.Gravity(g="g"),
        constraints=links,
        parameters={"m": 1.0, "l": 1.0, "g": 9.81},
    )


def test_the_large_route_carries_the_constraint_forces(rng, monkeypatch):
    readable, fast = (
        _derive(lambda: _cartesian_chain(2), monkeypatch, threshold=t) for t in (10_000, 1)
    )
    assert readable[1].multipliers is not None and fast[1].multipliers is None  # numerics
    _assert_same(readable, fast, rng, count=2)


def test_long_closed_forms_of_the_multipliers_are_given_untidied(rng):
    """Three particles on a Cartesian chain (6 coordinates, so q'' is always given):
    tidying the multipliers took 5 s for 11,000 characters each; untidied they are
    the LU solution of the Schur complement, and still solve M q'' = f + A^T lambda,
    A q'' = beta at random points."""
    eom = _cartesian_chain(3).equations_of_motion()
    system, forms = eom.system, eom.constraints
    assert set(eom.accelerations) == {c.name for c in system.coordinates}
    assert len(str(eom.multipliers["lambda1"])) < 5000
    for _ in range(2):
        point = random_point(system, rng, {"l": (0.5, 2.0)})
        point |= {c.q_ddot.name: evaluate(eom.accelerations[c.name], point)
                  for c in system.coordinates}  # fmt: skip
        point |= {name: evaluate(value, point) for name, value in eom.multipliers.items()}
        for i in range(6):
            inertia = sum(
                evaluate(eom.mass_matrix[i, j], point) * point[c.q_ddot.name]
                for j, c in enumerate(system.coordinates)
            )
            force = evaluate(eom.forcing[i], point) + evaluate(eom.steps[i].constraint_force, point)
            assert_close(inertia, force, scale=1.0, what=f"row {i} of M q'' = f + A^T lambda")
        for j in range(3):
            rate = sum(
                evaluate(forms.matrix[j, k], point) * point[c.q_ddot.name]
                for k, c in enumerate(system.coordinates)
            )
            assert_close(rate, evaluate(forms.bias[j], point), scale=1.0, what=f"A q'' = beta, {j}")


@pytest.mark.slow
def test_a_large_constrained_chain_moves_as_the_chain_in_angles():
    """Four particles, eight Cartesian coordinates, four constraints (the large route) against
    the 4-link pendulum in angles: the last bob at t = 2 agrees to the tolerance."""
    n, angles = 4, [0.3, -0.2, 0.5, 0.1]
    start, x, y = {}, 0.0, 0.0
    for i, angle in enumerate(angles, 1):
        x, y = x + math.sin(angle), y - math.cos(angle)
        start |= {f"x{i}": x, f"y{i}": y}
    cartesian = _cartesian_chain(n).simulate(t_end=2.0, initial=start, rtol=1e-11, atol=1e-11)
    chain = chain_pendulum(n)
    values = {f"m{i}": 1.0 for i in range(1, n + 1)} | {f"l{i}": 1.0 for i in range(1, n + 1)}
    final = chain.simulate(
        t_end=2.0,
        initial={f"theta{i}": a for i, a in enumerate(angles, 1)},
        params=values | {"g": 9.81},
        rtol=1e-11,
        atol=1e-11,
    ).final_state
    theta = [final[f"theta{i}"] for i in range(1, n + 1)]
    assert cartesian.final_state["x4"] == pytest.approx(sum(map(math.sin, theta)), abs=1e-8)
    assert cartesian.final_state["y4"] == pytest.approx(-sum(map(math.cos, theta)), abs=1e-8)
