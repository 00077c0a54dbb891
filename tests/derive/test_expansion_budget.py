"""Expansions too large to make are refused before they start (issue 37, item 2).

SymEngine's expand runs in C++, where no deadline reaches: (q0' + ... + q19')^20 / 2,
156 characters, ran for 200 s and 6.8 GB and growing against a budget of 60 s.  The
number of terms an expansion makes is counted first (:func:`sizes.expanded_terms`,
checked here against SymPy's own expansion), and every place that hands SymEngine an
expansion asks it: the large route of derivation, and the angle rule of ``tidy`` and of
the kinetic energy's assembly.
"""

from __future__ import annotations

import importlib
import math

import pytest
import sympy

import lagrangian as lg
from lagrangian import algebra
from lagrangian.errors import ModelError
from lagrangian.sizes import MAX_EXPANDED_TERMS, expanded_terms

fast = importlib.import_module("lagrangian.derive.fast")  # lagrangian.derive is a function
term_tables = importlib.import_module("lagrangian.derive.term_tables")


def _limit(monkeypatch, terms: int) -> None:
    """MAX_EXPANDED_TERMS lowered where the large route reads it: L's count and the tables'."""
    monkeypatch.setattr(fast, "MAX_EXPANDED_TERMS", terms)
    monkeypatch.setattr(term_tables, "MAX_EXPANDED_TERMS", terms)


x, y, z, w = sympy.symbols("x y z w")
VELOCITIES = sympy.symbols("q0:20")


def _terms(expr) -> int:
    return len(sympy.Add.make_args(sympy.expand(expr)))


@pytest.mark.parametrize(
    "expr",
    [
        (x + y + z) ** 4,
        (x + y) ** 2 * (x + z) ** 3,
        (x + 2) * (y + 3) * (z + w),
        x**5 * (y + z),
        (x + y) ** sympy.Rational(5, 2),  # SymPy expands the whole part of the power
        sympy.Add(*VELOCITIES[:6]) ** 3 / 2 + x,
    ],
    ids=str,
)
def test_the_count_is_exact_where_no_terms_combine(expr):
    assert expanded_terms(expr) == _terms(expr)


@pytest.mark.parametrize(
    "expr",
    [
        (x + y) * (x - y),  # x^2 - y^2: two of the four combine
        sympy.sin((x + y + z) ** 4) + (x + y) ** -3,  # expanded inside: counted, one term each
        ((x + y) ** 2 + z) ** 3,
    ],
    ids=str,
)
def test_the_count_bounds_every_expansion_made_on_the_way(expr):
    inner = [_terms(a) for a in sympy.preorder_traversal(expr) if isinstance(a, sympy.Pow)]
    assert expanded_terms(expr) >= max([_terms(expr), *inner])


def test_a_power_of_a_sum_counts_its_multinomial_terms_without_making_them():
    # C(39, 20) = 68,923,264,410 terms: the count stops at the limit
    power = sympy.Add(*VELOCITIES) ** 20 / 2
    assert math.comb(39, 20) > MAX_EXPANDED_TERMS
    assert expanded_terms(power) == MAX_EXPANDED_TERMS + 1
    assert expanded_terms(sympy.Add(*VELOCITIES) ** 4) == math.comb(23, 4)


def test_the_count_of_products_alone_leaves_powers_of_sums_whole():
    assert expanded_terms((x + y) ** 9 * (z + w), powers=False) == 2
    assert expanded_terms((x + y) ** 9 * (z + w)) == 20


def _sum_of_velocities(n: int, first: int = 0) -> str:
    return " + ".join(f"q{(first + i) % 20}_dot" for i in range(n))


def _system(lagrangian: str, n: int) -> lg.System:
    return lg.System.from_lagrangian(lagrangian, coordinates=[f"q{i}" for i in range(n)])


@pytest.mark.parametrize(
    "lagrangian, n",
    [
        (f"({_sum_of_velocities(20)})^20/2", 20),  # the model
        # a product of sums: 3^20 terms
        (
            "*".join(f"(q{i}_dot + q{(i + 1) % 20}_dot + q{(i + 2) % 20}_dot)" for i in range(20)),
            20,
        ),
        (f"(({_sum_of_velocities(10)})^4 + 1)^5", 10),  # nested powers: C(720, 5) terms
        (f"({_sum_of_velocities(8)})^2/2 + sin(q0)*({_sum_of_velocities(8)})^40", 8),
    ],
    ids=["power of a sum", "product of sums", "nested powers", "a term of many"],
)
def test_a_lagrangian_whose_expansion_is_too_large_is_refused_before_it_is_made(
    lagrangian, n, monkeypatch
):
    import symengine

    def not_here(expr):
        raise AssertionError(f"expanded: {str(expr)[:80]}")

    monkeypatch.setattr(symengine, "expand", not_here)  # refused before expanding the L
    with pytest.raises(ModelError) as refused:
        _system(lagrangian, n).equations_of_motion()
    assert refused.value.field == "lagrangian"
    assert "expanded, it makes more than 2,000,000 terms" in str(refused.value)
    assert "too large to derive" in str(refused.value)


def test_what_the_tables_make_together_is_bounded(monkeypatch):
    """Each expansion alone may be small while the derivatives' tables grow: the count
    is of all of them together (monkeypatched low, so that the test stays quick)."""
    _limit(monkeypatch, 1_000)
    system = _system(f"({_sum_of_velocities(8)})^4/2 + ({_sum_of_velocities(8)})^2/2", 8)
    assert expanded_terms(system.lagrangian) < 400  # the L alone is well within
    with pytest.raises(ModelError, match="too large to derive"):
        fast.derive_large(system)


def test_the_angle_rule_leaves_an_expression_too_large_to_expand_as_it_is(monkeypatch):
    import symengine as se

    monkeypatch.setattr(se, "expand", lambda expr: pytest.fail("expanded"))
    sines = se.Add(*(se.sin(k * se.Symbol("x")) for k in range(1, 40)))
    assert algebra.combine_angles(sines**8) == sines**8  # C(46, 8) = 260 million terms
    small = sympy.Add(*(sympy.sin(k * x) for k in range(1, 40))) ** 6
    assert algebra._angle_sums_combined(small) == small  # 7 million: too long to read


def test_tidy_leaves_a_product_of_many_sums_unexpanded():
    product = sympy.Mul(*(VELOCITIES[i] + VELOCITIES[i + 1] for i in range(19)))
    assert algebra.expand_products(product) == product  # 2^19 terms
    assert algebra.expand_products((x + y) * (z + w)) == x * z + x * w + y * z + y * w


# -- a model built from particles, bodies or springs: the refusal names the field written --
COORDINATE_NAMES = [f"q{i}" for i in range(20)]
POSITIONS = " + ".join(COORDINATE_NAMES)


def test_a_particles_position_too_large_is_named_not_the_lagrangian():
    """The user wrote the position, not L: the refusal names ``particles[1].position[1]``."""
    system = lg.System.from_particles(
        COORDINATE_NAMES,
        [lg.Particle("a", 1, ("q0", 0)), lg.Particle("b", 1, ("q1", f"({POSITIONS})^20"))],
    )
    with pytest.raises(ModelError) as refused:
        system.equations_of_motion()
    assert refused.value.field == "particles[1].position[1]"
    assert str(refused.value).startswith("particles[1].position[1]: expanded, it makes more")


def test_a_bodys_angle_too_large_is_named():
    body = lg.RigidBody2D("a", 1, 1, ("q0", "q1"), f"({POSITIONS})^20")
    system = lg.System.from_particles(COORDINATE_NAMES, bodies=(body,))
    with pytest.raises(ModelError) as refused:
        system.equations_of_motion()
    assert refused.value.field == "bodies[0].angle"


def test_the_tables_refusal_of_a_particle_model_names_the_particle(monkeypatch):
    """L alone within the count, its derivatives' tables not: the same field is named."""
    _limit(monkeypatch, 1_000)
    names = COORDINATE_NAMES[:8]
    system = lg.System.from_particles(
        names,
        [lg.Particle("a", 1, ("q0", 0)), lg.Particle("b", 1, ("q1", f"({' + '.join(names)})^3"))],
    )
    with pytest.raises(ModelError, match="too large to derive") as refused:
        fast.derive_large(system)
    assert refused.value.field == "particles[1].position[1]"


def test_a_lagrangian_written_as_text_is_still_named_lagrangian():
    assert fast.lagrangian_field(_system("q0_dot^2/2", 1)) == "lagrangian"


def test_the_count_s_walk_reports_the_kind_of_every_node():
    """The large route asks the same walk whether |u| or sign(u) occur (no second walk)."""
    import symengine as se

    expr = sympy.sin(sympy.Abs(x - y) * z) ** 2 + sympy.sign(w) * (x + y) ** 3
    converted = algebra.to_symengine(expr)
    kinds: set = set()
    assert expanded_terms(converted, kinds=kinds) == expanded_terms(converted)
    every = set()
    pending = [converted]
    while pending:
        node = pending.pop()
        every.add(type(node))
        pending.extend(node.args)
    assert kinds == every
    assert {se.Abs, se.sign, se.sin} <= kinds


@pytest.mark.parametrize("depth", [5, 199, 200, 201, 1200])
def test_a_tree_nested_deeper_than_the_recursion_is_counted_the_same(depth):
    """The count recurses node by node; a tree nested deeper than its bound (or than
    Python's recursion limit, 1200 levels) is walked by a stack to the same answer:
    sin((sin((x + y)^3) + y)^3) ... each level the cube of a sum of two terms (4 terms
    expanded, C(4, 3)) inside a function (one term), and every kind of node reported."""
    import symengine as se

    for expr, sin in ((x, sympy.sin), (algebra.to_symengine(x), se.sin)):
        for _ in range(depth):
            expr = sin((expr + y) ** 3)
        kinds: set = set()
        assert expanded_terms(expr, kinds=kinds) == 4
        assert expanded_terms(expr, 3) == 4  # over its limit: limit + 1
        assert expanded_terms(expr, powers=False) == 2  # without powers: the sum's terms
        power = expr.args[0]
        assert {type(expr), type(power), type(power.args[0]), type(power.args[1])} <= kinds


def test_a_count_started_deep_in_the_stack_is_not_a_recursion_error():
    """The recursion's 200 levels fit under Python's limit from a shallow caller; called
    near that limit, the count falls back to its own stack with the same answer."""
    import sys

    expr = x
    for _ in range(150):  # 150 levels: within the recursion's bound
        expr = sympy.sin((expr + y) ** 3)

    def nested(depth: int) -> int:
        return expanded_terms(expr) if depth == 0 else nested(depth - 1)

    room = sys.getrecursionlimit() - len(_frames()) - 60  # about 60 levels left for the count
    assert nested(room) == 4


def _frames() -> list:
    import inspect

    return inspect.stack(0)
