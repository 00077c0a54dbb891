"""A worked solution as a LaTeX document that pdflatex compiles.

Only packages of Debian's ``texlive-latex-base`` and ``texlive-latex-recommended`` (and
``texlive-base``, which they need) are used: amsmath, amssymb, graphicx, geometry,
booktabs.  Every display is an ``align*`` whose right sides were broken between
terms (:mod:`.breaking`); the ``\\fit`` macro scales down what is still wider than its
share of the line, so no equation runs into the margin.  Text from the model is
escaped (:func:`.tex_text.tex_text`): it cannot run a command.
"""

from __future__ import annotations

from .document import Display, Math, Paragraph, Picture, Table, WorkedSolution
from .tex_text import tex_text

PREAMBLE = r"""\documentclass[11pt,a4paper]{article}
\usepackage[utf8]{inputenc}
\usepackage{amsmath,amssymb}
\usepackage{graphicx}
\usepackage[margin=2.5cm]{geometry}
\usepackage{booktabs}
\allowdisplaybreaks
% a picture stays near its text where it fits, rather than on a page of its own
\renewcommand{\topfraction}{0.9}
\renewcommand{\bottomfraction}{0.8}
\renewcommand{\textfraction}{0.07}
\renewcommand{\floatpagefraction}{0.7}
\setlength{\parindent}{0pt}
\setlength{\parskip}{0.6em}
% what is wider than its share of the line is scaled down to it
\newsavebox{\fitbox}
\newcommand{\fitto}[2]{\sbox{\fitbox}{#2}%
  \ifdim\wd\fitbox>#1\resizebox{#1}{!}{\usebox{\fitbox}}\else\usebox{\fitbox}\fi}
\newcommand{\fit}[1]{\fitto{0.8\linewidth}{$\displaystyle #1$}}
\newcommand{\fitwide}[1]{\fitto{0.95\linewidth}{$\displaystyle #1$}}
\newcommand{\fitlhs}[1]{\fitto{0.18\linewidth}{$\displaystyle #1$}}
"""


def tex_document(solution: WorkedSolution, figure_files: dict[str, str]) -> str:
    """The whole ``.tex`` file; ``figure_files`` maps a picture's name to its file."""
    lines = [
        PREAMBLE,
        r"\title{" + tex_text(solution.title) + "}",
        r"\date{}",
        r"\begin{document}",
        r"\maketitle",
    ]
    if solution.subtitle:
        lines.append(r"\begin{quote}" + tex_text(solution.subtitle) + r"\end{quote}")
    for section in solution.sections:
        command = r"\section" if section.level == 1 else r"\subsection"
        lines.append(f"{command}{{{_inline(section.title)}}}")
        for block in section.blocks:
            lines.append(_block(block, figure_files))
    lines.append(r"\end{document}")
    return "\n\n".join(lines) + "\n"


def _inline(items) -> str:
    return "".join(
        f"${item.latex}$" if isinstance(item, Math) else tex_text(item) for item in items
    )


def _block(block, figure_files: dict[str, str]) -> str:
    if isinstance(block, Paragraph):
        return _inline(block.parts)
    if isinstance(block, Display):
        return _display(block)
    if isinstance(block, Table):
        return _table(block)
    if isinstance(block, Picture):
        return "\n".join(
            [
                r"\begin{figure}[!htbp]",
                r"\centering",
                rf"\includegraphics[width=\linewidth,height=0.36\textheight,keepaspectratio]"
                rf"{{{figure_files[block.name]}}}",
                r"\caption{" + tex_text(block.caption) + "}",
                r"\end{figure}",
            ]
        )
    raise TypeError(f"not a block of a worked solution: {block!r}")


def _display(display: Display) -> str:
    rows = []
    for row in display.rows:
        relation = {"=": "="}.get(row.relation, row.relation)
        first, *rest = row.lines
        if not row.lhs and not relation:  # one formula across the line
            rows.append(rf"&\fitwide{{{first}}}")
            continue
        rows.append(rf"\fitlhs{{{row.lhs}}} &{relation} \fit{{{first}}}")
        rows += [rf"&\hphantom{{{relation}}}\quad \fit{{{{}} {line}}}" for line in rest]
        if row.note:
            rows.append(r"&\hphantom{=}\quad \text{(}" + _note(row.note) + r"\text{)}")
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def _note(items) -> str:
    """Inline content inside mathematics: text in ``\\text{}``, math as it is."""
    return "".join(
        item.latex if isinstance(item, Math) else r"\text{" + tex_text(item) + "}" for item in items
    )


def _table(table: Table) -> str:
    columns = "l" * len(table.header)
    header = " & ".join(tex_text(h) for h in table.header) + r" \\"
    body = [" & ".join(_inline(cell) for cell in row) + r" \\" for row in table.rows]
    tabular = "\n".join(
        [
            rf"\begin{{tabular}}{{{columns}}}",
            r"\toprule",
            header,
            r"\midrule",
            *body,
            r"\bottomrule",
            r"\end{tabular}",
        ]
    )
    return "\\begin{center}\n\\fitto{\\linewidth}{" + tabular + "}\n\\end{center}"
