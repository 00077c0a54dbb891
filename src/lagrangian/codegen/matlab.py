"""MATLAB / GNU Octave: one function file returning a struct of function handles,
printed by SymPy's Octave code printer (whose output is also MATLAB).

    model = NAME();                  % NAME: the file's name, NAME.m
    M = model.mass_matrix(t, y, params, u);       % n x n
    f = model.forcing(t, y, params, u);           % n x 1
    dydt = model.rhs(t, y, params, u);            % [q'; q''] = [q'; M \\ f]
    [t, y] = ode45(@(t, y) model.rhs(t, y, model.default_params), [0 10], y0);

``params`` and ``u`` may be omitted or empty (defaults, and every input 0).
Indices start at 1; vectors are columns.
"""

from __future__ import annotations

import re
from pathlib import Path

import sympy
from sympy.printing.octave import OctaveCodePrinter, known_fcns_src1, known_fcns_src2

from ..errors import ModelError, setting
from .comments import MATLAB_COMMENT, commented
from .header import default_values, header_lines
from .literals import FloatLiterals
from .program import Program, Routine
from .target import VECTORS, AbstractTarget

#: Keywords of MATLAB (``iskeyword``) and of GNU Octave: no function can be named by one.
KEYWORDS = frozenset(
    """
    break case catch classdef continue else elseif end for function global if otherwise
    parfor persistent return spmd switch try while arguments do until unwind_protect
    unwind_protect_cleanup end_try_catch end_unwind_protect endclassdef endenumeration
    endevents endfor endfunction endif endmethods endparfor endproperties endspmd
    endswitch endwhile enumeration events methods properties __FILE__ __LINE__
    """.split()  # noqa: SIM905 - a list of words
)

#: Built-ins a generated file may call: the functions and constants SymPy's Octave
#: printer writes, and those of the file's own code.  A function file named like one
#: shadows it for every caller on the path, and inside the file a call of it would call
#: the file's own function.
BUILTINS = frozenset(
    {*known_fcns_src1, *known_fcns_src2.values(), "sqrt", "pi", "e", "i", "j", "inf", "Inf",
     "nan", "NaN", "eps", "true", "false", "zeros", "nargin", "isempty"}
)  # fmt: skip

#: The file's own functions (besides the main one, named after the file).
OWN_FUNCTIONS = frozenset({"default_params", "dynamics", "mass_matrix", "forcing", "rhs"})

#: The file's variables: indexed like calls (``y(1)``), but they shadow nothing.
_VARIABLES = frozenset({"model", "t", "y", "params", "u", "p", "M", "f", "A", "b", "K", "x"})

#: A name MATLAB can give a function: a letter, then letters, digits, underscores (63 at most).
_FUNCTION_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,62}")


class _Printer(FloatLiterals, OctaveCodePrinter):
    """SymPy's Octave printer, floats written to read back exactly."""


class MatlabTarget(AbstractTarget, name="matlab", language="MATLAB", suffix=".m", base=1):
    """The MATLAB function file (see the module docstring)."""

    element = "{argument}({index})"

    def __init__(self) -> None:
        self._printer = _Printer({"strict": True})

    def expression(self, expr: sympy.Expr) -> str:
        return self._printer.doprint(expr)

    def check_file_name(self, path: Path) -> None:
        if not _FUNCTION_NAME.fullmatch(path.stem):
            raise ModelError(
                f"a MATLAB function file needs a name that is an identifier (its function is "
                f"called by it), not {path.stem!r}",
                field=setting("path"),
            )
        _check_function_name(path.stem, called=BUILTINS | OWN_FUNCTIONS)

    def render(self, program: Program, name: str) -> str:
        calls = {
            "mass_matrix": "M = model.mass_matrix(t, y, params, u): n x n",
            "forcing": "f = model.forcing(t, y, params, u): n x 1",
            "rhs": "dydt = model.rhs(t, y, params, u): [q'; q''] (M \\ f)",
        }
        head = header_lines(program, "MATLAB / Octave", base=1, calls=calls, brackets="()")
        head += [
            f"Use: model = {name}(); then e.g.",
            "  [t, y] = ode45(@(t, y) model.rhs(t, y, model.default_params), [0 10], y0);",
            "params and u may be omitted or [] (default values; every input 0).",
        ]
        defaults = "; ".join(default_values(program, "NaN"))
        lines = [f"function model = {name}()"]
        lines += commented(head, MATLAB_COMMENT)
        lines += [
            f"model.coordinates = {{{', '.join(_quoted(q.name) for q in program.coordinates)}}};",
            f"model.parameters = {{{', '.join(_quoted(p.name) for p in program.parameters)}}};",
            f"model.inputs = {{{', '.join(_quoted(u.name) for u in program.inputs)}}};",
            "model.default_params = default_params();",
            "model.mass_matrix = @mass_matrix;",
            "model.forcing = @forcing;",
            "model.rhs = @rhs;",
            "end",
            "",
            "function p = default_params()",
            f"p = [{defaults}];" if defaults else "p = zeros(0, 1);",
            "end",
        ]
        lines += self._function("[M, f, A, b]" if program.constraints else "[M, f]",
                                "dynamics", program, program.dynamics)  # fmt: skip
        lines += self._function("M", "mass_matrix", program, program.mass_matrix)
        lines += self._function("f", "forcing", program, program.forcing)
        n, m = program.n, program.constraints
        lines += ["", "function dydt = rhs(t, y, params, u)"]
        lines += self._defaults(program)
        if m:
            lines += [
                "[M, f, A, b] = dynamics(t, y, params, u);",
                f"K = [M, -A.'; A, zeros({m}, {m})];",
                "x = K \\ [f; b];",
                f"dydt = [y({n + 1}:{2 * n}); x(1:{n})];",
            ]
        else:
            lines += [
                "[M, f] = dynamics(t, y, params, u);",
                f"dydt = [y({n + 1}:{2 * n}); M \\ f];",
            ]
        lines.append("end")
        _check_function_name(name, called=BUILTINS | OWN_FUNCTIONS | _calls(lines[1:]))
        return "\n".join(lines) + "\n"

    def _defaults(self, program: Program) -> list[str]:
        return [
            "if nargin < 3 || isempty(params)",
            "  params = default_params();",
            "end",
            "if nargin < 4 || isempty(u)",
            f"  u = zeros({len(program.inputs)}, 1);",
            "end",
        ]

    def _function(self, results: str, name: str, program: Program, routine: Routine) -> list[str]:
        lines = ["", f"function {results} = {name}(t, y, params, u)", *self._defaults(program)]
        lines += self.opening(program, routine, "{symbol} = {value};")
        for label, matrix in routine.outputs:
            vector = label in VECTORS
            lines.append(f"{label} = zeros({matrix.rows}, {1 if vector else matrix.cols});")
            for index, text in self.entries(matrix, vector=vector):
                lines.append(f"{label}({index}) = {text};")
        lines.append("end")
        return lines


def _check_function_name(name: str, called: frozenset[str] | set[str]) -> None:
    """Refuse a function name that is a keyword or that of a function the file calls."""
    if name in KEYWORDS:
        raise ModelError(f"the MATLAB function cannot be named {name!r}: it is a keyword")
    if name in called:
        raise ModelError(
            f"the MATLAB function cannot be named {name!r}: the file calls {name!r} (a "
            f"built-in or one of its own functions), which the name would shadow"
        )


def _calls(lines: list[str]) -> set[str]:
    """The functions the code calls: names before "(" outside comments, but its variables."""
    code = "\n".join(line for line in lines if not line.lstrip().startswith("%"))
    return set(re.findall(r"\b([A-Za-z]\w*)\(", code)) - _VARIABLES


def _quoted(name: str) -> str:
    return f"'{name}'"
