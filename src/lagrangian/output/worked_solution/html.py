"""A worked solution as one HTML file that typesets its mathematics offline.

KaTeX (the page's own copy, its fonts embedded: :func:`~lagrangian.output.page.katex_assets`)
renders every formula when the file opens; with scripts off, the TeX itself shows.  Every
text of the model is HTML-escaped, and so is the TeX of each formula (KaTeX reads it back
as text): nothing a model holds becomes markup or script.  Pictures are the files written
beside it.
"""

from __future__ import annotations

import html

from ..page import katex_assets
from .document import Display, Math, Paragraph, Picture, Table, WorkedSolution
from .markdown import aligned

_STYLE = """
body { font-family: Georgia, 'Times New Roman', serif; line-height: 1.5; margin: 0; }
main { max-width: 52rem; margin: 0 auto; padding: 1rem 1.25rem 3rem; }
.display { overflow-x: auto; overflow-y: hidden; margin: 0.8em 0; }
table { border-collapse: collapse; margin: 0.8em auto; }
th, td { padding: 0.25em 0.8em; border-bottom: 1px solid #ccc; text-align: left; }
.table { overflow-x: auto; }
figure { margin: 1em 0; text-align: center; }
figure img { max-width: 100%; height: auto; }
figcaption { font-size: 0.9em; color: #444; }
@media (max-width: 600px) { .display { font-size: 0.85em; } }
blockquote { color: #333; border-left: 3px solid #ccc; margin-left: 0; padding-left: 1em; }
"""
#: Typesets each formula where it stands; a formula KaTeX cannot read shows in red (its TeX).
_RENDER = """
for (const element of document.querySelectorAll(".math")) {
  katex.render(element.textContent, element, {
    displayMode: element.classList.contains("display"), throwOnError: false,
  });
}
"""


def html_document(solution: WorkedSolution, figure_files: dict[str, str]) -> str:
    """The whole ``.html`` file; ``figure_files`` maps a picture's name to its file."""
    css, script = katex_assets()
    title = html.escape(solution.title)
    body = [f"<h1>{title}</h1>"]
    if solution.subtitle:
        body.append(f"<blockquote>{html.escape(solution.subtitle)}</blockquote>")
    for section in solution.sections:
        tag = "h2" if section.level == 1 else "h3"
        body.append(f"<{tag}>{_inline(section.title)}</{tag}>")
        body += [_block(block, figure_files) for block in section.blocks]
    return "\n".join(
        [
            "<!DOCTYPE html>",
            '<html lang="en">',
            "<head>",
            '<meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{title}</title>",
            f"<style>{css}</style>",
            f"<style>{_STYLE}</style>",
            "</head>",
            "<body>",
            "<main>",
            *body,
            "</main>",
            f"<script>{_script(script)}</script>",
            f"<script>{_RENDER}</script>",
            "</body>",
            "</html>",
            "",
        ]
    )


def _script(text: str) -> str:
    """A script that cannot end its element early."""
    return text.replace("</script", "<\\/script").replace("<!--", "<\\!--")


def _inline(items) -> str:
    return "".join(
        f'<span class="math">{html.escape(item.latex)}</span>'
        if isinstance(item, Math)
        else html.escape(item)
        for item in items
    )


def _block(block, figure_files: dict[str, str]) -> str:
    if isinstance(block, Paragraph):
        return f"<p>{_inline(block.parts)}</p>"
    if isinstance(block, Display):
        return f'<div class="math display">{html.escape(aligned(block))}</div>'
    if isinstance(block, Table):
        header = "".join(f"<th>{html.escape(h)}</th>" for h in block.header)
        rows = "".join(
            "<tr>" + "".join(f"<td>{_inline(cell)}</td>" for cell in row) + "</tr>"
            for row in block.rows
        )
        table = f"<table><thead><tr>{header}</tr></thead><tbody>{rows}</tbody></table>"
        return f'<div class="table">{table}</div>'
    if isinstance(block, Picture):
        caption = html.escape(block.caption)
        source = html.escape(figure_files[block.name])
        image = f'<img src="{source}" alt="{caption}">'
        return f"<figure>{image}<figcaption>{caption}</figcaption></figure>"
    raise TypeError(f"not a block of a worked solution: {block!r}")
