"""The safe expression parser: text (or LaTeX) -> SymPy, never through Python evaluation.

User text (model files, the command line) is tokenized and parsed by hand; the
parser builds SymPy objects itself and refuses everything outside the
expression language (see ``DESIGN.md`` section 3) with a
:class:`~lagrangian.errors.ParseError` that gives the position.  Sizes are
bounded by :class:`ParseLimits`, so no input can hang or exhaust the machine.

    Namespace(symbols={name: sympy.Expr}, functions={name: DeclaredFunction})
    parse_expression(text, namespace, limits=DEFAULT_LIMITS, terms=None) -> sympy.Expr
    Terms()   (terms of sums built once across the texts of one namespace: a model's)
    referenced_names(text, limits=DEFAULT_LIMITS) -> ReferencedNames
    syntax_tree(text) -> Node, token_ends(text) -> {start: end}   (the text as written)
    BUILTIN_FUNCTIONS, BUILTIN_CONSTANTS, RESERVED_NAMES, ParseLimits, DEFAULT_LIMITS
"""

from lagrangian.parsing.expression import (
    ReferencedNames,
    parse_expression,
    referenced_names,
    syntax_tree,
    token_ends,
)
from lagrangian.parsing.limits import DEFAULT_LIMITS, ParseLimits
from lagrangian.parsing.names import (
    BUILTIN_CONSTANTS,
    BUILTIN_FUNCTIONS,
    RESERVED_NAMES,
    DeclaredFunction,
    Namespace,
)
from lagrangian.parsing.terms import Terms

__all__ = [
    "BUILTIN_CONSTANTS",
    "BUILTIN_FUNCTIONS",
    "DEFAULT_LIMITS",
    "RESERVED_NAMES",
    "DeclaredFunction",
    "Namespace",
    "ParseLimits",
    "ReferencedNames",
    "Terms",
    "parse_expression",
    "referenced_names",
    "syntax_tree",
    "token_ends",
]
