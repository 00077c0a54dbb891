"""The safe expression parser: text (or LaTeX) -> SymPy, never through ``eval``.

Public interface used by the rest of the package (implementation in the
modules of this subpackage):

    Namespace(symbols={name: sympy.Expr}, functions={name: DeclaredFunction})
    parse_expression(text, namespace, limits=DEFAULT_LIMITS) -> sympy.Expr
    referenced_names(text, limits=DEFAULT_LIMITS) -> ReferencedNames
    BUILTIN_FUNCTIONS, BUILTIN_CONSTANTS, ParseLimits, DEFAULT_LIMITS
"""
