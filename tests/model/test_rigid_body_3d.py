"""3-D rigid bodies: the rotation kinematics, the equivalent ways to give a body, and errors.

Independent references: rotation matrices typed from SymPy's ``rot_axis1/2/3``
(passive, so transposed here), the body-frame angular velocity as the axial
vector of R^T dR/dt evaluated numerically, and hand-typed kinetic energies.
"""

from __future__ import annotations

import functools
import random
import textwrap

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.derive.fast import derive_large
from lagrangian.errors import ModelError
from lagrangian.model.rotation import CONVENTIONS, euler_matrix, euler_rate_matrix

ACTIVE = {
    "x": lambda a: sympy.rot_axis1(a).T,
    "y": lambda a: sympy.rot_axis2(a).T,
    "z": lambda a: sympy.rot_axis3(a).T,
}

TOP = """
name = "Heavy symmetric top"
coordinates = ["phi", "theta", "psi"]

[parameters]
M = 1.0
l = 0.5
g = 9.81
I1 = 0.1
I3 = 0.05

[[bodies]]
name = "top"
mass = "M"
position = ["l*sin(theta)*sin(phi)", "-l*sin(theta)*cos(phi)", "l*cos(theta)"]
inertia = ["I1", "I1", "I3"]
{orientation}

[gravity]
g = "g"
"""
EULER = 'orientation = {euler = ["phi", "theta", "psi"], convention = "zxz"}'


@functools.cache
def euler_top() -> lg.System:
    """The top in zxz Euler angles, loaded once: two tests compare its (immutable, kept)
    derivation with another route's."""
    return lg.loads(TOP.format(orientation=EULER))


def numbers(expr, point):
    """``expr`` at ``point`` ({name: value}), by name."""
    return float(expr.xreplace({s: point[s.name] for s in expr.free_symbols}))


def random_state(system, rng, *, angle=(0.3, 2.8)):
    point = {p.name: p.default for p in system.parameters}
    for c in system.coordinates:
        point[c.name] = rng.uniform(*angle)
        point[c.q_dot.name] = rng.uniform(-2, 2)
    point["t"] = rng.uniform(0, 1)
    return point


def accelerations(compiled, point):
    """q'' of the compiled equations at ``point`` ({name: value})."""
    names = compiled.coordinate_names
    y = np.array([point[n] for n in names] + [point[f"{n}_dot"] for n in names])
    params = compiled.parameter_vector(
        {k: v for k, v in point.items() if k in compiled.parameter_names}
    )
    return compiled.rhs(point.get("t", 0.0), y, params)[len(names) :]


@pytest.mark.parametrize("convention", sorted(CONVENTIONS))
def test_euler_rates_equal_the_axial_vector_of_Rt_Rdot(convention):
    t = sympy.Symbol("t")
    angles = [sympy.Function(f"a{k}")(t) for k in range(3)]
    reference = sympy.eye(3)
    for axis, angle in zip(convention, angles, strict=True):
        reference = reference * ACTIVE[axis](angle)
    omega = reference.T * reference.diff(t)
    axial = sympy.Matrix([omega[2, 1], omega[0, 2], omega[1, 0]])
    values = sympy.symbols("x0:3")
    rates = sympy.symbols("v0:3")
    replacements = {a.diff(t): v for a, v in zip(angles, rates, strict=True)}
    replacements.update(dict(zip(angles, values, strict=True)))
    axial = axial.subs(replacements)
    ours = euler_rate_matrix(values, convention) * sympy.Matrix(rates)
    matrix = euler_matrix(values, convention)
    rng = random.Random(sorted(CONVENTIONS).index(convention))
    for _ in range(3):
        point = {s: rng.uniform(-3, 3) for s in (*values, *rates)}
        assert np.allclose(
            np.array(axial.xreplace(point), float),
            np.array(ours.xreplace(point), float),
            atol=1e-12,
        )
        expected = reference.subs(dict(zip(angles, values, strict=True))).xreplace(point)
        assert np.allclose(np.array(matrix.xreplace(point), float), np.array(expected, float))


@pytest.mark.slow
def test_rotation_matrix_form_gives_the_euler_form():
    phi, theta, psi = sympy.symbols("phi theta psi")
    matrix = ACTIVE["z"](phi) * ACTIVE["x"](theta) * ACTIVE["z"](psi)
    rows = ", ".join("[" + ", ".join(f'"{x}"' for x in matrix.row(j)) + "]" for j in range(3))
    by_matrix = lg.loads(TOP.format(orientation=f"orientation = {{rotation = [{rows}]}}"))
    by_euler = euler_top()
    matrix_form, euler_form = (
        lg.compile_equations(system.equations_of_motion()) for system in (by_matrix, by_euler)
    )
    rng = random.Random(7)
    for _ in range(4):
        point = random_state(by_euler, rng)
        assert numbers(by_matrix.lagrangian, point) == pytest.approx(
            numbers(by_euler.lagrangian, point), rel=1e-12
        )
        assert np.allclose(accelerations(matrix_form, point), accelerations(euler_form, point))


@pytest.mark.slow
def test_full_tensor_equals_principal_moments_in_the_rotated_frame():
    """Tensor Q D Q^T with orientation R equals moments D with orientation R Q."""
    q = sympy.Matrix([[3, -4, 0], [4, 3, 0], [0, 0, 5]]) / 5  # a rotation about z
    d = sympy.diag(*sympy.symbols("A B C", positive=True))
    phi, theta, psi = sympy.symbols("phi theta psi", real=True)
    r = ACTIVE["z"](phi) * ACTIVE["x"](theta) * ACTIVE["z"](psi)
    position = ("x", "y", "z")
    tensor = q * d * q.T
    coordinates = ["x", "y", "z", "phi", "theta", "psi"]
    values = {"A": 1.0, "B": 1.5, "C": 2.0, "m": 2.0}
    full = lg.System.from_particles(
        coordinates,
        bodies=[
            lg.RigidBody(
                "b",
                "m",
                position,
                tuple(tuple(tensor.row(j)) for j in range(3)),
                euler=("phi", "theta", "psi"),
                convention="zxz",
            )
        ],
        parameters=values,
    )
    rotated = r * q
    principal = lg.System.from_particles(
        coordinates,
        bodies=[
            lg.RigidBody(
                "b",
                "m",
                position,
                ("A", "B", "C"),
                rotation=tuple(tuple(rotated.row(j)) for j in range(3)),
            )
        ],
        parameters=values,
    )
    rng = random.Random(11)
    for _ in range(4):
        point = random_state(full, rng)
        assert numbers(full.lagrangian, point) == pytest.approx(
            numbers(principal.lagrangian, point), rel=1e-12
        )


def test_large_route_gives_the_readable_equations():
    system = euler_top()
    readable = system.equations_of_motion()
    large = derive_large(system)
    rng = random.Random(3)
    for _ in range(3):
        point = random_state(system, rng)
        for a, b in zip(readable.mass_matrix, large.mass_matrix, strict=True):
            assert numbers(a, point) == pytest.approx(numbers(b, point), rel=1e-12, abs=1e-12)
        for a, b in zip(readable.forcing, large.forcing, strict=True):
            assert numbers(a, point) == pytest.approx(numbers(b, point), rel=1e-12, abs=1e-12)


def test_two_tops_and_a_cart_take_the_large_route_with_the_textbook_energy():
    """7 coordinates: T is assembled on the SymEngine route; it must equal the hand-typed T."""
    body = """
[[bodies]]
mass = "M"
position = ["x + l*sin({b})*sin({a})", "-l*sin({b})*cos({a})", "l*cos({b})"]
inertia = ["I1", "I1", "I3"]
orientation = {{euler = ["{a}", "{b}", "{c}"], convention = "zxz"}}
"""
    text = (
        textwrap.dedent("""
        coordinates = ["x", "a1", "b1", "c1", "a2", "b2", "c2"]
        [parameters]
        M = 1.0
        l = 0.5
        I1 = 0.1
        I3 = 0.05
    """)
        + body.format(a="a1", b="b1", c="c1")
        + body.format(a="a2", b="b2", c="c2")
    )
    system = lg.loads(text)
    s = system.symbols
    M, l, I1, I3, xd = s["M"], s["l"], s["I1"], s["I3"], s["x_dot"]
    expected = 0
    for k in "12":
        a, b = s[f"a{k}"], s[f"b{k}"]
        ad, bd, cd = s[f"a{k}_dot"], s[f"b{k}_dot"], s[f"c{k}_dot"]
        centre = sympy.Matrix(
            [xd + l * sympy.diff(sympy.sin(b) * sympy.sin(a), a) * ad
             + l * sympy.diff(sympy.sin(b) * sympy.sin(a), b) * bd,
             -l * (sympy.cos(b) * sympy.cos(a) * bd - sympy.sin(b) * sympy.sin(a) * ad),
             -l * sympy.sin(b) * bd]
        )  # fmt: skip
        expected += M * centre.dot(centre) / 2
        expected += I1 * (bd**2 + ad**2 * sympy.sin(b) ** 2) / 2
        expected += I3 * (cd + ad * sympy.cos(b)) ** 2 / 2
    rng = random.Random(5)
    for _ in range(3):
        point = random_state(system, rng)
        assert numbers(system.kinetic, point) == pytest.approx(numbers(expected, point), rel=1e-12)


BAD = [
    ('inertia = ["I1", "I3"]', "bodies[0].inertia", "3 principal moments"),
    ('inertia = [["I1", 0, 0], [0, "I1", 0]]', "bodies[0].inertia", "3 principal moments"),
    ("inertia = [1, -0.5, 1]", "bodies[0].inertia", "negative"),
    ("inertia = [0.1, 0.1, 0.5]", "bodies[0].inertia", "triangle inequality"),
    ("inertia = [[1, 0.2, 0], [0, 1, 0], [0, 0, 1]]", "bodies[0].inertia", "not symmetric"),
    ("inertia = [[1, 2, 0], [2, 1, 0], [0, 0, 1]]", "bodies[0].inertia", "negative principal"),
]


@pytest.mark.parametrize(("inertia", "field", "words"), BAD)
def test_unphysical_or_misshapen_inertia_is_refused(inertia, field, words):
    text = TOP.format(orientation=EULER).replace('inertia = ["I1", "I1", "I3"]', inertia)
    with pytest.raises(ModelError) as raised:
        lg.loads(text, source="top.toml")
    message = str(raised.value)
    assert message.startswith(f"top.toml: {field}") and words in message
    assert "\n" not in message


@pytest.mark.parametrize(
    ("orientation", "field", "words"),
    [
        ('orientation = {euler = ["phi", "theta", "psi"], convention = "zxy2"}',
         "bodies[0].orientation.convention", "unknown convention 'zxy2'"),
        ('orientation = {euler = ["phi", "theta"]}', "bodies[0].orientation.euler", "3 Euler"),
        ("orientation = {}", "bodies[0].orientation", "one of them"),
        ('orientation = {rotation = [["2", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]]}',
         "bodies[0].orientation.rotation", "not orthogonal"),
        ('orientation = {rotation = [["cos(theta)", "sin(theta)", "0"], '
         '["sin(theta)", "-cos(theta)", "0"], ["0", "0", "1"]]}',
         "bodies[0].orientation.rotation", "reflection"),
        ('orientation = {rotation = [["cos(theta)", "0"], ["0", "1"]]}',
         "bodies[0].orientation.rotation", "3 x 3"),
        ('orientation = {euler = ["phi", "theta", "psi_dot"]}',
         "bodies[0].orientation.euler[2]", "velocities"),
    ],
)  # fmt: skip
def test_bad_orientation_is_refused(orientation, field, words):
    with pytest.raises(ModelError) as raised:
        lg.loads(TOP.format(orientation=orientation), source="top.toml")
    message = str(raised.value)
    assert message.startswith(f"top.toml: {field}") and words in message


def test_a_3d_body_needs_three_components_and_cli_exits_2(tmp_path, capsys):
    text = (
        TOP.format(orientation=EULER)
        .replace('"l*cos(theta)"]', "]")
        .replace('"-l*sin(theta)*cos(phi)", ]', '"-l*sin(theta)*cos(phi)"]')
    )
    path = tmp_path / "top.toml"
    path.write_text(text)
    assert main(["derive", str(path)]) == ExitStatus.BAD_INPUT
    err = capsys.readouterr().err.strip()
    assert "bodies[0].position" in err and "expected 3 components" in err
    assert len(err.splitlines()) == 1


def test_a_body_in_python_with_springs_and_gravity_uses_its_centre():
    system = lg.System.from_particles(
        ["z", "phi", "theta", "psi"],
        bodies=[
            lg.RigidBody("b", "m", ("0", "0", "z"), ("A", "A", "C"), euler=("phi", "theta", "psi"))
        ],
        springs=[lg.Spring("k", ("b", (0, 0, 0)))],
        gravity=lg.Gravity("g"),
    )
    s = system.symbols
    assert (
        sympy.simplify(system.potential - (s["k"] * s["z"] ** 2 / 2 + s["m"] * s["g"] * s["z"]))
        == 0
    )


@pytest.mark.parametrize("form", ["euler", "rotation"])
def test_a_body_turned_at_a_given_rate_has_the_explicit_terms_of_T(form):
    """A disc forced to turn about the vertical at rate w (phi = w t), free to tilt and spin:
    T = I1 (theta'^2 + w^2 sin^2 theta)/2 + I3 (psi' + w cos theta)^2 / 2."""
    if form == "euler":
        orientation = {"euler": ("w*t", "theta", "psi"), "convention": "zxz"}
    else:
        phi, theta, psi = sympy.symbols("phi theta psi")
        matrix = ACTIVE["z"](phi) * ACTIVE["x"](theta) * ACTIVE["z"](psi)
        matrix = matrix.subs(phi, sympy.Symbol("w") * sympy.Symbol("t"))
        orientation = {"rotation": tuple(tuple(str(x) for x in matrix.row(j)) for j in range(3))}
    system = lg.System.from_particles(
        ["theta", "psi"],
        bodies=[lg.RigidBody("disc", "m", (0, 0, 0), ("I1", "I1", "I3"), **orientation)],
        parameters={"m": 1.0, "I1": 1.0, "I3": 1.5, "w": 2.0},
    )
    s = system.symbols
    theta, w = s["theta"], s["w"]
    expected = s["I1"] * (s["theta_dot"] ** 2 + w**2 * sympy.sin(theta) ** 2) / 2
    expected += s["I3"] * (s["psi_dot"] + w * sympy.cos(theta)) ** 2 / 2
    rng = random.Random(9)
    for _ in range(4):
        point = random_state(system, rng) | {"w": rng.uniform(0.5, 2)}
        assert numbers(system.kinetic, point) == pytest.approx(numbers(expected, point), rel=1e-12)


def test_a_rotation_matrix_without_a_finite_value_is_refused():
    nowhere = '["sqrt(-1 - theta^2)", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]'
    where = r"bodies\[0\]\.orientation\.rotation: the matrix has no finite value"
    with pytest.raises(ModelError, match=where):
        lg.loads(TOP.format(orientation=f"orientation = {{rotation = [{nowhere}]}}"))


@pytest.mark.parametrize(
    ("old", "new", "field", "words"),
    [
        ('inertia = ["I1", "I1", "I3"]', 'inertia = ["I1", "I1", "I3"]\ncenter = [0, 0]',
         "bodies[0].center", "unknown key"),
        ('inertia = ["I1", "I1", "I3"]', "", "bodies[0].inertia", "missing field"),
        ('inertia = ["I1", "I1", "I3"]', 'inertia = ["I1", "I1", true]', "bodies[0].inertia[2]",
         "expected an expression"),
        (EULER, "orientation = 5", "bodies[0].orientation", "expected a table"),
        (EULER, 'orientation = {euler = "phi"}', "bodies[0].orientation.euler", "expected a list"),
        (EULER, 'orientation = {euler = ["phi", "theta", "psi"], convention = 3}',
         "bodies[0].orientation.convention", "expected text"),
        (EULER, 'orientation = {euler = ["phi", "theta", "psi"], spin = 1}',
         "bodies[0].orientation.spin", "unknown key"),
        (EULER, 'orientation = {euler = ["phi", "theta", "psi"], rotation = [[1, 0, 0], '
         "[0, 1, 0], [0, 0, 1]]}", "bodies[0].orientation", "one of them"),
        ('mass = "M"', 'mass = "M*theta"', "bodies[0].mass", "not allowed"),
    ],
)  # fmt: skip
def test_malformed_3d_body_fields_name_the_field(old, new, field, words):
    text = TOP.format(orientation=EULER)
    assert text.count(old) == 1
    with pytest.raises(ModelError) as raised:
        lg.loads(text.replace(old, new), source="top.toml")
    message = str(raised.value)
    assert message.startswith(f"top.toml: {field}") and words in message, message
