"""Shared helpers of the test suite: seeded random points, evaluation by name, comparisons.

Symbols of a ``System`` carry assumptions (real, positive), so a reference
expression typed in a test with plain ``sympy.Symbol("x")`` is a different
symbol.  Everything here therefore works BY NAME: a point is a dict
``{name: float}`` and :func:`evaluate` substitutes each free symbol of an
expression by the value of its name, whatever its assumptions.

Unspecified functions (``A(x, y, z)`` and ``Derivative(A(x, y, z), x)``) are
replaced, also by name, by concrete ones given as Python callables of SymPy
arguments, e.g. ``{"A": lambda x, y, z: sympy.sin(x) * y}``.
"""

from __future__ import annotations

import contextlib
import importlib
import random
import signal
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence

import mpmath
import pytest
import sympy
from sympy.core.function import AppliedUndef

#: Digits used to evaluate expressions (far more than the tolerances need).
DIGITS = 30
#: Default relative tolerance of the comparisons.
RTOL = 1e-9

COORDINATE_RANGE = (-2.0, 2.0)
VELOCITY_RANGE = (-2.0, 2.0)
POSITIVE_RANGE = (0.5, 2.0)
REAL_RANGE = (-2.0, 2.0)
TIME_RANGE = (-2.0, 2.0)

ConcreteFunctions = Mapping[str, Callable[..., sympy.Expr]]


# -- random points -------------------------------------------------------------
def random_point(
    system,
    rng: random.Random,
    ranges: Mapping[str, tuple[float, float]] | None = None,
    *,
    avoid: Callable[[Mapping[str, float]], bool] | None = None,
) -> dict[str, float]:
    """A random value for every name of ``system``: q, q_dot, q_ddot, parameters and t.

    Coordinates in [-2, 2], velocities in [-2, 2], positive parameters in
    [0.5, 2] (negative ones in [-2, -0.5], non-negative in [0, 2]), other
    parameters and t in [-2, 2]; ``ranges`` overrides any name
    (e.g. ``{"r": (0.5, 2.0)}`` to keep a radius away from 0).  ``avoid``
    rejects points (near singular ones) and draws again.
    """
    ranges = dict(ranges or {})
    for _ in range(1000):
        point = {}
        for c in system.coordinates:
            point[c.name] = _draw(rng, ranges.get(c.name, COORDINATE_RANGE))
            point[c.q_dot.name] = _draw(rng, ranges.get(c.q_dot.name, VELOCITY_RANGE))
            point[c.q_ddot.name] = _draw(rng, ranges.get(c.q_ddot.name, VELOCITY_RANGE))
        for p in system.parameters:
            point[p.name] = _draw(rng, ranges.get(p.name, parameter_range(p.symbol)))
        point["t"] = _draw(rng, ranges.get("t", TIME_RANGE))
        if avoid is None or not avoid(point):
            return point
    raise AssertionError("no acceptable random point found")


def parameter_range(symbol: sympy.Symbol) -> tuple[float, float]:
    """Where a parameter's random values lie, respecting its sign assumption."""
    if symbol.is_positive:
        return POSITIVE_RANGE
    if symbol.is_negative:
        return (-POSITIVE_RANGE[1], -POSITIVE_RANGE[0])
    if symbol.is_nonnegative:
        return (0.0, POSITIVE_RANGE[1])
    return REAL_RANGE


def _draw(rng: random.Random, bounds: tuple[float, float]) -> float:
    low, high = bounds
    return rng.uniform(low, high)


# -- unspecified functions -----------------------------------------------------
def substitute_functions(expr: sympy.Expr, functions: ConcreteFunctions) -> sympy.Expr:
    """Replace unspecified functions (matched by name) by concrete ones, then do derivatives."""
    if not functions:
        return expr
    classes = {applied.func for applied in expr.atoms(AppliedUndef)}
    for cls in classes:
        concrete = functions.get(cls.__name__)
        if concrete is None:
            continue
        arity = len(next(iter(a for a in expr.atoms(AppliedUndef) if a.func == cls)).args)
        dummies = sympy.symbols(f"_arg0:{arity}", cls=sympy.Dummy)
        expr = expr.replace(cls, sympy.Lambda(dummies, concrete(*dummies)))
    return expr.doit()


# -- evaluation ------------------------------------------------------------------
def evaluate(
    expr: sympy.Expr | float | int,
    point: Mapping[str, float],
    functions: ConcreteFunctions | None = None,
) -> complex | float:
    """The value of ``expr`` at ``point`` ({name: value}), symbols matched by name."""
    expr = sympy.sympify(expr)
    expr = substitute_functions(expr, functions or {})
    leftover = expr.atoms(AppliedUndef)
    if leftover:
        raise AssertionError(f"unspecified functions left in the expression: {leftover}")
    mapping = {}
    for symbol in expr.free_symbols:
        if symbol.name not in point:
            raise AssertionError(f"no value for '{symbol.name}' in {sorted(point)}")
        mapping[symbol] = sympy.Float(point[symbol.name], DIGITS)
    value = expr.xreplace(mapping).evalf(DIGITS)
    if value.free_symbols:
        raise AssertionError(f"could not evaluate {expr} (left: {value.free_symbols})")
    value = complex(value)
    return value.real if value.imag == 0 else value


def scale_of(
    expr: sympy.Expr, point: Mapping[str, float], functions: ConcreteFunctions | None = None
) -> float:
    """The size of the terms of ``expr`` at ``point``: a scale for "is this zero?"."""
    expr = substitute_functions(sympy.sympify(expr), functions or {})
    terms = sympy.Add.make_args(sympy.expand(expr))
    return max(1e-300, sum(abs(evaluate(term, point)) for term in terms))


def substitute_by_name(expr: sympy.Expr, replacements: Mapping[str, sympy.Expr]) -> sympy.Expr:
    """Replace each free symbol whose NAME is a key by the given expression."""
    mapping = {s: replacements[s.name] for s in expr.free_symbols if s.name in replacements}
    return expr.xreplace(mapping)


def plain(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` with every symbol replaced by an assumption-free symbol of the same name."""
    return expr.xreplace({s: sympy.Symbol(s.name) for s in expr.free_symbols})


# -- comparison ------------------------------------------------------------------
def assert_close(actual, expected, rtol: float = RTOL, *, scale: float = 0.0, what: str = ""):
    """|actual - expected| <= rtol * max(|actual|, |expected|, scale, tiny)."""
    size = max(abs(actual), abs(expected), scale, 1e-12)
    assert abs(actual - expected) <= rtol * size, (
        f"{what}: got {actual!r}, expected {expected!r} (relative error "
        f"{abs(actual - expected) / size:.3e} > {rtol:g})"
    )


def solve_linear(matrix: Sequence[Sequence[float]], rhs: Sequence[float]) -> list[float]:
    """x with matrix x = rhs, in extended precision (mpmath)."""
    with mpmath.workdps(DIGITS):
        a = mpmath.matrix([[mpmath.mpf(float(v)) for v in row] for row in matrix])
        b = mpmath.matrix([mpmath.mpf(float(v)) for v in rhs])
        return [float(v) for v in mpmath.lu_solve(a, b)]


def total_time_derivative(expr: sympy.Expr, coordinates: Sequence[str]) -> sympy.Expr:
    """d/dt of an expression of (q, q_dot, t), by the chain rule, with symbols by name.

    Plain symbols named ``q``, ``q_dot``, ``q_ddot`` and ``t`` are used for the
    result; the expression may hold symbols with any assumptions.
    """
    expr = plain(expr)
    t = sympy.Symbol("t")
    result = sympy.diff(expr, t)
    for name in coordinates:
        q, q_dot, q_ddot = sympy.symbols(f"{name} {name}_dot {name}_ddot")
        result += sympy.diff(expr, q) * q_dot + sympy.diff(expr, q_dot) * q_ddot
    return result


def slow_where(values: Iterable, is_slow: Callable[[object], bool]) -> list:
    """``values`` for ``pytest.mark.parametrize``, those where ``is_slow(value)`` marked
    slow (left out of plain ``pytest``: tests/conftest.py)."""
    return [pytest.param(value, marks=pytest.mark.slow) if is_slow(value) else value
            for value in values]  # fmt: skip


@contextlib.contextmanager
def timer_handler(which: int, signum: int, handler: Callable, delay: float) -> Iterator[None]:
    """While inside, ``handler`` receives ``signum`` from the interval timer ``which``
    armed ``delay`` seconds ahead; the timer is stopped and the handler restored on the
    way out (a test leaves every disposition as it found it)."""
    previous = signal.signal(signum, handler)
    signal.setitimer(which, delay)
    try:
        yield
    finally:
        signal.setitimer(which, 0)
        signal.signal(signum, previous)


def spring_bar_and_bob():
    """A planar mechanism with every kind of part a picture draws: a bob on a vertical
    line hung from a spring at the origin, and a bar (a planar rigid body) turning about
    (1, 0) under gravity."""
    import lagrangian as lg
    from lagrangian.model import Gravity, Particle, RigidBody2D, Spring

    return lg.System.from_particles(
        ["y", "phi"],
        particles=[Particle("bob", "m", ("0", "-y"))],
        bodies=[RigidBody2D("bar", "M", "M*a**2/12", ("1", "0"), "phi")],
        springs=[Spring("k", ("bob", (0, 0)), rest_length="L0")],
        gravity=Gravity("g"),
        parameters={"m": 1.0, "M": 2.0, "a": 0.6, "k": 20.0, "L0": 0.5, "g": 9.81},
        initial={"y": 0.9, "phi_dot": 1.0},
    )


def counting(monkeypatch, module: str, name: str) -> list:
    """Patch ``module.name`` to record the arguments of its calls (and still do its work)."""
    target = importlib.import_module(module)
    original = getattr(target, name)
    calls: list = []

    def counted(*args, **kwargs):
        calls.append(args)
        return original(*args, **kwargs)

    monkeypatch.setattr(target, name, counted)
    return calls
