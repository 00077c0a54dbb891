"""What cannot be compiled or evaluated, and the exact messages that say so."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.numeric import BACKENDS, compile_equations

from .cases import DEFINITIONS, assert_arrays_close, compiled, equations


def charge():
    return equations("velocity_dependent_potential")


def test_unspecified_functions_without_definitions():
    with pytest.raises(lg.ModelError) as error:
        compile_equations(charge())
    assert str(error.value) == (
        "functions V(x, y, z), A(x, y, z), B(x, y, z), C(x, y, z) are unspecified: "
        "give a definition of each (definitions={NAME: EXPR})"
    )


def test_one_unspecified_function():
    definitions = {k: v for k, v in DEFINITIONS["velocity_dependent_potential"].items() if k != "A"}
    with pytest.raises(lg.ModelError) as error:
        compile_equations(charge(), definitions=definitions)
    assert str(error.value) == (
        "function A(x, y, z) is unspecified: give a definition (definitions={NAME: EXPR})"
    )


def test_definitions_as_lambdas_equal_definitions_as_text():
    x, y, z = sympy.symbols("x y z")
    lambdas = {
        "V": sympy.Lambda((x, y, z), x**2 / 2 + y * z + sympy.cos(z)),
        "A": sympy.Lambda((x, y, z), -y * z / 2 + sympy.sin(x * y)),
        "B": sympy.Lambda((x, y, z), x * z / 2 + sympy.exp(-(z**2))),
        "C": sympy.Lambda((x, y, z), x * y * z / 3 + sympy.cos(x)),
    }
    from_lambdas = compile_equations(charge(), definitions=lambdas)
    from_text = compiled("velocity_dependent_potential")
    assert set(from_lambdas.definitions) == {"V", "A", "B", "C"}
    y0 = np.array([0.3, -0.7, 1.1, 0.5, 0.2, -0.4])
    for function in ("rhs", "rhs_jacobian", "energy"):
        assert_arrays_close(
            getattr(from_lambdas, function)(0.0, y0, []),
            getattr(from_text, function)(0.0, y0, []),
            1e-14,
            function,
        )


@pytest.mark.parametrize(
    ("definitions", "message"),
    [
        (
            {"D": "x"},
            "definitions: 'D' is not a declared function (declared: V, A, B, C)",
        ),
        ({"A": "x +"}, "definitions.A: unexpected end of expression at position 4 in 'x +'"),
        ({"A": "x*w"}, "definitions.A: unknown symbol 'w' at position 3 in 'x*w'"),
        (
            {"A": "x*t"},
            "definitions.A: the definition depends on t but A(x, y, z) does not: "
            "declare t among its arguments in 'x*t'",
        ),
        ({"A": 3.0}, "definitions.A: expected text or a sympy.Lambda, got float"),
        (
            {"A": sympy.Lambda(sympy.Symbol("x"), sympy.Symbol("x"))},
            "definitions.A: A(x, y, z) takes 3 argument(s), the Lambda 1",
        ),
    ],
)
def test_bad_definitions(definitions, message):
    with pytest.raises(lg.ModelError) as error:
        compile_equations(charge(), definitions=definitions)
    assert str(error.value) == message


def test_definitions_may_use_parameters():
    system = lg.System.from_lagrangian(
        "m*x_dot^2/2 - U",
        coordinates=["x"],
        functions={"U": ["x"]},
        parameters={"m": 2.0, "k": 3.0},
    )
    result = compile_equations(system.equations_of_motion(), definitions={"U": "k*x^2/2"})
    params = result.parameter_vector()
    assert_arrays_close(result.rhs(0.0, [0.5, 0.0], params), [0.0, -3.0 * 0.5 / 2.0], 1e-15)


def test_missing_parameter_values_are_named():
    system = lg.System.from_lagrangian("m*x_dot^2/2 - k*x^2/2", coordinates=["x"])
    result = compile_equations(system.equations_of_motion())
    assert result.parameter_names == ("k", "m")
    assert dict(result.default_parameters) == {}
    with pytest.raises(lg.ModelError) as error:
        result.parameter_vector()
    assert (
        str(error.value) == "no value for parameter(s) k, m (give them with params={NAME: VALUE})"
    )
    with pytest.raises(lg.ModelError) as error:
        result.rhs(0.0, [1.0, 0.0], [2.0])
    assert str(error.value) == "expected 2 parameter values (k, m), got 1: no value for m"
    assert_arrays_close(
        result.rhs(0.0, [1.0, 0.0], result.parameter_vector({"k": 2.0, "m": 4.0})),
        [0.0, -0.5],
        1e-15,
    )


def test_parameters_in_model_order_with_defaults():
    result = compiled("double_pendulum")
    assert result.parameter_names == ("m1", "m2", "l1", "l2", "g")
    assert dict(result.default_parameters) == {
        "m1": 1.0,
        "m2": 1.0,
        "l1": 1.0,
        "l2": 1.0,
        "g": 9.81,
    }
    assert result.coordinate_names == ("theta1", "theta2")
    assert result.backend == "numpy"


def test_a_state_of_the_wrong_size():
    result = compiled("double_pendulum")
    with pytest.raises(ValueError, match=r"the state has 2n = 4 rows"):
        result.rhs(0.0, [0.1, 0.2], result.parameter_vector())


def test_unknown_backend():
    assert set(BACKENDS) == {"numpy", "jax"}
    with pytest.raises(lg.ModelError) as error:
        compile_equations(equations("simple_pendulum"), backend="torch")
    assert str(error.value) == "unknown backend 'torch' (backends: jax, llvm, numba, numpy)"


def test_jax_missing(monkeypatch):
    monkeypatch.setitem(sys.modules, "jax", None)  # import jax now raises ImportError
    monkeypatch.setitem(sys.modules, "jax.numpy", None)
    with pytest.raises(lg.MissingDependencyError) as error:
        compile_equations(equations("simple_pendulum"), backend="jax")
    assert str(error.value) == (
        "backend 'jax' needs JAX: pip install \".[jax]\" in a clone of lagrangian"
    )


@pytest.mark.slow
def test_numpy_backend_does_not_import_jax():
    import subprocess

    code = (
        "import sys, lagrangian as lg; from lagrangian.numeric import compile_equations; "
        "c = compile_equations(lg.load('simple_pendulum').equations_of_motion()); "
        "c.rhs(0.0, [0.1, 0.0], c.parameter_vector()); print('jax' in sys.modules)"
    )
    output = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert output.stdout.strip() == "False"
