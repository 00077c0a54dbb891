"""The LaTeX of a worked solution's expressions: printed once with the toolkit's notation
(:func:`~lagrangian.output.large.latex_printer`), broken into lines (:mod:`.breaking`),
folded after :data:`MAX_ROW_LINES` lines, and named rather than printed when too long
to read."""

from __future__ import annotations

from ...algebra import as_expression
from ...model import System
from ..large import latex_printer
from ..latex import top_level_terms
from ..notation import too_long_to_print
from .breaking import LINE_WIDTH, broken_lines
from .document import Row

TOO_LONG = r"\text{too long to print; derive --json gives it}"
#: Lines a row shows at most (twice the longest of the built-in examples' rows): a longer
#: one shows its first lines, then how many terms it leaves out, never pages of one sum.
MAX_ROW_LINES = 8


class Shower:
    """LaTeX of expressions: printed once, broken into lines, named when too long."""

    def __init__(self, system: System) -> None:
        self._print = latex_printer(system)

    def __call__(self, expr) -> str:
        return TOO_LONG if too_long_to_print(as_expression(expr)) else self._print(expr)

    def row(self, lhs: str, expr, note=(), width: float = LINE_WIDTH) -> Row:
        return Row(lhs, folded(broken_lines(self(expr), width)), note=note)


def folded(lines: list[str]) -> tuple[str, ...]:
    """``lines`` (a broken sum), the first MAX_ROW_LINES - 1 of them and a last one that
    says how many terms are left out, where there are more than MAX_ROW_LINES."""
    if len(lines) <= MAX_ROW_LINES:
        return tuple(lines)
    left = sum(len(top_level_terms(line)) for line in lines[MAX_ROW_LINES - 1 :])
    said = rf"+ \cdots \quad \text{{({left} more terms; the --json output gives them)}}"
    return (*lines[: MAX_ROW_LINES - 1], said)
