"""State-space linearization x' = A x + B u, y = C x + D u, against independent results.

* the cart-pole's textbook A, B about the upright and the hanging pole;
* the double pendulum on a cart against sympy.physics.mechanics (LagrangesMethod,
  its own linearizer) at four operating points and random parameter values;
* finite differences of our compiled right-hand side (A, B at equilibria and
  about a steady conical motion of the spherical pendulum, whose small
  oscillations have omega^2 = phi_dot0^2 (1 + 3 cos^2 theta0));
* python-control's poles of the upright cart-pole (when python-control is installed).
"""

from __future__ import annotations

import functools
import json
import math
import sys

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis.state_space import state_space
from lagrangian.cli import main
from lagrangian.numeric import compile_equations

CART_POLE = """
name = "Cart-pole"
coordinates = ["x", "theta"]   # theta from the upward vertical
[parameters]
M = 1.0
m = 0.1
l = 0.5
g = 9.81
[[particles]]
name = "cart"
mass = "M"
position = ["x", "0"]
[[particles]]
name = "bob"
mass = "m"
position = ["x + l*sin(theta)", "l*cos(theta)"]
[gravity]
g = "g"
[inputs]
F = "x"
"""

DOUBLE_PENDULUM_ON_CART = """
name = "Double pendulum on a cart"
coordinates = ["x", "theta1", "theta2"]   # angles from the downward vertical
[parameters]
M = 1.0
m1 = 0.5
m2 = 0.5
l1 = 1.0
l2 = 1.0
g = 9.81
[[particles]]
name = "cart"
mass = "M"
position = ["x", "0"]
[[particles]]
name = "bob1"
mass = "m1"
position = ["x + l1*sin(theta1)", "-l1*cos(theta1)"]
[[particles]]
name = "bob2"
mass = "m2"
position = ["x + l1*sin(theta1) + l2*sin(theta2)", "-l1*cos(theta1) - l2*cos(theta2)"]
[gravity]
g = "g"
[inputs]
F = "x"
"""


def by_name(expr: sympy.Expr, system) -> sympy.Expr:
    """``expr`` written with plain symbols, rebound to the system's symbols by name."""
    return expr.xreplace({s: system.symbol(s.name) for s in expr.free_symbols})


def same_matrix(ours: sympy.MatrixBase, theirs: sympy.MatrixBase, system) -> bool:
    theirs = sympy.Matrix(theirs).applyfunc(lambda e: by_name(sympy.sympify(e), system))
    return ours.shape == theirs.shape and all(
        sympy.simplify(a - b) == 0 for a, b in zip(ours, theirs, strict=True)
    )


@functools.cache
def loaded(text: str) -> lg.System:
    """The model of ``text``, loaded once per module: a System is immutable and keeps its
    derivation, so the tests of one model share it instead of deriving it again each."""
    return lg.loads(text)


# -- the cart-pole: textbook A, B ------------------------------------------------------
M, m, l, g = sympy.symbols("M m l g", positive=True)


def test_cart_pole_upright_matches_the_textbook():
    """Upright (theta = 0): x'' = -m g/M theta + F/M, theta'' = (M + m) g/(M l) theta - F/(M l)."""
    system = loaded(CART_POLE)
    linear = system.state_space(at={"theta": 0})
    assert linear.states == ("x", "theta", "x_dot", "theta_dot")
    assert linear.inputs == ("F",)
    textbook_a = sympy.Matrix(
        [
            [0, 0, 1, 0],
            [0, 0, 0, 1],
            [0, -m * g / M, 0, 0],
            [0, (M + m) * g / (M * l), 0, 0],
        ]
    )
    textbook_b = sympy.Matrix([0, 0, 1 / M, -1 / (M * l)])
    assert same_matrix(linear.A, textbook_a, system)
    assert same_matrix(linear.B, textbook_b, system)
    assert sympy.eye(4) == linear.C and sympy.zeros(4, 1) == linear.D
    numbers = linear.numeric()
    assert numbers.A[2, 1] == pytest.approx(-0.1 * 9.81 / 1.0, rel=1e-14)
    assert numbers.A[3, 1] == pytest.approx(1.1 * 9.81 / 0.5, rel=1e-14)
    assert numbers.B[:, 0] == pytest.approx([0, 0, 1.0, -2.0], rel=1e-14)


def test_cart_pole_hanging_matches_the_textbook():
    """Hanging: the textbook angle phi from the downward vertical, bob at x + l sin(phi), has
    x'' = m g/M phi + F/M, phi'' = -(M + m) g/(M l) phi - F/(M l).  Here theta = pi - phi."""
    system = loaded(CART_POLE)
    linear = system.state_space(at={"theta": sympy.pi})
    phi_rows = sympy.Matrix(
        [
            [0, 0, 1, 0],
            [0, 0, 0, 1],
            [0, m * g / M, 0, 0],
            [0, -(M + m) * g / (M * l), 0, 0],
        ]
    )
    phi_b = sympy.Matrix([0, 0, 1 / M, -1 / (M * l)])
    # x = (x, phi, ...) -> (x, theta - pi, ...) = S x with S = diag(1, -1, 1, -1)
    flip = sympy.diag(1, -1, 1, -1)
    assert same_matrix(linear.A, flip * phi_rows * flip, system)
    assert same_matrix(linear.B, flip * phi_b, system)


def test_cart_pole_text_values_and_default_point():
    system = loaded(CART_POLE)
    from_text = system.state_space(at={"theta": "pi"})
    assert from_text.point == {"theta": sympy.pi}
    assert same_matrix(from_text.A, system.state_space(at={"theta": sympy.pi}).A, system)
    found = system.state_space()  # the first equilibrium found, inputs at 0
    assert set(found.point) == {"theta"}
    assert found.point["theta"] in (0, sympy.pi)


def test_outputs_give_c_and_d():
    """y = (tip x-position, F): C = (1, l cos(theta0), 0, 0), D = (0, 1)^T."""
    system = loaded(CART_POLE)
    linear = system.state_space(
        at={"theta": 0}, outputs={"tip": "x + l*sin(theta)", "push": "2*F + x_dot"}
    )
    assert linear.outputs == ("tip", "push")
    assert same_matrix(linear.C, sympy.Matrix([[1, l, 0, 0], [0, 0, 1, 0]]), system)
    assert sympy.Matrix([[0], [2]]) == linear.D
    chosen = system.state_space(at={"theta": 0}, outputs=["theta", "x_dot"])
    assert sympy.Matrix([[0, 1, 0, 0], [0, 0, 1, 0]]) == chosen.C


# -- the double pendulum on a cart: sympy.physics.mechanics as the oracle ----------------
@functools.cache
def double_pendulum_on_cart():
    """Its equations of motion, derived once for the four operating points."""
    return loaded(DOUBLE_PENDULUM_ON_CART).equations_of_motion()


@functools.cache
def mechanics_double_pendulum_on_cart():
    """The double pendulum on a cart in sympy.physics.mechanics, its equations formed and
    its Linearizer made once (what LagrangesMethod.linearize makes anew each call): (the
    Linearizer, the coordinates, the input F, the parameters)."""
    from sympy.physics.mechanics import (
        LagrangesMethod,
        Lagrangian,
        Particle,
        Point,
        ReferenceFrame,
        dynamicsymbols,
    )

    x, t1, t2 = dynamicsymbols("x theta1 theta2")
    force = dynamicsymbols("F")
    symbols = sympy.symbols("M m1 m2 l1 l2 g", positive=True)
    mass, m1, m2, l1, l2, gravity = symbols
    frame = ReferenceFrame("N")
    origin = Point("O")
    origin.set_vel(frame, 0)
    cart = origin.locatenew("cart", x * frame.x)
    bob1 = cart.locatenew("bob1", l1 * sympy.sin(t1) * frame.x - l1 * sympy.cos(t1) * frame.y)
    bob2 = bob1.locatenew("bob2", l2 * sympy.sin(t2) * frame.x - l2 * sympy.cos(t2) * frame.y)
    for point in (cart, bob1, bob2):
        point.set_vel(frame, point.pos_from(origin).dt(frame))
    parts = [Particle("pc", cart, mass), Particle("p1", bob1, m1), Particle("p2", bob2, m2)]
    parts[1].potential_energy = m1 * gravity * bob1.pos_from(origin).dot(frame.y)
    parts[2].potential_energy = m2 * gravity * bob2.pos_from(origin).dot(frame.y)
    method = LagrangesMethod(
        Lagrangian(frame, *parts), [x, t1, t2], forcelist=[(cart, force * frame.x)], frame=frame
    )
    method.form_lagranges_equations()
    q = [x, t1, t2]
    return method.to_linearizer(q_ind=q, qd_ind=[s.diff() for s in q]), q, force, symbols


def mechanics_linearization(values: dict[str, float], angles: tuple) -> tuple[np.ndarray, ...]:
    """A, B of the double pendulum on a cart by sympy's Linearizer, at ``values``."""
    linearizer, q, force, symbols = mechanics_double_pendulum_on_cart()
    qd = [s.diff() for s in q]
    point = dict(zip(q, (0, *angles), strict=True)) | dict.fromkeys(qd, 0)
    point |= {s.diff(): 0 for s in qd}
    a, b = linearizer.linearize(A_and_B=True, op_point=point)
    assert list(linearizer.r) == [force]
    table = {s: values[s.name] for s in symbols}
    return (
        np.array(a.subs(table).evalf(), dtype=float),
        np.array(b.subs(table).evalf(), dtype=float),
    )


@pytest.mark.slow
@pytest.mark.parametrize(
    "angles",
    [(0, 0), (sympy.pi, 0), (0, sympy.pi), (sympy.pi, sympy.pi)],
    ids=["down-down", "up-down", "down-up", "up-up"],
)
def test_double_pendulum_on_cart_matches_sympy_mechanics(angles, rng):
    values = {name: rng.uniform(0.5, 2.0) for name in ("M", "m1", "m2", "l1", "l2")}
    values["g"] = 9.81
    linear = state_space(double_pendulum_on_cart(), {"theta1": angles[0], "theta2": angles[1]})
    ours = linear.numeric(values)
    a, b = mechanics_linearization(values, angles)
    assert ours.A.shape == (6, 6) and ours.B.shape == (6, 1)
    scale = np.abs(a).max()
    assert np.abs(ours.A - a).max() <= 1e-12 * scale
    assert np.abs(ours.B - b).max() <= 1e-12 * np.abs(b).max()


# -- finite differences of the compiled right-hand side --------------------------------
def finite_difference_matrices(system, state, params, inputs=(), step=1e-6):
    """A, B by central differences of the compiled rhs (inputs are parameters there)."""
    compiled = compile_equations(system.equations_of_motion())
    names = compiled.parameter_names

    def rhs(y, p):
        return np.asarray(compiled.rhs(0.0, y, compiled.parameter_vector(p)), dtype=float)

    state = np.asarray(state, dtype=float)
    a = np.empty((state.size, state.size))
    for j in range(state.size):
        e = np.zeros(state.size)
        e[j] = step
        a[:, j] = (rhs(state + e, params) - rhs(state - e, params)) / (2 * step)
    b = np.empty((state.size, len(inputs)))
    for k, name in enumerate(inputs):
        assert name in names
        up, down = dict(params), dict(params)
        up[name] = params.get(name, 0.0) + step
        down[name] = params.get(name, 0.0) - step
        b[:, k] = (rhs(state, up) - rhs(state, down)) / (2 * step)
    return a, b


@pytest.mark.parametrize(
    ("model", "point", "state"),
    [
        (CART_POLE, {"theta": 0}, [0.7, 0.0, 0.0, 0.0]),
        (CART_POLE, {"theta": sympy.pi}, [-0.3, math.pi, 0.0, 0.0]),
        (DOUBLE_PENDULUM_ON_CART, {"theta1": sympy.pi, "theta2": 0}, [0.2, math.pi, 0, 0, 0, 0]),
    ],
)
def test_a_and_b_are_the_derivatives_of_our_rhs(model, point, state):
    system = loaded(model)
    linear = system.state_space(at=point)
    params = dict(system.parameter_values)
    a, b = finite_difference_matrices(system, state, params, inputs=("F",))
    numbers = linear.numeric()
    assert np.allclose(numbers.A, a, rtol=1e-7, atol=1e-7 * np.abs(a).max())
    assert np.allclose(numbers.B, b, rtol=1e-7, atol=1e-7 * np.abs(b).max())


def test_steady_conical_motion_of_the_spherical_pendulum():
    """About theta0 with phi_dot0^2 = g/(l cos theta0): A is the derivative of our rhs, and
    its non-zero eigenvalues are +-i omega with omega^2 = phi_dot0^2 (1 + 3 cos^2 theta0)."""
    system = lg.load("spherical_pendulum")
    g, length = system.parameter_values["g"], system.parameter_values["l"]
    theta0 = 0.6
    rate = math.sqrt(g / (length * math.cos(theta0)))
    linear = system.state_space(at={"theta": theta0, "phi_dot": rate})
    assert linear.states == ("theta", "phi", "theta_dot", "phi_dot")
    numbers = linear.numeric()
    a, _ = finite_difference_matrices(
        system, [theta0, 0.4, 0.0, rate], dict(system.parameter_values)
    )
    assert np.allclose(numbers.A, a, rtol=1e-7, atol=1e-7 * np.abs(a).max())
    eigenvalues = np.linalg.eigvals(numbers.A)
    omega_squared = rate**2 * (1 + 3 * math.cos(theta0) ** 2)
    oscillating = sorted(eigenvalues, key=abs)[-2:]
    assert [abs(e.real) for e in oscillating] == pytest.approx([0, 0], abs=1e-9)
    assert [e.imag**2 for e in oscillating] == pytest.approx([omega_squared] * 2, rel=1e-10)


def test_an_equilibrium_held_by_a_nominal_input():
    """A pendulum held at theta0 by the torque tau0 = m g l sin(theta0): theta'' =
    (tau - m g l sin(theta))/(m l^2), so A = [[0, 1], [-g cos(theta0)/l, 0]], B = [0, 1/(m l^2)]."""
    system = lg.System.from_particles(
        ["theta"],
        [lg.Particle("bob", "m", ("l*sin(theta)", "-l*cos(theta)"))],
        gravity=lg.Gravity("g"),
        parameters={"m": 1.5, "l": 0.7, "g": 9.81},
        inputs={"tau": "theta"},
    )
    linear = system.state_space(at={"theta": "1/2", "tau": "m*g*l*sin(1/2)"})
    m_, l_, g_ = (system.symbol(n) for n in ("m", "l", "g"))
    expected_a = sympy.Matrix([[0, 1], [-g_ * sympy.cos(sympy.Rational(1, 2)) / l_, 0]])
    assert same_matrix(linear.A, expected_a, system)
    assert same_matrix(linear.B, sympy.Matrix([0, 1 / (m_ * l_**2)]), system)
    tau0 = 1.5 * 9.81 * 0.7 * math.sin(0.5)
    params = dict(system.parameter_values) | {"tau": tau0}
    a, b = finite_difference_matrices(system, [0.5, 0.0], params, inputs=("tau",))
    numbers = linear.numeric()
    assert np.allclose(numbers.A, a, rtol=1e-7) and np.allclose(numbers.B, b, rtol=1e-7)
    with pytest.raises(lg.ModelError, match="not an equilibrium"):
        system.state_space(at={"theta": "1/2"})  # without the torque it falls


def test_text_and_latex_of_the_matrices():
    from lagrangian.output.state_space import format_state_space, latex_state_space

    linear = loaded(CART_POLE).state_space(at={"theta": 0}, outputs={"tip": "x + l*sin(theta)"})
    text = format_state_space(linear)
    assert "about θ = 0" in text and "x = (x, θ, ẋ, θ̇)" in text and "y = (tip)" in text
    rows = [" ".join(line.split()) for line in text.splitlines()]
    assert "[ 0 -g m/M 0 0 ]" in rows and "[ 1 l 0 0 ]" in rows
    latex = latex_state_space(linear)
    assert r"- \frac{g m}{M}" in latex and r"- \frac{1}{M l}" in latex
    assert latex.count("bmatrix") == 8
    assert linear._repr_latex_() == latex  # Jupyter shows the same


# -- python-control --------------------------------------------------------------------
def test_to_control_poles_of_the_upright_cart_pole():
    control = pytest.importorskip("control")
    system = loaded(CART_POLE)
    plant = system.state_space(at={"theta": 0}).to_control()
    assert isinstance(plant, control.StateSpace)
    rate = math.sqrt(1.1 * 9.81 / (1.0 * 0.5))  # sqrt((M + m) g / (M l))
    poles = sorted(plant.poles(), key=lambda p: p.real)
    assert [p.real for p in poles] == pytest.approx([-rate, 0, 0, rate], abs=1e-7)
    assert plant.ninputs == 1 and plant.noutputs == 4


def test_to_control_without_python_control_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "control", None)  # import control -> ImportError
    linear = loaded(CART_POLE).state_space(at={"theta": 0})
    with pytest.raises(lg.MissingDependencyError, match=r"needs python-control: pip install"):
        linear.to_control()


# -- errors ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("at", "options", "message"),
    [
        ({"theta": 0.3}, {}, r"not an equilibrium or steady motion: q'' = "),
        ({"thet": 0}, {}, r"'thet' is not a coordinate, velocity, input or parameter"),
        ({"theta": 0, "theta_dot": 1}, {}, r"not a steady motion: theta moves"),
        ({"x": 1}, {}, r"the point must give theta"),
        ({"theta": 0}, {"inputs": ["G"]}, r"'G' is not an input \(inputs: F\)"),
        ({"theta": 0}, {"outputs": {"y": "x +"}}, r"outputs.y: "),
        ({"theta": 0}, {"outputs": ["tip"]}, r"'tip' is not a coordinate or velocity"),
        ({"theta": "pi/"}, {}, r"at.theta: "),
    ],
)
def test_bad_points_and_outputs_are_one_line_errors(at, options, message):
    system = loaded(CART_POLE)
    with pytest.raises(lg.ModelError, match=message) as caught:
        system.state_space(at=at, **options)
    assert "\n" not in str(caught.value)


def test_constrained_systems_are_refused():
    system = lg.load("rolling_disc")
    with pytest.raises(lg.ModelError, match="with constraints is not supported"):
        system.state_space(at={})


@pytest.mark.slow
def test_analyze_state_space_json_and_errors(capsys, tmp_path):
    model = tmp_path / "cart_pole.toml"
    model.write_text(CART_POLE)
    status = main(["analyze", str(model), "--state-space", "--at", "theta=pi", "--json"])
    document = json.loads(capsys.readouterr().out)
    assert status == 0
    section = document["state_space"]
    assert section["states"] == ["x", "theta", "x_dot", "theta_dot"]
    assert section["inputs"] == ["F"]
    assert section["point"] == {"theta": "pi"}
    assert section["B"] == [["0"], ["0"], ["1/M"], ["1/(M*l)"]]
    assert section["numeric"]["B"] == [[0.0], [0.0], [1.0], [2.0]]
    assert "equilibria" in document  # additive: the analysis is all there
    status = main(["analyze", str(model), "--state-space", "--at", "theta=0.3"])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and "not an equilibrium" in err
    status = main(["analyze", str(model), "--at", "theta=0"])
    err = capsys.readouterr().err
    assert status == 2 and "--at and --output go with --state-space" in err
