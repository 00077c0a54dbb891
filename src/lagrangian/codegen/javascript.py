"""JavaScript: one ES module, printed by SymPy's JavaScript printer (for the browser page).

    mass_matrix(t, y, params = DEFAULT_PARAMS, u = null) -> M, n arrays of n numbers
    forcing(t, y, params = DEFAULT_PARAMS, u = null) -> f, n numbers
    rhs(t, y, params = DEFAULT_PARAMS, u = null) -> y' = [q', q''], 2n numbers

Plain functions over plain arrays (no dependency, no typed arrays required); ``u``
null or omitted means every input 0.  ``rhs`` solves M q'' = f (with constraints the
bordered system of :mod:`lagrangian.codegen.program`) by Gaussian elimination with
partial pivoting (the one every language prints,
:func:`lagrangian.codegen.steps.elimination`) and throws an ``Error`` where the
matrix is singular.  This module is the whole target: one class and one line in
:data:`lagrangian.codegen.TARGETS`.
"""

from __future__ import annotations

import json
import math
from typing import ClassVar

import sympy
from sympy.printing.jscode import JavascriptCodePrinter

from .comments import CommentStyle, commented
from .header import call_lines, default_values, header_lines, name_constants
from .literals import FloatLiterals
from .program import Program, Routine
from .steps import Assign, Function, If, Index, Loop, StepPrinter, elimination
from .target import AbstractTarget

#: Line comments: only a line break ends one (U+2028 and U+2029 are line breaks in
#: JavaScript, and :func:`~lagrangian.codegen.comments.commented` splits at them).
JAVASCRIPT_COMMENT = CommentStyle("", "// ", "", ())


class JavaScriptStepPrinter(StepPrinter):
    """Functions of :mod:`lagrangian.codegen.steps` as JavaScript (the linear solve)."""

    operators: ClassVar[dict[str, str]] = {"and": "&&", "or": "||", "==": "===", "!=": "!=="}
    end, absolute, indent = ";", "Math.abs", "  "

    def number(self, value) -> str:
        if isinstance(value, int):
            return str(value)
        return repr(float(value)) if math.isfinite(value) else f"{'-' * (value < 0)}Infinity"

    def choose(self, condition: str, then: str, otherwise: str) -> str:
        return f"({condition} ? {then} : {otherwise})"

    def index(self, node: Index) -> str:
        return self.expression(node.array) + "".join(
            f"[{self.top(self.expression(e))}]" for e in node.indices
        )

    def _assign(self, node: Assign, depth: int, pad: str) -> list[str]:
        kind = "" if node.kind is None else "let "
        target, value = self.expression(node.target), self.top(self.expression(node.value))
        return [f"{pad}{kind}{target} = {value};"]

    def _loop(self, node: Loop, depth: int, pad: str) -> list[str]:
        start, stop, index = self.bound(node.start), self.bound(node.stop), node.index
        head = f"{pad}for (let {index} = {start}; {index} < {stop}; {index}++) {{"
        return [head, *self.block(node.body, depth + 1), f"{pad}}}"]

    def _if(self, node: If, depth: int, pad: str) -> list[str]:
        head = f"{pad}if ({self.top(self.expression(node.condition))}) {{"
        return [head, *self.block(node.then, depth + 1), f"{pad}}}"]

    def function(self, function: Function) -> str:
        arguments = ", ".join(name for name, _ in function.arguments)
        return "\n".join(
            [f"function {function.name}({arguments}) {{", *self.block(function.body, 1), "}"]
        )


def _solve(size: int) -> str:
    """``solve(K, r)``: x with K x = r (K: ``size`` rows of numbers; K, r overwritten), by
    the printed elimination; an ``Error`` where K is singular."""
    return "\n".join([
        JavaScriptStepPrinter(size).function(elimination(size)),
        "",
        "function solve(K, r) {",
        f"  const x = new Array({size});",
        '  if (eliminate(K, r, x, 0)) throw new Error("singular mass matrix");',
        "  return x;",
        "}",
    ])  # fmt: skip


class _Printer(FloatLiterals, JavascriptCodePrinter):
    """SymPy's JavaScript printer, floats written to read back as the same double."""


class JavaScriptTarget(
    AbstractTarget, name="javascript", language="JavaScript", suffix=".mjs", base=0
):
    """The ES module (see the module docstring)."""

    def __init__(self) -> None:
        self._printer = _Printer({"strict": True})

    def expression(self, expr: sympy.Expr) -> str:
        return self._printer.doprint(expr)

    def render(self, program: Program, name: str) -> str:
        signature = "(t, y, params = DEFAULT_PARAMS, u = null)"
        calls = call_lines(signature, "n rows of n numbers", "n numbers", "Gaussian elimination")
        head = header_lines(program, "JavaScript (ES module)", base=0, calls=calls)
        lines = [*commented(head, JAVASCRIPT_COMMENT), ""]
        defaults = ", ".join(default_values(program, "NaN"))
        lines += [
            *name_constants(program, "export const {name} = {value};", _names),
            f"export const DEFAULT_PARAMS = [{defaults}];",
            "",
            _solve(program.n + program.constraints),
        ]
        # dynamics (M, f and the constraint rows at once) serves rhs; the others are exported
        lines += self.function("dynamics", program, program.dynamics, exported=False)
        for routine in (program.mass_matrix, program.forcing):
            lines += self.function(routine.name, program, routine)
        n, m = program.n, program.constraints
        names = ", ".join(label for label, _ in program.dynamics.outputs)
        lines += [
            "",
            f"export function rhs{signature} {{",
            f"  const [{names}] = dynamics(t, y, params, u);",
        ]
        if m:  # [[M, -A^T], [A, 0]] [q''; lambda] = [f; b]
            lines += [
                "  const K = [",
                "    ...M.map((row, i) => [...row, ...A.map((a) => -a[i])]),",
                f"    ...A.map((a) => [...a, ...new Array({m}).fill(0.0)]),",
                "  ];",
                f"  const accelerations = solve(K, [...f, ...b]).slice(0, {n});",
            ]
        else:
            lines.append("  const accelerations = solve(M, f);")
        lines += [f"  return [...Array.from(y).slice({n}, {2 * n}), ...accelerations];", "}", ""]
        return "\n".join(lines)

    def function(
        self, name: str, program: Program, routine: Routine, *, exported: bool = True
    ) -> list[str]:
        """The lines of ``function name(t, y, params = DEFAULT_PARAMS, u = null)``: an exported
        one returns its first output, the others the array of all outputs in order (how a
        page adds routines of its own, :meth:`Program.routine`, to the module)."""
        head = "export function" if exported else "function"
        lines = ["", f"{head} {name}(t, y, params = DEFAULT_PARAMS, u = null) {{"]
        lines += self.opening(
            program, routine, "  const {symbol} = {value};", no_input="u == null ? 0.0 : {value}"
        )
        outputs, results = self.literal_outputs(routine, "  const {label} = {value};")
        lines += outputs
        returned = results[0] if exported else "[" + ", ".join(results) + "]"
        lines += [f"  return {returned};", "}"]
        return lines


def _names(names: list[str]) -> str:
    """A JavaScript array of the model's names (JSON strings are JavaScript strings)."""
    return json.dumps(names, ensure_ascii=True)
