import numpy as np
import sympy

from lagrangian.pointwise import evaluate

x, y = sympy.symbols("x y", real=True)
f = sympy.Function("f")


def test_a_matrix_at_a_point_equals_sympys_value():
    matrix = sympy.Matrix([[sympy.sin(x) * y, sympy.atan2(x, 1)], [sympy.pi * x, sympy.E**y]])
    point = {x: -0.7, y: 1.3}
    expected = np.array(matrix.subs(point).evalf(), dtype=float)
    np.testing.assert_allclose(evaluate(matrix, point), expected, rtol=1e-15)


def test_overflow_is_no_value_instead_of_a_hang():
    tower = sympy.exp(sympy.exp(sympy.exp(sympy.exp(sympy.exp(x)))))
    assert evaluate(tower, {x: 1.0}) is None
    assert evaluate(sympy.Matrix([[tower, 1]]), {x: 1.0}) is None


def test_complex_undefined_and_missing_values_are_none():
    assert evaluate(sympy.sqrt(x - 2), {x: 1.0}) is None
    assert evaluate(1 / x, {x: 0.0}) is None
    assert evaluate(x * y, {x: 1.0}) is None
    assert float(evaluate(sympy.sqrt(x - 2), {x: 3.0})) == 1.0


def test_function_values_replace_whole_subexpressions():
    # f(x) must not be replaced inside Derivative(f(x), x), which would make it 0
    expr = f(x) ** 2 + 3 * sympy.Derivative(f(x), x) + sympy.DiracDelta(x)
    value = evaluate(expr, {f(x): 2.0, sympy.Derivative(f(x), x): 5.0, x: 0.5})
    assert float(value) == 19.0


def test_surely_nonzero_is_quick_and_never_wrong_about_identities():
    from lagrangian.pointwise import surely_nonzero

    m = sympy.Symbol("m", positive=True)
    n = sympy.Symbol("n", negative=True)
    assert surely_nonzero(sympy.sin(x) + 1)
    big = sympy.Integer(10**9)
    assert surely_nonzero(big * sympy.sin(x) - big * sympy.cos(x) * sympy.Rational(1, 10**6))
    for identity in (
        sympy.sin(x) ** 2 + sympy.cos(x) ** 2 - 1,
        sympy.sqrt(m**2) - m + 0 * x,
        sympy.Abs(n) + n + 0 * x,
        10**12 * sympy.cos(x) ** 2 - 10**12 * (1 - sympy.sin(x) ** 2),
        sympy.Float(2.5) * x,  # floats are not converted: no claim
        f(x) - f(x) + sympy.Derivative(f(x), x),  # not decidable here: no claim
    ):
        assert not surely_nonzero(identity)
