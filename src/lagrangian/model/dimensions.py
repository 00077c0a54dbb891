"""Physical dimensions as exponent vectors over the SI base dimensions, and their names.

A dimension is a tuple of seven exact exponents (:class:`fractions.Fraction`) of mass,
length, time, current, temperature, amount of substance and luminous intensity: a force
is (1, 1, -2, 0, 0, 0, 0), kg*m/s^2.  Products add the vectors and powers scale them, so
checking a model's dimensions is linear algebra over these exponents
(:mod:`.dimension_check`).  Angles are dimensionless, as in SI (the radian is 1).

This module needs no unit library: it names dimensions in SI units (``N``, ``J``,
``kg*m^2``) for messages and outputs.  Reading unit text (``"50 cm"``) is
:mod:`.quantities`' work.
"""

from __future__ import annotations

from collections.abc import Iterable
from fractions import Fraction

import sympy

Dimension = tuple[int | Fraction, ...]

#: The base dimensions, in pint's spelling, and the SI unit of each.
BASE = ("[mass]", "[length]", "[time]", "[current]", "[temperature]", "[substance]",
        "[luminosity]")  # fmt: skip
SI_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd")


def dimension(mass=0, length=0, time=0, current=0, temperature=0, substance=0, luminosity=0):
    """The dimension with these exponents: ``dimension(length=1, time=-2)`` is an acceleration."""
    exponents = (mass, length, time, current, temperature, substance, luminosity)
    return tuple(_exact(e) for e in exponents)


def _exact(value) -> int | Fraction:
    """An exponent as an int when whole (faster to add than a Fraction), else a Fraction."""
    value = Fraction(value)
    return value.numerator if value.denominator == 1 else value


def times(a: Dimension, b: Dimension) -> Dimension:
    """The dimension of a product."""
    return tuple(x + y for x, y in zip(a, b, strict=True))


def over(a: Dimension, b: Dimension) -> Dimension:
    """The dimension of a quotient."""
    return tuple(x - y for x, y in zip(a, b, strict=True))


def power(a: Dimension, exponent: Fraction) -> Dimension:
    """The dimension of ``a`` raised to a rational power."""
    return tuple(_exact(x * exponent) for x in a)


DIMENSIONLESS = dimension()
MASS = dimension(mass=1)
LENGTH = dimension(length=1)
TIME = dimension(time=1)
VELOCITY = dimension(length=1, time=-1)
ACCELERATION = dimension(length=1, time=-2)
FORCE = dimension(mass=1, length=1, time=-2)
ENERGY = dimension(mass=1, length=2, time=-2)
POWER = dimension(mass=1, length=2, time=-3)
STIFFNESS = dimension(mass=1, time=-2)
INERTIA = dimension(mass=1, length=2)
MOMENTUM = dimension(mass=1, length=1, time=-1)
ANGULAR_MOMENTUM = dimension(mass=1, length=2, time=-1)
RATE = dimension(time=-1)
DAMPING = dimension(mass=1, time=-1)

#: What a dimension is called in a message: (singular, plural, SI unit).
KINDS = {
    MASS: ("a mass", "masses", "kg"),
    LENGTH: ("a length", "lengths", "m"),
    TIME: ("a time", "times", "s"),
    VELOCITY: ("a velocity", "velocities", "m/s"),
    ACCELERATION: ("an acceleration", "accelerations", "m/s^2"),
    FORCE: ("a force", "forces", "N"),
    ENERGY: ("an energy", "energies", "J"),
    POWER: ("a power", "powers", "W"),
    STIFFNESS: ("a stiffness", "stiffnesses", "N/m"),
    INERTIA: ("a moment of inertia", "moments of inertia", "kg*m^2"),
    MOMENTUM: ("a momentum", "momenta", "kg*m/s"),
    ANGULAR_MOMENTUM: ("an angular momentum", "angular momenta", "kg*m^2/s"),
    RATE: ("a rate", "rates", "1/s"),
    DAMPING: ("a damping coefficient", "damping coefficients", "N*s/m"),
}
#: Named SI units of the dimensions that have one (the rest are written in base units).
_NAMED = {FORCE: "N", ENERGY: "J", POWER: "W", STIFFNESS: "N/m", DAMPING: "N*s/m"}


def _exponent(value: Fraction) -> str:
    if value == 1:
        return ""
    if value.denominator == 1:
        return f"^{value.numerator}"
    return f"^({value.numerator}/{value.denominator})"


def unit_text(value: Dimension, *, angle: bool = False) -> str:
    """The SI unit of a dimension: ``N``, ``kg*m^2``, ``m/s^2``, ``1`` (dimensionless).

    ``angle``: the quantity is an angle or derived from one (a coordinate without
    dimension, its velocity, an angular frequency), so that rad is said: ``rad``,
    ``rad/s``.
    """
    if angle and value == DIMENSIONLESS:
        return "rad"
    if value in _NAMED:
        return _NAMED[value]
    above = [f"{unit}{_exponent(e)}" for unit, e in zip(SI_UNITS, value, strict=True) if e > 0]
    below = [f"{unit}{_exponent(-e)}" for unit, e in zip(SI_UNITS, value, strict=True) if e < 0]
    numerator = "*".join(above) or ("rad" if angle else "1")
    if not below:
        return numerator
    denominator = below[0] if len(below) == 1 else f"({'*'.join(below)})"
    return f"{numerator}/{denominator}"


#: An angle's rate described: its dimension is 1/s, but it is said in rad/s.
ANGULAR_RATE = ("an angular rate", "angular rates", "rad/s")


def describe(value: Dimension, *, plural: bool = False, angular: bool = False) -> str:
    """A dimension in words with its SI unit: ``a force (N)``, ``energies (J)``,
    ``dimensionless``, ``of dimension kg*m/s^3``; ``angular``: the quantity is an angle's
    rate (a velocity of a coordinate without dimension), ``an angular rate (rad/s)``."""
    if angular and value == RATE:
        singular, many, unit = ANGULAR_RATE
        return f"{many if plural else singular} ({unit})"
    if value == DIMENSIONLESS:
        return "dimensionless"
    if value in KINDS:
        singular, many, unit = KINDS[value]
        return f"{many if plural else singular} ({unit})"
    return f"of dimension {unit_text(value)}"


def from_pint(dimensionality: Iterable[tuple[str, float]]) -> Dimension:
    """The dimension of pint's ``dimensionality`` items (``[length]``: 1.0, ...)."""
    exponents = dict.fromkeys(BASE, 0)
    for name, exponent in dimensionality:
        exponents[name] = _exact(Fraction(exponent).limit_denominator(1000))
    return tuple(exponents[name] for name in BASE)


def dimension_of(expr: sympy.Expr, dimensions: dict[sympy.Symbol, Dimension]) -> Dimension | None:
    """The dimension of a SymPy expression over symbols of known ``dimensions``, or None
    when it has none (a sum of terms of different dimensions, an unknown symbol, a
    dimensioned function argument).  Zero has every dimension: None is never its answer
    alone, it takes the dimension of the other terms.

    For naming the units of results (a conserved quantity, a Hamiltonian) that were
    derived from a model whose dimensions were checked; the check itself is
    :mod:`.dimension_check`.
    """
    found = _dimension_of(expr, dimensions, {})
    return DIMENSIONLESS if found is _ANY else found


_ANY = object()  # the dimension of 0: any


def _dimension_of(expr, dimensions, memo):
    if expr in memo:
        return memo[expr]
    if expr.is_Symbol or expr in dimensions:  # a name, or a declared function applied
        result = dimensions.get(expr)
    elif expr.is_Number:
        result = _ANY if expr == 0 else DIMENSIONLESS
    elif expr.is_NumberSymbol:
        result = DIMENSIONLESS
    elif expr.is_Add:
        result = _ANY
        for term in expr.args:
            found = _dimension_of(term, dimensions, memo)
            if found is None or (result is not _ANY and found is not _ANY and found != result):
                result = None
                break
            if found is not _ANY:
                result = found
    elif expr.is_Mul:
        result = DIMENSIONLESS
        for factor in expr.args:
            found = _dimension_of(factor, dimensions, memo)
            if found is None or found is _ANY:
                result = found
                break
            result = times(result, found)
    elif expr.is_Pow:
        base = _dimension_of(expr.base, dimensions, memo)
        exponent = expr.exp
        if base is None or base is _ANY:
            result = base
        elif exponent.is_Rational:
            result = power(base, Fraction(int(exponent.p), int(exponent.q)))
        else:
            result = DIMENSIONLESS if base == DIMENSIONLESS else None
    elif isinstance(expr, sympy.Abs):
        result = _dimension_of(expr.args[0], dimensions, memo)
    elif isinstance(expr, sympy.Function) and all(
        _dimension_of(a, dimensions, memo) in (DIMENSIONLESS, _ANY) for a in expr.args
    ):
        result = DIMENSIONLESS
    else:
        result = None
    memo[expr] = result
    return result
