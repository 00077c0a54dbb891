"""The fixed-step schemes written once (lagrangian.codegen.steps), printed as Python and C."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lagrangian.codegen.c import CPrinter
from lagrangian.codegen.steps import (
    CStepPrinter,
    NumbaStepPrinter,
    elimination,
    scheme_program,
    workspace_layout,
)
from lagrangian.integrate import tableaus

METHODS = ["rk4", "midpoint", "stormer-verlet"]


def oscillator():
    """The fillers of L = q'^2/2 - q^2/2 (M = 1, force -q), as the generated ones fill."""

    def mass_force(t, y, p, matrix, force):
        matrix[0, 0], force[0] = 1.0, -y[0]

    def momenta(t, y, p, out):
        out[0] = y[1]

    def momenta_force(t, y, p, out, force):
        out[0], force[0] = y[1], -y[0]

    def mass(t, y, p, matrix):
        matrix[0, 0] = 1.0

    def jacobian(t, y, p, h, matrix):
        matrix[0, 0] = 1.0 + h * h / 4

    def gradient(t, y, p, out):
        out[0] = -y[0]

    def eliminate(matrix, rhs, out, offset, n):
        out[offset : offset + n] = np.linalg.solve(matrix, rhs)

    return {**locals(), "np": np, "math": math, "njit": lambda *a, **k: lambda f: f}


@pytest.mark.parametrize("method", METHODS)
def test_printed_python_steps_an_oscillator(method):
    program = scheme_program(method, 1, tableau=tableaus.RK4, stall=0.5)
    namespace = oscillator()
    printer = NumbaStepPrinter(1)  # our own printed text, no model text:
    exec(printer.function(elimination(1)) + "\n" + printer.scheme(program), namespace)
    name = program.name
    work = workspace_layout(program).allocated()
    y, h = np.array([1.0, 0.0]), 0.01
    counts = np.zeros(3, dtype=np.int64)
    namespace[f"{name}_init"](0.0, y, None, work, counts)
    for k in range(100):
        assert namespace[f"{name}_step"](k * h, h, y, None, work, 1e-14, 1e-10, 30, counts) == 0
    evaluations = {"rk4": 400, "stormer-verlet": 101}  # the midpoint's depend on its iterations
    assert counts[0] == evaluations.get(method, counts[0]) > 100
    tolerance = 1e-9 if method == "rk4" else 1e-4
    np.testing.assert_allclose(y, [math.cos(1.0), -math.sin(1.0)], atol=tolerance)
    energy = (y[0] ** 2 + y[1] ** 2) / 2
    assert abs(energy - 0.5) < (1e-9 if method == "rk4" else 1e-4)


@pytest.mark.parametrize("method", METHODS)
def test_c_text_has_the_kernel_interface(method):
    program = scheme_program(method, 2, tableau=tableaus.RK4, stall=0.5)
    text = CStepPrinter(2, CPrinter("float32")).scheme(program)
    assert "typedef struct" in text and "lg_state;" in text
    assert "void lg_init(lg_state *state" in text and "int lg_step(lg_state *state" in text
    assert "double" not in text and "floor" not in text.replace("rounding_floor", "")
