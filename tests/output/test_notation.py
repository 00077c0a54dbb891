"""Textbook notation in text and LaTeX."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian.output import latex_expression, unicode_expression
from lagrangian.output.notation import latex_name, unicode_name


@pytest.mark.parametrize(
    "name, text, latex",
    [
        ("theta", "θ", r"\theta"),
        ("theta_dot", "θ̇", r"\dot{\theta}"),
        ("theta_ddot", "θ̈", r"\ddot{\theta}"),
        ("theta1_dot", "θ̇₁", r"\dot{\theta}_{1}"),
        ("x_dot", "ẋ", r"\dot{x}"),
        ("omega", "ω", r"\omega"),
    ],
)
def test_names(name, text, latex):
    assert unicode_name(name) == text
    assert latex_name(name) == latex


def test_one_line_text_reads_like_a_textbook():
    theta, theta_dot, theta_ddot, m, l, g = sympy.symbols("theta theta_dot theta_ddot m l g")
    expr = (
        m * l**2 * theta_ddot + m * g * l * sympy.sin(theta) + theta_dot**2 * sympy.sin(theta) ** 2
    )
    text = unicode_expression(expr)
    assert text.startswith("l² m θ̈")  # accelerations first
    assert "sin²(θ)" in text or "sin²θ" in text
    assert "*" not in text and "**" not in text


def test_declared_functions_print_by_name():
    system = lg.load("velocity_dependent_potential")
    eom = system.equations_of_motion()
    text = unicode_expression(eom.equations[0], system)
    assert "∂A/∂y" in text and "∂V/∂x" in text and "(x, y, z)" not in text
    latex = latex_expression(eom.equations[0], system)
    assert r"\frac{\partial A}{\partial y}" in latex


def test_jupyter_display():
    system = lg.load("simple_pendulum")
    assert system._repr_latex_().startswith("$L = ")
    assert r"\ddot{\theta}" in system.equations_of_motion()._repr_latex_()


@pytest.mark.slow
def test_closed_forms_too_long_to_read_are_named_not_printed():
    """The 5-link chain's q''_1 runs to thousands of operations: text and LaTeX say so
    (printing the 6-link's took 20 s and 2.8 MB); JSON keeps every closed form."""
    import json

    from derive.test_chain_pendulum import chain_pendulum
    from lagrangian.output import derive_document, format_equations, latex_equations

    eom = chain_pendulum(5).equations_of_motion()
    text, latex = format_equations(eom), latex_equations(eom)
    assert "θ̈₁: too long to print (more than 5,000 nodes); derive --json gives it" in text
    assert "θ̈₅ = " in text  # the last link's is short enough
    assert r"\ddot{\theta}_{1} &: \text{too long to print" in latex
    document = json.loads(json.dumps(derive_document(eom)))
    assert set(document["accelerations"]) == {f"theta{i}" for i in range(1, 6)}


@pytest.mark.parametrize(
    "name, latex",
    [
        ("mechanical_energy", r"\mathrm{mechanical\_energy}"),  # was \mathcal{mechani}_{energy}
        ("angular_momentum", r"\mathrm{angular\_momentum}"),
        ("lam", r"\mathrm{lam}"),
        ("lambda1", r"\lambda_{1}"),  # a Greek letter stays one
        ("k_spring", "k_{spring}"),  # a letter with a subscript stays one
        ("p_theta2", r"p_{\theta_{2}}"),  # the momentum of theta2: was p_{theta2}
        ("p_phi1", r"p_{\phi_{1}}"),
        ("p_theta", r"p_{\theta}"),
        ("p_x", "p_{x}"),
        ("k_12", "k_{12}"),
    ],
)
def test_a_name_that_begins_with_a_word_is_written_upright(name, latex):
    assert latex_name(name) == latex


def test_every_quantity_name_is_typeset_by_the_one_rule():
    from lagrangian.output.page_content import page_content

    # a bead on a turning wire: its mechanical energy is not conserved, h is
    document = page_content(lg.load("rotating_wire_bead")).document
    (section,) = [s for s in document["sections"] if s["title"] == "Conserved quantities"]
    latex = " ".join(item.get("latex", "") for item in section["items"])
    assert r"\mathrm{mechanical\_energy} = " in latex
    assert r"\mathcal" not in latex
