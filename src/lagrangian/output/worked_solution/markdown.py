"""A worked solution as Markdown with TeX mathematics (``$...$`` inline, ``$$...$$``
displayed), as GitHub, GitLab, Jupyter and pandoc read it; pictures as image links."""

from __future__ import annotations

import re

from .document import Display, Math, Paragraph, Picture, Table, WorkedSolution

#: Characters that would start Markdown's own syntax (or its mathematics) inside text.
_MARKUP = re.compile(r"([\\`*_{}\[\]<>#|$~])")


def markdown_document(solution: WorkedSolution, figure_files: dict[str, str]) -> str:
    """The whole ``.md`` file; ``figure_files`` maps a picture's name to its file."""
    lines = [f"# {_text(solution.title)}"]
    if solution.subtitle:
        lines.append(f"> {_text(solution.subtitle)}")
    for section in solution.sections:
        lines.append("#" * (section.level + 1) + " " + _inline(section.title))
        for block in section.blocks:
            lines.append(_block(block, figure_files))
    return "\n\n".join(lines) + "\n"


def _text(text: str) -> str:
    # one line (a newline would end a table row), the spaces around math kept
    return _MARKUP.sub(r"\\\1", re.sub(r"\s+", " ", text))


def _inline(items) -> str:
    return "".join(f"${item.latex}$" if isinstance(item, Math) else _text(item) for item in items)


def _block(block, figure_files: dict[str, str]) -> str:
    if isinstance(block, Paragraph):
        return _inline(block.parts)
    if isinstance(block, Display):
        return "$$\n" + aligned(block) + "\n$$"
    if isinstance(block, Table):
        header = "| " + " | ".join(_text(h) for h in block.header) + " |"
        rule = "|" + "---|" * len(block.header)
        rows = ["| " + " | ".join(_inline(cell) for cell in row) + " |" for row in block.rows]
        return "\n".join([header, rule, *rows])
    if isinstance(block, Picture):
        return f"![{_text(block.caption)}]({figure_files[block.name]})\n\n*{_text(block.caption)}*"
    raise TypeError(f"not a block of a worked solution: {block!r}")


def aligned(display: Display) -> str:
    """The rows of ``display`` as one ``aligned`` environment (KaTeX and MathJax read it)."""
    rows = []
    for row in display.rows:
        first, *rest = row.lines
        rows.append(f"{row.lhs} &{row.relation} {first}")
        rows += [rf"&\quad {{}} {line}" for line in rest]
        if row.note:
            note = "".join(
                item.latex if isinstance(item, Math) else r"\text{" + _math_text(item) + "}"
                for item in row.note
            )
            rows.append(rf"&\quad \text{{(}}{note}\text{{)}}")
    # a little room between rows: stacked fractions otherwise touch
    return "\\begin{aligned}\n" + " \\\\[0.3em]\n".join(rows) + "\n\\end{aligned}"


def _math_text(text: str) -> str:
    """Text inside ``\\text{}`` of KaTeX or MathJax: its braces and backslashes escaped."""
    return re.sub(r"([\\{}$&#%_^~])", r"\\\1", text)
