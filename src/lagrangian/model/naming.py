"""The naming rules of a model: coordinate names and parameter entries."""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Mapping, Sequence

from ..errors import LikelyTypoWarning, ModelError
from ..parsing import BUILTIN_CONSTANTS, BUILTIN_FUNCTIONS
from ..parsing.suggest import Slips
from ..symbols import (
    ACCELERATION_SUFFIX,
    TIME_NAME,
    VELOCITY_SUFFIX,
    Coordinate,
    is_identifier,
)
from .system import PARAMETER_SIGNS
from .values import SIGN_BREAKS

#: Names a model may not declare: time and the expression language's built-ins.
RESERVED = frozenset({TIME_NAME, *BUILTIN_FUNCTIONS, *BUILTIN_CONSTANTS})


def coordinates_named(names: Sequence[str]) -> tuple[Coordinate, ...]:
    if isinstance(names, str) or not isinstance(names, Sequence) or not names:
        raise ModelError("expected a non-empty list of coordinate names", field="coordinates")
    seen: set[str] = set()
    coordinates = []
    for name in names:
        if not isinstance(name, str) or not is_identifier(name):
            raise ModelError(f"invalid coordinate name {name!r}", field="coordinates")
        if name in RESERVED:
            raise ModelError(
                f"'{name}' is reserved and cannot be a coordinate", field="coordinates"
            )
        if name.endswith((VELOCITY_SUFFIX, ACCELERATION_SUFFIX)):
            raise ModelError(
                f"coordinate '{name}' must not end in {VELOCITY_SUFFIX} or {ACCELERATION_SUFFIX}",
                field="coordinates",
            )
        if name in seen:
            raise ModelError(f"coordinate '{name}' is listed twice", field="coordinates")
        seen.add(name)
        coordinates.append(Coordinate.named(name))
    clashes = seen & {c.q_dot.name for c in coordinates} | seen & {
        c.q_ddot.name for c in coordinates
    }
    if clashes:
        raise ModelError(f"coordinate names clash: {sorted(clashes)}", field="coordinates")
    return tuple(coordinates)


def parameter_entry(entry: object, where: str) -> tuple[float | None, str]:
    """(default value, sign) of one parameter entry."""
    sign = None
    value = entry
    if isinstance(entry, Mapping):
        unknown = set(entry) - {"value", "sign"}
        if unknown:
            raise ModelError(f"unknown key(s) {sorted(unknown)}; expected value, sign", field=where)
        value = entry.get("value")
        sign = entry.get("sign")
        if sign is not None and sign not in PARAMETER_SIGNS:
            raise ModelError(
                f"sign must be one of {', '.join(PARAMETER_SIGNS)}", field=where, text=str(sign)
            )
    if value is not None:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ModelError(f"expected a number, got {value!r}", field=where)
        if not math.isfinite(value):
            raise ModelError(f"expected a finite number, got {value!r}", field=where)
        value = float(value)
    if sign is None:
        sign = "positive" if value is None or value > 0 else "real"
    breaks = SIGN_BREAKS.get(sign)
    if value is not None and breaks is not None and breaks(value):  # as for values given later
        raise ModelError(f"value {value} contradicts sign '{sign}'", field=where)
    return value, sign


def warn_of_likely_typos(
    parameters: Iterable[str],
    coordinates: Sequence[Coordinate],
    *,
    declared: bool,
    source: str | None = None,
) -> None:
    """Warn (:class:`~lagrangian.errors.LikelyTypoWarning`) of each parameter named like a
    slip for a coordinate, velocity or acceleration: ``xdot``, ``x_dott``, ``dx``, ``thetta``.

    A parameter is a constant, so a velocity misspelt as one gives equations of
    motion that are wrong without any error.  ``declared``: the user listed the
    name as a parameter (a model file); otherwise it became one by being used.
    """
    slips = Slips(name for c in coordinates for name in (c.name, c.q_dot.name, c.q_ddot.name))
    for name in parameters:
        meant = slips.meant(name)
        if meant is None:
            continue
        how = "is declared as a parameter" if declared else "is not declared and became a parameter"
        where = ": ".join(part for part in (source, f"parameters.{name}") if part)
        warnings.warn(
            f"{where}: '{name}' {how} (a constant); did you mean '{meant}'?",
            LikelyTypoWarning,
            stacklevel=4,
        )
