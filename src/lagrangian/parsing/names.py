"""What a name can mean: built-in functions and constants, declared symbols and functions.

Built-in names are reserved: a :class:`Namespace` may not redefine them, so
``pi`` is always the constant and ``sin`` always the function.  The tables of
Greek letters (Unicode characters and LaTeX commands) and of LaTeX function
commands also live here, so that both tokenizers spell names the same way.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import sympy
from sympy.core.function import UndefinedFunction

BUILTIN_FUNCTIONS: Mapping[str, tuple[Callable[..., sympy.Expr], int]] = MappingProxyType(
    {
        "sin": (sympy.sin, 1),
        "cos": (sympy.cos, 1),
        "tan": (sympy.tan, 1),
        "cot": (sympy.cot, 1),
        "sec": (sympy.sec, 1),
        "csc": (sympy.csc, 1),
        "asin": (sympy.asin, 1),
        "acos": (sympy.acos, 1),
        "atan": (sympy.atan, 1),
        "atan2": (sympy.atan2, 2),
        "sinh": (sympy.sinh, 1),
        "cosh": (sympy.cosh, 1),
        "tanh": (sympy.tanh, 1),
        "exp": (sympy.exp, 1),
        "log": (sympy.log, 1),
        "sqrt": (sympy.sqrt, 1),
        "Abs": (sympy.Abs, 1),
        "sign": (sympy.sign, 1),
    }
)
"""Name -> (SymPy function, number of arguments)."""

BUILTIN_CONSTANTS: Mapping[str, sympy.Expr] = MappingProxyType({"pi": sympy.pi, "E": sympy.E})

RESERVED_NAMES: frozenset[str] = frozenset(BUILTIN_FUNCTIONS) | frozenset(BUILTIN_CONSTANTS)
"""Names that a model may not declare."""

_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def name_problem(name: str) -> str | None:
    """Why ``name`` cannot be a declared name, or None when it can."""
    if not _NAME.match(name):
        return f"'{name}' is not a valid name (letters, digits and '_', starting with a letter)"
    if name in RESERVED_NAMES:
        return f"'{name}' is a built-in name"
    return None


def arity_message(name: str, expected: int, given: int) -> str:
    plural = "" if expected == 1 else "s"
    return f"{name}() takes {expected} argument{plural} ({given} given)"


@dataclass(frozen=True)
class DeclaredFunction:
    """An unspecified function of the model, e.g. a potential ``A(x, y, z)``.

    Written bare (``A``) it means ``function(*arguments)``; called, it takes
    exactly ``len(arguments)`` arguments.
    """

    function: UndefinedFunction
    arguments: tuple[sympy.Expr, ...]

    def __post_init__(self) -> None:
        if not isinstance(self.function, UndefinedFunction):
            raise TypeError(f"not an undefined SymPy function: {self.function!r}")
        arguments = tuple(self.arguments)
        if not all(isinstance(argument, sympy.Expr) for argument in arguments):
            raise TypeError(f"arguments of {self.function} must be SymPy expressions")
        object.__setattr__(self, "arguments", arguments)


@dataclass(frozen=True)
class Namespace:
    """The names an expression may use: ``symbols`` (values) and declared ``functions``.

    A name in both is a declared function: bare, it means the function applied
    to its declared arguments; called, it takes exactly that many arguments.
    """

    symbols: Mapping[str, sympy.Expr]
    functions: Mapping[str, DeclaredFunction] = field(default_factory=dict)

    def __post_init__(self) -> None:
        symbols = dict(self.symbols)
        functions = dict(self.functions)
        for name in (*symbols, *functions):
            problem = name_problem(name) if isinstance(name, str) else f"{name!r} is not a str"
            if problem is not None:
                raise ValueError(f"invalid namespace entry: {problem}")
        for name, value in symbols.items():
            if not isinstance(value, sympy.Expr):
                raise TypeError(f"symbol '{name}' must be a SymPy expression: {value!r}")
        for name, value in functions.items():
            if not isinstance(value, DeclaredFunction):
                raise TypeError(f"function '{name}' must be a DeclaredFunction: {value!r}")
        object.__setattr__(self, "symbols", MappingProxyType(symbols))
        object.__setattr__(self, "functions", MappingProxyType(functions))


LATEX_FUNCTIONS: Mapping[str, str] = MappingProxyType(
    {
        "sin": "sin",
        "cos": "cos",
        "tan": "tan",
        "cot": "cot",
        "sec": "sec",
        "csc": "csc",
        "arcsin": "asin",
        "arccos": "acos",
        "arctan": "atan",
        "sinh": "sinh",
        "cosh": "cosh",
        "tanh": "tanh",
        "exp": "exp",
        "ln": "log",
        "log": "log",
    }
)
"""LaTeX command (without backslash) -> built-in function name."""

_LOWER_GREEK = [
    "alpha",
    "beta",
    "gamma",
    "delta",
    "epsilon",
    "zeta",
    "eta",
    "theta",
    "iota",
    "kappa",
    "lambda",
    "mu",
    "nu",
    "xi",
    "omicron",
    "pi",
    "rho",
    "sigma",
    "tau",
    "upsilon",
    "phi",
    "chi",
    "psi",
    "omega",
]
_UPPER_GREEK = [
    "Gamma",
    "Delta",
    "Theta",
    "Lambda",
    "Xi",
    "Pi",
    "Sigma",
    "Upsilon",
    "Phi",
    "Psi",
    "Omega",
]
_VARIANT_GREEK = ["varepsilon", "vartheta", "varkappa", "varpi", "varrho", "varsigma", "varphi"]

LATEX_GREEK: Mapping[str, str] = MappingProxyType(
    {name: name for name in (*_LOWER_GREEK, *_UPPER_GREEK, *_VARIANT_GREEK)} | {"ell": "l"}
)
"""LaTeX command (without backslash) -> name: ``\\theta`` -> ``theta``, ``\\ell`` -> ``l``."""

_LOWER_CHARS = "αβγδεζηθικλμνξοπρστυφχψω"
_UPPER_CHARS = "ΓΔΘΛΞΠΣΥΦΨΩ"

UNICODE_GREEK: Mapping[str, str] = MappingProxyType(
    dict(zip(_LOWER_CHARS, _LOWER_GREEK, strict=True))
    | dict(zip(_UPPER_CHARS, _UPPER_GREEK, strict=True))
    | {"ς": "sigma", "ϑ": "theta", "ϕ": "phi", "ϵ": "epsilon", "ϱ": "rho", "µ": "mu"}
)
"""Greek character -> name: ``θ`` -> ``theta`` (variant letter forms -> the plain name)."""
