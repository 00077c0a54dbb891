"""Property tests: random Lagrangians against an independent derivation.

A random Lagrangian in 1-3 coordinates (x, y, z) is built from plain
``sympy.Symbol`` objects named like the toolkit's (``x``, ``x_dot``, ``t``):

- a positive-definite kinetic part: sum c_i(q, t) q_dot_i^2 / 2 with c_i >= 1,
  plus cross terms e_ij s_ij(q) q_dot_i q_dot_j with |e_ij s_ij| <= 1/4, so by
  Gershgorin the mass matrix stays positive definite everywhere;
- optional terms linear in the velocities, g_i(q, t) q_dot_i (gyroscopic);
- a potential of polynomial and trigonometric terms, with or without t.

The independent route is SymPy's ``euler_equations`` on the same L written
with functions of t, solved for the accelerations at a random point with
``sympy.linsolve``.  The Lagrangian is given to ``from_lagrangian`` as a SymPy
expression and, in some examples, also as text (``str(expr)``): both must give
the same system.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import pytest
import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sympy.calculus.euler import euler_equations

import lagrangian as lg
from helpers import assert_close, evaluate, plain, random_point

NAMES = ("x", "y", "z")
t = sympy.Symbol("t")
a, b = sympy.symbols("a b")  # parameters (positive)

SETTINGS = settings(
    max_examples=15,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


@dataclass(frozen=True)
class RandomLagrangian:
    coordinates: tuple[str, ...]
    lagrangian: sympy.Expr
    kinetic: sympy.Expr
    potential: sympy.Expr
    as_text: bool
    seed: int

    def __repr__(self) -> str:  # what hypothesis prints for a failing example
        return (
            f"RandomLagrangian(coordinates={self.coordinates}, L={self.lagrangian}, "
            f"as_text={self.as_text}, seed={self.seed})"
        )


@st.composite
def random_lagrangians(draw, with_time: bool | None = None) -> RandomLagrangian:
    n = draw(st.integers(1, 3))
    names = NAMES[:n]
    q = [sympy.Symbol(name) for name in names]
    v = [sympy.Symbol(f"{name}_dot") for name in names]
    if with_time is None:
        with_time = draw(st.booleans())

    def some_q():
        return draw(st.sampled_from(q))

    # kinetic energy: diagonal coefficients >= 1
    diagonal_choices = [
        lambda: sympy.Integer(1),
        lambda: 1 + some_q() ** 2,
        lambda: 2 + sympy.cos(some_q()),
        lambda: a + 1 + sympy.sin(some_q()) ** 2,
    ]
    if with_time:
        diagonal_choices.append(lambda: 2 + sympy.sin(t))
    kinetic = sympy.Integer(0)
    for i in range(n):
        coefficient = draw(st.sampled_from(diagonal_choices))()
        kinetic += coefficient * v[i] ** 2 / 2
    # cross terms, |M_ij| <= 1/4: rows of off-diagonal entries sum to <= 1/2 < 1
    for i in range(n):
        for j in range(i + 1, n):
            if draw(st.booleans()):
                size = draw(st.sampled_from([sympy.Rational(1, 4), sympy.Rational(-1, 5)]))
                shape = draw(
                    st.sampled_from(
                        [lambda: 1, lambda: sympy.cos(some_q()), lambda: sympy.sin(some_q())]
                    )
                )()
                kinetic += size * shape * v[i] * v[j]
    # terms linear in the velocities (part of L, neither T nor V here)
    linear_choices = [
        lambda: some_q() * some_q(),
        lambda: sympy.sin(some_q()),
        lambda: b * some_q() ** 2,
    ]
    if with_time:
        linear_choices += [lambda: some_q() * t, lambda: sympy.cos(t) * some_q()]
    gyroscopic = sympy.Integer(0)
    for i in range(n):
        if draw(st.booleans()):
            coefficient = draw(st.sampled_from([1, -1, 2, sympy.Rational(1, 2)]))
            gyroscopic += coefficient * draw(st.sampled_from(linear_choices))() * v[i]
    # potential: polynomial and trigonometric terms
    potential_choices = [
        lambda: some_q() ** 2,
        lambda: some_q() ** 3,
        lambda: some_q() ** 4 / 4,
        lambda: some_q() * some_q(),
        lambda: sympy.sin(some_q()),
        lambda: a * sympy.cos(some_q() - some_q()),
        lambda: sympy.exp(-(some_q() ** 2)),
    ]
    if with_time:
        potential_choices += [lambda: some_q() * sympy.cos(t), lambda: t**2 * some_q() ** 2]
    terms = draw(st.lists(st.sampled_from(potential_choices), min_size=1, max_size=4))
    if with_time:  # make sure t is really there
        terms.append(draw(st.sampled_from(potential_choices[-2:])))
    potential = sympy.Integer(0)
    for term in terms:
        potential += draw(st.sampled_from([1, -1, 3, sympy.Rational(1, 3)])) * term()
    return RandomLagrangian(
        coordinates=names,
        lagrangian=kinetic + gyroscopic - potential,
        kinetic=kinetic + gyroscopic,
        potential=potential,
        as_text=draw(st.booleans()),
        seed=draw(st.integers(0, 2**32 - 1)),
    )


def euler_equations_accelerations(
    lagrangian: sympy.Expr, coordinates: tuple[str, ...], point: dict[str, float]
) -> dict[str, float]:
    """Independent route: euler_equations on L(q(t), q'(t), t), solved at ``point``."""
    functions = [sympy.Function(name)(t) for name in coordinates]
    to_time = {}
    for name, f in zip(coordinates, functions, strict=True):
        to_time[sympy.Symbol(f"{name}_dot")] = f.diff(t)
        to_time[sympy.Symbol(name)] = f
    equations = euler_equations(plain(lagrangian).xreplace(to_time), functions, t)
    back = {}
    for name, f in zip(coordinates, functions, strict=True):
        back[f.diff(t, 2)] = sympy.Symbol(f"{name}_ddot")
        back[f.diff(t)] = sympy.Symbol(f"{name}_dot")
        back[f] = sympy.Symbol(name)
    unknowns = [sympy.Symbol(f"{name}_ddot") for name in coordinates]
    numeric = []
    for equation in equations:
        expr = (equation.lhs - equation.rhs).xreplace(back)
        values = {s: sympy.Float(point[s.name], 30) for s in expr.free_symbols if s not in unknowns}
        numeric.append(sympy.expand(expr.xreplace(values)))
    (solution,) = sympy.linsolve(numeric, unknowns)
    return {name: float(value) for name, value in zip(coordinates, solution, strict=True)}


@pytest.mark.slow
@pytest.mark.parametrize("with_time", [False, True], ids=["autonomous", "explicit_t"])
@SETTINGS
@given(data=st.data())
def test_accelerations_agree_with_euler_equations(with_time: bool, data):
    case = data.draw(random_lagrangians(with_time=with_time), label="case")
    system = lg.System.from_lagrangian(case.lagrangian, coordinates=list(case.coordinates))
    assert [c.name for c in system.coordinates] == list(case.coordinates)
    assert sympy.expand(plain(system.lagrangian) - case.lagrangian) == 0
    eom = system.equations_of_motion()
    point = random_point(system, random.Random(case.seed))
    expected = euler_equations_accelerations(case.lagrangian, case.coordinates, point)
    for name in case.coordinates:
        assert_close(evaluate(eom.accelerations[name], point), expected[name], scale=1.0, what=name)

    if case.as_text or with_time:
        text = str(case.lagrangian)
        from_text = lg.System.from_lagrangian(text, coordinates=list(case.coordinates))
        assert from_text.parameter_names == system.parameter_names
        assert sympy.expand(plain(from_text.lagrangian) - plain(system.lagrangian)) == 0
        eom_text = from_text.equations_of_motion()
        for name in case.coordinates:
            assert_close(
                evaluate(eom_text.accelerations[name], point),
                expected[name],
                scale=1.0,
                what=f"{name} (from text {text!r})",
            )


@pytest.mark.slow
@settings(
    max_examples=10,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(random_lagrangians())
def test_energies_route_gives_the_same_equations(case: RandomLagrangian):
    """from_energies(T, V) (T holding the linear terms) is L = T - V."""
    via_energies = lg.System.from_energies(
        kinetic=case.kinetic, potential=case.potential, coordinates=list(case.coordinates)
    )
    assert sympy.expand(plain(via_energies.lagrangian) - case.lagrangian) == 0
    point = random_point(via_energies, random.Random(case.seed))
    expected = euler_equations_accelerations(case.lagrangian, case.coordinates, point)
    eom = via_energies.equations_of_motion()
    for name in case.coordinates:
        assert_close(evaluate(eom.accelerations[name], point), expected[name], scale=1.0, what=name)


@SETTINGS
@given(random_lagrangians())
def test_symbols_are_rebound_by_name(case: RandomLagrangian):
    """Every symbol of the adopted L is the model's own; t makes the system non-autonomous."""
    system = lg.System.from_lagrangian(case.lagrangian, coordinates=list(case.coordinates))
    own = set(system.symbols.values())
    assert system.lagrangian.free_symbols <= own
    assert {s.name for s in system.lagrangian.free_symbols} == {
        s.name for s in case.lagrangian.free_symbols
    }
    assert system.is_autonomous == (not case.lagrangian.has(t))
    assert set(system.parameter_names) == {
        s.name for s in case.lagrangian.free_symbols if s.name in ("a", "b")
    }
    for p in system.parameters:
        assert system.symbol(p.name).is_positive
