"""From the syntax tree to SymPy objects: names looked up, numbers guarded.

SymPy evaluates numbers eagerly: ``Pow(9, 10**9)`` computes a billion-digit
integer, ``sqrt`` of a long number factors it by trial division, and a product
merges ``2**(x + c) * 2**(-x)`` into ``2**c``.  So before each power, product,
sum and function call the size of the exact numbers it could create is
estimated (:mod:`.limits`) and refused above the limits.  Division by zero and
other infinite or undefined results are refused where they arise, and so is
every power or function value that is not real (``sqrt(-1)``, ``acos(2)``:
:mod:`.constants`), the only places where real arguments can give one.  A
constant beyond the range of double precision (``cosh(123456789)``,
``exp(-10**6)``, ``2**exp(700)``) is refused where ``exp``, ``sinh``, ``cosh`` or a
power make it: no numerical stage could use it, and SymPy deciding the sign of
one (``sign``, ``Abs``, ``atan2``) evaluates it at ever higher precision, for
minutes.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence

import sympy

from lagrangian.errors import ParseError, UnknownNameError
from lagrangian.parsing.constants import NotRealError, RealConstants
from lagrangian.parsing.limits import (
    ARGUMENT_NODE_BUDGET,
    ROOT_DIGITS_LIMIT,
    ROOT_WORK_BUDGET_US,
    ParseLimits,
    count_new_nodes,
    exp_size,
    magnitude,
    numeric_size,
    rational_size,
    root_sizes,
    root_work_us,
    sum_size,
)
from lagrangian.parsing.names import (
    BUILTIN_CONSTANTS,
    BUILTIN_FUNCTIONS,
    Namespace,
    arity_message,
)
from lagrangian.parsing.nodes import Call, Name, Negate, Node, Number, Power, Product, Sum
from lagrangian.parsing.split import without_spaces
from lagrangian.parsing.suggest import likely_meant
from lagrangian.parsing.terms import Terms, plain_call, plain_product, sorted_sum

_NON_FINITE = (sympy.S.ComplexInfinity, sympy.S.NaN, sympy.S.Infinity, sympy.S.NegativeInfinity)
_TRIGONOMETRIC = frozenset({"sin", "cos", "tan", "cot", "sec", "csc"})
_INVERSE_TRIGONOMETRIC = (sympy.asin, sympy.acos, sympy.atan, sympy.atan2)
_HALF = sympy.Rational(1, 2)
#: ln of the largest double and of the smallest (subnormal) one: e**x beyond them is not
#: a double (inf or 0).
_LOG_LARGEST = math.log(sys.float_info.max)
_LOG_SMALLEST = math.log(math.ulp(0.0))
#: For ``sinh`` and ``cosh`` (e**|x| / 2): only their size can leave the range.
_GROWING = {"sinh", "cosh"}
#: A call or power as built, for a message: made only for one (printing each costs).
Shown = Callable[[], str]


def build_expression(
    node: Node, text: str, namespace: Namespace, limits: ParseLimits, terms: Terms | None = None
) -> sympy.Expr:
    """The SymPy expression of ``node``, with names from ``namespace``.

    ``terms``: the terms of top-level sums built before with the same namespace and limits
    (a :class:`Terms`, shared by the texts of one model), each built once.
    """
    builder = _Builder(text, namespace, limits)
    if terms is not None and isinstance(node, Sum):
        return builder.top_sum(node, terms)
    return builder.build(node)


def build_terms(
    text: str,
    pieces: Sequence[tuple[int, int, bool]],
    namespace: Namespace,
    limits: ParseLimits,
    terms: Terms,
    parse: Callable[[int, int], Node],
) -> sympy.Expr:
    """The sum of the terms of ``text`` at ``pieces`` ((start, end, negated), as
    :func:`~.split.top_level_terms` finds them), each built once per ``terms``; a term not
    built before is ``parse(start, end)``.  The same value, charged against the same limits,
    as :func:`build_expression` of the text's tree."""
    builder = _Builder(text, namespace, limits)
    position = pieces[0][0]
    return builder.sum_of_terms([(*piece, None) for piece in pieces], position, terms, parse)


def is_non_finite(value: sympy.Expr) -> bool:
    return any(value is special for special in _NON_FINITE)


class _Builder:
    def __init__(self, text: str, namespace: Namespace, limits: ParseLimits):
        self.text = text
        self.namespace = namespace
        self.limits = limits
        self.root_work_us = 0.0
        self.argument_nodes = 0
        self.charged: set[sympy.Basic] = set()
        self.constants = RealConstants()
        self.charges: list | None = None  # while a term is recorded: what it charged

    def top_sum(self, node: Sum, terms: Terms) -> sympy.Expr:
        """:meth:`sum` of the whole text's sum, each term built once per ``terms``."""
        pieces = []
        operands = node.terms
        for k, operand in enumerate(operands):
            start = operand.position + (1 if k else 0)  # past the operator, 1 character
            end = operands[k + 1].position if k + 1 < len(operands) else len(self.text)
            if not terms.latex:  # the same key as the split's (LaTeX spaces may be commands)
                start, end = without_spaces(self.text, start, end)
            pieces.append((start, end, operand.inverted, operand.node))
        return self.sum_of_terms(pieces, node.position, terms)

    def sum_of_terms(
        self,
        pieces: Sequence[tuple[int, int, bool, Node | None]],
        position: int,
        terms: Terms,
        parse: Callable[[int, int], Node] | None = None,
    ) -> sympy.Expr:
        """The sum of the terms written at ``text[start:end]`` (negated where marked), each
        built once per ``terms``; a term not built before is ``parse(start, end)`` where no
        tree of it is given."""
        values = []
        for start, end, negated, node in pieces:
            key = (self.text[start:end], terms.latex)
            found = terms.built.get(key)
            if found is None:
                self.charges = []
                value = self.build(parse(start, end) if node is None else node)
                terms.built[key] = (value, [(f, args, at - start) for f, args, at in self.charges])
                self.charges = None
            else:
                value, charges = found
                for charge, args, offset in charges:  # in the order the build made them
                    getattr(self, charge)(args, start + offset)
            if negated:  # -value made once per term (SymPy makes a new product each time)
                negation = terms.negated.get(key)
                if negation is None:
                    negation = terms.negated[key] = -value
                value = negation
            values.append(value)
        limit = self.limits.max_result_digits
        self.check_digits(sum_size(values, limit, terms.number_sizes), position)
        ordered = terms.in_canonical_order(values)  # the same sum, its sort done mostly
        # the same sum, where Add would only keep the terms
        made = sorted_sum(ordered, terms.plain_parts)
        if made is not None:
            return made
        return self.evaluate(lambda: sympy.Add(*ordered), "the sum", position)

    def error(self, message: str, position: int | None) -> ParseError:
        return ParseError(message, self.text, position)

    def build(self, node: Node) -> sympy.Expr:
        match node:
            case Number():
                return node.value
            case Name():
                return self.name(node.name, node.position)
            case Call():
                return self.call(node)
            case Negate():
                operand = self.build(node.operand)
                return self.evaluate(lambda: -operand, "the negation", node.position)
            case Sum():
                return self.sum(node)
            case Product():
                return self.product(node)
            case Power(base=Call(juxtaposed=True) as call) if (
                call.name not in self.namespace.functions
            ):  # LaTeX k(r - l)^2 is k (r - l)^2: the exponent binds to the group, not to k
                raised = self.power(self.build(call.args[0]), self.build(node.exponent),
                                    node.position)  # fmt: skip
                left = self.name(call.name, call.position)
                return self.multiply([left, raised], node.position)
            case Power():
                base = self.build(node.base)
                return self.power(base, self.build(node.exponent), node.position)
        raise TypeError(f"not a syntax tree node: {node!r}")

    def evaluate(self, compute: Callable[[], sympy.Expr], what: str, position: int) -> sympy.Expr:
        """``compute()``, with SymPy's own failures reported as parse errors.

        SymPy's automatic evaluation can fail in many ways on odd input (for
        example ``atan(tan(7**300))`` raises AttributeError inside SymPy 1.14),
        so any exception from the computation itself is the user's input refused.
        """
        try:
            return compute()
        except Exception as error:
            detail = " ".join(str(error).split())
            if len(detail) > 80:
                detail = detail[:77] + "..."
            raise self.error(f"cannot evaluate {what}: {detail}", position) from None

    # -- names and calls ---------------------------------------------------------

    def name(self, name: str, position: int) -> sympy.Expr:
        if name in BUILTIN_CONSTANTS:
            return BUILTIN_CONSTANTS[name]
        declared = self.namespace.functions.get(name)
        if declared is not None:
            return self.evaluate(
                lambda: declared.function(*declared.arguments), f"{name}()", position
            )
        value = self.namespace.symbols.get(name)
        if value is None:
            known = [*self.namespace.symbols, *self.namespace.functions]
            raise UnknownNameError(name, self.text, position, likely_meant(name, known))
        return value

    def call(self, node: Call) -> sympy.Expr:
        name = node.name
        if name in BUILTIN_FUNCTIONS:
            return self.builtin(name, [self.build(arg) for arg in node.args], node.position)
        declared = self.namespace.functions.get(name)
        if declared is not None:
            expected = len(declared.arguments)
            if len(node.args) != expected:
                raise self.error(arity_message(name, expected, len(node.args)), node.position)
            args = [self.build(arg) for arg in node.args]
            return self.evaluate(lambda: declared.function(*args), f"{name}()", node.position)
        if node.juxtaposed:  # LaTeX m(a + b)
            left = self.name(name, node.position)
            return self.multiply([left, self.build(node.args[0])], node.position)
        if name in self.namespace.symbols:
            raise self.error(f"'{name}' is not a function", node.position)
        meant = likely_meant(name, [*self.namespace.functions, *BUILTIN_FUNCTIONS])
        hint = f" (did you mean '{meant}'?)" if meant else ""
        raise self.error(f"unknown function '{name}'{hint}", node.position)

    def builtin(self, name: str, args: list[sympy.Expr], position: int) -> sympy.Expr:
        self.charge_arguments(args, position)

        def shown() -> str:  # the call as built, for a message (printed only for one)
            return f"{name}({', '.join(map(str, args))})"

        if name == "sqrt":
            return self.power(args[0], _HALF, position, shown=shown)
        if name == "exp":
            self.check_exp(args[0], position)
            self.check_range(args[0], sympy.S.One, shown, position)
        elif name in _GROWING:
            self.check_range(sympy.Abs(args[0]), sympy.S.One, shown, position, growing=True)
        elif name in _TRIGONOMETRIC and isinstance(args[0], _INVERSE_TRIGONOMETRIC):
            # cos(asin(r)) is sqrt(1 - r**2): a root of a number twice as long as r.
            self.check_root(2 * sum(numeric_size(arg) for arg in args[0].args), position)
        function = BUILTIN_FUNCTIONS[name][0]
        result = plain_call(function, args[0]) if len(args) == 1 else None
        if result is None:
            result = self.evaluate(lambda: function(*args), f"{name}()", position)
        if is_non_finite(result):
            raise self.error(f"{_clip(shown())} is infinite or undefined", position)
        self.check_real(result, shown, position)
        return result

    # -- arithmetic ----------------------------------------------------------------

    def sum(self, node: Sum) -> sympy.Expr:
        terms = []
        for operand in node.terms:
            value = self.build(operand.node)
            terms.append(-value if operand.inverted else value)
        self.check_digits(sum_size(terms, self.limits.max_result_digits), node.position)
        return self.evaluate(lambda: sympy.Add(*terms), "the sum", node.position)

    def product(self, node: Product) -> sympy.Expr:
        factors = []
        for operand in node.factors:
            value = self.build(operand.node)
            if operand.inverted:
                if value == 0:
                    raise self.error("division by zero", operand.position)
                if value.is_Rational:  # much faster than Pow(value, -1)
                    value = sympy.Rational(value.q, value.p)
                else:
                    value = self.power(value, sympy.S.NegativeOne, operand.position)
            factors.append(value)
        return self.multiply(factors, node.position)

    def multiply(self, factors: Sequence[sympy.Expr], position: int) -> sympy.Expr:
        self.check_digits(sum(numeric_size(factor) for factor in factors), position)
        roots = [size for factor in factors for size in root_sizes(factor)]
        if len(roots) > 1:
            self.check_root(sum(roots), position)
        result = plain_product(factors)
        if result is None:
            result = self.evaluate(lambda: sympy.Mul(*factors), "the product", position)
        if is_non_finite(result):
            raise self.error("division by zero", position)
        return result

    def power(
        self, base: sympy.Expr, exponent: sympy.Expr, position: int, shown: Shown | None = None
    ) -> sympy.Expr:
        if shown is None:

            def shown() -> str:
                return f"({base})**({exponent})"

        exact = base.is_Rational and exponent.is_Rational  # bounded by its digits instead
        if base.is_number and exponent.is_number and not exact:
            log_base = sympy.log(sympy.Abs(base, evaluate=False), evaluate=False)
            self.check_range(exponent, log_base, shown, position)
        if exponent.is_Rational:
            self.check_power(base, exponent, position)
            if base == 0 and exponent < 0:
                raise self.error("division by zero", position)
        else:
            if not exponent.is_number:
                self.charge_arguments([exponent], position)
            size = numeric_size(base)
            if base is sympy.E:
                self.check_exp(exponent, position)
            elif size:  # b**(x + c) times b**(-x) is the number b**c
                self.check_root(size, position)
                self.check_digits(size * magnitude(exponent), position)
        result = self.evaluate(lambda: sympy.Pow(base, exponent), "the power", position)
        if is_non_finite(result):
            raise self.error("division by zero", position)
        self.check_real(result, shown, position)
        return result

    # -- guards ----------------------------------------------------------------------

    def check_power(self, base: sympy.Expr, exponent: sympy.Rational, position: int) -> None:
        """Refuse ``base**exponent`` if the exponent or the number it makes is too large."""
        limit = self.limits.max_exponent
        if abs(exponent) > limit:
            raise self.error(f"exponent {_show(exponent)} too large (limit {limit})", position)
        size = numeric_size(base)
        if size == 0:
            return
        self.check_digits(size * abs(float(exponent)), position)
        if exponent.q != 1:
            if exponent.q > limit:
                raise self.error(
                    f"exponent {_show(exponent)} has too large a denominator (limit {limit})",
                    position,
                )
            self.check_root(size, position)

    def check_exp(self, argument: sympy.Expr, position: int) -> None:
        """``exp(c*log(b))`` is ``b**c``: guard it as that power (one per term of a sum)."""
        roots = 0.0
        for term in sympy.Add.make_args(argument):
            coefficient, rest = term.as_coeff_Mul()
            if isinstance(rest, sympy.log) and coefficient.is_Rational:
                self.check_power(rest.args[0], coefficient, position)
                if coefficient.q != 1:
                    roots += numeric_size(rest.args[0])
        self.check_digits(exp_size(argument), position)
        if roots > ROOT_DIGITS_LIMIT:
            self.check_root(roots, position)

    def check_range(
        self,
        exponent: sympy.Expr,
        log_base: sympy.Expr,
        shown: Shown,
        position: int,
        *,
        growing: bool = False,
    ) -> None:
        """Refuse the constant ``shown``, of size e**(exponent*log_base) (``growing``: about
        half that, as cosh), where it is certainly beyond the range of double precision."""
        if not exponent.is_number:
            return
        try:
            bounds = self.constants.bounds(sympy.Mul(exponent, log_base, evaluate=False))
        except NotRealError:
            return  # not real: refused as such where it is built
        if bounds is None:
            return
        low, high = bounds
        if growing:
            low, high = low - math.log(2), high - math.log(2)
        if low > _LOG_LARGEST or (high < _LOG_SMALLEST and not growing):
            size = low if low > _LOG_LARGEST else high
            raise self.error(
                f"the number {_clip(shown())} is beyond double precision "
                f"(about 10^{size / math.log(10):.4g})",
                position,
            )

    def check_real(self, result: sympy.Expr, shown: Shown, position: int) -> None:
        """Refuse a value that is not real: ``shown`` is the call or power as built."""
        try:
            self.constants.check(result)
        except NotRealError as error:
            raise self.error(f"{_clip(shown())} {error.reason}", position) from None

    def check_digits(self, size: float, position: int) -> None:
        """Refuse a number of ``size`` (``log10``) with more than ``max_result_digits`` digits."""
        limit = self.limits.max_result_digits
        if size >= limit:
            raise self.error(f"number too large ({_digits(size)}, limit {limit})", position)

    def charge_arguments(self, args: Sequence[sympy.Expr], position: int) -> None:
        """Count ``args`` against the budget of nodes SymPy queries assumptions of."""
        if self.charges is not None:
            self.charges.append(("charge_arguments", tuple(args), position))
        for arg in args:
            remaining = ARGUMENT_NODE_BUDGET - self.argument_nodes
            self.argument_nodes += count_new_nodes(arg, self.charged, remaining)
            if self.argument_nodes > ARGUMENT_NODE_BUDGET:
                raise self.error(
                    "expression too costly: arguments of functions and exponents too large "
                    f"(limit {ARGUMENT_NODE_BUDGET} compound nodes in all)",
                    position,
                )

    def check_root(self, digits: float, position: int) -> None:
        """Refuse a root of a number too long to factor, or too many roots in all."""
        if self.charges is not None:
            self.charges.append(("check_root", digits, position))
        if digits > ROOT_DIGITS_LIMIT:
            raise self.error(
                f"number too large for a root ({_digits(digits)}, limit {ROOT_DIGITS_LIMIT})",
                position,
            )
        self.root_work_us += root_work_us(digits)
        if self.root_work_us > ROOT_WORK_BUDGET_US:
            raise self.error("expression too costly: too many roots of numbers", position)


def _clip(shown: str) -> str:
    """A subexpression for a message: at most 60 characters."""
    return shown if len(shown) <= 60 else shown[:57] + "..."


def _show(value: sympy.Rational) -> str:
    if rational_size(value) > 18:
        return f"of {_digits(rational_size(value))}"
    return str(value.p) if value.q == 1 else f"{value.p}/{value.q}"


def _digits(size: float) -> str:
    """How many digits a number of ``size`` (``log10``) has, for a message."""
    return f"about {int(size) + 1} digits" if size < 1e15 else "more than 10^15 digits"
