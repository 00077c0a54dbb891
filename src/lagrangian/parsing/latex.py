r"""The LaTeX tokenizer: textbook notation to the parser's tokens.

Names are resolved here, so the parser sees one name token for each of
``\theta`` (``theta``), ``\theta_1`` and ``\theta_{1}`` (``theta1``), ``l_{ab}``
(``l_ab``), ``\dot{\theta}`` and ``\dot\theta`` (``theta_dot``), ``\ddot{x}``
(``x_ddot``), ``\dot{\theta}_1`` and ``\dot{\theta_1}`` (``theta1_dot``).
A subscript of digits is appended directly, any other with ``_``; an unbraced
subscript takes the whole run of letters and digits (``x_dot`` -> ``x_dot``).
A run of letters without a backslash is one name: ``ml`` is the name ``ml``.

Commands: Greek letters (and ``\ell``, the name ``l``), ``\sin`` ... ``\ln``
(:data:`~.names.LATEX_FUNCTIONS`), ``\frac`` (``\dfrac``, ``\tfrac``), ``\sqrt``,
``\cdot``, ``\times``, ``\div``, ``\left`` / ``\right`` before ``( ) [ ]``, and the
spacing commands ``\, \; \: \! \quad \qquad``, which are skipped.  Any other
command is an error that names it.
"""

from __future__ import annotations

from lagrangian.errors import ParseError
from lagrangian.parsing.lexer import (
    WHITESPACE,
    TokenList,
    check_name,
    describe_char,
    scan_name,
    scan_number,
    scan_operator,
    shorten,
    starts_name,
    starts_number,
    unexpected_character,
    with_dots,
)
from lagrangian.parsing.limits import ParseLimits
from lagrangian.parsing.names import LATEX_FUNCTIONS, LATEX_GREEK, UNICODE_GREEK
from lagrangian.parsing.nodes import Kind, Token

_SPACING = frozenset({",", ";", ":", "!", " ", "quad", "qquad", "displaystyle", "textstyle"})
_OPERATORS = {"cdot": "*", "times": "*", "div": "/"}
_FRACTIONS = frozenset({"frac", "dfrac", "tfrac"})
_ACCENTS = {"dot": 1, "ddot": 2}
_PUNCTUATION = {
    "(": Kind.LPAREN,
    ")": Kind.RPAREN,
    "[": Kind.LBRACKET,
    "]": Kind.RBRACKET,
    "{": Kind.LBRACE,
    "}": Kind.RBRACE,
    ",": Kind.COMMA,
}
_DELIMITERS = {"(": Kind.LPAREN, ")": Kind.RPAREN, "[": Kind.LBRACKET, "]": Kind.RBRACKET}


def looks_like_latex(text: str) -> bool:
    """LaTeX is recognised by a backslash or a brace."""
    return "\\" in text or "{" in text


def tokenize_latex(text: str, limits: ParseLimits) -> list[Token]:
    """The tokens of LaTeX text, ending with an END token at ``len(text)``."""
    return _Scanner(text, limits).run()


def _is_letter(char: str) -> bool:
    return char.isascii() and char.isalpha()


class _Scanner:
    def __init__(self, text: str, limits: ParseLimits):
        self.text = text
        self.limits = limits
        self.out = TokenList(text, limits)

    def run(self) -> list[Token]:
        text = self.text
        i = 0
        while i < len(text):
            char = text[i]
            if char in WHITESPACE:
                i += 1
            elif char == "\\":
                i = self.command(i)
            elif starts_number(text, i):
                value, j = scan_number(text, i, self.limits)
                self.out.add(Kind.NUMBER, i, j, value)
                i = j
            elif starts_name(text, i):
                name, j = scan_name(text, i, underscores=False)
                name, j = self.subscripts(j, name)
                self.out.add(Kind.NAME, i, j, check_name(name, text, i))
                i = j
            elif char in _PUNCTUATION:
                self.out.add(_PUNCTUATION[char], i, i + 1)
                i += 1
            else:
                j = scan_operator(text, i, self.out)
                if j is None:
                    raise unexpected_character(text, i)
                i = j
        return self.out.finish()

    def skip_space(self, i: int) -> int:
        while i < len(self.text) and self.text[i] in WHITESPACE:
            i += 1
        return i

    def command_name(self, start: int) -> tuple[str, int]:
        """The command at ``start`` (a backslash) without the backslash, and the offset after."""
        text = self.text
        i = start + 1
        if i >= len(text):
            raise ParseError("expected a command after '\\'", text, start)
        if not _is_letter(text[i]):
            if not text[i].isprintable():
                raise ParseError(f"unexpected character {describe_char(text[i])}", text, i)
            return text[i], i + 1
        while i < len(text) and _is_letter(text[i]):
            i += 1
        return text[start + 1 : i], i

    def command(self, start: int) -> int:
        name, i = self.command_name(start)
        out = self.out
        if name in _SPACING:
            return i
        if name in LATEX_GREEK:
            symbol, end = self.subscripts(i, LATEX_GREEK[name])
            out.add(Kind.NAME, start, end, symbol)
            return end
        if name in LATEX_FUNCTIONS:
            out.add(Kind.FUNCTION, start, i, LATEX_FUNCTIONS[name])
        elif name in _FRACTIONS:
            out.add(Kind.FRAC, start, i)
        elif name == "sqrt":
            out.add(Kind.SQRT, start, i)
        elif name in _OPERATORS:
            out.add(Kind.OPERATOR, start, i, _OPERATORS[name])
        elif name in ("left", "right"):
            return self.delimiter(start, i, name)
        elif name in _ACCENTS:
            return self.accent(start, i, name)
        else:
            raise ParseError(f"unknown LaTeX command '\\{shorten(name)}'", self.text, start)
        return i

    def delimiter(self, start: int, i: int, command: str) -> int:
        i = self.skip_space(i)
        if i >= len(self.text) or self.text[i] not in _DELIMITERS:
            raise ParseError(f"expected one of ( ) [ ] after '\\{command}'", self.text, i)
        self.out.add(_DELIMITERS[self.text[i]], start, i + 1)
        return i + 1

    def accent(self, start: int, i: int, command: str) -> int:
        r"""One name token: ``\dot{x}``, ``\dot x``, ``\ddot{\theta_1}``, ``\dot{\theta}_1``."""
        text = self.text
        i = self.skip_space(i)
        if i < len(text) and text[i] == "{":
            base, i = self.accent_target(self.skip_space(i + 1), command, whole=True)
            base, i = self.subscripts(i, base)
            i = self.skip_space(i)
            if i >= len(text) or text[i] != "}":
                raise ParseError(f"expected '}}' to close '\\{command}{{'", text, i)
            i += 1
        else:
            base, i = self.accent_target(i, command, whole=False)
        base, i = self.subscripts(i, base)
        name = check_name(with_dots(base, _ACCENTS[command], text, start), text, start)
        self.out.add(Kind.NAME, start, i, name)
        return i

    def accent_target(self, i: int, command: str, *, whole: bool) -> tuple[str, int]:
        text = self.text
        if i < len(text) and text[i] == "\\":
            name, end = self.command_name(i)
            if name not in LATEX_GREEK:
                raise ParseError(f"cannot put '\\{command}' over '\\{shorten(name)}'", text, i)
            return LATEX_GREEK[name], end
        if i < len(text) and starts_name(text, i):
            if whole:
                return scan_name(text, i, underscores=False)
            char = text[i]
            if char in UNICODE_GREEK:
                return UNICODE_GREEK[char], i + 1
            if _is_letter(char):
                return char, i + 1
        raise ParseError(f"expected a name after '\\{command}'", text, i)

    def subscripts(self, i: int, name: str) -> tuple[str, int]:
        """``name`` with the subscripts at ``i`` appended, and the offset after them."""
        text = self.text
        while i < len(text) and text[i] == "_":
            content, i = self.subscript(self.skip_space(i + 1), i)
            name += content if content.isdigit() else "_" + content
        return name, i

    def subscript(self, i: int, underscore: int) -> tuple[str, int]:
        text = self.text
        if i < len(text) and text[i] == "{":
            parts: list[str] = []
            i = self.skip_space(i + 1)
            while i < len(text) and text[i] != "}":
                part, i = self.subscript_part(i)
                parts.append(part)
                i = self.skip_space(i)
            if i >= len(text):
                raise ParseError("expected '}' to close the subscript", text, i)
            if not parts:
                raise ParseError("empty subscript", text, underscore)
            return "".join(parts), i + 1
        if i < len(text) and (text[i] == "\\" or (text[i].isascii() and text[i].isalnum())):
            return self.subscript_part(i)
        raise ParseError("expected a subscript after '_'", text, underscore)

    def subscript_part(self, i: int) -> tuple[str, int]:
        """A run of ASCII letters and digits, or a Greek command."""
        text = self.text
        if text[i] == "\\":
            name, end = self.command_name(i)
            if name not in LATEX_GREEK:
                raise ParseError(f"unexpected '\\{shorten(name)}' in a subscript", text, i)
            return LATEX_GREEK[name], end
        end = i
        while end < len(text) and text[end].isascii() and (text[end].isalnum()):
            end += 1
        if end == i:
            raise ParseError(f"unexpected {describe_char(text[i])} in a subscript", text, i)
        return text[i:end], end
