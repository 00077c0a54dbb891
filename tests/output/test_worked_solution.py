"""``lagrangian report``: the worked solution as LaTeX, Markdown and HTML.

Checked against what the toolkit says elsewhere and against numbers worked by hand (the
pendulum's ω = √(g/l)), the breaking of long equations against its own rule (lines no
wider than the line, the terms in their order), the escaping against a hostile model,
and the command line's errors by their exact text.  The PDFs themselves are in
``test_worked_solution_pdf.py`` (slow: pdflatex).
"""

from __future__ import annotations

import math
from html.parser import HTMLParser

import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.output.worked_solution import report_text, worked_solution
from lagrangian.output.worked_solution.breaking import (
    LINE_WIDTH,
    broken_lines,
    top_level_terms,
    visible_width,
)
from lagrangian.output.worked_solution.document import Display, Math, Paragraph, Table
from lagrangian.output.worked_solution.tex_text import tex_text
from output.test_page import HOSTILE_DESCRIPTION, HOSTILE_MODEL, HOSTILE_NAME


@pytest.fixture(scope="module")
def pendulum():
    return worked_solution(lg.load("simple_pendulum"), figures=False)


def _section(solution, title: str):
    return next(s for s in solution.sections if "".join(map(str, s.title)) == title)


def _rows(section) -> dict[str, str]:
    return {
        row.lhs: " ".join(row.lines)
        for block in section.blocks
        if isinstance(block, Display)
        for row in block.rows
    }


def _text(blocks) -> str:
    return " ".join(
        "".join(item if isinstance(item, str) else f"${item.latex}$" for item in block.parts)
        for block in blocks
        if isinstance(block, Paragraph)
    )


# -- breaking long equations -----------------------------------------------------------
def test_a_sum_is_cut_only_at_its_own_plus_and_minus():
    latex = (
        r"a b - \frac{c + d}{e} + \left(f - g\right) x"
        r" + \begin{pmatrix}1 + 2\end{pmatrix} - \cos{\left(h + k \right)}"
    )
    assert top_level_terms(latex) == [
        "a b",
        r"- \frac{c + d}{e}",
        r"+ \left(f - g\right) x",
        r"+ \begin{pmatrix}1 + 2\end{pmatrix}",
        r"- \cos{\left(h + k \right)}",
    ]
    assert top_level_terms(r"- g l m \sin{\left(\theta \right)}") == [
        r"- g l m \sin{\left(\theta \right)}"
    ]


def test_the_width_counts_what_is_shown():
    assert visible_width("abc") == 3
    assert visible_width(r"\frac{abcd}{e}") == pytest.approx(4.4)  # the wider part
    assert visible_width(r"x^{2}") == pytest.approx(1.7)
    assert visible_width(r"\left(x\right)") == 3  # the parentheses, not the commands
    assert visible_width(r"\dot{\theta}_{1}") == pytest.approx(1.7)
    assert visible_width(r"\sin{\left(x \right)}") == 6
    assert visible_width("a + b") == 4


@pytest.mark.slow
def test_long_sums_break_into_lines_that_fit_keeping_every_term_in_order():
    eom = lg.load("double_pendulum").equations_of_motion()
    from lagrangian.output.large import latex_printer

    show = latex_printer(eom.system)
    for step in eom.steps:
        for expr in (step.momentum_rate, step.equation, eom.system.lagrangian):
            latex = show(expr)
            lines = broken_lines(latex)
            assert " ".join(lines).split() == latex.split()  # nothing lost or reordered
            for line in lines:
                assert visible_width(line) <= LINE_WIDTH or len(top_level_terms(line)) == 1
            if visible_width(latex) > LINE_WIDTH:
                assert len(lines) > 1


# -- what the worked solution says -----------------------------------------------------
@pytest.mark.slow
def test_the_pendulum_is_worked_as_by_hand(pendulum):
    energies = _rows(_section(pendulum, "Energies and Lagrangian"))
    assert energies["T"] == r"\frac{l^{2} m \dot{\theta}^{2}}{2}"
    assert energies["V"] == r"- g l m \cos{\left(\theta \right)} + g l m"  # 0 at the bottom
    steps = _rows(_section(pendulum, "Lagrange's equations, step by step"))
    assert steps[r"\frac{\partial L}{\partial \dot{\theta}}"] == r"l^{2} m \dot{\theta}"
    assert steps["0"] == r"l \ddot{\theta} + g \sin{\left(\theta \right)}"
    hamiltonian = _rows(_section(pendulum, "Hamiltonian"))
    assert hamiltonian["H"] == (
        r"- g l m \cos{\left(\theta \right)} + g l m + \frac{p_{\theta}^{2}}{2 l^{2} m}"
    )
    matrix_form = _rows(_section(pendulum, "Equations of motion in mass-matrix form"))
    assert matrix_form[r"l^{2} m \ddot{\theta}"] == r"- g l m \sin{\left(\theta \right)}"
    assert matrix_form[r"\ddot{\theta}"] == r"- \frac{g \sin{\left(\theta \right)}}{l}"


@pytest.mark.slow
def test_each_equilibrium_has_its_verdict_and_numbers(pendulum):
    titles = ["".join(map(str, s.title)) for s in pendulum.sections if s.level == 2]
    assert titles == [r"Math(latex='\\theta = 0')", r"Math(latex='\\theta = \\pi')"]
    bottom, top = (s for s in pendulum.sections if s.level == 2)
    assert _text(bottom.blocks).startswith("Stable")
    assert _text(top.blocks).startswith("Unstable")
    assert _rows(bottom)[r"\omega^2"] == r"\frac{g}{l}"
    table = next(b for b in bottom.blocks if isinstance(b, Table))
    (row,) = table.rows
    omega = math.sqrt(9.81 / 1.0)  # g = 9.81, l = 1
    assert [cell[0] for cell in row] == [
        "1",
        f"{9.81:.6g}",
        f"{omega:.6g}",
        f"{2 * math.pi / omega:.6g}",
    ]
    assert "At the default values" in _text(bottom.blocks)


@pytest.mark.slow
def test_values_set_are_the_given_values(tmp_path, capsys):
    out = tmp_path / "pendulum.md"
    status = main(["report", "simple_pendulum", "--set", "l=2", "--no-figures", "--out", str(out)])
    assert status == ExitStatus.SUCCESS, capsys.readouterr().err
    text = out.read_text(encoding="utf-8")
    assert "At the given values" in text and "the default values" not in text
    omega = math.sqrt(9.81 / 2.0)
    assert f"| 1 | {9.81 / 2:.6g} | {omega:.6g} | {2 * math.pi / omega:.6g} |" in text
    assert capsys.readouterr().out == f"wrote {out}\n"


@pytest.mark.slow
def test_conserved_quantities_come_with_their_reasons():
    solution = worked_solution(lg.load("rotating_wire_bead"), figures=False)
    text = _text(_section(solution, "Conserved quantities").blocks)
    assert "Conserved: the Jacobi integral" in text
    assert "Not conserved: T + V differs from the energy function h" in text


@pytest.mark.slow
def test_a_model_without_a_hamiltonian_says_why():
    solution = worked_solution(lg.load("rolling_disc"), figures=False)
    assert _text(_section(solution, "Hamiltonian").blocks) == (
        "Not computed for systems with constraints."
    )


@pytest.mark.slow
def test_the_stability_condition_is_stated_when_the_verdict_depends_on_the_values():
    # a bead on a hoop turning at w: the bottom is stable iff g > R w^2 (by hand:
    # V_eff = -m g R cos(theta) - m R^2 w^2 sin^2(theta)/2, V_eff'' at 0 = m R (g - R w^2))
    system = lg.System.from_lagrangian(
        "m*R^2*(theta_dot^2 + w^2*sin(theta)^2)/2 + m*g*R*cos(theta)",
        coordinates=["theta"],
        parameters={"m": 1.0, "R": 1.0, "g": 9.81, "w": 2.0},
    )
    solution = worked_solution(system, figures=False)
    bottom = next(s for s in solution.sections if s.title == (Math(r"\theta = 0"),))
    assert _text(bottom.blocks).startswith(
        "Stable: every small motion about it is an oscillation (every ω² > 0), at the default"
        " values. It is stable if and only if $g > R w^{2}$."
    )


# -- the three formats -----------------------------------------------------------------
class _Checked(HTMLParser):
    """Every element closed in order (the void ones excepted)."""

    VOID = frozenset({"meta", "img", "br", "hr", "link", "input"})

    def __init__(self):
        super().__init__()
        self.open: list[str] = []
        self.maths = 0

    def handle_starttag(self, tag, attrs):
        if dict(attrs).get("class", "").startswith("math"):
            self.maths += 1
        if tag not in self.VOID:
            self.open.append(tag)

    def handle_endtag(self, tag):
        assert self.open and self.open[-1] == tag, (tag, self.open[-5:])
        self.open.pop()


@pytest.mark.slow
def test_the_html_is_well_formed_and_has_every_formula(pendulum):
    text = report_text(pendulum, "html")
    parser = _Checked()
    parser.feed(text)
    assert parser.open == []
    formulas = sum(isinstance(b, Display) for s in pendulum.sections for b in s.blocks)
    inline = sum(
        isinstance(item, Math)
        for s in pendulum.sections
        for b in s.blocks
        if isinstance(b, Paragraph | Table)
        for item in (
            b.parts if isinstance(b, Paragraph) else [x for r in b.rows for c in r for x in c]
        )
    )
    inline += sum(isinstance(item, Math) for s in pendulum.sections for item in s.title)
    assert parser.maths == formulas + inline
    assert "katex.render" in text
    assert "http" not in text.split("<main>")[1].split("</main>")[0]  # nothing to fetch


@pytest.mark.slow
def test_the_markdown_keeps_its_mathematics_balanced(pendulum):
    text = report_text(pendulum, "md")
    assert text.count("$$") % 2 == 0
    for line in text.splitlines():
        if "$$" not in line:
            assert line.count("$") % 2 == 0, line
    assert "$$\n\\begin{aligned}\nT &= \\frac{l^{2} m \\dot{\\theta}^{2}}{2}" in text
    assert r"at rest ($\dot{q} = 0$ and $\ddot{q} = 0$)" in text  # the spaces kept


def test_a_hostile_model_is_text_in_every_format(tmp_path):
    model = tmp_path / "hostile.toml"
    model.write_text(HOSTILE_MODEL, encoding="utf-8")
    solution = worked_solution(lg.load(str(model)), figures=False)
    html = report_text(solution, "html")
    assert HOSTILE_NAME not in html and HOSTILE_DESCRIPTION not in html
    assert "&lt;/script&gt;&lt;script&gt;window.pwned = 1&lt;/script&gt;" in html
    tex = report_text(solution, "tex")
    assert r"\textless{}/script\textgreater{}" in tex
    assert r"\textless{}img src=x onerror=\textquotedbl{}" not in tex  # quotes pass as text


def test_latex_commands_in_model_text_are_written_not_run():
    hostile = r"\input{/etc/passwd} $x$ & 50% #1 ~ ^ _ \write18{rm -rf /}"
    text = tex_text(hostile)
    assert "\\input" not in text and "\\write" not in text
    assert text == (
        r"\textbackslash{}input\{/etc/passwd\} \$x\$ \& 50\% \#1 \textasciitilde{}"
        r" \textasciicircum{} \_ \textbackslash{}write18\{rm -rf /\}"
    )


def test_unicode_of_the_analysis_becomes_mathematics():
    assert tex_text("h = Σ q̇ ∂L/∂q̇ - L") == (
        r"h = \ensuremath{\Sigma} \ensuremath{\dot{q}} \ensuremath{\partial}L/"
        r"\ensuremath{\partial \dot{q}} - L"
    )
    assert tex_text("pₓ = m ẋ, ω² r, Hénon") == (
        r"\ensuremath{p_{x}} = m \ensuremath{\dot{x}}, \ensuremath{\omega ^{2}} r, Hénon"
    )
    assert tex_text("emoji 😀") == "emoji ?"


# -- the command line ------------------------------------------------------------------
@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--to", "pdf"], "Invalid value for '--to': 'pdf' is not one of 'tex', 'md', 'html'."),
        ([], "choose the format with --to (tex, md, html)"),
        (
            ["--to", "tex", "--out", "notes.md"],
            "the tex report's file must end in .tex, not 'notes.md'",
        ),
        (
            ["--out", "notes.txt"],
            "choose the format with --to (tex, md, html), or an --out ending in .tex, .md or .html",
        ),
        (["--to", "md", "--set", "q=1"], "'q' is neither a parameter nor a coordinate or velocity"),
        (["--to", "md", "--set", "l=-1"], None),
        (
            ["--to", "md", "--define", "V=x"],
            "definitions: 'V' is not a declared function (declared: none)",
        ),
    ],
)
def test_bad_input_is_one_line_and_exit_2(arguments, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status = main(["report", "simple_pendulum", *arguments])
    assert status == ExitStatus.BAD_INPUT
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("lagrangian: error: ")
    if message is not None:
        assert err == f"lagrangian: error: {message}\n"
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_a_missing_folder_fails_before_the_work(capsys, tmp_path):
    out = tmp_path / "no" / "such" / "notes.tex"
    assert main(["report", "simple_pendulum", "--out", str(out)]) == ExitStatus.BAD_INPUT
    assert "does not exist" in capsys.readouterr().err


def test_the_formats_offered_are_the_registry():
    from lagrangian.cli.app import app
    from lagrangian.output.worked_solution import FORMATS

    (to,) = [p for p in app.commands["report"].params if "--to" in p.opts]
    assert sorted(to.type.choices) == sorted(FORMATS) == ["html", "md", "tex"]


def test_the_system_lists_its_bodies_and_springs():
    from helpers import spring_bar_and_bob
    from lagrangian.output.worked_solution.printing import Shower
    from lagrangian.output.worked_solution.system_section import system_section

    system = spring_bar_and_bob()
    tables = [b for b in system_section(system, Shower(system)).blocks if isinstance(b, Table)]
    bodies = next(t for t in tables if t.header[0] == "body")
    assert bodies.rows == (
        (
            ("bar",),
            (Math("M"),),
            (Math(r"\left(1, 0\right)"),),
            ("angle ", Math(r"\phi")),
            (Math(r"\frac{M a^{2}}{12}"),),
        ),
    )
    springs = next(t for t in tables if t.header[0] == "spring")
    assert springs.rows == ((("spring1",), (Math("k"),), (Math("L_{0}"),)),)  # named when built


def _mode_pictures(example: str):
    from lagrangian.analysis import analyze
    from lagrangian.output.worked_solution.content import REPORT_STAGES
    from lagrangian.output.worked_solution.figures import mode_pictures
    from lagrangian.output.worked_solution.printing import Shower

    system = lg.load(example)
    analysis = analyze(system.equations_of_motion(), stages=REPORT_STAGES)
    return mode_pictures(system, analysis, "the default values", Shower(system))


@pytest.mark.slow
@pytest.mark.parametrize(
    ("example", "said"),
    [
        # every omega^2 = 0 (a free particle: every configuration at rest): nothing moves
        (
            "free_particle_spherical",
            "No equilibrium about which the system oscillates: no normal modes to draw.",
        ),
        # the hanging bob's one mode lies along the circle, not along x or y
        (
            "cartesian_pendulum",
            "The normal modes of a constrained system are not drawn (its mode shapes lie in the"
            " directions the constraints allow, not along each coordinate).",
        ),
        ("driven_damped_pendulum", "No equilibrium: no normal modes to draw."),
    ],
)
def test_modes_are_drawn_only_where_they_show_an_oscillation(example, said):
    (paragraph,) = _mode_pictures(example)
    assert paragraph == Paragraph((said,))


@pytest.mark.slow
def test_the_hanging_cart_pole_is_drawn_about_its_stable_direction():
    paragraph, picture = _mode_pictures("cart_pole")
    assert paragraph.parts[1] == Math(r"\theta = \pi")  # marginal: a free translation
    assert picture.name == "modes"


@pytest.mark.slow
def test_a_note_said_in_its_section_is_not_repeated():
    solution = worked_solution(lg.load("cartesian_pendulum"), figures=False)
    assert "Notes" not in ["".join(map(str, s.title)) for s in solution.sections]
    assert _text(_section(solution, "Hamiltonian").blocks) == (
        "Not computed for systems with constraints."
    )


@pytest.mark.slow
def test_the_functions_defined_run_the_phase_portrait():
    from lagrangian.output.worked_solution.figures import phase_pictures

    system = lg.load("velocity_dependent_potential")  # V, A, B, C unspecified
    (said,) = phase_pictures(system, False)
    assert said.parts[0].startswith("No phase portrait: functions V(x, y, z), A(x, y, z)")
    # a charge in a uniform magnetic field along z (A = (-y/2, x/2, 0)): it runs
    definitions = {"V": "0", "A": "-y/2", "B": "x/2", "C": "0"}
    _, picture = phase_pictures(system, False, definitions)
    assert picture.name == "phase"


@pytest.mark.slow
def test_a_cyclic_coordinate_is_eliminated_by_routh():
    # the spherical pendulum by hand: p_phi = m l^2 sin^2(theta) phi_dot, R = L - p_phi phi_dot
    # = m l^2 theta_dot^2/2 + m g l cos(theta) - p_phi^2/(2 m l^2 sin^2(theta))
    solution = worked_solution(lg.load("spherical_pendulum"), figures=False)
    rows = _rows(_section(solution, "Routh's reduction"))
    assert rows[r"\dot{\phi}"] == r"\frac{p_{\phi}}{l^{2} m \sin^{2}{\left(\theta \right)}}"
    assert rows["R"] == (
        r"\frac{l^{2} m \dot{\theta}^{2}}{2} + g l m \cos{\left(\theta \right)}"
        r" - \frac{p_{\phi}^{2}}{2 l^{2} m \sin^{2}{\left(\theta \right)}}"
    )
    assert rows[r"V_{\mathrm{eff}}"] == (
        r"- g l m \cos{\left(\theta \right)}"
        r" + \frac{p_{\phi}^{2}}{2 l^{2} m \sin^{2}{\left(\theta \right)}}"
    )
