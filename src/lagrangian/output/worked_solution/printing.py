"""The LaTeX of a worked solution's expressions: printed once with the toolkit's notation
(:func:`~lagrangian.output.large.latex_printer`), broken into lines (:mod:`.breaking`),
and named rather than printed when too long to read."""

from __future__ import annotations

from ...algebra import as_expression
from ...model import System
from ..large import latex_printer
from ..notation import too_long_to_print
from .breaking import LINE_WIDTH, broken_lines
from .document import Row

TOO_LONG = r"\text{too long to print; derive --json gives it}"


class Shower:
    """LaTeX of expressions: printed once, broken into lines, named when too long."""

    def __init__(self, system: System) -> None:
        self._print = latex_printer(system)

    def __call__(self, expr) -> str:
        return TOO_LONG if too_long_to_print(as_expression(expr)) else self._print(expr)

    def row(self, lhs: str, expr, note=(), width: float = LINE_WIDTH) -> Row:
        return Row(lhs, tuple(broken_lines(self(expr), width)), note=note)
