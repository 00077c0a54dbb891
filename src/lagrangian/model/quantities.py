"""Read a value with a unit (``"50 cm"``, ``"9.81 m/s^2"``, ``"120 rpm"``) or a unit alone.

pint reads the unit and converts; it is imported here, on the first value with a unit,
and never by a model without one (``import lagrangian.cli`` does not load it).  Values
are converted to SI base units at once (``"50 cm"`` is 0.5 of a metre): no unit object
ever leaves this module.

The text is checked before pint sees it: its length, its characters, and the size of
every number in the unit (pint evaluates ``m**99999999`` as written).  A unit pint does
not know is named with the closest one it does (``parsecz``: did you mean ``parsec``?);
a unit with an offset (``degC``, ``degF``) is refused, since 20 degC is not 20 times
1 degC and no term of an equation of motion can carry one.
"""

from __future__ import annotations

import difflib
import functools
import math
import re
from dataclasses import dataclass
from fractions import Fraction

from ..errors import ModelError
from .dimensions import Dimension, from_pint

#: The longest value-with-unit text read.
MAX_TEXT = 100
_NUMBER = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*)", re.DOTALL)
_ALLOWED = re.compile(r"[A-Za-z_0-9*/^().\s\u00b5\u03bc\u00b0\u03a9\u2126-]*")
_LONG_NUMBER = re.compile(r"\d{3,}")


@dataclass(frozen=True)
class Unit:
    """A unit as the user wrote it (``text``), the factor that takes a number in it to SI
    base units, and its dimension."""

    text: str
    factor: float
    dimension: Dimension


@dataclass(frozen=True)
class Quantity:
    """A value given with a unit: its magnitude in SI base units, the unit, and the number
    as written (exact: ``90`` of ``90 deg``)."""

    value: float
    unit: Unit
    number: Fraction


@functools.cache
def _registry():
    import pint

    return pint.UnitRegistry()


def has_unit(text: str) -> bool:
    """Whether ``text`` (a value as given: ``"0.5"``, ``"50cm"``) carries a unit."""
    match = _NUMBER.fullmatch(text)
    return match is not None and bool(match[2].strip())


def read_quantity(text: str, where: str) -> Quantity:
    """The value ``text`` (a number and a unit, or a bare number: dimensionless) in SI.

    ``where`` names the field or option in the ModelError of a value that is not one.
    """
    _check_text(text, where)
    match = _NUMBER.fullmatch(text)
    if match is None:
        raise ModelError(
            f"expected a number and a unit, such as '50 cm', got {text!r}", field=where
        )
    number = float(match[1])
    unit = read_unit(match[2], where, quoted=text) if match[2].strip() else _ONE
    value = number * unit.factor
    if not math.isfinite(value):
        raise ModelError(f"{text!r} is beyond double precision", field=where)
    return Quantity(value, unit, Fraction(match[1]))


def read_unit(text: str, where: str, *, quoted: str | None = None) -> Unit:
    """The unit written in ``text`` (``"m/s^2"``, ``"rad"``), with its factor to SI base
    units; a ModelError naming ``where`` and the text for one that is not a unit."""
    quoted = text if quoted is None else quoted
    _check_text(text, where)
    registry = _registry()
    import pint

    try:
        parsed = registry.parse_units(text.strip().replace("^", "**"))
        base = registry.Quantity(1.0, parsed).to_base_units()
    except pint.UndefinedUnitError as error:
        raise ModelError(_unknown(error, registry), field=where, text=quoted) from None
    except pint.OffsetUnitCalculusError:
        raise _offset(quoted, where) from None
    except Exception:  # pint's parser fails on malformed text in many ways
        raise ModelError(f"{quoted!r} is not a unit", field=where) from None
    if not all(registry._units[name].is_multiplicative for name in _names(parsed)):
        raise _offset(quoted, where)
    factor = float(base.magnitude)
    if not (math.isfinite(factor) and factor > 0):
        raise ModelError(f"{quoted!r} is beyond double precision", field=where)
    return Unit(text.strip(), factor, from_pint(base.dimensionality.items()))


_ONE = Unit("1", 1.0, from_pint(()))


def _names(parsed) -> list[str]:
    return [str(name) for name in parsed._units]


def _offset(text: str, where: str) -> ModelError:
    return ModelError(
        f"{text!r} has a unit with an offset (degC, degF): a model's quantities are "
        "differences and products, give kelvin (K) instead",
        field=where,
    )


def _unknown(error, registry) -> str:
    """'unknown unit 'parsecz' (did you mean 'parsec'?)'."""
    name = str(getattr(error, "unit_names", None) or error).strip("'\"()[], ")
    known = set(registry._units) | {d.symbol for d in registry._units.values() if d.symbol}
    close = difflib.get_close_matches(name, sorted(known), n=1)
    hint = f" (did you mean '{close[0]}'?)" if close else ""
    return f"unknown unit '{name}'{hint}"


def _check_text(text: str, where: str) -> None:
    """Refuse text pint should not read: too long, odd characters, long numbers in units."""
    if not isinstance(text, str):
        raise ModelError(f"expected text with a unit, got {type(text).__name__}", field=where)
    if len(text) > MAX_TEXT:
        raise ModelError(f"a value with a unit is at most {MAX_TEXT} characters", field=where)
    match = _NUMBER.fullmatch(text)
    unit = match[2] if match else text
    if not _ALLOWED.fullmatch(unit) or "__" in unit:
        raise ModelError(f"{text!r} is not a number with a unit", field=where)
    if _LONG_NUMBER.search(unit):
        raise ModelError(f"{text!r}: exponents in a unit have at most two digits", field=where)
