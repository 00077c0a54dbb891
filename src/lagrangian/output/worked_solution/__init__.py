"""The worked solution of a model as a document for lecture notes (``lagrangian report``).

:func:`worked_solution` collects what the toolkit derives (the system, T, V, L, each step
of Lagrange's equations, M q'' = f, the conserved quantities with their reasons, H, the
equilibria with their stability and normal modes with numbers, a phase portrait and the
mode shapes) into a :class:`~.document.WorkedSolution`; :func:`write_report` writes it
as LaTeX, Markdown or HTML (:data:`FORMATS`), its pictures beside it.

>>> import lagrangian as lg
>>> solution = worked_solution(lg.load("simple_pendulum"), figures=False)
>>> [" ".join(map(str, s.title)) for s in solution.sections][:3]
['The system', 'Energies and Lagrangian', "Lagrange's equations, step by step"]
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ...errors import ModelError
from ...files import check_output_path, write_atomically
from .content import worked_solution
from .document import WorkedSolution
from .html import html_document
from .markdown import markdown_document
from .tex import tex_document


@dataclass(frozen=True)
class ReportFormat:
    """How one format is written: the document, the file suffixes it is known by, and
    the format of its pictures (vector for LaTeX, PNG for the screen)."""

    name: str
    render: Callable[[WorkedSolution, dict[str, str]], str]
    suffixes: tuple[str, ...]
    figure_suffix: str


#: The formats of ``lagrangian report --to``.
FORMATS = {
    "tex": ReportFormat("tex", tex_document, (".tex",), ".pdf"),
    "md": ReportFormat("md", markdown_document, (".md", ".markdown"), ".png"),
    "html": ReportFormat("html", html_document, (".html", ".htm"), ".png"),
}
#: Resolution of the PNG pictures (dots per inch).
PICTURE_DPI = 150


def report_format(to: str | None, path: str | os.PathLike | None) -> ReportFormat:
    """The format named by ``to``, else by the suffix of ``path``; one that does not fit
    the other is a :class:`~lagrangian.errors.ModelError`."""
    suffix = Path(path).suffix.lower() if path is not None else ""
    if to is None:
        found = [f for f in FORMATS.values() if suffix in f.suffixes]
        if not found:
            raise ModelError(
                f"choose the format ({', '.join(FORMATS)}),"
                " or a file name ending in .tex, .md or .html"
            )
        return found[0]
    if to not in FORMATS:
        raise ModelError(f"unknown report format '{to}' (formats: {', '.join(FORMATS)})")
    chosen = FORMATS[to]
    if path is not None and suffix not in chosen.suffixes:
        raise ModelError(
            f"the {to} report's file must end in {' or '.join(chosen.suffixes)},"
            f" not '{Path(path).name}'"
        )
    return chosen


def write_report(
    solution: WorkedSolution, path: str | os.PathLike, to: str | None = None
) -> list[Path]:
    """Write ``solution`` to ``path`` in the format ``to`` (default: by its suffix), its
    pictures beside it as ``<stem>-<name>.<suffix>``; return the files written, the
    document last.  Each file is written atomically."""
    from ..plots import save_figure

    chosen = report_format(to, path)
    target = check_output_path(path)
    files: dict[str, str] = {}
    written = []
    for picture in solution.pictures:
        name = f"{Path(path).stem}-{picture.name}{chosen.figure_suffix}"
        written.append(save_figure(picture.figure, target.parent / name, dpi=PICTURE_DPI))
        files[picture.name] = name
    text = chosen.render(solution, files)
    written.append(
        write_atomically(path, lambda temporary: temporary.write_text(text, encoding="utf-8"))
    )
    return written


def report_text(
    solution: WorkedSolution, to: str, figure_files: dict[str, str] | None = None
) -> str:
    """The document of ``solution`` in the format ``to``, as text (pictures referred to by
    ``figure_files``, a picture's name to its file; none written here)."""
    chosen = report_format(to, None)
    return chosen.render(
        solution,
        figure_files or {p.name: f"{p.name}{chosen.figure_suffix}" for p in solution.pictures},
    )


__all__ = [
    "FORMATS",
    "WorkedSolution",
    "report_format",
    "report_text",
    "worked_solution",
    "write_report",
]
