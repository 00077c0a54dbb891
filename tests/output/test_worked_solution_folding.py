"""A worked solution's rows folded after MAX_ROW_LINES lines (output/worked_solution/
printing.py): the first lines, then how many terms are left out; the PDF still compiles
with nothing over the margin."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian.output.latex import top_level_terms
from lagrangian.output.worked_solution import report_text
from lagrangian.output.worked_solution.document import Display, Section, WorkedSolution, parts
from lagrangian.output.worked_solution.printing import MAX_ROW_LINES, Shower
from output.test_worked_solution_pdf import _clean, _pdflatex

TERMS = 300


def _long_row():
    """V = sum of k x^k/(k+1) for k = 1 .. 300, as the worked solution shows it."""
    system = lg.System.from_lagrangian("m*x_dot^2/2", ["x"])
    x = sympy.Symbol("x", real=True)
    potential = sympy.Add(*(k * x**k / (k + 1) for k in range(1, TERMS + 1)))
    return Shower(system).row("V", potential)


def test_a_long_sum_shows_its_first_lines_and_how_many_terms_are_left_out():
    row = _long_row()
    assert len(row.lines) == MAX_ROW_LINES
    *shown, said = row.lines
    count = sum(len(top_level_terms(line)) for line in shown)
    assert said == (
        rf"+ \cdots \quad \text{{({TERMS - count} more terms; the --json output gives them)}}"
    )
    assert 0 < count < TERMS


@pytest.mark.slow
def test_a_folded_row_compiles_without_lines_over_the_margin(tmp_path):
    display = Display((_long_row(),))
    solution = WorkedSolution("Long", "A long potential", (Section(parts("V"), (display,)),))
    (tmp_path / "long.tex").write_text(report_text(solution, "tex"), encoding="utf-8")
    _clean(_pdflatex(tmp_path, "long"))
