"""Julia: one file of plain functions (``include("model.jl")``), printed by SymPy's Julia
code printer.

    mass_matrix(t, y, params=DEFAULT_PARAMS, u=DEFAULT_INPUTS) -> M, n x n
    forcing(t, y, params=DEFAULT_PARAMS, u=DEFAULT_INPUTS) -> f, length n
    rhs(t, y, params=DEFAULT_PARAMS, u=DEFAULT_INPUTS) -> y' = [q', q''] (M \\ f)

Arrays are allocated with the element type of the arguments, so automatic
differentiation (ForwardDiff's dual numbers) goes through.  Indices start at 1.
"""

from __future__ import annotations

import sympy
from sympy.printing.julia import JuliaCodePrinter

from .comments import JULIA_COMMENT, commented
from .header import default_values, header_lines, name_constants
from .literals import FloatLiterals
from .program import Program, Routine
from .target import VECTORS, AbstractTarget

_ARGUMENTS = "t, y, params=DEFAULT_PARAMS, u=DEFAULT_INPUTS"


class _Printer(FloatLiterals, JuliaCodePrinter):
    """SymPy's Julia printer, with atan2(y, x) written as Julia's atan(y, x)."""

    def _print_atan2(self, expr) -> str:
        y, x = expr.args
        return f"atan({self._print(y)}, {self._print(x)})"


class JuliaTarget(AbstractTarget, name="julia", language="Julia", suffix=".jl", base=1):
    """The Julia file (see the module docstring)."""

    def __init__(self) -> None:
        self._printer = _Printer({"strict": True})

    def expression(self, expr: sympy.Expr) -> str:
        return self._printer.doprint(expr)

    def render(self, program: Program, name: str) -> str:
        calls = {
            "mass_matrix": f"mass_matrix({_ARGUMENTS}) -> M (n x n)",
            "forcing": f"forcing({_ARGUMENTS}) -> f (length n)",
            "rhs": f"rhs({_ARGUMENTS}) -> y' = [q', q''] (M \\ f)",
        }
        head = header_lines(program, "Julia", base=1, calls=calls)
        lines = commented(head, JULIA_COMMENT)
        defaults = ", ".join(default_values(program, "NaN"))
        lines += [
            "",
            *name_constants(program, "const {name} = {value}", _strings),
            f"const DEFAULT_PARAMS = Float64[{defaults}]",
            f"const DEFAULT_INPUTS = zeros({len(program.inputs)})",
        ]
        lines += self._function("_dynamics", program, program.dynamics)
        lines += self._function("mass_matrix", program, program.mass_matrix)
        lines += self._function("forcing", program, program.forcing)
        n, m = program.n, program.constraints
        names = ", ".join(label for label, _ in program.dynamics.outputs)
        lines += ["", f"function rhs({_ARGUMENTS})", f"    {names} = _dynamics(t, y, params, u)"]
        if m:
            lines += [
                f"    K = vcat(hcat(M, -transpose(A)), hcat(A, zeros(eltype(A), {m}, {m})))",
                f"    accelerations = (K \\ vcat(f, b))[1:{n}]",
            ]
        else:
            lines.append("    accelerations = M \\ f")
        lines += [f"    return vcat(y[{n + 1}:{2 * n}], accelerations)", "end", ""]
        return "\n".join(lines)

    def _function(self, name: str, program: Program, routine: Routine) -> list[str]:
        lines = ["", f"function {name}({_ARGUMENTS})"]
        lines.append("    T = promote_type(eltype(y), eltype(params), eltype(u), typeof(t))")
        lines += self.opening(program, routine, "    {symbol} = {value}")
        labels = []
        for label, matrix in routine.outputs:
            vector = label in VECTORS
            size = f"{matrix.rows}" if vector else f"{matrix.rows}, {matrix.cols}"
            lines.append(f"    {label} = zeros(T, {size})")
            for index, text in self.entries(matrix, vector=vector):
                lines.append(f"    {label}[{index}] = {text}")
            labels.append(label)
        lines += [f"    return {', '.join(labels)}", "end"]
        return lines


def _strings(names: list[str]) -> str:
    return "String[" + ", ".join(f'"{name}"' for name in names) + "]"
