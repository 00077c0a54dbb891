"""Lagrangians whose mass matrix d^2 L / dq' dq' is singular are refused, naming the coordinates."""

from __future__ import annotations

import re

import pytest
import sympy

import lagrangian as lg
from lagrangian.derive.solve import check_regular
from lagrangian.symbols import Coordinate


def named(message: str, name: str) -> bool:
    return re.search(rf"(?<![\w]){re.escape(name)}(?![\w])", message) is not None


def derive_error(lagrangian, coordinates, **options) -> str:
    with pytest.raises(lg.SingularMassMatrixError) as caught:
        lg.System.from_lagrangian(
            lagrangian, coordinates=coordinates, **options
        ).equations_of_motion()
    message = str(caught.value)
    assert "\n" not in message
    return message


def test_singular_is_a_user_error():
    assert issubclass(lg.SingularMassMatrixError, lg.LagrangianError)


def test_lagrangian_linear_in_the_velocities():
    """L = x_dot y - V(x, y): no kinetic term at all (a first-order, Hamiltonian-like system)."""
    message = derive_error("x_dot*y - V(x, y)", ["x", "y"], functions={"V": ["x", "y"]})
    assert named(message, "x") and named(message, "y"), message
    assert "singular" in message


def test_lagrangian_linear_in_the_velocities_from_sympy():
    x, y, x_dot = sympy.symbols("x y x_dot")
    V = sympy.Function("V")
    message = derive_error(x_dot * y - V(x, y), ["x", "y"], functions={"V": ["x", "y"]})
    assert named(message, "x") and named(message, "y"), message


def test_velocities_only_in_a_combination():
    """L = (x_dot + y_dot)^2 / 2: rank 1, both velocities involved."""
    message = derive_error("(x_dot + y_dot)**2/2", ["x", "y"])
    assert named(message, "x") and named(message, "y"), message
    assert "singular" in message


def test_only_the_coordinates_at_fault_are_named():
    message = derive_error("u_dot**2/2 + (x_dot + y_dot)**2/2 - u**2", ["u", "x", "y"])
    assert named(message, "x") and named(message, "y"), message
    assert not named(message, "u"), message


def test_a_coordinate_without_kinetic_term_is_named():
    message = derive_error("x_dot**2/2 + x*y_dot - y**2/2", ["x", "y"])
    assert named(message, "y"), message
    # the offending coordinate is y; x has a kinetic term
    assert not re.search(r"no kinetic term for [^(]*\bx\b", message), message


def test_singular_only_at_isolated_points_is_accepted():
    """The spherical pendulum's M is singular at theta = 0 only: a regular system."""
    system = lg.System.from_lagrangian(
        "m*l**2*(theta_dot**2 + sin(theta)**2*phi_dot**2)/2 + m*g*l*cos(theta)",
        coordinates=["theta", "phi"],
    )
    eom = system.equations_of_motion()
    assert eom.accelerations is not None


# -- regular Lagrangians must not be called singular because of their units -----------------
x, y, x_dot, y_dot, k = sympy.symbols("x y x_dot y_dot k")


@pytest.mark.parametrize(
    "mass",
    [sympy.Float("9.109e-31"), sympy.Rational(1, 10**10), sympy.Float("5.97e24")],
    ids=["electron_mass_in_kg", "1e-10", "earth_mass_in_kg"],
)
def test_a_numeric_mass_of_any_magnitude_is_regular(mass):
    """L = mass x_dot^2/2 - k x^2/2 with a literal mass: x'' = -k x / mass, never 'singular'."""
    system = lg.System.from_lagrangian(mass * x_dot**2 / 2 - k * x**2 / 2, coordinates=["x"])
    eom = system.equations_of_motion()
    expected = -system.symbol("k") * system.symbol("x") / mass
    assert sympy.simplify(eom.accelerations["x"] - expected) == 0


def test_masses_of_very_different_magnitude_are_regular():
    """A planet (5.97e24) and a satellite (1) on a spring: M = diag(5.97e24, 1) is regular."""
    big = sympy.Float("5.97e24")
    lagrangian = big * x_dot**2 / 2 + y_dot**2 / 2 - k * (x - y) ** 2 / 2
    eom = lg.System.from_lagrangian(lagrangian, coordinates=["x", "y"]).equations_of_motion()
    assert eom.accelerations is not None


# -- floats lose I beside a huge rank-one term: the verdict "singular" is checked precisely --
def test_identity_plus_a_huge_rank_one_term_is_regular():
    """M = I + 3540 s^58 J (J all ones, s = x' + y' + z'): positive definite, but its
    condition number near 10^41 made the float rank 1."""
    coordinates = [Coordinate.named(name) for name in "xyz"]
    s = sum(c.q_dot for c in coordinates)
    check_regular(sympy.eye(3) + 60 * 59 * s**58 * sympy.ones(3, 3), coordinates)


@pytest.mark.slow  # Cramer's rule on the 58th powers: 15 s
def test_a_lagrangian_with_a_huge_rank_one_term_derives():
    """The model of the report, whole: its M is the matrix above."""
    lagrangian = "(x_dot^2 + y_dot^2 + z_dot^2)/2 + (x_dot + y_dot + z_dot)^60"
    system = lg.System.from_lagrangian(lagrangian, coordinates=["x", "y", "z"])
    eom = system.equations_of_motion()
    s = sum(system.symbol(f"{q}_dot") for q in "xyz")
    expected = sympy.eye(3) + 60 * 59 * s**58 * sympy.ones(3, 3)
    point = {system.symbol(f"{q}_dot"): sympy.Rational(k, 7) for k, q in enumerate("xyz", 2)}
    assert (eom.mass_matrix - expected).xreplace(point) == sympy.zeros(3, 3)


def test_a_singular_rank_one_term_is_still_refused():
    """s^58 J alone (no identity): rank 1 exactly."""
    coordinates = [Coordinate.named(name) for name in "xyz"]
    s = sum(c.q_dot for c in coordinates)
    with pytest.raises(lg.SingularMassMatrixError, match=r"\(rank 1 of 3\)"):
        check_regular(60 * 59 * s**58 * sympy.ones(3, 3), coordinates)


def test_a_huge_term_with_transcendental_entries_is_regular():
    """exp(x) keeps the entries irrational at the rational point: judged at 100 digits."""
    lagrangian = "(x_dot^2 + y_dot^2)/2 + exp(x)*(x_dot + y_dot)^60"
    eom = lg.System.from_lagrangian(lagrangian, coordinates=["x", "y"]).equations_of_motion()
    assert eom.mass_matrix.shape == (2, 2)


def test_a_truly_singular_matrix_keeps_its_message():
    message = derive_error("(x_dot + y_dot)**2/2", ["x", "y"])
    assert message == (
        "singular mass matrix (rank 1 of 2): the velocities of x, y enter the Lagrangian "
        "only in a combination; use fewer coordinates"
    )


def test_a_singular_matrix_with_transcendental_entries_is_refused():
    """M = v v^T with v = (sin x, cos x): rank 1 at every point, at 100 digits too."""
    message = derive_error("(sin(x)*x_dot + cos(x)*y_dot)**2/2", ["x", "y"])
    assert message.startswith("singular mass matrix (rank 1 of 2)"), message


def _symmetric_rows(n: int, singular: bool):
    """An n x n symmetric SymEngine matrix with transcendental entries, as rows: the chain's
    M (q_i - q_j cosines, regular), or the rank-one u u^T with u_i = l_i cos(q_i)."""
    import symengine as se

    q = [se.Symbol(f"q{i}") for i in range(n)]
    lengths = [se.Symbol(f"l{i}") for i in range(n)]
    if singular:
        u = [lengths[i] * se.cos(q[i]) for i in range(n)]
        return [tuple(u[i] * u[j] for j in range(n)) for i in range(n)]
    return [
        tuple((n - max(i, j)) * lengths[i] * lengths[j] * se.cos(q[i] - q[j]) for j in range(n))
        for i in range(n)
    ]


@pytest.mark.parametrize("singular", [False, True])
def test_the_large_route_rank_check_agrees_with_sympys(singular):
    """The large route's check evaluates only M's upper triangle; its verdict on a symmetric
    8 x 8 matrix is SymPy's exact one (check_regular on the same entries)."""
    from lagrangian.derive.fast import _regular_at_random_points

    rows = _symmetric_rows(8, singular)
    assert _regular_at_random_points(rows) is not singular
    matrix = sympy.Matrix([[x._sympy_() for x in row] for row in rows])
    coordinates = [Coordinate.named(f"q{i}") for i in range(8)]
    if singular:
        with pytest.raises(lg.SingularMassMatrixError):
            check_regular(matrix, coordinates)
    else:
        check_regular(matrix, coordinates)


@pytest.mark.parametrize("singular", [False, True])
def test_the_large_route_rank_check_on_an_indefinite_matrix(singular):
    """The rank is counted from eigenvalue magnitudes (a symmetric matrix's singular values):
    an indefinite regular matrix (eigenvalues of both signs) is full rank, and a sum of
    u u^T and -w w^T is rank two of three, as SymPy's exact check says."""
    import symengine as se

    x, y, a = se.symbols("x y a")
    u = [se.cos(x), se.sin(y), a]
    w = [a * se.sin(x), se.cos(x - y), se.Integer(1)]
    rows = [tuple(u[i] * u[j] - w[i] * w[j] for j in range(3)) for i in range(3)]
    if not singular:
        rows[0] = (rows[0][0] + 2 * a, *rows[0][1:])
    assert _regular_at_random_points_of(rows) is not singular
    matrix = sympy.Matrix([[entry._sympy_() for entry in row] for row in rows])
    coordinates = [Coordinate.named(f"q{i}") for i in range(3)]
    if singular:
        with pytest.raises(lg.SingularMassMatrixError):
            check_regular(matrix, coordinates)
    else:
        check_regular(matrix, coordinates)


def _regular_at_random_points_of(rows) -> bool:
    from lagrangian.derive.fast import _regular_at_random_points

    return _regular_at_random_points(rows)
