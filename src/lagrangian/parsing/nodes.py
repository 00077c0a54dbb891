"""Tokens and the syntax tree: what the tokenizers and the parser hand on.

The tree knows nothing of a namespace.  It is built once from text (plain or
LaTeX, which map to the same tree), then either turned into SymPy objects
(:mod:`.builder`) or searched for the names it uses (:mod:`.expression`).
Sums and products are n-ary, so a 10,000-term sum is one node, not a chain
10,000 deep.  ``position`` is always the 0-based offset in the original text.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import sympy


class Kind(enum.Enum):
    NUMBER = "number"
    NAME = "name"
    FUNCTION = "function"  # LaTeX function command: \sin, \ln ...
    OPERATOR = "operator"  # + - * / ^
    LPAREN = "("
    RPAREN = ")"
    LBRACKET = "["
    RBRACKET = "]"
    LBRACE = "{"
    RBRACE = "}"
    COMMA = ","
    FRAC = "\\frac"
    SQRT = "\\sqrt"
    END = "end"


@dataclass(frozen=True, slots=True)
class Token:
    """One token.  ``text`` is the source slice; ``value`` the number, name or operator."""

    kind: Kind
    text: str
    position: int
    value: object = None

    def describe(self) -> str:
        if self.kind is Kind.END:
            return "end of expression"
        return f"'{self.text}'"


@dataclass(frozen=True, slots=True)
class Number:
    value: sympy.Rational
    position: int


@dataclass(frozen=True, slots=True)
class Name:
    name: str
    position: int


@dataclass(frozen=True, slots=True)
class Call:
    """``name(args)``.  ``juxtaposed``: LaTeX ``m(a + b)``, a product unless ``m`` is a function."""

    name: str
    args: tuple[Node, ...]
    position: int
    juxtaposed: bool = False


@dataclass(frozen=True, slots=True)
class Negate:
    operand: Node
    position: int


@dataclass(frozen=True, slots=True)
class Operand:
    """A term of a sum (``inverted``: subtracted) or a factor of a product (divided by)."""

    inverted: bool
    node: Node
    position: int


@dataclass(frozen=True, slots=True)
class Sum:
    terms: tuple[Operand, ...]
    position: int


@dataclass(frozen=True, slots=True)
class Product:
    factors: tuple[Operand, ...]
    position: int


@dataclass(frozen=True, slots=True)
class Power:
    base: Node
    exponent: Node
    position: int


Node = Number | Name | Call | Negate | Sum | Product | Power
