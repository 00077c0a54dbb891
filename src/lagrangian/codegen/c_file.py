"""C99: one self-contained ``.c`` file (``#include <math.h>`` only), printed by SymPy's
C99 code printer
(:class:`lagrangian.codegen.c.CPrinter`).

    void mass_matrix(double t, const double *y, const double *params, const double *u,
                     double *M);                              M row-major, n x n
    void forcing(double t, const double *y, const double *params, const double *u, double *f);
    int rhs(double t, const double *y, const double *params, const double *u, double *dydt);

``u`` may be NULL (every input 0).  ``rhs`` solves the linear system by Gaussian
elimination with partial pivoting (:func:`lagrangian.codegen.c.gaussian_elimination`,
written out in the file, no LAPACK) and returns 0,
or 1 when the matrix is singular (``dydt`` is then left unspecified).
``default_params`` holds the default parameter values (NAN where the model has none).
"""

from __future__ import annotations

import sympy

from .c import CPrinter, gaussian_elimination
from .comments import C_COMMENT, commented
from .header import default_values, header_lines
from .program import Program, Routine
from .target import AbstractTarget

_ARGUMENTS = "double t, const double *y, const double *params, const double *u"


class CTarget(AbstractTarget, name="c", language="C", suffix=".c", base=0):
    """The C99 file (see the module docstring)."""

    comment = " *"

    def __init__(self) -> None:
        self._printer = CPrinter()

    def expression(self, expr: sympy.Expr) -> str:
        return self._printer.doprint(expr)

    def render(self, program: Program, name: str) -> str:
        n, size, m = program.n, program.size, program.constraints
        calls = {
            "mass_matrix": f"void mass_matrix({_ARGUMENTS}, double *M): M (n x n, row-major)",
            "forcing": f"void forcing({_ARGUMENTS}, double *f): f (n)",
            "rhs": f"int rhs({_ARGUMENTS}, double *dydt): y' = [q', q'']; 0, or 1 if singular",
        }
        head = header_lines(program, "C99", base=0, calls=calls)
        head.append("u may be NULL (every input 0). Compile: cc -O2 -c FILE.c (link with -lm).")
        parts = [*commented(head, C_COMMENT), ""]
        parts += ["#include <math.h>", "#include <stddef.h>", ""]
        parts += [
            f"#define LAGRANGIAN_N_COORDINATES {n}",
            f"#define LAGRANGIAN_N_PARAMETERS {len(program.parameters)}",
            f"#define LAGRANGIAN_N_INPUTS {len(program.inputs)}",
            f"#define LAGRANGIAN_N_CONSTRAINTS {m}",
            "",
        ]
        defaults = default_values(program, "NAN")
        parts.append(
            f"const double default_params[{max(len(defaults), 1)}] = "
            f"{{{', '.join(defaults) or '0.0'}}};"
        )
        parts.append("")
        blocks = ", ".join(f"double *{name}" for name, _ in program.dynamics.outputs)
        parts += self._function(f"static void dynamics({_ARGUMENTS}, {blocks})", program,
                                program.dynamics)  # fmt: skip
        parts += self._function(f"void mass_matrix({_ARGUMENTS}, double *M)", program,
                                program.mass_matrix)  # fmt: skip
        parts += self._function(f"void forcing({_ARGUMENTS}, double *f)", program, program.forcing)
        solved_size = size if m else n
        parts += [gaussian_elimination("solve_linear", solved_size, self._printer)]
        parts += [f"int rhs({_ARGUMENTS}, double *dydt)", "{"]
        names = [name for name, _ in program.dynamics.outputs]
        parts.append(f"    double M[{n * n}], f[{n}];")
        if m:
            parts.append(f"    double A[{m * n}], b[{m}], K[{size * size}], x[{size}];")
        parts.append(f"    dynamics(t, y, params, u, {', '.join(names)});")
        if m:
            parts += [
                f"    for (int i = 0; i < {size}; ++i) {{",
                f"        for (int j = 0; j < {size}; ++j) {{",
                "            double entry = 0.0;",
                f"            if (i < {n} && j < {n}) entry = M[i * {n} + j];",
                f"            else if (i < {n}) entry = -A[(j - {n}) * {n} + i];",
                f"            else if (j < {n}) entry = A[(i - {n}) * {n} + j];",
                f"            K[i * {size} + j] = entry;",
                "        }",
                f"        x[i] = i < {n} ? f[i] : b[i - {n}];",
                "    }",
                "    if (solve_linear(K, x, x, 0)) return 1;",
            ]
            solved = "x"
        else:
            parts.append("    if (solve_linear(M, f, f, 0)) return 1;")
            solved = "f"
        parts += [
            f"    for (int i = 0; i < {n}; ++i) {{",
            f"        dydt[i] = y[{n} + i];",
            f"        dydt[{n} + i] = {solved}[i];",
            "    }",
            "    return 0;",
            "}",
            "",
        ]
        return "\n".join(parts)

    def _function(self, signature: str, program: Program, routine: Routine) -> list[str]:
        lines = [signature, "{"]
        used = self.used_symbols(routine)
        for index, quantity in self.state_and_parameters(program):
            if quantity.symbol in used:
                lines.append(f"    const double {quantity.symbol} = {index};")
        for i, quantity in enumerate(program.inputs):
            if quantity.symbol in used:
                lines.append(f"    const double {quantity.symbol} = u ? u[{i}] : 0.0;")
        if program.time not in used:
            lines.append("    (void)t;")
        for argument, group in (("y", (*program.coordinates, *program.velocities)),
                                ("params", program.parameters), ("u", program.inputs)):  # fmt: skip
            if not any(q.symbol in used for q in group):
                lines.append(f"    (void){argument};")
        for symbol, expr in routine.temporaries:
            lines.append(f"    const double {symbol} = {self.expression(expr)};")
        for name, matrix in routine.outputs:
            for k, entry in enumerate(matrix):
                lines.append(f"    {name}[{k}] = {self.expression(entry)};")
        return [*lines, "}", ""]

    def state_and_parameters(self, program: Program):
        """(C text of the value, quantity) of every state entry and parameter."""
        for i, quantity in enumerate((*program.coordinates, *program.velocities)):
            yield f"y[{i}]", quantity
        for i, quantity in enumerate(program.parameters):
            yield f"params[{i}]", quantity
