"""What a fit compares with the data: coordinates, velocities, or expressions of them.

An observed expression h(t, q, q', p) is given as ``NAME = EXPR`` (``"x_tip =
l*sin(theta)"``) or as ``{NAME: EXPR}``, read by the safe parser (never evaluated as
Python) over the model's coordinates, velocities, parameters and ``t``.  A fit needs h
along a motion and, for its Jacobian by the chain rule,

    dh/dw = (dh/dy) (dy/dw) + dh/dp_w,

with dy/dw the sensitivities (:mod:`.sensitivity`) and dh/dy, dh/dp the symbolic
gradients made here once.  A measured coordinate or velocity is the expression that is
its own symbol.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import sympy

from ..errors import ModelError, ParseError, setting
from ..parsing import Namespace, parse_expression
from ..parsing.names import name_problem
from ..symbols import TIME_NAME, time_symbol

if TYPE_CHECKING:
    from ..model import System


def observed_expressions(system: System, observe: Mapping[str, str] | Sequence[str]) -> dict:
    """name -> SymPy expression of each observed expression: ``observe`` is a mapping
    name -> text, or texts ``"NAME = EXPR"``.  A ModelError names a bad one."""
    pairs = list(observe.items()) if isinstance(observe, Mapping) else [_split(t) for t in observe]
    symbols = _symbols(system)
    found = {}
    for name, text in pairs:
        where = f"{setting('observe')} {name}"
        problem = name_problem(name) if name else "an empty name"
        if problem is not None:
            raise ModelError(f"the name of an observed expression: {problem}", field=where)
        if name in symbols or name in found:
            raise ModelError(
                f"'{name}' is already a name of the model or of another observed expression; "
                "give the expression a new name",
                field=where,
            )
        if not isinstance(text, str):
            raise ModelError(f"expected an expression as text, got {text!r}", field=where)
        try:
            expression = parse_expression(text, Namespace(symbols=symbols))
        except ParseError as error:
            raise ModelError(str(error), field=where, text=text) from None
        found[name] = expression
    return found


def _split(text: str) -> tuple[str, str]:
    if not isinstance(text, str) or text.count("=") != 1:
        raise ModelError(
            f"an observed expression is 'NAME = EXPR', e.g. 'x_tip = l*sin(theta)', not {text!r}",
            field=setting("observe"),
        )
    name, expression = text.split("=")
    return name.strip(), expression.strip()


def _symbols(system: System) -> dict[str, sympy.Expr]:
    symbols = {c.q.name: c.q for c in system.coordinates}
    symbols |= {c.q_dot.name: c.q_dot for c in system.coordinates}
    symbols |= {p.name: p.symbol for p in system.parameters}
    symbols[TIME_NAME] = time_symbol()
    return symbols


@dataclass(frozen=True)
class Observation:
    """The observed columns, in order, with h, dh/dy and dh/dp compiled (NumPy, vectorised
    over the times): ``evaluate(t, states, p)`` -> h (m, c), dh/dy (m, c, 2n), dh/dp
    (m, c, number of parameters)."""

    names: tuple[str, ...]
    expressions: tuple[sympy.Expr, ...]
    function: object
    size: int
    parameters: int

    def evaluate(
        self, t: np.ndarray, states: np.ndarray, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        m, c = t.shape[0], len(self.names)
        flat = self.function(t, *states.T, *p)
        values = np.empty((m, c * (1 + self.size + self.parameters)))
        for j, value in enumerate(flat):
            values[:, j] = value  # a constant entry broadcasts over the times
        h = values[:, :c]
        dy = values[:, c : c * (1 + self.size)].reshape(m, c, self.size)
        dp = values[:, c * (1 + self.size) :].reshape(m, c, self.parameters)
        return h, dy, dp


def observation(system: System, columns: Sequence[str], expressions: Mapping) -> Observation:
    """The :class:`Observation` of the measured ``columns``: each a coordinate, a velocity
    or a name of ``expressions`` (name -> SymPy expression)."""
    symbols = _symbols(system)
    state = [c.q for c in system.coordinates] + [c.q_dot for c in system.coordinates]
    parameters = [p.symbol for p in system.parameters]
    chosen = []
    for name in columns:
        if name in expressions:
            chosen.append(expressions[name])
        elif name in symbols and symbols[name] in state:
            chosen.append(symbols[name])
        else:
            raise ModelError(f"'{name}' is neither a coordinate, a velocity nor observed")
    gradients_y = [sympy.diff(h, s) for h in chosen for s in state]
    gradients_p = [sympy.diff(h, s) for h in chosen for s in parameters]
    arguments = [time_symbol(), *state, *parameters]
    function = sympy.lambdify(arguments, [*chosen, *gradients_y, *gradients_p], modules="numpy")
    return Observation(tuple(columns), tuple(chosen), function, len(state), len(parameters))
