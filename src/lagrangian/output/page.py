"""The page of a model: one self-contained HTML file to read the solution and play with it.

:func:`page_html` returns the whole document: the worked solution typeset by KaTeX
(vendored in ``page_assets/katex``, its fonts embedded as data URIs) and a live
simulation of the model (:mod:`lagrangian.output.page_content` makes what the page
shows and runs; in ``page_assets``, ``integrators.js`` steps the motion, ``plots.js``
draws the phase portrait and time series, ``results.js`` the equilibria and modes with
their numbers, ``share.js`` the share link and embed mode, ``inertia.js`` refuses a 3-D
body's impossible inertia, ``section.js`` the Poincaré section panel
(:mod:`lagrangian.output.page_section`), ``page.js`` draws the mechanism and wires the
controls; with an exercise, ``tokens.js`` (plain text, Unicode and LaTeX read as
lagrangian.parsing reads them), ``expressions.js``, ``check.js`` and ``exercise.js`` check
the student's answers).

It works from the disk, offline, with no server: every script, style and font is
inline, and its Content-Security-Policy allows nothing else (no network request, no
script but the page's own three, by their sha256; styles inline; fonts and images as
data URIs).

Every text of the model (name, description, names) is data: it travels in a
``<script type="application/json">`` with ``<``, ``>``, ``&`` and the line
separators U+2028/U+2029 escaped, and the page shows it with ``textContent``; the
only other place a model's text reaches is the ``<title>`` (HTML-escaped) and the
comments of the generated code (where ``</script`` and ``<!--`` are broken up), so a
model named ``</script><script>...`` or ``<img src=x onerror=...>`` runs nothing.
"""

from __future__ import annotations

import base64
import hashlib
import html
import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from importlib import resources

from ..model import System
from .page_content import page_content
from .page_section import section_document

#: Everything the page may load: its own scripts (by hash), inline styles, data: fonts.
_CSP = (
    "default-src 'none'; script-src {scripts}; style-src 'unsafe-inline'; "
    "font-src data:; img-src data:; base-uri 'none'; form-action 'none'"
)
_PLACEHOLDER = re.compile(r"@(CSP|TITLE|KATEX_CSS|PAGE_CSS|MODEL|KATEX_JS|CODE)@")
#: What would end a script element early or open an HTML comment inside it.
_SCRIPT_BREAKS = re.compile(r"</(?=script)|<!--", re.IGNORECASE)


def page_html(
    system: System,
    *,
    parameters: Mapping[str, float] | None = None,
    initial: Mapping[str, float] | None = None,
    definitions: Mapping[str, str] | None = None,
    exercise: Sequence[str] | None = None,
) -> str:
    """The page of ``system`` (a whole HTML document) at ``parameters`` and ``initial``
    values (defaults: the model's; both can be changed in the page); ``definitions``
    ({NAME: EXPR}) give the model's unspecified functions, without which the page shows
    the solution only.  ``exercise`` (steps of :data:`~lagrangian.output.exercise.STEPS`)
    hides the worked solution and asks the student for those steps, each answer checked
    in the page (:mod:`lagrangian.output.exercise`).

    Raises :class:`~lagrangian.errors.ModelError` (and the other errors of deriving a
    model) for names or values that do not fit it.
    """
    return built_page(
        system, parameters=parameters, initial=initial, definitions=definitions, exercise=exercise
    ).html


@dataclass(frozen=True)
class Page:
    """A page's ``html`` and whether its analysis ``decided`` every stage within its time
    (then the page is the same on any machine, and worth keeping: :mod:`.page_cache`)."""

    html: str
    decided: bool


def built_page(
    system: System,
    *,
    parameters: Mapping[str, float] | None = None,
    initial: Mapping[str, float] | None = None,
    definitions: Mapping[str, str] | None = None,
    exercise: Sequence[str] | None = None,
) -> Page:
    """The :class:`Page` of ``system`` (the arguments as for :func:`page_html`)."""
    content = page_content(
        system, parameters=parameters, initial=initial, definitions=definitions, exercise=exercise
    )
    page_script = "\n".join(_asset(name) for name in _PAGE_SCRIPTS)
    if content.script is None:
        code = _inside_script(page_script + _START.format(code="null"))
    else:
        code = _inside_script(content.script + page_script + _START.format(code=_CODE))
    document = content.document
    if content.script is not None:  # the Poincaré section panel's (section.js)
        document = {**document, "section": section_document(system, document["constraints"])}
    katex = _inside_script(_asset("katex/katex.min.js"))
    hashes = " ".join(f"'sha256-{_digest(text)}'" for text in (katex, code))
    parts = {
        "CSP": _CSP.format(scripts=hashes),
        "TITLE": html.escape(system.name or "model"),
        "KATEX_CSS": _katex_css(),
        "PAGE_CSS": _asset("page.css") + _asset("exercise.css"),
        "MODEL": json_for_html(document),
        "KATEX_JS": katex,
        "CODE": code,
    }
    html_text = _PLACEHOLDER.sub(lambda match: parts[match.group(1)], _asset("page.html"))
    return Page(html_text, content.decided)


#: The page's own script, in the order appended to the generated module: the integrators,
#: the plots, then the page that uses them.
_PAGE_SCRIPTS = (
    "integrators.js",
    "plots.js",
    "results.js",
    "share.js",
    "inertia.js",
    "section.js",
    "page.js",
    "tokens.js",
    "expressions.js",
    "check.js",
    "exercise.js",
)
#: Reads the document (data, never code) and starts the page with the generated functions.
_START = """
const lagrangianModel = JSON.parse(document.getElementById("lagrangian-model").textContent);
lagrangianPage(lagrangianModel, {code});
if (lagrangianModel.exercise) {{
  lagrangianExercise(lagrangianModel.exercise, document.getElementById("solution"));
}}
"""
#: The generated functions the page calls (``null`` where the model cannot run).
_CODE = (
    "{ rhs, mass_matrix, solve, scene, observables, variational,"
    ' results: typeof results === "function" ? results : null }'
)


def json_for_html(document: object) -> str:
    """``document`` as JSON safe inside a ``<script>`` element of HTML: ``<``, ``>``,
    ``&`` escaped (so no ``</script>`` or ``<!--`` can appear), and everything beyond
    ASCII, U+2028 and U+2029 included, as ``\\u`` escapes."""
    text = json.dumps(document, ensure_ascii=True, allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _inside_script(text: str) -> str:
    """``text`` unable to end its script element early (``</script`` -> ``<\\/script``,
    the same in JavaScript strings and harmless in comments)."""
    return _SCRIPT_BREAKS.sub(lambda match: "<\\/" if match.group(0) == "</" else "<\\!--", text)


def _digest(text: str) -> str:
    return base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode("ascii")


@cache
def _asset(name: str) -> str:
    return resources.files(__package__).joinpath("page_assets", name).read_text("utf-8")


@cache
def _katex_css() -> str:
    """KaTeX's style sheet with each font as an embedded WOFF2 (the other formats dropped:
    every browser that runs the page reads WOFF2)."""
    fonts = resources.files(__package__).joinpath("page_assets", "katex", "fonts")

    def embedded(match: re.Match) -> str:
        data = fonts.joinpath(f"{match.group(1)}.woff2").read_bytes()
        encoded = base64.b64encode(data).decode("ascii")
        return f'src:url(data:font/woff2;base64,{encoded}) format("woff2")'

    css = _asset("katex/katex.min.css")
    return re.sub(r"src:url\(fonts/([\w-]+)\.woff2\) format\(\"woff2\"\)[^;}]*", embedded, css)


def katex_assets() -> tuple[str, str]:
    """KaTeX's style sheet (fonts embedded) and script, as the page has them: for other
    documents that typeset offline (the worked solution's HTML, ``lagrangian report``)."""
    return _katex_css(), _asset("katex/katex.min.js")
