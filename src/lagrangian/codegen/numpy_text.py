"""Python with NumPy: one module, printed by SymPy's NumPy printer.

    mass_matrix(t, y, params=DEFAULT_PARAMS, u=None) -> M, (n, n)
    forcing(t, y, params=DEFAULT_PARAMS, u=None) -> f, (n,)
    rhs(t, y, params=DEFAULT_PARAMS, u=None) -> y' = [q', q''], (2n,)

``u=None`` means every input 0; ``rhs`` solves with ``numpy.linalg.solve`` and
fits ``scipy.integrate.solve_ivp(rhs, ..., args=(params,))``.
"""

from __future__ import annotations

import keyword
import sys
from pathlib import Path

import sympy
from sympy.printing.numpy import NumPyPrinter

from ..errors import ModelError, setting
from .comments import PYTHON_COMMENT, commented
from .header import call_lines, default_values, header_lines, name_constants
from .literals import FloatLiterals
from .program import Program, Routine
from .target import AbstractTarget

#: Modules a generated file imports, directly or through NumPy and SciPy (the standard
#: library's): a module file named like one is imported in its place from its folder.
SHADOWED = frozenset({"numpy", "scipy", *sys.stdlib_module_names})


class _Printer(FloatLiterals, NumPyPrinter):
    """SymPy's NumPy printer, floats written to read back exactly."""


class NumPyTextTarget(
    AbstractTarget, name="numpy", language="Python (NumPy)", suffix=".py", base=0
):
    """The Python module (see the module docstring)."""

    def __init__(self) -> None:
        self._printer = _Printer({"fully_qualified_modules": True, "strict": True})

    def expression(self, expr: sympy.Expr) -> str:
        return self._printer.doprint(expr)

    def check_file_name(self, path: Path) -> None:
        if path.suffix != ".py":
            return  # not importable as a module: no name to clash
        stem = path.stem
        if not stem.isidentifier() or keyword.iskeyword(stem):
            raise ModelError(
                f"a Python module needs a name that is an identifier and not a keyword "
                f"(import NAME), not {stem!r}",
                field=setting("path"),
            )
        if stem in SHADOWED:
            raise ModelError(
                f"a module named {stem!r} would be imported instead of Python's {stem!r} "
                f"(which the file and NumPy import): choose another name",
                field=setting("path"),
            )

    def render(self, program: Program, name: str) -> str:
        signature = "(t, y, params=DEFAULT_PARAMS, u=None)"
        calls = call_lines(signature, "shape (n, n)", "shape (n,)", "numpy.linalg.solve")
        head = header_lines(program, "Python (NumPy)", base=0, calls=calls)
        # the first line fixes the encoding: a comment there or on line 2 could declare one
        # (PEP 263), and a model named "coding: utf-7" would then decode "+AAo-" as a newline
        lines = ["# -*- coding: utf-8 -*-", *commented(head, PYTHON_COMMENT), ""]
        lines += ["import numpy", ""]
        defaults = ", ".join(default_values(program, "float('nan')"))
        lines += [
            *name_constants(program, "{name} = {value}", lambda names: repr(tuple(names))),
            f"DEFAULT_PARAMS = numpy.array([{defaults}], dtype=float)",
            "",
        ]
        lines += self._function("_dynamics", program, program.dynamics)
        lines += self._function("mass_matrix", program, program.mass_matrix)
        lines += self._function("forcing", program, program.forcing)
        n, m = program.n, program.constraints
        names = ", ".join(name for name, _ in program.dynamics.outputs)
        lines += [
            "",
            "def rhs(t, y, params=DEFAULT_PARAMS, u=None):",
            "    \"\"\"y' = [q', q'']: M q'' = f solved (with constraints: see the header).\"\"\"",
            f"    {names} = _dynamics(t, y, params, u)",
        ]
        if m:
            lines += [
                "    K = numpy.block([[M, -A.T], [A, numpy.zeros((A.shape[0], A.shape[0]))]])",
                f"    accelerations = numpy.linalg.solve(K, numpy.concatenate([f, b]))[:{n}]",
            ]
        else:
            lines.append("    accelerations = numpy.linalg.solve(M, f)")
        lines += [
            "    y = numpy.asarray(y, dtype=float)",
            f"    return numpy.concatenate([y[{n}:], accelerations])",
            "",
        ]
        return "\n".join(lines)

    def _function(self, name: str, program: Program, routine: Routine) -> list[str]:
        lines = ["", f"def {name}(t, y, params=DEFAULT_PARAMS, u=None):"]
        lines += self.opening(
            program, routine, "    {symbol} = {value}", no_input="0.0 if u is None else {value}"
        )
        statement = "    {label} = numpy.array({value}, dtype=float).reshape({shape})"
        outputs, results = self.literal_outputs(routine, statement)
        lines += outputs
        lines.append(f"    return {', '.join(results)}")
        return lines
