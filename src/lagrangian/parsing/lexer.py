"""The plain-text tokenizer, and the scanners it shares with the LaTeX one.

Plain text is numbers, names, ``+ - * / ** ^``, parentheses and commas; every
other character is an error that names it.  A few Unicode spellings are
accepted: Greek letters in names (``θ`` -> ``theta``), a dot or two above a
letter (``θ̇`` -> ``theta_dot``, ``ẍ`` -> ``x_ddot``), subscript digits
(``θ₁`` -> ``theta1``), superscript powers (``x²`` -> ``x**2``) and the
operators ``· × ⋅ − ÷``.

Numbers are exact: ``0.1`` is ``Rational(1, 10)`` and ``1e-3`` is
``Rational(1, 1000)``, built from the digits checked here.
"""

from __future__ import annotations

import unicodedata

import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing.limits import LITERAL_EXPONENT_LIMIT, ParseLimits
from lagrangian.parsing.names import UNICODE_GREEK
from lagrangian.parsing.nodes import Kind, Token

WHITESPACE = frozenset(" \t\r\n\f\v\u00a0")
UNICODE_OPERATORS = {"·": "*", "×": "*", "⋅": "*", "−": "-", "÷": "/"}
SUPERSCRIPT_DIGITS = {c: str(i) for i, c in enumerate("⁰¹²³⁴⁵⁶⁷⁸⁹")}
SUPERSCRIPT_MINUS = "⁻"
SUBSCRIPT_DIGITS = {c: str(i) for i, c in enumerate("₀₁₂₃₄₅₆₇₈₉")}
_DOTS = {"\u0307": 1, "\u0308": 2}  # combining dot above, diaeresis
_DOT_SUFFIX = {1: "_dot", 2: "_ddot"}
_ASCII_LETTERS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ")
_ASCII_DIGITS = frozenset("0123456789")
_SHOWN_NAME = 40  # characters of a long name quoted in an error


def describe_char(char: str) -> str:
    """A character as an error message shows it: ``'['`` or ``U+0000``."""
    if char == "'":
        return '"\'"'
    if char.isprintable() and not char.isspace():
        return f"'{char}'"
    return f"U+{ord(char):04X}"


def unexpected_character(text: str, position: int) -> ParseError:
    return ParseError(f"unexpected character {describe_char(text[position])}", text, position)


class TokenList:
    """Tokens appended one by one, refused as soon as there are more than ``max_nodes``."""

    def __init__(self, text: str, limits: ParseLimits):
        self.text = text
        self.limits = limits
        self.limit = limits.max_nodes
        self.tokens: list[Token] = []

    def add(self, kind: Kind, start: int, end: int, value: object = None) -> None:
        if len(self.tokens) >= self.limit:
            raise ParseError(
                f"expression too large (more than {self.limit} tokens)", self.text, start
            )
        self.tokens.append(Token(kind, self.text[start:end], start, value))

    def finish(self) -> list[Token]:
        self.tokens.append(Token(Kind.END, "", len(self.text)))
        return self.tokens


def is_digit(char: str) -> bool:
    return char in _ASCII_DIGITS


def starts_number(text: str, i: int) -> bool:
    return is_digit(text[i]) or (text[i] == "." and i + 1 < len(text) and is_digit(text[i + 1]))


def scan_number(text: str, start: int, limits: ParseLimits) -> tuple[sympy.Rational, int]:
    """The exact value of the literal at ``start`` and the offset after it."""
    end = len(text)
    i = start
    while i < end and is_digit(text[i]):
        i += 1
    whole = text[start:i]
    fraction = ""
    if i < end and text[i] == ".":
        j = i + 1
        while j < end and is_digit(text[j]):
            j += 1
        fraction = text[i + 1 : j]
        i = j
    exponent = 0
    if i < end and text[i] in "eE":
        j = i + 1
        if j < end and text[j] in "+-":
            j += 1
        if j < end and is_digit(text[j]):
            k = j
            while k < end and is_digit(text[k]):
                k += 1
            exponent = _literal_exponent(text, i + 1, k, start)
            i = k
    digits = whole + fraction
    if len(digits) > limits.max_number_digits:
        raise ParseError(
            f"number with {len(digits)} digits too long (limit {limits.max_number_digits})",
            text,
            start,
        )
    mantissa = int(digits)
    shift = exponent - len(fraction)
    if shift >= 0:
        return sympy.Integer(mantissa * 10**shift), i
    return sympy.Rational(mantissa, 10**-shift), i


def _literal_exponent(text: str, start: int, end: int, number_start: int) -> int:
    shown = text[start:end]
    digits = shown.lstrip("+-").lstrip("0") or "0"
    if len(digits) > len(str(LITERAL_EXPONENT_LIMIT)) or int(digits) > LITERAL_EXPONENT_LIMIT:
        if len(shown) > 12:
            shown = shown[:12] + "..."
        raise ParseError(
            f"exponent {shown} too large (limit {LITERAL_EXPONENT_LIMIT})", text, number_start
        )
    return -int(digits) if shown.startswith("-") else int(digits)


def starts_name(text: str, i: int) -> bool:
    """Whether a name starts at ``i``: an ASCII or Greek letter, possibly dotted."""
    char = text[i]
    if char in _ASCII_LETTERS or char in UNICODE_GREEK:
        return True
    base, dots = _decompose(char)
    return dots > 0 and (base in _ASCII_LETTERS or base in UNICODE_GREEK)


def scan_name(text: str, start: int, *, underscores: bool) -> tuple[str, int]:
    """The name at ``start`` (Greek letters spelled out, dots as a suffix) and the offset after.

    ``underscores``: whether ``_`` belongs to the name (plain text) or is left for
    the caller (a LaTeX subscript).
    """
    parts: list[str] = []
    dots = 0
    i = start
    end = len(text)
    while i < end:
        char = text[i]
        if char in _ASCII_LETTERS or is_digit(char) or (underscores and char == "_"):
            parts.append(char)
        elif char in UNICODE_GREEK:
            parts.append(UNICODE_GREEK[char])
        elif char in SUBSCRIPT_DIGITS:
            parts.append(SUBSCRIPT_DIGITS[char])
        elif char in _DOTS:
            dots += _DOTS[char]
        else:
            base, extra = _decompose(char)
            if not extra or not (base in _ASCII_LETTERS or base in UNICODE_GREEK):
                break
            parts.append(UNICODE_GREEK.get(base, base))
            dots += extra
        i += 1
    return with_dots("".join(parts), dots, text, start), i


def with_dots(name: str, dots: int, text: str, position: int) -> str:
    """``name`` with the suffix of ``dots`` time derivatives (``_dot``, ``_ddot``)."""
    if dots == 0:
        return name
    if dots not in _DOT_SUFFIX:
        raise ParseError(f"too many dots over '{shorten(name)}' (at most 2)", text, position)
    return name + _DOT_SUFFIX[dots]


def check_name(name: str, text: str, position: int) -> str:
    """``name`` if it is allowed: never containing ``__`` (it cannot start with ``_``)."""
    if "__" in name:
        raise ParseError(
            f"invalid name '{shorten(name)}': names may not contain '__'", text, position
        )
    return name


def shorten(name: str) -> str:
    return name if len(name) <= _SHOWN_NAME else name[: _SHOWN_NAME - 3] + "..."


def _decompose(char: str) -> tuple[str, int]:
    """A precomposed letter as (base letter, dots above it): ``ẋ`` -> ``('x', 1)``."""
    if char.isascii():
        return char, 0
    decomposed = unicodedata.normalize("NFD", char)
    if len(decomposed) < 2 or any(mark not in _DOTS for mark in decomposed[1:]):
        return char, 0
    return decomposed[0], sum(_DOTS[mark] for mark in decomposed[1:])


def scan_superscript(text: str, start: int, out: TokenList) -> int:
    """``x²`` and ``x⁻¹``: add the tokens of ``^2`` (``^ - 1``) and return the offset after."""
    out.add(Kind.OPERATOR, start, start + 1, "^")
    i = start
    if text[i] == SUPERSCRIPT_MINUS:
        out.add(Kind.OPERATOR, i, i + 1, "-")
        i += 1
    digits_start = i
    while i < len(text) and text[i] in SUPERSCRIPT_DIGITS:
        i += 1
    if i == digits_start:
        raise ParseError("expected superscript digits", text, i)
    most = out.limits.max_number_digits
    if i - digits_start > most:
        raise ParseError(
            f"superscript number with {i - digits_start} digits too long (limit {most})",
            text,
            digits_start,
        )
    value = "".join(SUPERSCRIPT_DIGITS[c] for c in text[digits_start:i])
    out.add(Kind.NUMBER, digits_start, i, sympy.Integer(int(value)))
    return i


def scan_operator(text: str, i: int, out: TokenList) -> int | None:
    """Add the operator at ``i`` (``**`` and ``^`` are both ``^``); None if there is none."""
    char = text[i]
    if char == "*" and text.startswith("**", i):
        out.add(Kind.OPERATOR, i, i + 2, "^")
        return i + 2
    if char in "+-*/^":
        out.add(Kind.OPERATOR, i, i + 1, char)
        return i + 1
    if char in UNICODE_OPERATORS:
        out.add(Kind.OPERATOR, i, i + 1, UNICODE_OPERATORS[char])
        return i + 1
    if char in SUPERSCRIPT_DIGITS or char == SUPERSCRIPT_MINUS:
        return scan_superscript(text, i, out)
    return None


_PLAIN_PUNCTUATION = {"(": Kind.LPAREN, ")": Kind.RPAREN, ",": Kind.COMMA}


def tokenize(text: str, limits: ParseLimits) -> list[Token]:
    """The tokens of plain text, ending with an END token at ``len(text)``."""
    out = TokenList(text, limits)
    i = 0
    end = len(text)
    while i < end:
        char = text[i]
        if char in WHITESPACE:
            i += 1
        elif starts_number(text, i):
            value, j = scan_number(text, i, limits)
            out.add(Kind.NUMBER, i, j, value)
            i = j
        elif starts_name(text, i):
            name, j = scan_name(text, i, underscores=True)
            out.add(Kind.NAME, i, j, check_name(name, text, i))
            i = j
        elif char == "_":
            name, _ = scan_name(text, i, underscores=True)
            raise ParseError(
                f"invalid name '{shorten(name)}': names may not start with '_'", text, i
            )
        elif char in _PLAIN_PUNCTUATION:
            out.add(_PLAIN_PUNCTUATION[char], i, i + 1)
            i += 1
        else:
            j = scan_operator(text, i, out)
            if j is None:
                raise unexpected_character(text, i)
            i = j
    return out.finish()
