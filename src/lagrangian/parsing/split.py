"""The terms of a long plain text's top-level sum, found without tokenizing the text.

A large model's texts are long sums of the same few terms (the n-th bob of a chain is
``l1*sin(theta1) + ... + ln*sin(thetan)``: O(n^2) characters for the model).  Each distinct
term is built once (:class:`~.terms.Terms`); this finds where the terms are with one
scan of the signs and parentheses, so that only a term not met before is tokenized and
parsed.  The split is the parser's: a ``+``/``-`` outside parentheses that follows an
operand (not a number's exponent, ``1e-3``, nor a sign after ``*``, ``/``, ``^`` or
another sign).  Where a text could be split otherwise (non-ASCII text, unbalanced
parentheses, one term), None sends it to the full parse, and so does any error: a text
is refused by the full parse, with its message and position.
"""

from __future__ import annotations

import re

#: What the split looks at: signs and parentheses.
_MARKS = re.compile(r"[-+()]")
#: Whitespace the tokenizer skips, ASCII (the split takes ASCII text only).
_SPACE = " \t\r\n\f\v"
_OPERAND_CHARACTERS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.")


def top_level_terms(text: str) -> list[tuple[int, int, bool]] | None:
    """[(start, end, negated)] of the terms of ``text``'s top-level sum, as the parser
    splits it (past the sign, without the spaces around each term), or None
    where the text is not ASCII, its parentheses do not balance, or it has one term."""
    if not text.isascii():
        return None
    first = len(text) - len(text.lstrip(_SPACE))
    depth = 0
    cuts: list[int] = []
    for match in _MARKS.finditer(text, first):
        at = match.start()
        mark = text[at]
        if mark == "(":
            depth += 1
        elif mark == ")":
            depth -= 1
            if depth < 0:
                return None
        elif depth == 0 and at > first and _follows_operand(text, at):
            cuts.append(at)
    if depth or not cuts:
        return None
    terms = [(*without_spaces(text, first, cuts[0]), False)]
    for k, at in enumerate(cuts):
        end = cuts[k + 1] if k + 1 < len(cuts) else len(text)
        terms.append((*without_spaces(text, at + 1, end), text[at] == "-"))
    return terms


def without_spaces(text: str, start: int, end: int) -> tuple[int, int]:
    """(start, end) of ``text[start:end]`` without the whitespace around it: a term is
    the same term whatever the spaces around it (the last of a sum has none after it)."""
    while start < end and text[start] in _SPACE:
        start += 1
    while end > start and text[end - 1] in _SPACE:
        end -= 1
    return start, end


def _follows_operand(text: str, at: int) -> bool:
    """Whether the sign at ``at`` is a binary operator: not after an operator or another
    sign (``a*-b``, ``a - -b``: unary), nor the sign of a number's exponent (``2.5e-3``)."""
    before = at - 1
    while text[before] in _SPACE:
        before -= 1
    previous = text[before]
    if previous in "*/^+-":
        return False
    if previous in "eE" and before == at - 1 and text[at + 1 : at + 2].isdigit():
        start = before  # the run of name and number characters the e ends
        while start > 0 and text[start - 1] in _OPERAND_CHARACTERS:
            start -= 1
        if text[start].isdigit() or text[start] == ".":
            return False  # scanned as a number with its exponent
    return True
