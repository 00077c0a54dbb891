"""``check``: held-out student answers on systems that are not among the examples.

Each expected verdict, reason and term list below was worked out by hand from the
physics (T, V, L and Lagrange's equations of the bead on a rotating hoop, the spring
pendulum, a charge in a uniform magnetic field and the Atwood machine), not read off the
code: a right answer, each equivalence (a constant, a factor, a total time derivative,
a combination of equations) and each kind of error (missing, extra, factor, sign; an
equation with an error or not related).
"""

from __future__ import annotations

from pathlib import Path

import pytest
import sympy

import lagrangian as lg
from lagrangian.errors import ModelError

MODELS = Path(__file__).parent / "check_models"


def model(name: str) -> lg.System:
    return lg.load(MODELS / f"{name}.toml")


# (model, answers, verdict, reason, terms as (term, problem, expected))
CASES = [
    # -- bead on a hoop turning at omega about its vertical diameter
    ("rotating_hoop", {"kinetic": "m*R^2*(theta_dot^2 + omega^2*sin(theta)^2)/2"},
     "right", "right", []),
    ("rotating_hoop", {"kinetic": "m*R^2*theta_dot^2/2"}, "wrong",
     "the term R^2*m*omega^2*sin(theta)^2/2 is missing",
     [("R**2*m*omega**2*sin(theta)**2/2", "missing", "R**2*m*omega**2*sin(theta)**2/2")]),
    ("rotating_hoop", {"kinetic": "m*R^2*(theta_dot^2 + omega^2*sin(theta)^2)"}, "wrong",
     "the term R^2*m*theta_dot^2 should be R^2*m*theta_dot^2/2; the term "
     "R^2*m*omega^2*sin(theta)^2 should be R^2*m*omega^2*sin(theta)^2/2",
     [("R**2*m*theta_dot**2", "factor", "R**2*m*theta_dot**2/2"),
      ("R**2*m*omega**2*sin(theta)**2", "factor", "R**2*m*omega**2*sin(theta)**2/2")]),
    ("rotating_hoop",
     {"lagrangian": "m*R^2*(theta_dot^2 + omega^2*sin(theta)^2)/2 - m*g*R*cos(theta)"},
     "wrong", "the term -R*g*m*cos(theta) has the wrong sign: it should be R*g*m*cos(theta)",
     [("-R*g*m*cos(theta)", "sign", "R*g*m*cos(theta)")]),
    ("rotating_hoop",
     {"equations": ["R*theta_ddot = R*omega^2*sin(theta)*cos(theta) - g*sin(theta)"]},
     "right", "right: the equation of theta", []),
    ("rotating_hoop",
     {"equations": ["theta_ddot = omega^2*sin(theta)*cos(theta) - g/R*sin(theta)"]},
     "equivalent", "right up to a factor: the equation of theta times 1/(R^2*m)", []),
    ("rotating_hoop", {"equations": ["R*theta_ddot = R*omega^2*sin(theta) - g*sin(theta)"]},
     "wrong", "the equation of theta with errors (all terms on the left): the term "
     "(-R*omega^2 + g)*sin(theta) should be g*sin(theta); the term "
     "-R*omega^2*sin(theta)*cos(theta) is missing",
     [("(-R*omega**2 + g)*sin(theta)", "factor", "g*sin(theta)"),
      ("-R*omega**2*sin(theta)*cos(theta)", "missing", "-R*omega**2*sin(theta)*cos(theta)")]),
    ("rotating_hoop",
     {"hamiltonian": "p_theta^2/(2*m*R^2) - m*R^2*omega^2*sin(theta)^2/2 - m*g*R*cos(theta)"},
     "right", "right", []),
    ("rotating_hoop",  # the Jacobi integral, not T + V
     {"conserved": ["m*R^2*theta_dot^2/2 - m*R^2*omega^2*sin(theta)^2/2 - m*g*R*cos(theta)"]},
     "right", "right: its rate of change along every motion is 0", []),
    ("rotating_hoop",
     {"conserved": ["m*R^2*theta_dot^2/2 + m*R^2*omega^2*sin(theta)^2/2 - m*g*R*cos(theta)"]},
     "wrong", "not conserved: its rate of change along the motion is not 0; as energy: the "
     "term R^2*m*omega^2*sin(theta)^2/2 has the wrong sign: it should be "
     "-R^2*m*omega^2*sin(theta)^2/2",
     [("R**2*m*omega**2*sin(theta)**2/2", "sign", "-R**2*m*omega**2*sin(theta)**2/2")]),
    # -- pendulum on a spring
    ("spring_pendulum",  # twice the energy, without the spring: compared in its own scale
     {"conserved": ["m*(r_dot^2 + r^2*theta_dot^2) - 2*m*g*r*cos(theta)"]}, "wrong",
     "not conserved: its rate of change along the motion is not 0; as energy: the term k*r^2 "
     "is missing; the term -2*k*l0*r is missing",
     [("k*r**2", "missing", "k*r**2"), ("-2*k*l0*r", "missing", "-2*k*l0*r")]),
    ("spring_pendulum", {"conserved": ["m*r_dot^2"]}, "wrong",  # one term is no scale
     "not conserved: its rate of change along the motion is not 0", []),
    ("spring_pendulum", {"kinetic": "m*(r_dot^2 + r*theta_dot^2)/2"}, "wrong",
     "the term m*r^2*theta_dot^2/2 is missing; the term m*r*theta_dot^2/2 should not be there",
     [("m*r**2*theta_dot**2/2", "missing", "m*r**2*theta_dot**2/2"),
      ("m*r*theta_dot**2/2", "extra", None)]),
    ("spring_pendulum", {"potential": "k*(r-l0)^2/2 - m*g*r*cos(theta) + 7*m*g"},
     "equivalent", "right up to a constant (7*g*m), which changes no motion", []),
    ("spring_pendulum", {"potential": "k*r^2/2 - m*g*r*cos(theta)"}, "wrong",
     "the term -k*l0*r is missing", [("-k*l0*r", "missing", "-k*l0*r")]),
    ("spring_pendulum",
     {"lagrangian": r"\frac{1}{2} m (\dot{r}^2 + r^2 \dot{\theta}^2) + m g r \cos\theta"
                    r" - \frac{1}{2} k (r - l_0)^2"},
     "right", "right", []),
    ("spring_pendulum",
     {"equations": ["m*r_ddot = m*r*theta_dot^2 + m*g*cos(theta) - k*(r - l0)"]},
     "right", "right: the equation of r", []),
    ("spring_pendulum", {"equations": ["r*theta_ddot + 2*r_dot*theta_dot + g*sin(theta) = 0"]},
     "equivalent", "right up to a factor: the equation of theta times 1/(m*r)", []),
    ("spring_pendulum",
     {"equations": ["m*r_ddot - m*r*theta_dot^2 - m*g*cos(theta) + k*(r - l0)"
                    " + r^2*theta_ddot + 2*r*r_dot*theta_dot + g*r*sin(theta)"]},
     "equivalent", "right: a combination of the equations of r and theta", []),
    ("spring_pendulum", {"equations": ["r*theta_ddot + r_dot*theta_dot + g*sin(theta) = 0"]},
     "wrong", "the equation of theta with errors (all terms on the left): the term "
     "r_dot*theta_dot should be 2*r_dot*theta_dot",
     [("r_dot*theta_dot", "factor", "2*r_dot*theta_dot")]),
    ("spring_pendulum", {"equations": ["r_dot = r*theta_dot"]}, "wrong",
     "not related to the equations of motion (of r, theta)", []),
    # -- a charge in a uniform magnetic field (symmetric gauge in the model)
    ("magnetic_field", {"lagrangian": "m*(x_dot^2 + y_dot^2)/2 + e*B*x*y_dot"},  # Landau gauge
     "equivalent", "right up to a total time derivative: the same equations of motion", []),
    ("magnetic_field", {"lagrangian": "m*(x_dot^2 + y_dot^2) + e*B*(x*y_dot - y*x_dot)"},
     "equivalent", "right up to the constant factor 2: the same equations of motion", []),
    ("magnetic_field", {"lagrangian": "m*(x_dot^2 + y_dot^2)/2 - e*B*x*y_dot"}, "wrong",
     "the term -B*e*x*y_dot should be B*e*x*y_dot/2; the term -B*e*x_dot*y/2 is missing",
     [("-B*e*x*y_dot", "factor", "B*e*x*y_dot/2"),
      ("-B*e*x_dot*y/2", "missing", "-B*e*x_dot*y/2")]),
    ("magnetic_field", {"equations": ["m*x_ddot = e*B*x_dot"]}, "wrong",
     "the equation of x with errors (all terms on the left): the term -B*e*y_dot is "
     "missing; the term -B*e*x_dot should not be there",
     [("-B*e*y_dot", "missing", "-B*e*y_dot"), ("-B*e*x_dot", "extra", None)]),
    ("magnetic_field", {"kinetic": "m*(x_dot^2 + y_dot^2)/2"}, "right", "right", []),
    ("magnetic_field", {"momenta": {"p_y": "m*y_dot"}}, "wrong",
     "the term B*e*x/2 is missing", [("B*e*x/2", "missing", "B*e*x/2")]),
    ("magnetic_field", {"conserved": ["m*(x_dot^2 + y_dot^2)/2"]},
     "right", "right: its rate of change along every motion is 0", []),
    # -- Atwood machine, x the descent of m1
    ("atwood", {"equations": ["x_ddot = (m1 - m2)*g/(m1 + m2)"]}, "equivalent",
     "right up to a factor: the equation of x times 1/(m1 + m2)", []),
    ("atwood", {"equations": ["(m1 + m2)*x_ddot = (m1 + m2)*g"]}, "wrong",
     "the equation of x with errors (all terms on the left): the term -g*(m1 + m2) should "
     "be g*(-m1 + m2)", [("-g*(m1 + m2)", "factor", "g*(-m1 + m2)")]),
    ("atwood", {"potential": "m1*g*x - m2*g*x"}, "wrong",
     "the term g*x*(m1 - m2) has the wrong sign: it should be g*x*(-m1 + m2)",
     [("g*x*(m1 - m2)", "sign", "g*x*(-m1 + m2)")]),
    ("atwood", {"kinetic": "(m1 + m2)*x_dot^2/2 + (x_dot + g)^8"}, "wrong",  # kept whole
     "the term (g + x_dot)^8 should not be there", [("(g + x_dot)**8", "extra", None)]),
    ("atwood", {"kinetic": "m1*x_dot^2/2"}, "wrong",
     "the term m1*x_dot^2/2 should be x_dot^2*(m1 + m2)/2",
     [("m1*x_dot**2/2", "factor", "x_dot**2*(m1 + m2)/2")]),
]  # fmt: skip


@pytest.mark.parametrize(
    ("name", "answers", "verdict", "reason", "terms"),
    CASES,
    ids=[f"{c[0]}-{next(iter(c[1]))}-{i}" for i, c in enumerate(CASES)],
)
def test_held_out_answers(name, answers, verdict, reason, terms):
    result = model(name).check(**answers)
    assert (result.verdict, result.reason) == (verdict, reason)
    assert [(t.term, t.problem, t.expected) for t in result.terms] == terms
    for term in result.terms:  # the JSON contract: SymPy syntax, a known problem
        assert term.problem in ("missing", "extra", "factor", "sign")


def test_the_expected_terms_are_the_right_ones_in_the_model_names():
    # independent of the diagnosis: replacing each wrong or missing term by its expected
    # form (and dropping the extra ones) gives back the right kinetic energy
    system = model("spring_pendulum")
    given = "m*(r_dot^2 + r*theta_dot^2)/2"
    result = system.check(kinetic=given)
    names = dict(system.symbols)
    repaired = sympy.parse_expr(given.replace("^", "**"), local_dict=names)
    for term in result.terms:
        wrong = sympy.parse_expr(term.term, local_dict=names)
        right = sympy.parse_expr(term.expected or "0", local_dict=names)
        repaired += right - (0 if term.problem == "missing" else wrong)
    assert sympy.simplify(repaired - system.kinetic) == 0


def test_several_answers_and_the_document():
    result = model("atwood").check(
        kinetic="(m1 + m2)*x_dot^2/2", potential="(m2 - m1)*g*x", equations=["x_ddot = g"]
    )
    document = result.document()
    assert document["verdict"] == "wrong"
    assert [a["verdict"] for a in document["answers"]] == ["right", "right", "wrong"]
    assert document["reason"].startswith("kinetic: right; potential: right; equation: ")
    assert set(document) == {"verdict", "reason", "terms", "answers"}
    assert all(set(t) == {"term", "problem", "expected"} for t in document["terms"])


def test_sympy_answers_and_equations_as_equalities():
    system = model("atwood")
    x_ddot, m1, m2, g = (system.symbol(n) for n in ("x_ddot", "m1", "m2", "g"))
    equation = sympy.Eq((m1 + m2) * x_ddot, (m1 - m2) * g)
    assert system.check(equations=[equation]).verdict == "right"


@pytest.mark.parametrize(
    ("answers", "message"),
    [
        ({"kinetic": "m*l^2*thta_dot^2/2"},
         "kinetic: unknown symbol 'thta_dot' (did you mean 'theta_dot'?) at position 7 in "
         "'m*l^2*thta_dot^2/2'"),
        ({"potential": "m*g*(l"},
         "potential: expected ')' to close '(' at position 5, found end of expression at "
         "position 7 in 'm*g*(l'"),
        ({"equations": ["a = b = c"]},
         "equations 1: an equation is 'lhs = rhs' or one expression (= 0) in 'a = b = c'"),
        ({"momenta": {"p_x": "m*x_dot"}},
         "momenta: 'p_x' is not a momentum of the model (momenta: p_theta)"),
        ({"kinetic": "(theta_dot + l)^3*(m + g)^3*(theta + 1)^3*(l + m + g + theta)^6"},
         "kinetic: too many terms to compare one by one (2688 once multiplied out, at most 500)"),
        ({}, "nothing to check: give an answer (kinetic, potential, lagrangian, equations, "
             "hamiltonian, conserved or momenta)"),
    ],
)  # fmt: skip
def test_bad_answers_are_one_line_errors(answers, message):
    with pytest.raises(ModelError) as caught:
        lg.load("simple_pendulum").check(**answers)
    assert str(caught.value) == message
