"""A surface of section g(t, q, q') = 0 written as text, and the axes a section is drawn on.

``"theta1 = 0"``, ``"x = y"``, ``"q1 + q2 = pi"``: two expressions of the model's
coordinates, velocities, parameters and t joined by one ``=``, each read by the safe
parser (:mod:`lagrangian.parsing`), never evaluated as Python; the section is
g = left - right = 0.  A crossing counts in the ``direction`` asked for: ``+`` where g
increases, ``-`` where it decreases, ``both``.  An angle that turns over crosses
``theta = 0`` only once; write ``sin(theta) = 0`` to cut it at every turn (and at pi).

The axes of the points are state variables: coordinates, velocities ``q_dot`` or
momenta ``p_q`` = dL/dq' (:mod:`lagrangian.symbols` names them).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import sympy

from ..errors import ModelError, ParseError
from ..parsing import Namespace, parse_expression
from ..symbols import momentum_name, time_symbol, velocity_name

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: --direction names -> the event direction of g.
DIRECTIONS = {"+": 1, "-": -1, "both": 0}


@dataclass(frozen=True)
class Section:
    """g = left - right of the text ``text``; ``coordinate`` is q when the text is
    ``q = <constant>`` (then the energy can be solved for q' on the section), else None."""

    text: str
    expression: sympy.Expr
    direction: int
    coordinate: str | None
    value: float | None
    function: Callable[[float, np.ndarray, np.ndarray], float]

    @property
    def direction_name(self) -> str:
        """The direction as it is given: ``+``, ``-`` or ``both``."""
        return next(name for name, sign in DIRECTIONS.items() if sign == self.direction)


def parse_section(compiled: CompiledSystem, text: str, direction: str = "+") -> Section:
    """The section ``text`` (``left = right``) of ``compiled``'s model; a ModelError names
    what is wrong (no ``=``, an unknown name, the position of a syntax error)."""
    if direction not in DIRECTIONS:
        raise ModelError(f"the direction must be one of {', '.join(DIRECTIONS)}, not {direction!r}")
    if not isinstance(text, str) or text.count("=") != 1:
        raise ModelError(
            f"a section is 'expression = expression' with one '=', e.g. 'x = 0', not {text!r}",
            field="section",
        )
    system = compiled.equations.system
    coordinates = [c.q for c in system.coordinates]
    velocities = [c.q_dot for c in system.coordinates]
    parameters = [p.symbol for p in system.parameters]
    symbols = {s.name: s for s in (*coordinates, *velocities, *parameters)}
    symbols["t"] = time_symbol()
    sides, offset = [], 0
    for side in text.split("="):
        try:
            sides.append(parse_expression(side, Namespace(symbols=symbols)))
        except ParseError as error:
            if error.position is not None:  # where it is in the whole text
                error = ParseError(error.message, text, error.position + offset)
            raise ModelError(str(error), field="section", text=text) from None
        offset += len(side) + 1
    left, right = sides
    expression = left - right
    state = (*coordinates, *velocities)
    if not expression.free_symbols & set(state):
        raise ModelError(f"the section {text!r} depends on no coordinate or velocity")
    evaluate = sympy.lambdify(section_arguments(system), expression, modules="math")
    size = len(state)

    def function(t: float, y: np.ndarray, params: np.ndarray) -> float:
        return float(evaluate(t, *y[:size], *params))

    constant = right.free_symbols.isdisjoint(state) and not right.has(time_symbol())
    coordinate = str(left) if left in coordinates and constant else None
    value = None
    if coordinate is not None:
        defaults = {p.symbol: compiled.default_parameters.get(p.name) for p in system.parameters}
        value = float(right.subs(defaults)) if right.free_symbols <= set(defaults) else None
    return Section(text, expression, DIRECTIONS[direction], coordinate, value, function)


def section_arguments(system) -> tuple[sympy.Symbol, ...]:
    """(t, q..., q_dot..., parameters...): the arguments of a section's function."""
    coordinates = [c.q for c in system.coordinates]
    velocities = [c.q_dot for c in system.coordinates]
    return (time_symbol(), *coordinates, *velocities, *(p.symbol for p in system.parameters))


def state_names(compiled: CompiledSystem) -> tuple[str, ...]:
    """q..., q_dot... of ``compiled``: the order of a state vector."""
    names = compiled.coordinate_names
    return (*names, *(velocity_name(q) for q in names))


def axis_values(
    compiled: CompiledSystem, names: Sequence[str], t: np.ndarray, y: np.ndarray, params
) -> np.ndarray:
    """The values (len(names), K) of coordinates, velocities or momenta p_q at the K states
    y (2n, K) and times t (K,)."""
    states = state_names(compiled)
    momenta = [momentum_name(q) for q in compiled.coordinate_names]
    unknown = [name for name in names if name not in states and name not in momenta]
    if unknown:
        known = ", ".join([*states, *momenta])
        raise ModelError(f"unknown axis '{unknown[0]}' (axes: {known})", field="axes")
    rows = []
    p = None
    for name in names:
        if name in states:
            rows.append(y[states.index(name)])
            continue
        if p is None:
            n = compiled.n
            p = np.asarray(compiled.momenta(t, y[:n], y[n:], params), dtype=float).reshape(n, -1)
        rows.append(p[momenta.index(name)])
    return np.array(rows, dtype=float).reshape(len(names), y.shape[1])
