"""Text, LaTeX and JSON of a :class:`~lagrangian.analysis.state_space.StateSpace`.

The JSON is the additive key ``"state_space"`` of ``analyze --state-space --json``:

    {"point": {"theta": "pi"}, "states": ["x", "theta", "x_dot", "theta_dot"],
     "inputs": ["F"], "outputs": [...],
     "A": [["0", ...], ...], "B": ..., "C": ..., "D": ...,      # SymPy str() text
     "parameters": {"M": 1.0, ...},                            # the values used below
     "numeric": {"A": [[0.0, ...], ...], "B": ..., "C": ..., "D": ...}}

``numeric`` is null when a parameter the matrices use has no default value.
"""

from __future__ import annotations

import sympy

from ..analysis.state_space import StateSpace
from ..errors import ModelError
from .latex import latex_expression
from .notation import latex_name, unicode_name
from .text import unicode_expression

_MATRICES = ("A", "B", "C", "D")


def state_space_document(model: StateSpace) -> dict:
    """The ``"state_space"`` value of ``analyze --state-space --json`` (module docstring)."""
    document: dict = {
        "point": {name: str(value) for name, value in model.point.items()},
        "states": list(model.states),
        "inputs": list(model.inputs),
        "outputs": list(model.outputs),
    }
    for name in _MATRICES:
        document[name] = _entries(getattr(model, name))
    used = model.parameters
    document["parameters"] = {name: model.values[name] for name in used if name in model.values}
    try:
        numbers = model.numeric()
    except ModelError:
        document["numeric"] = None
    else:
        document["numeric"] = {name: getattr(numbers, name).tolist() for name in _MATRICES}
    return document


def format_state_space(model: StateSpace) -> str:
    """The matrices as readable text, one row per line, with the names of x, u and y."""
    system = model.system
    show = lambda entry: unicode_expression(entry, system)  # noqa: E731
    point = ", ".join(f"{unicode_name(k)} = {show(v)}" for k, v in model.point.items())
    lines = [
        f"State space x' = A x + B u, y = C x + D u about {point or 'the origin'}",
        "  x = (" + ", ".join(unicode_name(s) for s in model.states) + ")",
        "  u = (" + ", ".join(unicode_name(s) for s in model.inputs) + ")",
        "  y = (" + ", ".join(unicode_name(s) for s in model.outputs) + ")",
    ]
    for name in _MATRICES:
        matrix = getattr(model, name)
        lines.append(f"{name} ({matrix.rows} x {matrix.cols}):")
        if matrix.rows == 0 or matrix.cols == 0:
            lines.append("  (empty)")
            continue
        cells = [[show(entry) for entry in matrix.row(i)] for i in range(matrix.rows)]
        widths = [max(len(row[j]) for row in cells) for j in range(matrix.cols)]
        for row in cells:
            lines.append(
                "  [ " + "  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) + " ]"
            )
    return "\n".join(lines)


def latex_state_space(model: StateSpace) -> str:
    """A, B, C, D as ``bmatrix`` blocks in one ``align*``."""
    system = model.system
    rows = []
    for name in _MATRICES:
        matrix = getattr(model, name)
        if matrix.rows == 0 or matrix.cols == 0:
            rows.append(rf"{name} &= \text{{(empty)}}")
            continue
        body = r" \\ ".join(
            " & ".join(latex_expression(entry, system) for entry in matrix.row(i))
            for i in range(matrix.rows)
        )
        rows.append(rf"{name} &= \begin{{bmatrix}} {body} \end{{bmatrix}}")
    state = ", ".join(latex_name(s) for s in model.states)
    rows.append(rf"x &= ({state})")
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def _entries(matrix: sympy.MatrixBase) -> list[list[str]]:
    return [[str(entry) for entry in matrix.row(i)] for i in range(matrix.rows)]
