"""What a model's page shows, as data: the worked solution in LaTeX, the scene, the code.

:func:`page_content` reads a :class:`~lagrangian.model.System` once and returns a
:class:`PageContent`: a JSON-ready document (names, values, the LaTeX of every
section of the worked solution, the description of the drawing) and the JavaScript
the page runs, all generated through the JavaScript target of
:mod:`lagrangian.codegen` from one :class:`~lagrangian.codegen.Program`:

    rhs(t, y, params)          y' = [q', q''] (the target's module, M q'' = f solved)
    scene(t, y, params)        [P, C, A, S, G, R, m, W, J]: the particles (P x D), the
                               centres (B x 2) and angles (B x 1) of the planar bodies,
                               both ends of every spring (2S x D), the centres (S3 x 3)
                               and rotations (S3 x 9, row by row) of the 3-D bodies, the
                               particles' masses (P x 1), the planar bodies' mass and
                               moment of inertia (B x 2), the 3-D bodies' mass and
                               inertia tensor (S3 x 10: m, then I row by row)
    observables(t, y, params)  [E, I]: the energy function h = q' dL/dq' - L and the
                               conserved quantities the analysis found
    variational(t, y, params)  [p, F]: the momenta dL/dq' and L_q + Q, for the
                               variational midpoint integrator of the page

The positions are those :mod:`lagrangian.output.geometry` draws for ``animate``; which
points a rod joins (and which 3-D bodies hang from the origin) the page decides as
``animate`` does, along its own first seconds of the motion.  Sizes follow the
parameters: the page draws each 3-D body's outline from its mass and inertia at the
values of the moment, by the rules of :mod:`lagrangian.output.solids`.  Nothing here is HTML:
:mod:`lagrangian.output.page` places the document and the code in the page.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..algebra import as_expression
from ..analysis import Analysis, analyze
from ..codegen import Program, program
from ..codegen.definitions import function_definitions, substitute
from ..codegen.javascript import JavaScriptTarget
from ..derive import EquationsOfMotion, derive
from ..errors import ModelError
from ..model import RigidBody, System
from ..model.linkage_assembly import assembled_state
from ..model.values import check_parameter_values
from .exercise import exercise_document, exercise_steps
from .geometry import ROD_TOLERANCE, coordinates_drawn, geometry
from .large import latex_printer
from .latex import equation_rows, step_rows
from .linkage_drawing import links_as_bars
from .mechanism import (
    BODY_COLOR,
    MARGIN,
    PIVOT_COLOR,
    ROD_COLOR,
    SOLID_COLOR,
    SPRING_COLOR,
    TRACK_COLOR,
    TRAIL_ALPHA,
)
from .notation import latex_name, too_long_to_print, unicode_name
from .page_bodies import inertia_entries, mass_entries
from .page_dop853 import stepper_coefficients
from .page_folding import folded_block
from .page_results import results_script, results_section
from .solids import EQUAL, FLAT, RIM_POINTS
from .tracks import tracks

#: Seconds each stage of the analysis may take for a page (the rest is said undecided).
ANALYSIS_SECONDS = 5.0
#: What the worked solution shows (the Hamiltonian and the steady motions are left to
#: ``analyze``: for the double pendulum H was a third of the page's writing time).
PAGE_STAGES = ("conserved quantities", "equilibria", "modes", "Routh reduction")
#: The page's integration time when the model gives none.
DEFAULT_T_END = 20.0
#: matplotlib's tab10, the colours ``animate`` gives the particles (C0, C1, ...).
PARTICLE_COLORS = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)


@dataclass(frozen=True)
class PageContent:
    """The page's document (JSON-ready: str, float, list, dict) and its JavaScript (None
    when the model cannot run: ``document["unavailable"]`` says why); ``decided``: every
    stage of the analysis ended within its time, so the page is the same on any machine."""

    document: dict
    script: str | None
    decided: bool = True


def page_content(
    system: System,
    *,
    parameters: Mapping[str, float] | None = None,
    initial: Mapping[str, float] | None = None,
    definitions: Mapping[str, str] | None = None,
    exercise: Sequence[str] | None = None,
) -> PageContent:
    """The :class:`PageContent` of ``system`` at ``parameters`` and ``initial`` values
    (defaults: the model's); ``definitions`` give its unspecified functions (as for
    :func:`~lagrangian.numeric.compile_equations`), without them the page shows the
    solution only; ``exercise`` adds the exercise of those steps
    (:func:`~lagrangian.output.exercise.exercise_document`).  Raises the project's errors
    for names or values that do not fit."""
    values = _parameter_values(system, parameters)
    # a linkage starts on its loops, as simulate starts it (the page's own integrator would
    # otherwise pull the given guesses onto them, changing the energy it reports the drift of)
    state = assembled_state(system, _initial_state(system, initial), values)
    # every definition checked (a declared name, text the parser reads) as simulate checks
    # it, also where a function left undefined means that the page runs no motion
    function_definitions(system, definitions)
    eom = derive(system)
    missing = _unspecified(eom, definitions)
    code = None if missing else program(eom, definitions=definitions)
    # the analysis is of the system with its inputs at 0 (as analyze's); derived once
    # where there are none
    free = derive(system.without_inputs()) if system.input_names else eom
    analysis = analyze(free, timeout=ANALYSIS_SECONDS, stages=PAGE_STAGES)
    conserved = analysis.conservation.conserved if analysis.conservation is not None else ()
    parameter_names = [q.name for q in code.parameters] if code else _parameters(system)
    symbols = {p.name: p.symbol for p in system.parameters if p.name in parameter_names}
    signs = {p.name: p.sign for p in system.parameters}
    results, expressions = results_section(analysis, latex_printer(system), symbols)
    document = {
        "name": system.name,
        "description": system.description,
        "coordinates": [{"name": c.name, "velocity": c.q_dot.name} for c in system.coordinates],
        # each with its assumed sign: the page refuses a value that breaks it, as --set does
        "parameters": [
            {"name": name, "value": values[name], "sign": signs.get(name, "real")}
            for name in parameter_names
        ],
        "inputs": [{"name": name, "value": values.get(name, 0.0)} for name in system.input_names],
        "initial": state,
        # the controls' labels typeset: theta1_dot as \dot{\theta}_{1} (with its unit, in a
        # dimensioned model: the values are SI)
        "labels": {
            name: latex_name(name) + _latex_unit(system, name)
            for name in (*parameter_names, *system.input_names, *state)
        },
        # the plots' axes and legends: theta1_dot as θ̇₁
        "symbols": {name: unicode_name(name) for name in state},
        "t_end": float(system.simulate_settings.get("t_end", DEFAULT_T_END)),
        "constraints": code.constraints if code else 0,
        "conserved": [
            {"name": q.name, "latex": _quantity_latex(q.name), "description": q.description}
            for q in conserved
        ],
        "sections": _sections(eom, analysis, results),
        "dop853": stepper_coefficients(),  # the page steps as simulate does
    }
    if system.units is not None:  # the readouts' units: t, the energy, each conserved one;
        # the plots' axes: t, each coordinate and its rate
        rates = [f"{q}_dot" for q in system.coordinate_names]
        names = ["t", "energy", *(q.name for q in conserved), *system.coordinate_names, *rates]
        document["units"] = {n: u for n in names if (u := system.units.column_unit(n))}
    if exercise:
        document["exercise"] = exercise_document(eom, exercise_steps(exercise))
    if code is None:  # the solution only: nothing to run without the functions
        functions = ", ".join(missing)
        document["unavailable"] = (
            f"No live simulation: the functions {functions} are unspecified; a page written"
            " with a definition of each runs the motion."
        )
        return PageContent(document, None, decided=not analysis.undecided)
    document["scene"] = _scene(system, values)
    document["masses"] = mass_entries(system)
    document["inertias"] = inertia_entries(system)
    script = _script(code, system, conserved)
    script += results_script(code, expressions)
    return PageContent(document, script, decided=not analysis.undecided)


def _latex_unit(system: System, name: str) -> str:
    r"""``\ [\mathrm{m}]`` after a control's label in a dimensioned model, else nothing."""
    unit = system.units.column_unit(name) if system.units is not None else None
    return rf"\ [\mathrm{{{unit}}}]" if unit else ""


def _unspecified(eom: EquationsOfMotion, definitions: Mapping[str, str] | None) -> list[str]:
    """The declared functions the equations use that ``definitions`` does not give."""
    used = {
        applied.func.__name__
        for entry in (*eom.mass_matrix, *eom.forcing)
        for applied in entry.atoms(AppliedUndef)
    }
    return sorted(used - set(definitions or {}))


def _parameters(system: System) -> list[str]:
    inputs = set(system.input_names)
    return [p.name for p in system.parameters if p.name not in inputs]


def _parameter_values(system: System, given: Mapping[str, float] | None) -> dict[str, float]:
    given = {name: float(value) for name, value in (given or {}).items()}
    check_parameter_values(system, given)
    values = {**system.parameter_values, **given}
    missing = [p.name for p in system.parameters if p.name not in values]
    if missing:
        raise ModelError(f"no value for parameter(s) {', '.join(missing)}")
    return {name: float(value) for name, value in values.items()}


def _initial_state(system: System, given: Mapping[str, float] | None) -> dict[str, float]:
    """{q: value, q_dot: value} for every coordinate: the model's, then ``given``."""
    names = [n for c in system.coordinates for n in (c.name, c.q_dot.name)]
    given = dict(given or {})
    unknown = sorted(set(given) - set(names))
    if unknown:
        raise ModelError(
            f"'{unknown[0]}' is not a coordinate or velocity of the model"
            f" (they are: {', '.join(names)})"
        )
    state = {name: float(system.initial.get(name, 0.0)) for name in names}
    for name, value in given.items():
        state[name] = float(value)
        if not np.isfinite(state[name]):
            raise ModelError(f"the initial value of '{name}' must be finite, not {value!r}")
    return state


# -- the worked solution ---------------------------------------------------------------


def _sections(eom: EquationsOfMotion, analysis: Analysis, results: dict) -> list[dict]:
    """Titled blocks: each a list of items, ``{"latex": ...}`` (display math, or inline
    math that breaks across lines with ``"wrap": true``; with ``"folded": LHS`` a long row
    typeset when opened, :mod:`.page_folding`), ``{"text": ...}`` (a sentence,
    shown as text) or ``{"equilibrium": ...}`` (:mod:`.page_results`, whose section
    ``results`` is)."""
    system = eom.system
    show = latex_printer(system)
    sections = [
        {"title": "Lagrange's equations", "items": folded_block(equation_rows(eom))},
        {"title": "Step by step", "items": folded_block(step_rows(eom)), "folded": True},
        {"title": "M q'' = f", "items": [{"latex": _matrix_form(eom, show)}]},
    ]
    conservation = analysis.conservation
    items: list[dict] = []
    if conservation is not None:
        for q in conservation.conserved:
            items.append(
                {
                    "latex": f"{_quantity_latex(q.name)} = {_shown(q.expression, show)}",
                    "text": f"conserved: {q.description}" if q.description else "conserved",
                }
            )
        for q in conservation.not_conserved:
            items.append(
                {
                    "latex": f"{_quantity_latex(q.name)} = {_shown(q.expression, show)}",
                    "text": f"not conserved: {q.reason}",
                }
            )
        if not items:
            items.append({"text": "No conserved quantity was found."})
    sections.append({"title": "Conserved quantities", "items": items})
    sections.append(results)
    notes = [*analysis.notes, *(f"{u.stage}: {u.reason}" for u in analysis.undecided)]
    contacts = [impact.name for impact in getattr(eom.system, "impacts", ())]
    if contacts:  # the page's integrator knows no impacts: say so, not a silent wrong motion
        notes.append(
            f"The contacts ({', '.join(contacts)}) are not simulated in this page: its motion "
            "passes through them. lagrangian simulate, plot and animate stop at each impact."
        )
    if notes:
        sections.append({"title": "Notes", "items": [{"text": note} for note in notes]})
    return sections


def _matrix_form(eom: EquationsOfMotion, show) -> str:
    mass = sympy.Matrix(eom.mass_matrix)
    forcing = sympy.Matrix(eom.forcing)
    accelerations = r"\\".join(latex_name(c.q_ddot.name) for c in eom.coordinates)
    if any(too_long_to_print(e) for e in (*mass, *forcing)):
        return r"M\,\ddot{q} = f:\ \text{too long to print; derive --json gives it}"
    rows_m = r"\\".join(" & ".join(show(x) for x in mass.row(i)) for i in range(mass.rows))
    rows_f = r"\\".join(show(entry) for entry in forcing)
    return (
        rf"\begin{{pmatrix}}{rows_m}\end{{pmatrix}}"
        rf"\begin{{pmatrix}}{accelerations}\end{{pmatrix}}"
        rf" = \begin{{pmatrix}}{rows_f}\end{{pmatrix}}"
    )


def _shown(expr: sympy.Expr, show) -> str:
    return r"\text{too long to print}" if too_long_to_print(expr) else show(expr)


def _quantity_latex(name: str) -> str:
    if name.startswith("p_"):
        return f"p_{{{latex_name(name[2:])}}}"
    return {"energy": "h"}.get(name, latex_name(name))  # one naming rule for every name


# -- the drawing -----------------------------------------------------------------------


def _drawn(system: System) -> System:
    if not system.particles and not system.bodies:
        return coordinates_drawn(system)
    return links_as_bars(system)  # a linkage's links from start to end


def _scene(system: System, values: Mapping[str, float]) -> dict:
    """What is drawn and how; the positions come from ``scene`` in the code, and the page
    decides which points a rod joins as :func:`~lagrangian.output.geometry.rods` does (a
    distance constant along the motion, within ``rod_tolerance``), along its own run."""
    view = geometry(system, values)
    return {
        "dimension": view.dimension,
        "views": [list(v) for v in view.views],
        "vertical": view.vertical,
        "coordinates_only": view.coordinates_only,
        "particles": [
            {"name": name, "color": PARTICLE_COLORS[i % 10]}
            for i, name in enumerate(view.particle_names)
        ],
        "rod_tolerance": ROD_TOLERANCE,
        "springs": len(view.system.springs),
        # a 3-D body's outline, from its mass and inertia in the page (they follow the
        # parameters): the box or disc of lagrangian.output.solids.solid_shape
        "solids": len(view.solids),
        "solid_rules": {"flat": FLAT, "equal": EQUAL, "rim_points": RIM_POINTS},
        "palette": list(PARTICLE_COLORS),
        "style": _style(),
        "tracks": [] if view.coordinates_only else [t.document() for t in tracks(system)],
    }


def _style() -> dict:
    """The colours and proportions ``animate`` draws with (:mod:`lagrangian.output.mechanism`)."""
    return {
        "rod": ROD_COLOR,
        "track": TRACK_COLOR,
        "spring": SPRING_COLOR,
        "body": BODY_COLOR,
        "pivot": PIVOT_COLOR,
        "solid": SOLID_COLOR,
        "margin": MARGIN,
        "trail_alpha": TRAIL_ALPHA,
    }


# -- the code --------------------------------------------------------------------------


def _script(code: Program, system: System, conserved) -> str:
    """The target's module (rhs) and the page's routines, one ES module text."""
    target = JavaScriptTarget()
    drawn = _drawn(system)
    forms = code.forms

    def defined(matrix) -> sympy.Matrix:
        return sympy.Matrix(matrix).applyfunc(lambda e: substitute(e, forms.definitions))

    dimension = len(drawn.particles[0].position) if drawn.particles else 3
    solids = [b for b in drawn.bodies if isinstance(b, RigidBody)]
    planar = [b for b in drawn.bodies if not isinstance(b, RigidBody)]
    scene = code.routine(
        "scene",
        [
            ("P", defined(_rows([p.position for p in drawn.particles], dimension))),
            ("C", defined(_rows([b.center for b in planar], 2))),
            ("A", defined(_rows([[b.angle] for b in planar], 1))),
            ("S", defined(_rows([end for s in drawn.springs for end in s.ends], dimension))),
            ("G", defined(_rows([b.position for b in solids], 3))),
            ("R", defined(_rows([_flat(b.rotation) for b in solids], 9))),
            # masses and moments, so that sizes follow the parameters: a particle's dot,
            # a planar body's bar of the uniform rod's length sqrt(12 I / m)
            ("m", defined(_rows([[p.mass] for p in drawn.particles], 1))),
            ("W", defined(_rows([[b.mass, b.inertia] for b in planar], 2))),
            ("J", defined(_rows([[b.mass, *_flat(b.inertia)] for b in solids], 10))),
        ],
    )
    observables = code.routine(
        "observables",
        [
            ("E", sympy.Matrix([forms.energy])),
            ("I", defined(_rows([[q.expression] for q in conserved], 1))),
        ],
    )
    gradient = [sympy.diff(forms.lagrangian, q) for q in forms.coordinates]
    variational = code.routine(
        "variational",
        [
            ("p", sympy.Matrix(forms.momenta)),
            ("F", sympy.Matrix(gradient) + sympy.Matrix(forms.nonconservative_forces)),
        ],
    )
    lines = [target.render(code, "page")]
    for name, routine in (
        ("scene", scene),
        ("observables", observables),
        ("variational", variational),
    ):
        lines += target.function(name, code, routine, exported=False)
    return "\n".join(lines) + "\n"


def _flat(matrix) -> list:
    return [x for row in matrix for x in row]


def _rows(rows: list, width: int) -> sympy.Matrix:
    """The rows as a matrix of ``width`` columns (an empty one for no rows)."""
    if not rows:
        return sympy.zeros(0, width)
    return sympy.Matrix([[as_expression(x) for x in row] for row in rows])
