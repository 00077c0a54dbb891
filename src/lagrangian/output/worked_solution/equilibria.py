"""The equilibria of a worked solution: each point, its stability, and its normal modes
with numbers (ω², ω, the period 2π/ω and the mode shape at the parameter values, as
``analyze`` prints them: :func:`~lagrangian.output.analysis.modes_at_values`)."""

from __future__ import annotations

import math

import sympy

from ...algebra import as_expression
from ...analysis import Analysis
from ..analysis import modes_at_values
from ..notation import latex_name, unicode_name
from .breaking import LINE_WIDTH, visible_width
from .document import Display, Math, Paragraph, Row, Section, Table, joined, parts

#: What each verdict means, said to a student.
_VERDICTS = {
    "stable": "Stable: every small motion about it is an oscillation (every ω² > 0).",
    "asymptotically stable": "Asymptotically stable: small motions about it die out.",
    "marginal": (
        "Marginal: a direction with ω² = 0 (a free motion), the others oscillate;"
        " linear theory does not decide the rest."
    ),
    "unstable": "Unstable: some ω² < 0, a small displacement grows.",
    "undetermined": "Stability undetermined.",
}


def equilibria_sections(analysis: Analysis, show, values_said: str) -> list[Section]:
    """A section on the equilibria, then one subsection per equilibrium."""
    system = analysis.equations.system
    missing = {u.stage: u.reason for u in analysis.undecided}
    intro = [
        Paragraph(
            parts(
                "The equilibria are the points at rest that stay at rest (",
                Math(r"\dot{q} = 0"),
                " and ",
                Math(r"\ddot{q} = 0"),
                "). About each, the linearized motion ",
                Math(r"M_0\,\delta\ddot{q} + K_0\,\delta q = 0"),
                " has the squared angular frequencies ",
                Math(r"\omega^2"),
                ", the roots of ",
                Math(r"\det(K_0 - \omega^2 M_0) = 0"),
                ".",
            )
        )
    ]
    not_applied = [
        n.removeprefix("equilibria: ") for n in analysis.notes if n.startswith("equilibria: ")
    ]
    if "equilibria" in missing:
        intro.append(Paragraph(parts(f"Not decided: {missing['equilibria']}.")))
    elif not analysis.equilibria:
        for said in not_applied or ["none found"]:
            intro.append(Paragraph(parts(said[:1].upper() + said[1:] + ".")))
    sections = [Section(parts("Equilibria and normal modes"), tuple(intro))]
    for e in analysis.equilibria:
        found = e.point.items()
        if getattr(e, "numeric", False):  # a root found numerically: its digits fit a title
            found = [(k, _digits(v)) for k, v in found]
        point = [parts(Math(f"{latex_name(k)} = {show(v)}")) for k, v in found]
        title = joined(point) if point else parts("every configuration")
        sections.append(Section(title, _equilibrium_blocks(e, show, system, values_said), 2))
    return sections


def _digits(value, significant: int = 6):
    """A number shown with ``significant`` digits (as the tables show it); else as it is."""
    value = as_expression(value)
    return sympy.Float(value, significant) if value.is_Float else value


def _equilibrium_blocks(e, show, system, values_said: str) -> tuple:
    modes = e.modes
    verdict = _VERDICTS.get(modes.stability.value, modes.stability.value)
    blocks: list = []
    if getattr(e, "at_defaults", False):
        verdict = verdict.rstrip(".") + f", at {values_said}."
        condition = getattr(e, "stability_condition", None)
        if condition is not None:
            verdict_parts = parts(
                verdict, " It is stable if and only if ", Math(relation(condition, show)), "."
            )
        else:
            verdict_parts = parts(verdict)
    else:
        verdict_parts = parts(verdict)
    if e.numeric:
        verdict_parts = verdict_parts + parts(f" (Found numerically, at {values_said}.)")
    blocks.append(Paragraph(verdict_parts))
    if getattr(e, "free", ()):
        free = joined([parts(Math(latex_name(n))) for n in e.free])
        member = joined(
            [parts(Math(f"{latex_name(k)} = {show(v)}")) for k, v in e.representative.items()]
        )
        blocks.append(
            Paragraph(
                parts(
                    "A family of equilibria, free: ",
                    *free,
                    "; the modes at the member ",
                    *member,
                    ".",
                )
            )
        )
    if getattr(e, "degenerate", ()):
        names = joined([parts(Math(latex_name(n))) for n in e.degenerate])
        blocks.append(
            Paragraph(
                parts(
                    "The coordinates are singular here (",
                    *names,
                    " degenerate): the modes of the regular directions.",
                )
            )
        )
    squares = modes.omega_squared
    if squares:
        many = len(squares) > 1
        rows = [
            Row(rf"\omega_{{{k + 1}}}^2" if many else r"\omega^2", (show(w2),))
            for k, w2 in enumerate(squares)
        ]
        periods = [show(p) for p in modes.periods] if modes.closed_form else []
        if periods and all(visible_width(p) <= LINE_WIDTH for p in periods):
            rows += [
                Row(rf"T_{{{k + 1}}}" if len(periods) > 1 else "T", (p,))
                for k, p in enumerate(periods)
            ]
        blocks.append(Display(tuple(rows)))
    zero_modes = list(getattr(e, "zero_modes", ()))
    for name in dict.fromkeys(zero_modes):
        count = zero_modes.count(name)
        blocks.append(
            Paragraph(
                parts(Math(r"\omega^2 = 0"), f"{f' (×{count})' if count > 1 else ''}: {name}.")
            )
        )
    if modes.note:
        blocks.append(Paragraph(parts(f"({modes.note})")))
    table = _numbers_table(modes, system, values_said)
    if table is not None:
        blocks += table
    return tuple(blocks)


def _numbers_table(modes, system, values_said: str) -> list | None:
    """The modes as numbers at the parameter values: a sentence and a table."""
    numbers = modes_at_values(modes, system)
    if numbers is None:
        numbers = _already_numbers(modes)
    if numbers is None:
        return None
    shapes = numbers.get("mode_shapes")
    header = ["mode", "ω²", "ω", "period"]
    names = system.coordinate_names
    if shapes:
        header.append("shape (" + ", ".join(map(unicode_name, names)) + ")")
    rows = []
    for k, w2 in enumerate(numbers["omega_squared"]):
        omega, period = numbers["omega"][k], numbers["periods"][k]
        row = [
            parts(str(k + 1)),
            parts(f"{w2:.6g}"),
            parts("—" if omega is None else f"{omega:.6g}"),
            parts("—" if period is None else f"{period:.6g}"),
        ]
        if shapes:
            row.append(parts("(" + ", ".join(f"{x:.4g}" for x in shapes[k]) + ")"))
        rows.append(tuple(row))
    at = joined(
        [parts(Math(f"{latex_name(n)} = {v:g}")) for n, v in numbers.get("parameters", {}).items()]
    )
    where = parts(f"At {values_said}", *((" (", *at, ")") if at else ()), ":")
    return [Paragraph(where), Table(tuple(header), tuple(rows))]


def _already_numbers(modes) -> dict | None:
    """ω², ω and periods of modes whose ω² are numbers already (no parameter in them)."""
    try:
        squares = [complex(sympy.N(as_expression(w2))) for w2 in modes.omega_squared]
    except TypeError:
        return None
    if not squares or any(abs(w.imag) > 1e-9 * max(1.0, abs(w.real)) for w in squares):
        return None
    real = [w.real for w in squares]
    omega = [math.sqrt(w) if w > 0 else None for w in real]
    document = {
        "omega_squared": real,
        "omega": omega,
        "periods": [2 * math.pi / w if w else None for w in omega],
    }
    try:
        shapes = [[float(sympy.N(as_expression(x))) for x in shape] for shape in modes.shapes]
    except TypeError:
        shapes = []
    if shapes and len(shapes[0]) > 1:
        document["mode_shapes"] = shapes
    return document


def relation(condition, show) -> str:
    """``a > b`` (and ``a > b \\wedge c > d``) in LaTeX."""
    conditions = condition.args if isinstance(condition, sympy.And) else (condition,)
    return r" \wedge ".join(
        f"{show(c.lhs)} {_RELATIONS.get(c.rel_op, c.rel_op)} {show(c.rhs)}" for c in conditions
    )


_RELATIONS = {">=": r"\geq", "<=": r"\leq", "!=": r"\neq", "==": "="}
