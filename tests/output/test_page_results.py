"""The equilibria of a page as data (lagrangian.output.page_results): formulas that
KaTeX can break across lines, and the column of expressions whose numbers the page
shows, checked against the analysis' own numbers at the parameter values."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis import analyze
from lagrangian.output.analysis import modes_at_values
from lagrangian.output.page_results import breakable_latex, results_section


def test_a_product_with_a_long_sum_is_written_with_plain_parentheses():
    g, l, m, a, b = sympy.symbols("g l m a b", positive=True)
    expr = -g * (a + sympy.sqrt(b) - 2 * m) / (2 * l * m)
    latex = breakable_latex(expr, sympy.latex)
    assert latex == r"-\dfrac{g}{2 l m}\,(a + \sqrt{b} - 2 m)"
    assert r"\left(" not in latex  # KaTeX never breaks inside \left( \right)


def test_a_sum_and_a_monomial_are_written_as_they_are_with_display_fractions():
    x, y = sympy.symbols("x y")
    assert breakable_latex(x + y / 2, sympy.latex) == r"x + \dfrac{y}{2}"
    assert breakable_latex(-x / y, sympy.latex) == r"- \dfrac{x}{y}"


@pytest.mark.slow  # the double pendulum's analysis
def test_the_evaluated_column_gives_the_analysis_numbers():
    system = lg.load("double_pendulum")
    eom = system.equations_of_motion()
    analysis = analyze(eom, stages=("equilibria", "modes"))
    symbols = {p.name: p.symbol for p in system.parameters}
    section, expressions = results_section(analysis, sympy.latex, symbols)
    at = {p.symbol: p.default for p in system.parameters}
    blocks = [item["equilibrium"] for item in section["items"] if "equilibrium" in item]
    assert len(blocks) == len(analysis.equilibria) == 4
    for block, e in zip(blocks, analysis.equilibria, strict=True):
        expected = modes_at_values(e.modes, system)["omega_squared"]
        shown = [float(expressions[m["value"]["x"]].xreplace(at)) for m in block["modes"]]
        assert shown == pytest.approx(expected, rel=1e-12)
        assert block["depends"] is True  # stable or not, at the values of the moment
    # each point of the double pendulum is a number: nothing to evaluate there
    assert all("number" in p["value"] for b in blocks for p in b["point"])


def test_the_numbers_routine_is_printed_or_left_out_whole():
    from lagrangian.codegen import program
    from lagrangian.derive import derive
    from lagrangian.output.page_results import results_script

    system = lg.load("harmonic_oscillator")
    k, m = system.symbol("k"), system.symbol("m")
    code = program(derive(system))
    script = results_script(code, [k / m])
    assert script.startswith("\nfunction results(t, y, params = DEFAULT_PARAMS, u = null) {")
    assert "const X = [[p_k/p_m]];" in script
    # a function JavaScript has not (SymPy's strict printer refuses it): no routine, and
    # the page shows the symbolic forms; it is not a page that fails to be written
    assert results_script(code, [k / m, sympy.gamma(k)]) == ""
    assert results_script(code, []) == ""
