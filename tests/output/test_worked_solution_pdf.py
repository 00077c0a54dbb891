"""The worked solutions as a teacher gets them: every example's LaTeX compiled by pdflatex
(no error, nothing over the margin), the pictures included, and the HTML typeset by KaTeX
in Chromium (no console error, no formula left unrendered, nothing wider than a phone).

pdflatex comes from Debian's texlive-latex-base and texlive-latex-recommended (``.ci/run``
installs them); where it is missing these tests skip and say so.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.examples import example_names
from lagrangian.output.worked_solution import report_text, worked_solution

pytestmark = pytest.mark.slow


def _pdflatex(folder: Path, name: str) -> str:
    """Compile ``folder/name.tex`` (twice: the second run settles the floats); its log."""
    pdflatex = shutil.which("pdflatex")
    if pdflatex is None:
        pytest.skip(
            "pdflatex is not installed (apt install texlive-latex-base texlive-latex-recommended)"
        )
    for _ in range(2):
        done = subprocess.run(
            [
                pdflatex,
                "-interaction=nonstopmode",
                "-halt-on-error",
                "-no-shell-escape",
                f"{name}.tex",
            ],
            cwd=folder,
            capture_output=True,
            text=True,
            timeout=300,
        )
        log = (folder / f"{name}.log").read_text(encoding="utf-8", errors="replace")
        assert done.returncode == 0, log[-3000:]
    return log


def _clean(log: str) -> None:
    """No line over the margin, no character missing from a font, no undefined reference."""
    assert "Overfull \\hbox" not in log, [line for line in log.splitlines() if "Overfull" in line]
    assert "Missing character" not in log
    assert "undefined" not in log.lower()


@pytest.mark.parametrize("example", example_names())
def test_every_examples_report_compiles_without_overfull_lines(example, tmp_path):
    solution = worked_solution(lg.load(example), figures=False)
    (tmp_path / f"{example}.tex").write_text(report_text(solution, "tex"), encoding="utf-8")
    _clean(_pdflatex(tmp_path, example))
    assert (tmp_path / f"{example}.pdf").stat().st_size > 10_000


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """The double pendulum's report in the three formats, with its pictures, by the CLI."""
    folder = tmp_path_factory.mktemp("report")
    for to in ("tex", "md", "html"):
        out = folder / f"double_pendulum.{to}"
        assert (
            main(["report", "double_pendulum", "--to", to, "--out", str(out)]) == ExitStatus.SUCCESS
        )
    return folder


def test_the_pictures_are_beside_the_document_and_in_the_pdf(written):
    names = sorted(p.name for p in written.iterdir())
    for picture in ("modes", "phase"):
        assert f"double_pendulum-{picture}.pdf" in names  # vector, for LaTeX
        assert f"double_pendulum-{picture}.png" in names  # for the screen
    log = _pdflatex(written, "double_pendulum")
    _clean(log)
    assert "<double_pendulum-modes.pdf" in log and "<double_pendulum-phase.pdf" in log
    markdown = (written / "double_pendulum.md").read_text(encoding="utf-8")
    assert "(double_pendulum-modes.png)" in markdown and "(double_pendulum-phase.png)" in markdown


@pytest.mark.parametrize("width", [1400, 412])
def test_the_html_typesets_every_formula_offline(browser, written, width):
    page = browser.new_page(viewport={"width": width, "height": 900})
    messages, requests = [], []
    page.on("console", lambda message: messages.append((message.type, message.text)))
    page.on("pageerror", lambda error: messages.append(("pageerror", str(error))))
    page.on("request", lambda request: requests.append(request.url))
    page.goto((written / "double_pendulum.html").resolve().as_uri())
    page.wait_for_load_state("load")
    counts = page.evaluate(
        """() => ({
            formulas: document.querySelectorAll('.math').length,
            typeset: document.querySelectorAll('.math > .katex, .math > .katex-display').length,
            errors: document.querySelectorAll('.katex-error').length,
            pictures: [...document.images].filter(i => i.complete && i.naturalWidth > 0).length,
            overflow: document.documentElement.scrollWidth - window.innerWidth,
        })"""
    )
    page.close()
    assert [m for m in messages if m[0] in ("error", "pageerror")] == []
    assert all(url.startswith("file://") for url in requests), requests
    assert counts["formulas"] > 50
    assert counts["typeset"] == counts["formulas"]
    assert counts["errors"] == 0
    assert counts["pictures"] == 2
    assert counts["overflow"] <= 0  # long formulas scroll in their own box


def test_a_model_cannot_run_latex_in_the_notes(tmp_path):
    # a description that would read a file and write one, were it LaTeX
    hostile = r"\input{/etc/hostname} \immediate\write18{touch pwned} $x$ & 50% #1 ~ ^ _ }{"
    model = tmp_path / "hostile.toml"
    model.write_text(
        f'name = "Hostile {{\\\\relax}}"\ndescription = {json.dumps(hostile)}\n'
        'coordinates = ["x"]\nkinetic = "m*x_dot**2/2"\npotential = "k*x**2/2"\n'
        "[parameters]\nk = 1.0\nm = 1.0\n",
        encoding="utf-8",
    )
    solution = worked_solution(lg.load(str(model)), figures=False)
    (tmp_path / "hostile.tex").write_text(report_text(solution, "tex"), encoding="utf-8")
    log = _pdflatex(tmp_path, "hostile")
    _clean(log)
    assert "(/etc/hostname" not in log.replace("\n", "")  # TeX logs a file it opens so
    assert not (tmp_path / "pwned").exists()


def test_a_mechanism_with_a_body_and_a_spring_compiles_with_its_pictures(tmp_path):
    from helpers import spring_bar_and_bob
    from lagrangian.output.worked_solution import write_report

    written = write_report(worked_solution(spring_bar_and_bob()), tmp_path / "bar.tex")
    assert [p.name for p in written] == ["bar-modes.pdf", "bar-phase.pdf", "bar.tex"]
    _clean(_pdflatex(tmp_path, "bar"))
