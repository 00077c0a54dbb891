"""What the page's Poincaré section panel is given (lagrangian.output.page_section): the
interpolant's coefficients where a section of an energy shell makes sense, and why not
elsewhere.  The panel itself is checked in a browser: test_page_section_browser.py."""

from __future__ import annotations

import json
import re

import pytest

import lagrangian as lg
from lagrangian.output.page import page_html
from lagrangian.output.page_section import section_document

TWO_OSCILLATORS = """
name = "two oscillators"
coordinates = ["x", "y"]
kinetic = "(x_dot^2 + y_dot^2)/2"
potential = "{potential}"
"""


def test_an_autonomous_conservative_model_gets_the_dense_output_of_dop853():
    document = section_document(lg.load("henon_heiles"), constraints=0)
    assert document["available"] is True
    dense = document["dense"]
    # SciPy's DOP853 dense output: stages 14-16 (each on the 13 before it and those
    # added), at their nodes, and four rows D over all 16 stages
    assert [len(row) for row in dense["A"]] == [13, 14, 15]
    assert len(dense["C"]) == 3 and all(0 < c < 1 for c in dense["C"])
    assert [len(row) for row in dense["D"]] == [16] * 4


@pytest.mark.parametrize(
    ("system", "why"),
    [
        (lambda: lg.load("simple_pendulum"), "needs two coordinates or more: this model has one"),
        (
            lambda: lg.loads(TWO_OSCILLATORS.format(potential="(x^2 + y^2)/2 - x*cos(t)")),
            "the model depends on t",
        ),
        (lambda: lg.load("planar_particle_forces"), "forces or dissipation change the energy"),
    ],
)
def test_a_model_without_an_energy_shell_is_told_why(system, why):
    document = section_document(system(), constraints=0)
    assert document["available"] is False
    assert why in document["why"]


def test_the_page_carries_the_panels_document():
    html = page_html(lg.loads(TWO_OSCILLATORS.format(potential="(x^2 + 2*y^2)/2")))
    model = re.search(r'id="lagrangian-model">(.*?)</script>', html, re.S).group(1)
    assert json.loads(model)["section"]["available"] is True
    assert "function lagrangianSection(" in html
