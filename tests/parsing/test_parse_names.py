"""referenced_names (no namespace needed) and the validation of Namespace."""

from __future__ import annotations

import pytest
import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing import (
    RESERVED_NAMES,
    DeclaredFunction,
    Namespace,
    ReferencedNames,
    parse_expression,
    referenced_names,
)


def names(symbols: str, functions: str = "") -> ReferencedNames:
    return ReferencedNames(frozenset(symbols.split()), frozenset(functions.split()))


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("m*g*y + V(x) + pi", names("m g y x", "V")),
        ("sin(theta) + E**k", names("theta k")),
        ("A + A(x, y, z)", names("A x y z", "A")),
        ("atan2(y, x)", names("y x")),
        ("1 + 2", names("")),
        ("θ̇**2", names("theta_dot")),
        (
            r"\frac{1}{2} m l^{2} \dot{\theta}^{2} + m g l \cos\theta",
            names("m l theta_dot g theta"),
        ),
        (r"\frac{1}{2} m \dot{\theta}_1^2", names("m theta1_dot")),
        ("m(a + b)", names("a b", "m")),  # plain text: a call
        (r"m(a + b)\,", names("m a b")),  # LaTeX: one argument in parentheses is a product
        (r"\pi(a) + W(a, b)\,", names("a b", "W")),
        (r"\sqrt[n]{x}", names("n x")),
    ],
)
def test_referenced_names(text, expected):
    assert referenced_names(text) == expected


@pytest.mark.parametrize("text", ["x +", "2x", "x[0]", "sin", "sin(x, y)", r"\foo", "__x", ""])
def test_invalid_syntax_raises(text):
    with pytest.raises(ParseError):
        referenced_names(text)


def test_limits_apply():
    with pytest.raises(ParseError):
        referenced_names("(" * 100 + "x" + ")" * 100)
    with pytest.raises(ParseError):
        referenced_names("x" * 20_001)


def test_names_are_found_without_building_anything():
    # an unknown name and a huge number are fine here: nothing is evaluated
    assert referenced_names("unknown * 9**9**9**9") == names("unknown")


def test_declared_names_discovered_then_parsed():
    text = "k*x**2/2 + V(x) + c"
    found = referenced_names(text)
    symbols = {name: sympy.Symbol(name, real=True) for name in found.symbols}
    functions = {
        name: DeclaredFunction(sympy.Function(name), (symbols["x"],)) for name in found.functions
    }
    expression = parse_expression(text, Namespace(symbols, functions))
    assert expression.free_symbols == set(symbols.values())


class TestNamespace:
    def test_is_read_only(self):
        x = sympy.Symbol("x")
        source = {"x": x}
        namespace = Namespace(source)
        source["y"] = sympy.Symbol("y")
        assert "y" not in namespace.symbols
        with pytest.raises(TypeError):
            namespace.symbols["z"] = x  # type: ignore[index]
        assert dict(namespace.functions) == {}

    @pytest.mark.parametrize("name", sorted(RESERVED_NAMES))
    def test_refuses_reserved_names(self, name):
        with pytest.raises(ValueError, match="built-in"):
            Namespace({name: sympy.Symbol(name)})

    @pytest.mark.parametrize("name", ["_x", "1x", "x y", "x.y", "", "θ", "x\n"])
    def test_refuses_invalid_names(self, name):
        with pytest.raises(ValueError, match="not a valid name"):
            Namespace({name: sympy.Symbol("x")})

    def test_a_name_in_both_is_the_function(self):
        x = sympy.Symbol("x")
        f = sympy.Function("f")
        namespace = Namespace({"f": f(x), "x": x}, {"f": DeclaredFunction(f, (x,))})
        assert parse_expression("f + f(2*x)", namespace) == f(x) + f(2 * x)
        with pytest.raises(ParseError, match="takes 1 argument"):
            parse_expression("f(x, x)", namespace)

    def test_refuses_values_that_are_not_expressions(self):
        with pytest.raises(TypeError):
            Namespace({"x": 1})  # type: ignore[dict-item]
        with pytest.raises(TypeError):
            Namespace({"x": "x"})  # type: ignore[dict-item]
        with pytest.raises(TypeError):
            Namespace({}, {"f": sympy.Function("f")})  # type: ignore[dict-item]

    def test_declared_function_checks_its_parts(self):
        with pytest.raises(TypeError):
            DeclaredFunction(sympy.sin, (sympy.Symbol("x"),))  # type: ignore[arg-type]
        with pytest.raises(TypeError):
            DeclaredFunction(sympy.Function("f"), ("x",))  # type: ignore[arg-type]
        declared = DeclaredFunction(sympy.Function("f"), [sympy.Symbol("x")])  # type: ignore[arg-type]
        assert declared.arguments == (sympy.Symbol("x"),)
