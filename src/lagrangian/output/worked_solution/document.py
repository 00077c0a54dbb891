"""The pieces of a worked solution, independent of the format it is written in.

A :class:`WorkedSolution` is a title and :class:`Section` s; a section holds blocks:
a :class:`Paragraph` (text with inline mathematics), a :class:`Display` (rows
``lhs = rhs`` aligned at the relation, each right side already broken into lines,
:mod:`.breaking`), a :class:`Table` and a :class:`Picture` (a matplotlib figure and its
caption).  Mathematics is LaTeX, text is plain Unicode: each writer (:mod:`.tex`,
:mod:`.markdown`, :mod:`.html`) escapes the text for its own format.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Math:
    """Inline mathematics (LaTeX)."""

    latex: str


#: A run of inline content: text (plain Unicode) or mathematics.
Inline = tuple["str | Math", ...]


@dataclass(frozen=True)
class Paragraph:
    parts: Inline


@dataclass(frozen=True)
class Row:
    """``lhs relation rhs``: ``lines`` hold the right side, broken (each continuation
    line begins with its own ``+`` or ``-``); ``note`` follows the row, in parentheses."""

    lhs: str
    lines: tuple[str, ...]
    relation: str = "="
    note: Inline = ()


@dataclass(frozen=True)
class Display:
    """Rows shown together, aligned at their relations."""

    rows: tuple[Row, ...]


@dataclass(frozen=True)
class Table:
    header: tuple[str, ...]
    rows: tuple[tuple[Inline, ...], ...]


@dataclass(frozen=True)
class Picture:
    """A figure written beside the document as ``<stem>-<name>.<suffix>``."""

    name: str
    caption: str
    figure: object  # a matplotlib Figure


Block = Paragraph | Display | Table | Picture


@dataclass(frozen=True)
class Section:
    title: Inline
    blocks: tuple[Block, ...]
    level: int = 1  # 1: a section, 2: a subsection


@dataclass(frozen=True)
class WorkedSolution:
    title: str
    subtitle: str
    sections: tuple[Section, ...]

    @property
    def pictures(self) -> tuple[Picture, ...]:
        return tuple(b for s in self.sections for b in s.blocks if isinstance(b, Picture))


def parts(*items: str | Math) -> Inline:
    """Inline content from text and :class:`Math` items (empty text left out)."""
    return tuple(item for item in items if item != "")


def joined(items: list[Inline], separator: str = ", ") -> Inline:
    """Runs of inline content one after the other, ``separator`` between them."""
    out: list[str | Math] = []
    for i, item in enumerate(items):
        if i:
            out.append(separator)
        out.extend(item)
    return tuple(out)
