"""Free text in generated files: comment lines that no text can end early.

An exported file's header carries the model's own words (its ``name`` and
``description``), and a model file may come from anyone.  Copied raw, that text
could end the comment and become code: ``*/`` in C, a line break in Python,
Julia and MATLAB (a lone CR, U+2028, a vertical tab...), ``=#`` or ``%}`` in
their block comments, a NUL that makes the file unreadable.  :func:`commented`
is the one way the writers put text in a comment:

* the text is split at every line break :meth:`str.splitlines` knows, and each
  piece becomes its own comment line;
* the remaining control and format characters (Unicode categories Cc and Cf:
  NUL, escape, bidirectional overrides that make code read differently from
  what runs) become U+FFFD;
* each sequence that ends, opens or nests a comment in the language
  (:attr:`CommentStyle.breaking`) is broken apart with a space, until none is left.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Iterable
from dataclasses import dataclass

#: What a control or format character in free text is shown as.
REPLACEMENT = "\N{REPLACEMENT CHARACTER}"


@dataclass(frozen=True)
class CommentStyle:
    """How a language writes a block of comment lines.

    ``opening`` / ``closing``: lines before and after the block (C's ``/*`` and
    `` */``), empty for line comments; ``prefix``: what starts each line;
    ``breaking``: two-character sequences that would end, open or nest a comment
    (or, in C, make a trigraph) and are never written inside one.
    """

    opening: str
    prefix: str
    closing: str
    breaking: tuple[str, ...]

    def __post_init__(self) -> None:
        assert all(len(sequence) == 2 and " " not in sequence for sequence in self.breaking)


#: C (and CUDA): one block comment; ``??`` would begin a trigraph (``??/`` is a backslash).
C_COMMENT = CommentStyle("/*", " * ", " */", ("*/", "/*", "??"))
#: Python: line comments, where only a line break ends one.
PYTHON_COMMENT = CommentStyle("", "# ", "", ())
#: Julia: line comments; ``#=`` ... ``=#`` are its (nesting) block comments.
JULIA_COMMENT = CommentStyle("", "# ", "", ("#=", "=#"))
#: MATLAB / Octave: line comments; ``%{`` ``%}`` (and Octave's ``#{`` ``#}``) delimit blocks.
MATLAB_COMMENT = CommentStyle("", "% ", "", ("%{", "%}", "#{", "#}"))


def plain_lines(text: str) -> list[str]:
    """``text`` as lines that hold no line break and no control or format character."""
    return [
        "".join(REPLACEMENT if unicodedata.category(c) in ("Cc", "Cf") else c for c in line)
        for line in (text.splitlines() or [""])
    ]


def one_line(text: str) -> str:
    """``text`` on one line (line breaks become spaces), without control characters."""
    return " ".join(plain_lines(text))


def comment_safe(text: str, style: CommentStyle) -> str:
    """``text`` as one line that stays inside a comment of ``style``."""
    safe = one_line(text)
    changed = True
    while changed:  # a split pair cannot form a new one: no sequence holds a space
        changed = False
        for sequence in style.breaking:
            if sequence in safe:
                safe = safe.replace(sequence, f"{sequence[0]} {sequence[1]}")
                changed = True
    return safe


def commented(lines: Iterable[str], style: CommentStyle) -> list[str]:
    """The comment block of ``lines`` (each may hold line breaks: they become new lines)."""
    block = [style.opening] if style.opening else []
    for line in lines:
        for piece in plain_lines(line):
            block.append(f"{style.prefix}{comment_safe(piece, style)}".rstrip())
    if style.closing:
        block.append(style.closing)
    return block
