"""The two entry points: ``parse_expression`` (text -> SymPy) and ``referenced_names``.

Text goes through a tokenizer (plain or LaTeX, chosen by
:func:`~.latex.looks_like_latex`), the parser (tokens -> syntax tree) and the
builder (tree -> SymPy).  No step evaluates Python: names are looked up in the
namespace, numbers are built from checked digits, and SymPy objects are made
by calling ``Add``, ``Mul``, ``Pow`` and the function classes directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing.builder import build_expression, build_terms, is_non_finite
from lagrangian.parsing.latex import looks_like_latex, tokenize_latex
from lagrangian.parsing.lexer import tokenize
from lagrangian.parsing.limits import DEFAULT_LIMITS, ParseLimits, log_size
from lagrangian.parsing.names import BUILTIN_CONSTANTS, BUILTIN_FUNCTIONS, Namespace
from lagrangian.parsing.nodes import (
    Call,
    Kind,
    Name,
    Negate,
    Node,
    Number,
    Power,
    Product,
    Sum,
    Token,
)
from lagrangian.parsing.parser import parse_tokens
from lagrangian.parsing.split import top_level_terms
from lagrangian.parsing.terms import Terms


@dataclass(frozen=True)
class ReferencedNames:
    """The names an expression uses, other than the built-in ones.

    ``symbols``: names used as values (a declared function written bare counts
    here).  ``functions``: names called with arguments.  In LaTeX, ``m(a + b)``
    with one argument is a product, so ``m`` counts as a symbol.
    """

    symbols: frozenset[str]
    functions: frozenset[str]


def parse_expression(
    text: str,
    namespace: Namespace,
    limits: ParseLimits = DEFAULT_LIMITS,
    *,
    trees: dict[str, Node] | None = None,
    terms: Terms | None = None,
) -> sympy.Expr:
    """The SymPy expression written in ``text`` (plain or LaTeX).

    ``trees``: where to keep the syntax tree, ``trees[text]``, for a later pass over the
    text as written (a dimensioned model's check: it is not parsed twice).
    ``terms``: the terms already built for texts parsed with the same ``namespace`` and
    ``limits`` (:class:`~.terms.Terms`): a term of the text's top-level sum written
    alike is built once, its limits still charged to each text.

    Raises :class:`~lagrangian.errors.ParseError` (with the 0-based
    ``position``) for anything that is not a valid expression, and
    :class:`~lagrangian.errors.UnknownNameError` for a name that is neither in
    ``namespace`` nor built in.

    >>> x = sympy.Symbol("x")
    >>> parse_expression("x**2/2 + 0.5", Namespace({"x": x}))
    x**2/2 + 1/2
    """
    if not isinstance(namespace, Namespace):
        raise TypeError(f"namespace must be a Namespace, not {type(namespace).__name__}")
    result = None
    if terms is not None and trees is None:
        result = _built_by_terms(text, namespace, limits, terms)
    if result is None:
        tree = _parse_tree(text, limits)
        if trees is not None:
            trees[text] = tree
        if terms is not None:
            terms.latex = looks_like_latex(text)
        result = build_expression(tree, text, namespace, limits, terms)
    if not isinstance(result, sympy.Expr):
        raise ParseError("not an expression", text, None)
    union = terms.union if terms is not None else _whole  # a sum's terms looked at once
    if is_non_finite(result) or union(result, _non_finite):
        raise ParseError("division by zero", text, None)
    _check_numbers(union(result, _rationals), text, limits)
    return result


def referenced_names(text: str, limits: ParseLimits = DEFAULT_LIMITS) -> ReferencedNames:
    """The names ``text`` uses, found without a namespace.

    Raises :class:`~lagrangian.errors.ParseError` for invalid syntax, at the
    same place as :func:`parse_expression`.  Nothing is evaluated, so unknown
    names and numeric limits (``9**9**9``) are not errors here.

    >>> names = referenced_names("m*g*y + V(x)")
    >>> sorted(names.symbols), sorted(names.functions)
    (['g', 'm', 'x', 'y'], ['V'])
    >>> sorted(referenced_names(r"\\frac{1}{2} m \\dot{\\theta}^2").symbols)
    ['m', 'theta_dot']
    """
    symbols: set[str] = set()
    functions: set[str] = set()
    stack: list[Node] = [_parse_tree(text, limits)]
    while stack:
        node = stack.pop()
        match node:
            case Name(name=name) if name not in BUILTIN_CONSTANTS:
                symbols.add(name)
            case Call(name=name, args=args, juxtaposed=juxtaposed):
                if juxtaposed:
                    if name not in BUILTIN_CONSTANTS:
                        symbols.add(name)
                elif name not in BUILTIN_FUNCTIONS:
                    functions.add(name)
                stack.extend(args)
            case Negate(operand=operand):
                stack.append(operand)
            case Sum(terms=operands) | Product(factors=operands):
                stack.extend(operand.node for operand in operands)
            case Power(base=base, exponent=exponent):
                stack.extend((base, exponent))
            case Name() | Number():
                pass
    return ReferencedNames(frozenset(symbols), frozenset(functions))


def syntax_tree(text: str, limits: ParseLimits = DEFAULT_LIMITS) -> Node:
    """The syntax tree of ``text`` (plain or LaTeX), for a pass that reads the expression
    as written (the dimension check names a term as the user wrote it)."""
    return _parse_tree(text, limits)


def token_ends(text: str, limits: ParseLimits = DEFAULT_LIMITS) -> dict[int, int]:
    """Where each token of ``text`` starts -> where it ends (0-based offsets): with the
    positions of a :func:`syntax_tree`, the span of text a node was written with."""
    tokens = tokenize_latex(text, limits) if looks_like_latex(text) else tokenize(text, limits)
    return {token.position: token.position + len(token.text) for token in tokens}


_NON_FINITE = (sympy.zoo, sympy.nan, sympy.oo, -sympy.oo)


def _whole(expr: sympy.Basic, what):
    return what(expr)


def _non_finite(expr: sympy.Basic) -> set:
    """{True} where ``expr`` holds an infinity or nan (a set: see Terms.union)."""
    return {True} if expr.has(*_NON_FINITE) else set()


def _rationals(expr: sympy.Basic) -> set:
    return expr.atoms(sympy.Rational)


def _check_numbers(numbers: set, text: str, limits: ParseLimits) -> None:
    """A last check that no number in the result (``numbers``: its rationals) is longer
    than the limit allows.

    The estimates made before each operation should already have refused such
    a number; this guards the printing of the result (Python cannot print an
    integer of more than 4,300 digits) against anything they missed.
    """
    for number in numbers:
        if max(log_size(number.p), log_size(number.q)) >= limits.max_result_digits:
            raise ParseError(
                f"number too large (limit {limits.max_result_digits} digits)", text, None
            )


def _built_by_terms(
    text: object, namespace: Namespace, limits: object, terms: Terms
) -> sympy.Expr | None:
    """The value of a long plain sum whose terms are split without a parse
    (:func:`~.split.top_level_terms`), only the terms not built before parsed; None where
    the split does not apply or anything is wrong: the full parse then refuses the text
    where it does, with its message.
    """
    if not (
        isinstance(text, str)
        and isinstance(limits, ParseLimits)
        and len(text) <= limits.max_length
        and not looks_like_latex(text)
    ):
        return None
    pieces = top_level_terms(text)
    if pieces is None:
        return None
    made: dict[int, list[Token]] = {}  # start -> the tokens of a term not met before
    count = len(pieces) - 1  # the signs between the terms
    try:
        for start, end, _ in pieces:
            written = text[start:end]
            found = terms.tokens.get(written)
            if found is None or (written, False) not in terms.built:
                tokens = tokenize(written, limits)
                found = terms.tokens[written] = len(tokens) - 1  # without END
                made[start] = [Token(t.kind, t.text, t.position + start, t.value) for t in tokens]
            count += found
        if count > limits.max_nodes:
            return None  # refused by the full parse ("too large"), at its token
        terms.latex = False

        def parse(start: int, end: int) -> Node:
            return parse_tokens(made[start], text, limits, latex=False)

        return build_terms(text, pieces, namespace, limits, terms, parse)
    except ParseError:
        return None


def _parse_tree(text: str, limits: ParseLimits) -> Node:
    if not isinstance(text, str):
        raise TypeError(f"expression text must be a str, not {type(text).__name__}")
    if not isinstance(limits, ParseLimits):
        raise TypeError(f"limits must be ParseLimits, not {type(limits).__name__}")
    if len(text) > limits.max_length:
        raise ParseError(
            f"expression too long ({len(text)} characters, limit {limits.max_length})", text, None
        )
    latex = looks_like_latex(text)
    tokens = tokenize_latex(text, limits) if latex else tokenize(text, limits)
    if tokens[0].kind is Kind.END:
        raise ParseError("empty expression", text, 0)
    return parse_tokens(tokens, text, limits, latex=latex)
