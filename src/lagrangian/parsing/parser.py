r"""Recursive descent from tokens to the syntax tree, for plain text and for LaTeX.

Plain text::

    sum      := term (("+" | "-") term)*
    term     := unary (("*" | "/") unary)*
    unary    := ("+" | "-") unary | power
    power    := primary ["^" unary]                    (right-associative)
    primary  := NUMBER | NAME | NAME "(" [sum ("," sum)*] ")" | "(" sum ")"

so ``-x^2`` is ``-(x^2)``, ``x^y^z`` is ``x^(y^z)`` and ``2^-x`` is allowed.
LaTeX changes and adds::

    term     := unary (("*" | "/") unary | power)*     (juxtaposition multiplies)
    power    := primary ["^" exponent]
    exponent := ["+" | "-"] primary                    (x^2, x^{a+b}, x^-1)
    primary  += "[" sum "]" | "{" sum "}" | FRAC arg arg | SQRT ["[" sum "]"] arg
              | FUNCTION ["^" exponent] ("(" sum ")" | unary)
    arg      := "{" sum "}" | primary

A function command without parentheses takes the next factor with its power:
``\sin\theta^2`` is ``sin(theta^2)`` and ``\sin^2\theta`` is ``sin(theta)^2``.
Each parenthesis, brace, call, sign and exponent counts one level of nesting
against ``max_depth``, which bounds the recursion.
"""

from __future__ import annotations

import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing.lexer import shorten
from lagrangian.parsing.limits import ParseLimits
from lagrangian.parsing.names import BUILTIN_CONSTANTS, BUILTIN_FUNCTIONS, arity_message
from lagrangian.parsing.nodes import (
    Call,
    Kind,
    Name,
    Negate,
    Node,
    Number,
    Operand,
    Power,
    Product,
    Sum,
    Token,
)

_FACTOR_STARTS = frozenset(
    {
        Kind.NUMBER,
        Kind.NAME,
        Kind.FUNCTION,
        Kind.LPAREN,
        Kind.LBRACKET,
        Kind.LBRACE,
        Kind.FRAC,
        Kind.SQRT,
    }
)
_CLOSERS = {Kind.LPAREN: Kind.RPAREN, Kind.LBRACKET: Kind.RBRACKET, Kind.LBRACE: Kind.RBRACE}


def parse_tokens(tokens: list[Token], text: str, limits: ParseLimits, *, latex: bool) -> Node:
    """The syntax tree of ``tokens`` (which end with an END token)."""
    return _Parser(tokens, text, limits, latex).parse()


class _Parser:
    def __init__(self, tokens: list[Token], text: str, limits: ParseLimits, latex: bool):
        self.tokens = tokens
        self.text = text
        self.max_depth = limits.max_depth
        self.latex = latex
        self.index = 0
        self.depth = 0

    # -- helpers ---------------------------------------------------------------

    def peek(self) -> Token:
        return self.tokens[self.index]

    def next(self) -> Token:
        token = self.tokens[self.index]
        if token.kind is not Kind.END:
            self.index += 1
        return token

    def error(self, message: str, token: Token) -> ParseError:
        return ParseError(message, self.text, token.position)

    def unexpected(self, token: Token) -> ParseError:
        if token.kind is Kind.END:
            return self.error("unexpected end of expression", token)
        return self.error(f"unexpected {token.describe()}", token)

    def enter(self, token: Token) -> None:
        self.depth += 1
        if self.depth > self.max_depth:
            raise self.error(f"expression nested too deeply (limit {self.max_depth})", token)

    def leave(self) -> None:
        self.depth -= 1

    @staticmethod
    def is_operator(token: Token, operators: str) -> bool:
        return token.kind is Kind.OPERATOR and token.value in operators

    def expect_close(self, opening: Token) -> None:
        closer = _CLOSERS[opening.kind]
        token = self.peek()
        if token.kind is not closer:
            raise self.error(
                f"expected '{closer.value}' to close '{opening.text}' at position "
                f"{opening.position + 1}, found {token.describe()}",
                token,
            )
        self.next()

    # -- grammar ---------------------------------------------------------------

    def parse(self) -> Node:
        node = self.sum()
        token = self.peek()
        if token.kind in (Kind.RPAREN, Kind.RBRACKET, Kind.RBRACE):
            raise self.error(f"unmatched {token.describe()}", token)
        if token.kind is not Kind.END:
            raise self.unexpected(token)
        return node

    def sum(self) -> Node:
        first = self.peek()
        terms = [Operand(False, self.term(), first.position)]
        while self.is_operator(self.peek(), "+-"):
            operator = self.next()
            terms.append(Operand(operator.value == "-", self.term(), operator.position))
        if len(terms) == 1:
            return terms[0].node
        return Sum(tuple(terms), first.position)

    def term(self) -> Node:
        first = self.peek()
        factors = [Operand(False, self.unary(), first.position)]
        while True:
            token = self.peek()
            if self.is_operator(token, "*/"):
                self.next()
                factors.append(Operand(token.value == "/", self.unary(), token.position))
            elif token.kind in _FACTOR_STARTS:
                factors.append(Operand(False, self.juxtaposed(token), token.position))
            else:
                break
        if len(factors) == 1:
            return factors[0].node
        return Product(tuple(factors), first.position)

    def juxtaposed(self, token: Token) -> Node:
        """A factor written right after another: multiplication in LaTeX, an error in text."""
        previous = self.tokens[self.index - 1]
        if not self.latex:
            left = shorten(previous.text)
            if previous.kind is Kind.NUMBER and token.kind is Kind.LPAREN:
                raise self.error(
                    f"'{left}' is not a function: write '{left}*(...)' to multiply", previous
                )
            raise self.error(
                f"implicit multiplication is not allowed: write '{left}*{shorten(token.text)}'",
                token,
            )
        if token.kind is Kind.NUMBER:
            raise self.error(
                f"write '\\cdot' before the number {token.describe()}, or put the number first",
                token,
            )
        return self.power()

    def unary(self) -> Node:
        token = self.peek()
        if not self.is_operator(token, "+-"):
            return self.power()
        self.next()
        self.enter(token)
        operand = self.unary()
        self.leave()
        return Negate(operand, token.position) if token.value == "-" else operand

    def power(self) -> Node:
        base = self.primary()
        caret = self.peek()
        if not self.is_operator(caret, "^"):
            return base
        self.next()
        self.enter(caret)
        exponent = self.exponent() if self.latex else self.unary()
        self.leave()
        if self.latex and self.is_operator(self.peek(), "^"):
            raise self.error("double superscript: use braces, as in x^{a^b}", self.peek())
        return Power(base, exponent, caret.position)

    def exponent(self) -> Node:
        """A LaTeX superscript: one signed primary (``^2``, ``^{a+b}``, ``^-1``)."""
        sign = self.peek()
        if not self.is_operator(sign, "+-"):
            return self.primary()
        self.next()
        operand = self.primary()
        return Negate(operand, sign.position) if sign.value == "-" else operand

    def primary(self) -> Node:
        token = self.peek()
        kind = token.kind
        if kind is Kind.NUMBER:
            self.next()
            return Number(token.value, token.position)
        if kind is Kind.NAME:
            self.next()
            return self.name(token)
        if kind in _CLOSERS:
            return self.group()
        if kind is Kind.FRAC:
            return self.fraction()
        if kind is Kind.SQRT:
            return self.root()
        if kind is Kind.FUNCTION:
            return self.function()
        raise self.unexpected(token)

    def group(self) -> Node:
        opening = self.next()
        self.enter(opening)
        node = self.sum()
        self.expect_close(opening)
        self.leave()
        return node

    def name(self, token: Token) -> Node:
        name = token.value
        if self.peek().kind is Kind.LPAREN:
            return self.call(token)
        if name in BUILTIN_FUNCTIONS:
            raise self.error(f"'{name}' is a function: write {name}(...)", token)
        return Name(name, token.position)

    def call(self, token: Token) -> Node:
        name = token.value
        opening = self.next()
        self.enter(opening)
        args = self.arguments(opening)
        self.leave()
        if name in BUILTIN_FUNCTIONS:
            self.check_arity(name, len(args), token)
            return Call(name, args, token.position)
        if self.latex and len(args) == 1:
            return Call(name, args, token.position, juxtaposed=True)
        if name in BUILTIN_CONSTANTS:
            raise self.error(f"'{name}' is not a function", token)
        return Call(name, args, token.position)

    def arguments(self, opening: Token) -> tuple[Node, ...]:
        args: list[Node] = []
        if self.peek().kind is not Kind.RPAREN:
            args.append(self.sum())
            while self.peek().kind is Kind.COMMA:
                self.next()
                args.append(self.sum())
        self.expect_close(opening)
        return tuple(args)

    def check_arity(self, name: str, given: int, token: Token) -> None:
        expected = BUILTIN_FUNCTIONS[name][1]
        if given != expected:
            raise self.error(arity_message(name, expected, given), token)

    # -- LaTeX constructs --------------------------------------------------------

    def argument(self, command: Token) -> Node:
        """The argument of ``\\frac`` or ``\\sqrt``: a braced group or a single primary."""
        token = self.peek()
        if token.kind is Kind.LBRACE:
            return self.group()
        if token.kind is Kind.NUMBER and len(token.text) > 1:
            raise self.error(
                f"ambiguous argument {token.describe()} of '{command.text}': use braces, "
                "as in \\frac{1}{2}",
                token,
            )
        return self.primary()

    def fraction(self) -> Node:
        command = self.next()
        self.enter(command)
        numerator = self.argument(command)
        below = self.peek()
        denominator = self.argument(command)
        self.leave()
        factors = (
            Operand(False, numerator, command.position),
            Operand(True, denominator, below.position),
        )
        return Product(factors, command.position)

    def root(self) -> Node:
        command = self.next()
        self.enter(command)
        index = None
        index_position = command.position
        if self.peek().kind is Kind.LBRACKET:
            opening = self.next()
            index_position = self.peek().position
            index = self.sum()
            self.expect_close(opening)
        radicand = self.argument(command)
        self.leave()
        if index is None:
            return Call("sqrt", (radicand,), command.position)
        one = Operand(False, Number(sympy.Integer(1), command.position), command.position)
        inverse = Product((one, Operand(True, index, index_position)), index_position)
        return Power(radicand, inverse, command.position)

    def function(self) -> Node:
        r"""``\sin x``, ``\sin(x)``, ``\sin^2 x``, ``\sin^{2}(x)``."""
        command = self.next()
        name = command.value
        self.enter(command)
        exponent = caret = None
        if self.is_operator(self.peek(), "^"):
            caret = self.next()
            exponent = self.exponent()
            if isinstance(exponent, Negate):
                raise self.error(
                    f"'{command.text}^{{-1}}' is ambiguous: write the inverse function "
                    f"or ({command.text} x)^{{-1}}",
                    caret,
                )
        if self.peek().kind is Kind.LPAREN:
            opening = self.next()
            args = self.arguments(opening)
            self.check_arity(name, len(args), command)
        else:
            first = self.peek()
            argument = self.unary()
            if isinstance(argument, Number) and self.peek().kind in _FACTOR_STARTS:
                raise self.error(
                    f"ambiguous argument of '{command.text}': use parentheses, as in "
                    f"{command.text}({shorten(first.text)} x)",
                    first,
                )
            args = (argument,)
        self.leave()
        call = Call(name, args, command.position)
        if exponent is None:
            return call
        return Power(call, exponent, caret.position)
