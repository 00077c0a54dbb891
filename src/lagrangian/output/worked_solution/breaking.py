"""Long equations broken where a teacher breaks them: between the terms of a sum.

A line of a printed page holds about :data:`LINE_WIDTH` characters of mathematics (the
right-hand side of an ``align*`` row in an 11 pt A4 page with 2.5 cm margins).  The
LaTeX of an expression is cut before each ``+`` or ``-`` of its outermost sum, and the
terms are packed greedily into lines no wider than that; what is still too wide (one
term, a matrix) the LaTeX document scales down to the line (its ``\\fit`` macro), so
nothing runs into the margin.

The width of a piece of LaTeX is estimated from what it shows (:func:`visible_width`):
a fraction is as wide as the wider of its numerator and denominator, a superscript
counts 0.7, ``\\left(`` counts its parenthesis only, a function name its letters.
"""

from __future__ import annotations

import re

from ..latex import top_level_terms

#: Characters of mathematics a broken line holds (right-hand sides).
LINE_WIDTH = 56.0
#: Commands that show nothing of their own.
_INVISIBLE = frozenset(
    {"left", "right", "displaystyle", "textstyle", "limits", "big", "Big", "bigl", "bigr"}
)
#: Commands whose one argument is what they show.
_ACCENTS = frozenset(
    {
        "dot",
        "ddot",
        "dddot",
        "hat",
        "bar",
        "vec",
        "tilde",
        "mathrm",
        "mathbf",
        "mathcal",
        "mathit",
        "boldsymbol",
        "operatorname",
        "text",
        "overline",
    }
)
_FRACTIONS = frozenset({"frac", "dfrac", "tfrac"})
_SPACES = {",": 0.3, ":": 0.35, ";": 0.4, " ": 0.5, "quad": 2.0, "qquad": 4.0, "!": -0.2}
_TOKEN = re.compile(r"\\[A-Za-z]+|\\.|[{}^_]|\s+|.")
_OPERATORS = frozenset("+-=<>")


def broken_lines(latex: str, width: float = LINE_WIDTH) -> list[str]:
    """``latex`` as lines of at most ``width`` (estimated), cut between terms of its sum;
    a single term wider than that stays one line (the document scales it)."""
    if visible_width(latex) <= width:
        return [latex]
    lines: list[str] = []
    for term in top_level_terms(latex):
        if lines and visible_width(lines[-1] + " " + term) <= width:
            lines[-1] = f"{lines[-1]} {term}"
        else:
            lines.append(term)
    return lines


def visible_width(latex: str) -> float:
    """About how many characters wide ``latex`` is when typeset (see the module)."""
    tokens = [t for t in _TOKEN.findall(latex) if not t.isspace()]
    width, _ = _sequence(tokens, 0)
    return width


def _sequence(tokens: list[str], i: int) -> tuple[float, int]:
    """The width of the tokens from ``i`` to the closing brace of their group (or the end)."""
    total = 0.0
    while i < len(tokens) and tokens[i] != "}":
        width, i = _item(tokens, i)
        total += width
    return total, i + 1


def _item(tokens: list[str], i: int) -> tuple[float, int]:
    """The width of the item that starts at ``i`` and the index after it."""
    token = tokens[i]
    if token == "{":
        return _sequence(tokens, i + 1)
    if token in ("^", "_"):
        width, j = _argument(tokens, i + 1)
        return 0.7 * width, j
    if token.startswith("\\") and len(token) > 1:
        name = token[1:]
        if name in _FRACTIONS:
            top, j = _argument(tokens, i + 1)
            bottom, j = _argument(tokens, j)
            return max(top, bottom) + 0.4, j
        if name in _ACCENTS:
            return _argument(tokens, i + 1)
        if name in ("begin", "end"):
            _, j = _argument(tokens, i + 1)
            return 0.0, j
        if name == "sqrt":
            width, j = _argument(tokens, i + 1)
            return width + 1.0, j
        if name in _SPACES:
            return _SPACES[name], i + 1
        if name in _INVISIBLE:
            return 0.0, i + 1
        if len(name) > 1 and name.islower() and name in _FUNCTIONS:
            return float(len(name)), i + 1
        return 1.0, i + 1  # a Greek letter, an escaped brace, \cdot, \partial
    if token in _OPERATORS:
        return 2.0, i + 1
    return 1.0, i + 1


def _argument(tokens: list[str], i: int) -> tuple[float, int]:
    if i >= len(tokens):
        return 0.0, i
    return _item(tokens, i)


_FUNCTIONS = frozenset(
    ("sin", "cos", "tan", "cot", "sec", "csc", "sinh", "cosh", "tanh", "coth", "arcsin",
     "arccos", "arctan", "exp", "log", "ln", "det", "min", "max")
)  # fmt: skip
