"""The worked solution of a model, section by section, as a teacher writes it up.

The system (coordinates, parameters, how it is built), T, V and L, Lagrange's equation of
each coordinate step by step (as ``derive --steps``), the equations in mass-matrix form
M q'' = f, the conserved quantities with their reasons, the Hamiltonian, the equilibria
with their stability (and the condition on the parameters where the analysis found one),
the normal modes with numbers at the parameter values, and the pictures: a phase
portrait and the mode shapes (:mod:`.figures`).  Everything is read from the library's
own results (:func:`~lagrangian.derive.derive`, :func:`~lagrangian.analysis.analyze`);
nothing is derived here.
"""

from __future__ import annotations

from collections.abc import Mapping

from ...analysis import Analysis, analyze
from ...budget import STAGE_SECONDS
from ...codegen.definitions import function_definitions
from ...derive import EquationsOfMotion, derive
from ...model import System
from ..notation import latex_name, step_terms
from .breaking import LINE_WIDTH, broken_lines, visible_width
from .document import Display, Math, Paragraph, Row, Section, WorkedSolution, joined, parts
from .equilibria import equilibria_sections
from .figures import mode_pictures, phase_pictures
from .printing import Shower
from .system_section import system_section

#: The stages of the analysis a worked solution shows (steady motions are left to analyze).
REPORT_STAGES = ("conserved quantities", "Hamiltonian", "equilibria", "modes", "Routh reduction")

#: The left side of each term of a coordinate's equation (see notation.step_terms).
_STEP_LHS = {
    "momentum": r"\frac{{\partial L}}{{\partial {q_dot}}}",
    "momentum_rate": r"\frac{{d}}{{dt}}\frac{{\partial L}}{{\partial {q_dot}}}",
    "force_gradient": r"\frac{{\partial L}}{{\partial {q}}}",
    "generalized_force": r"Q_{{{q}}}",
    "dissipation_force": r"\frac{{\partial \mathcal{{F}}}}{{\partial {q_dot}}}",
    "constraint_force": r"\sum_j \lambda_j a_{{j {q}}}",
    "equation": "0",
}


def worked_solution(
    system: System,
    *,
    given: bool = False,
    figures: bool = True,
    timeout: float | None = STAGE_SECONDS,
    definitions: Mapping[str, str] | None = None,
) -> WorkedSolution:
    """The :class:`WorkedSolution` of ``system`` at its parameter values (``given``: the
    values were set by the user, and the document says "the given values"); ``figures``:
    with the phase portrait and the mode shapes (a run of the model, a few seconds);
    ``timeout``: CPU seconds for each stage of the analysis; ``definitions`` ({NAME:
    EXPR}) give the model's unspecified functions for the phase portrait's run."""
    # every definition checked as simulate checks it (a declared name, text the parser
    # reads) before the work, also where no picture will run the model
    function_definitions(system, definitions)
    eom = derive(system)
    free = derive(system.without_inputs()) if system.input_names else eom
    analysis = analyze(free, timeout=timeout, stages=REPORT_STAGES)
    show = Shower(system)
    values_said = "the given values" if given else "the default values"
    sections = [
        system_section(system, show),
        _energy_section(system, show),
        _steps_section(eom, show),
        _matrix_section(eom, show),
        _conserved_section(analysis, show),
        _hamiltonian_section(analysis, show),
        *_routh_sections(analysis, show),
        *equilibria_sections(analysis, show, values_said),
    ]
    if figures:
        sections.append(
            Section(parts("Mode shapes"), mode_pictures(system, analysis, values_said, show), 2)
        )
        sections.append(
            Section(parts("Phase portrait"), phase_pictures(system, given, definitions))
        )
    notes = [n for n in analysis.notes if n not in _said(analysis)]
    notes += [f"{u.stage}: {u.reason}" for u in analysis.undecided]
    if notes:
        sections.append(Section(parts("Notes"), tuple(Paragraph(parts(n)) for n in notes)))
    return WorkedSolution(system.name, system.description, tuple(sections))


def _energy_section(system: System, show: Shower) -> Section:
    if system.kinetic is None:
        blocks: list = [Paragraph(parts("The model gives its Lagrangian directly:"))]
        rows = [show.row("L", system.lagrangian)]
    else:
        blocks = [
            Paragraph(
                parts(
                    "The kinetic energy ",
                    Math("T"),
                    ", the potential energy ",
                    Math("V"),
                    " and the Lagrangian ",
                    Math("L = T - V"),
                    ":",
                )
            )
        ]
        rows = [
            show.row("T", system.kinetic),
            show.row("V", system.potential),
            show.row("L", system.lagrangian),
        ]
    if system.dissipation != 0:
        rows.append(show.row(r"\mathcal{F}", system.dissipation))
    blocks.append(Display(tuple(rows)))
    if system.dissipation != 0:
        blocks.append(
            Paragraph(parts(Math(r"\mathcal{F}"), " is Rayleigh's dissipation function."))
        )
    return Section(parts("Energies and Lagrangian"), tuple(blocks))


def _steps_section(eom: EquationsOfMotion, show: Shower) -> Section:
    law = r"\frac{d}{dt}\frac{\partial L}{\partial \dot{q}} - \frac{\partial L}{\partial q}"
    law += r" = Q_q - \frac{\partial \mathcal{F}}{\partial \dot{q}}"
    if eom.constraints is not None:
        law += r" + \sum_j \lambda_j a_{jq}"
    blocks: list = [
        Paragraph(parts("For each coordinate ", Math("q"), ", Lagrange's equation reads")),
        Display((Row("", (law,), relation=""),)),
    ]
    for step in eom.steps:
        c = step.coordinate
        names = {"q": latex_name(c.name), "q_dot": latex_name(c.q_dot.name)}
        rows = []
        for what, value in step_terms(step):
            note = ()
            if what == "equation" and step.divided_by != 1:
                note = parts("divided by ", Math(show(step.divided_by)))
            rows.append(show.row(_STEP_LHS[what].format(**names), value, note))
        blocks.append(Paragraph(parts("Coordinate ", Math(names["q"]), ":")))
        blocks.append(Display(tuple(rows)))
    return Section(parts("Lagrange's equations, step by step"), tuple(blocks))


def _matrix_section(eom: EquationsOfMotion, show: Shower) -> Section:
    n = len(eom.coordinates)
    mass = [[show(eom.mass_matrix[i, j]) for j in range(n)] for i in range(n)]
    forcing = [show(eom.forcing[i, 0]) for i in range(n)]
    accelerations = r"\\".join(latex_name(c.q_ddot.name) for c in eom.coordinates)
    blocks: list = [
        Paragraph(
            parts(
                "The equations are linear in the accelerations: ",
                Math(r"M\,\ddot{q} = f"),
                ", with ",
                Math(
                    r"\ddot{q} = \left("
                    + ", ".join(latex_name(c.q_ddot.name) for c in eom.coordinates)
                    + r"\right)"
                ),
                (", the constraint forces " + "added to f" if eom.constraints is not None else ""),
                ":",
            )
        )
    ]
    widest_row = max(sum(visible_width(x) + 2 for x in row) for row in mass)
    widest_f = max(visible_width(x) for x in forcing)
    if n == 1:  # a scalar equation: m q'' = f
        (c,) = eom.coordinates
        lhs = show(eom.mass_matrix[0, 0] * c.q_ddot)
        blocks.append(Display((show.row(lhs, eom.forcing[0, 0]),)))
    elif widest_row + widest_f + 6 <= LINE_WIDTH:  # one matrix equation reads best
        matrix = r"\begin{pmatrix}" + r"\\".join(" & ".join(r) for r in mass) + r"\end{pmatrix}"
        vector = r"\begin{pmatrix}" + r"\\".join(forcing) + r"\end{pmatrix}"
        q = r"\begin{pmatrix}" + accelerations + r"\end{pmatrix}"
        blocks.append(Display((Row("", (f"{matrix}{q} = {vector}",), relation=""),)))
    else:  # entry by entry, each broken into lines
        names = [latex_name(c.name) for c in eom.coordinates]
        rows = [
            show.row(f"M_{{{names[i]} {names[j]}}}", eom.mass_matrix[i, j])
            for i in range(n)
            for j in range(i, n)
        ]
        rows += [show.row(f"f_{{{names[i]}}}", eom.forcing[i, 0]) for i in range(n)]
        blocks.append(
            Paragraph(parts("M is symmetric; its entries on and above the diagonal, and f:"))
        )
        blocks.append(Display(tuple(rows)))
    if eom.accelerations is not None:
        solved = {c: show(eom.accelerations[c.name]) for c in eom.coordinates}
        lines = {c: broken_lines(text) for c, text in solved.items()}
        if all(_readable(broken) for broken in lines.values()):
            blocks.append(Paragraph(parts("Solved for the accelerations:")))
            rows = [Row(latex_name(c.q_ddot.name), tuple(lines[c])) for c in solved]
            blocks.append(Display(tuple(rows)))
        else:
            blocks.append(
                Paragraph(
                    parts(
                        "Solved for the accelerations, the expressions are too long to read"
                        " here: lagrangian derive --json gives them."
                    )
                )
            )
    return Section(parts("Equations of motion in mass-matrix form"), tuple(blocks))


def _conserved_section(analysis: Analysis, show: Shower) -> Section:
    conservation = analysis.conservation
    if conservation is None:
        return Section(parts("Conserved quantities"), (Paragraph(parts("Not decided in time.")),))
    cyclic = [parts(Math(latex_name(n))) for n in conservation.cyclic_coordinates]
    blocks: list = [
        Paragraph(parts("Cyclic coordinates: ", *(joined(cyclic) if cyclic else ("none",)), "."))
    ]
    for q in conservation.conserved:
        blocks.append(Display((show.row(quantity_latex(q.name), q.expression),)))
        blocks.append(
            Paragraph(parts("Conserved: ", q.description or "its time derivative vanishes", "."))
        )
    for q in conservation.not_conserved:
        blocks.append(Display((show.row(quantity_latex(q.name), q.expression),)))
        blocks.append(Paragraph(parts("Not conserved: ", q.reason, ".")))
    if not conservation.conserved and not conservation.not_conserved:
        blocks.append(Paragraph(parts("No conserved quantity was found.")))
    return Section(parts("Conserved quantities"), tuple(blocks))


def _hamiltonian_section(analysis: Analysis, show: Shower) -> Section:
    if analysis.hamiltonian is None:
        reasons = [
            n.removeprefix("Hamiltonian: ") for n in analysis.notes if n.startswith("Hamiltonian")
        ]
        reasons += [u.reason for u in analysis.undecided if u.stage == "Hamiltonian"]
        text = reasons[0] if reasons else "not computed"
        return Section(parts("Hamiltonian"), (Paragraph(parts(text[:1].upper() + text[1:] + ".")),))
    eom = analysis.equations
    momenta = joined(
        [
            parts(
                Math(
                    rf"p_{{{latex_name(c.name)}}} = \partial L/\partial {latex_name(c.q_dot.name)}"
                )
            )
            for c in eom.coordinates
        ]
    )
    blocks = (
        Paragraph(
            parts(
                "With the momenta ",
                *momenta,
                ", the Hamiltonian ",
                Math(r"H = \sum_q p_q \dot{q} - L"),
                " in the coordinates and momenta:",
            )
        ),
        Display((show.row("H", analysis.hamiltonian.expression),)),
    )
    return Section(parts("Hamiltonian"), blocks)


def _said(analysis: Analysis) -> set[str]:
    """The notes the sections say already: why there is no Hamiltonian, no equilibria."""
    said = set()
    if analysis.hamiltonian is None:
        said |= {n for n in analysis.notes if n.startswith("Hamiltonian: ")}
    if not analysis.equilibria:
        said |= {n for n in analysis.notes if n.startswith("equilibria: ")}
    return said


def _readable(lines: list[str]) -> bool:
    """At most three lines, none much wider than a line (a fraction cannot be broken)."""
    return len(lines) <= 3 and all(visible_width(line) <= 1.15 * LINE_WIDTH for line in lines)


def _routh_sections(analysis: Analysis, show: Shower) -> list[Section]:
    """The cyclic coordinates eliminated (Routh): their velocities, R and V_eff."""
    reduction = analysis.reduction
    if reduction is None:
        return []
    cyclic = joined([parts(Math(latex_name(n))) for n in reduction.cyclic])
    momenta = joined([parts(Math(latex_name(str(p)))) for p in reduction.momenta.values()])
    rows = [show.row(latex_name(f"{n}_dot"), v) for n, v in reduction.velocities.items()]
    blocks = (
        Paragraph(
            parts(
                "The cyclic coordinates ",
                *cyclic,
                " are eliminated with their constant momenta ",
                *momenta,
                ": their velocities follow from the momenta,",
            )
        ),
        Display(tuple(rows)),
        Paragraph(
            parts(
                "and the Routhian ",
                Math(r"R = L - \sum_c p_c \dot{q}_c"),
                " is a Lagrangian for the other coordinates; its potential part is the"
                " effective potential ",
                Math(r"V_{\mathrm{eff}}"),
                ", whose stationary points are the steady motions:",
            )
        ),
        Display(
            (
                show.row("R", reduction.routhian),
                show.row(r"V_{\mathrm{eff}}", reduction.effective_potential),
            )
        ),
    )
    return [Section(parts("Routh's reduction"), blocks)]


def quantity_latex(name: str) -> str:
    """A conserved quantity's name in LaTeX: p_phi as a momentum, energy as h, others as text."""
    if name.startswith("p_"):
        return f"p_{{{latex_name(name[2:])}}}"
    if name == "energy":
        return "h"
    return r"\text{" + name.replace("_", r"\_") + "}"
