"""Text, LaTeX and JSON (DESIGN section 5, ``analyze --json``) of an `Analysis`."""

from __future__ import annotations

from collections.abc import Mapping

from ..algebra import as_expression
from ..analysis import Analysis
from ..errors import PYTHON_SPELLING, setting, spelled
from .large import latex_printer, plain_printer, unicode_printer
from .notation import latex_name, too_long_to_print, unicode_name
from .units import (
    OMEGA,
    OMEGA_SQUARED,
    PERIOD,
    bracketed,
    expression_unit,
    latex_mode_numbers,
    latex_unit,
    latex_units_row,
    name_unit,
    units_line,
    units_section,
)

#: What text and LaTeX say instead of an expression too long to read (the Hamiltonian of
#: a densely coupled 6-coordinate system printed for minutes): JSON has them all.
TOO_LONG = "too long to print; analyze --json gives it"


def _readable(printer):
    return lambda expr: TOO_LONG if too_long_to_print(expr) else printer(expr)


def analysis_document(analysis: Analysis) -> dict:
    """The ``analyze --json`` document; expressions are SymPy ``str()`` text (SymEngine's,
    which parses back the same, for large ones).

    A stage that ran out of time is listed in ``undecided`` ({stage, reason}); its
    fields are null (conserved quantities, Hamiltonian) or empty, never a guess.
    """
    conservation = analysis.conservation
    decided = conservation is not None
    system = analysis.equations.system
    text = plain_printer(system)  # SymEngine's str for large ones
    document: dict = {
        "name": analysis.equations.system.name,
        "cyclic_coordinates": list(conservation.cyclic_coordinates) if decided else None,
        "conserved": [
            {"name": q.name, "expression": text(q.expression), "description": q.description}
            | _unit_field(system, q.expression)
            for q in conservation.conserved
        ]
        if decided
        else None,
        "not_conserved": [
            {"name": q.name, "expression": text(q.expression), "reason": q.reason}
            for q in conservation.not_conserved
        ]
        if decided
        else None,
        "hamiltonian": None
        if analysis.hamiltonian is None
        else text(analysis.hamiltonian.expression),
        "equilibria": [_equilibrium_document(e, text, system) for e in analysis.equilibria],
        "steady_motions": [_equilibrium_document(e, text, system) for e in analysis.steady_motions],
        "notes": list(analysis.notes),
        "undecided": [{"stage": u.stage, "reason": u.reason} for u in analysis.undecided],
    }
    section = units_section(system)
    if section is not None:  # additive: a dimensioned model's units (issue 31)
        document["units"] = section
        if analysis.hamiltonian is not None:
            document["hamiltonian_units"] = expression_unit(system, analysis.hamiltonian.expression)
    if analysis.reduction is not None:
        reduction = analysis.reduction
        document["reduction"] = {
            "cyclic": list(reduction.cyclic),
            "momenta": {name: text(p) for name, p in reduction.momenta.items()},
            "routhian": text(reduction.routhian),
            "effective_potential": text(reduction.effective_potential),
        }
    return document


def _unit_field(system, expr) -> dict:
    """``{"units": "J"}`` for a quantity of a dimensioned model, else nothing."""
    unit = expression_unit(system, expr)
    return {} if unit is None else {"units": unit}


def _equilibrium_document(e, text, system) -> dict:
    multipliers = getattr(e, "multipliers", None)
    extra = {"multipliers": {k: text(v) for k, v in multipliers.items()}} if multipliers else {}
    document = extra | {
        "point": {name: text(value) for name, value in e.point.items()},
        "stable": e.stable,
        "stability": e.modes.stability.value,
        "omega_squared": [text(w2) for w2 in e.modes.omega_squared],
        "periods": [text(p) for p in e.modes.periods],
        "numeric": e.numeric,
        "closed_form": e.modes.closed_form,
    }
    # additive fields (DESIGN section 5 keeps the keys above): families, singular
    # coordinates, named zero modes, and how the verdict depends on the parameters
    if getattr(e, "free", ()):
        document["free"] = list(e.free)
        document["representative"] = {k: text(v) for k, v in e.representative.items()}
    if getattr(e, "family_dimension", 0):
        document["family_dimension"] = e.family_dimension
    if getattr(e, "degenerate", ()):
        document["degenerate"] = list(e.degenerate)
    if getattr(e, "zero_modes", ()):
        document["zero_modes"] = list(e.zero_modes)
    if getattr(e, "at_defaults", False):  # the verdict, said: "unstable", not just true
        document["stability_at_defaults"] = e.modes.stability.value
    numbers = modes_at_values(e.modes, system)
    if numbers is not None:
        document["at_parameter_values"] = numbers
    if system.units is not None:
        document["units"] = {"omega_squared": OMEGA_SQUARED, "omega": OMEGA, "periods": PERIOD}
    condition = getattr(e, "stability_condition", None)
    if condition is not None:
        document["stability_condition"] = text(condition)
    if multipliers is not None:  # additive: a constrained point's modes in the coordinates q
        document["mode_shapes"] = [[text(x) for x in shape] for shape in e.modes.shapes]
        if e.redundant:
            document["redundant_constraints"] = e.redundant
    velocities = getattr(e, "velocities", None)
    if velocities:
        document["cyclic_velocities"] = {k: text(v) for k, v in velocities.items()}
        document["momenta"] = {k: text(v) for k, v in e.momenta.items()}
    return document


#: Where a numerical result holds: at the model's defaults, or at values given in their
#: place (``analyze --set``), which the text must not call the defaults.
AT_DEFAULTS = "at the default parameter values"
AT_GIVEN = "at the given values"


def format_analysis(
    analysis: Analysis,
    *,
    spelling: Mapping[str, str] = PYTHON_SPELLING,
    values_given: bool = False,
) -> str:
    """The analysis as readable Unicode text; ``values_given``: some parameter values were
    given in place of the defaults (the numerical results are said to hold at them)."""
    at = AT_GIVEN if values_given else AT_DEFAULTS
    system = analysis.equations.system
    show = _readable(unicode_printer(system))
    conservation = analysis.conservation
    missing = {u.stage: u.reason for u in analysis.undecided}
    lines = [
        f"{system.name}   (coordinates: {', '.join(map(unicode_name, system.coordinate_names))})"
    ]
    lines += [line for line in (units_line(system),) if line is not None]
    if conservation is None:
        reason = missing.get("conserved quantities", "not computed")
        lines += ["", f"Cyclic coordinates and conserved quantities: {reason}"]
    else:
        cyclic = ", ".join(map(unicode_name, conservation.cyclic_coordinates)) or "none"
        lines += ["", f"Cyclic coordinates: {cyclic}", "", "Conserved:"]
        for q in conservation.conserved:
            unit = bracketed(expression_unit(system, q.expression))
            lines.append(f"  {_name(q.name)} = {show(q.expression)}   ({q.description}){unit}")
        if not conservation.conserved:
            lines.append("  nothing")
    if conservation is not None and conservation.not_conserved:
        lines += ["", "Not conserved:"]
        for q in conservation.not_conserved:
            lines.append(f"  {_name(q.name)} = {show(q.expression)}   because {q.reason}")
    if analysis.hamiltonian is not None:
        unit = bracketed(expression_unit(system, analysis.hamiltonian.expression))
        lines += ["", f"Hamiltonian:  H = {show(analysis.hamiltonian.expression)}{unit}"]
    elif "Hamiltonian" in missing:
        lines += ["", f"Hamiltonian: {missing['Hamiltonian']}"]
    lines += ["", "Equilibria (at rest, staying at rest):"]
    not_applied = [n for n in analysis.notes if n.startswith("equilibria: ")]
    if "equilibria" in missing:
        lines.append(f"  {missing['equilibria']}")
    elif not analysis.equilibria and not_applied:  # not searched is not "none found"
        lines.append(f"  not computed: {not_applied[0].removeprefix('equilibria: ')}")
    else:
        lines += _equilibrium_lines(analysis.equilibria, show, system, at)
    if analysis.reduction is not None:
        reduction = analysis.reduction
        lines += ["", f"Routh reduction of {', '.join(map(unicode_name, reduction.cyclic))}:"]
        lines.append(f"  R = {show(reduction.routhian)}")
        lines.append(f"  V_eff = {show(reduction.effective_potential)}")
        lines += ["", "Steady motions (cyclic momenta fixed, the other coordinates at rest):"]
        if "steady motions" in missing:
            lines.append(f"  {missing['steady motions']}")
        else:
            lines += _equilibrium_lines(analysis.steady_motions, show, system, at)
    if analysis.notes:
        lines += ["", "Notes:"] + [f"  {note}" for note in analysis.notes]
    if analysis.undecided:
        lines += ["", f"Undecided ({spelled(_more_time(analysis.undecided), spelling)}):"]
        lines += [f"  {u.stage}: {u.reason}" for u in analysis.undecided]
    return "\n".join(lines)


def _more_time(undecided) -> str:
    """Which budget ran out, and a timeout that gives each stage four times as much."""
    spent = [u.seconds for u in undecided if u.seconds is not None]
    if not spent:
        return f"out of time; a larger {setting('timeout')} gives more"
    return (
        f"out of time: each stage had {max(spent):g} s of CPU; a larger {setting('timeout')}"
        f" gives more, e.g. {4 * max(spent):g}"
    )


def _equilibrium_lines(points, show, system, at: str = AT_DEFAULTS) -> list[str]:
    # a parameter written ω (omega, a turning wire's rate) and the modes' ω in one line
    # read as one quantity ("at ω = 1: ω² = -1"): the modes' are then said in words
    words = any(unicode_name(p.name) == "ω" for p in system.parameters)
    units = (lambda unit: bracketed(unit)) if system.units is not None else (lambda unit: "")
    lines = []
    for e in points:
        point = ", ".join(f"{unicode_name(k)} = {show(v)}" for k, v in e.point.items()) or (
            "every configuration"
        )
        numeric = f"  [numeric, {at}]" if e.numeric else ""
        lines.append(f"  {point}: {_verdict(e, show, at)}{numeric}")
        free = getattr(e, "free", ())
        if free:
            member = ", ".join(
                f"{unicode_name(k)} = {show(v)}" for k, v in e.representative.items()
            )
            names = ", ".join(map(unicode_name, free))
            lines.append(f"    a family of equilibria, free: {names}; modes at the member {member}")
        if getattr(e, "family_dimension", 0):
            lines.append(
                f"    one member of a family of equilibria (up to {e.family_dimension} free"
                " directions; roots found numerically, grouped by the value of V)"
            )
        if getattr(e, "degenerate", ()):
            names = ", ".join(map(unicode_name, e.degenerate))
            lines.append(
                f"    {names} degenerate here (the coordinates are singular at this point):"
                " modes of the regular directions"
            )
        velocities = getattr(e, "velocities", None)
        if velocities:
            turning = ", ".join(f"{unicode_name(k)}̇ = {show(v)}" for k, v in velocities.items())
            lines.append(f"    turning at {turning}")
        multipliers = getattr(e, "multipliers", None)
        if multipliers:
            forces = ", ".join(f"{unicode_name(k)} = {show(v)}" for k, v in multipliers.items())
            lines.append(f"    constraint forces at rest: {forces}")
        elif getattr(e, "redundant", 0):
            lines.append("    constraint forces at rest: not determined (redundant constraints)")
        if e.modes.omega_squared:
            squares = ", ".join(show(w2) for w2 in e.modes.omega_squared)
            lines.append(f"    squared angular frequencies: {squares}{units(OMEGA_SQUARED)}")
        if e.modes.periods:
            periods = [p if e.modes.closed_form else p.evalf(6) for p in e.modes.periods]
            lines.append("    periods: " + ", ".join(show(p) for p in periods) + units(PERIOD))
        numbers = modes_at_values(e.modes, system)
        if numbers is not None:
            lines += _number_lines(numbers, words, system)
        elif multipliers is not None and e.modes.shapes:  # numbers already: the shapes in q
            shapes = ", ".join(_numbers(shape) for shape in e.modes.shapes)
            names = ", ".join(map(unicode_name, system.coordinate_names))
            lines.append(f"    mode shapes ({names}): {shapes}")
        zero_modes = list(getattr(e, "zero_modes", ()))
        for name in dict.fromkeys(zero_modes):  # each kind once, with its count
            count = zero_modes.count(name)
            zero = "a zero frequency" if words else "ω² = 0"
            lines.append(f"    {zero}{f' (×{count})' if count > 1 else ''}: {name}")
        if e.modes.note:
            lines.append(f"    ({e.modes.note})")
    return lines or ["  none found"]


def modes_at_values(modes, system) -> dict | None:
    """ω², ω, periods and mode shapes of ``modes`` as numbers at the system's parameter
    values (its defaults, or what ``--set`` gave), as the demo prints them.

    None where the symbolic ω² are numbers already (nothing to add), or where one is not
    a real number at the values (a parameter without one, complex gyroscopic roots).
    """
    import math

    import sympy

    squares = [as_expression(w2) for w2 in modes.omega_squared]
    if not squares or all(w2.is_number for w2 in squares):
        return None
    used = sorted({s.name for w2 in squares for s in w2.free_symbols})
    values = system.parameter_values
    if any(name not in values for name in used):
        return None
    at = {p.symbol: sympy.Float(values[p.name]) for p in system.parameters if p.name in values}
    numbers = []
    for w2 in squares:
        number = complex(w2.xreplace(at).evalf())
        if abs(number.imag) > 1e-9 * max(1.0, abs(number.real)):
            return None
        numbers.append(number.real)
    omega = [math.sqrt(w2) if w2 > 0 else None for w2 in numbers]
    document = {
        "parameters": {name: values[name] for name in used},
        "omega_squared": numbers,
        "omega": omega,
        "periods": [2 * math.pi / w if w else None for w in omega],
    }
    shapes = []
    for shape in modes.shapes:
        entries = [complex(as_expression(x).xreplace(at).evalf()) for x in shape]
        shapes.append([x.real for x in entries])
    if shapes and len(shapes[0]) > 1:  # one coordinate: the shape says nothing
        document["mode_shapes"] = shapes
    return document


def _number_lines(numbers: dict, words: bool = False, system=None) -> list[str]:
    """The lines of :func:`modes_at_values`: ω, periods and shapes at the values (``words``:
    ω² and ω named in words, where a parameter is written ω), in SI units where the
    ``system`` has units."""
    dimensioned = system is not None and system.units is not None

    def unit(text: str) -> str:
        return f" {text}" if dimensioned and text else ""

    at = ", ".join(
        f"{unicode_name(n)} = {v:g}{unit(name_unit(system, n) if dimensioned else '')}"
        for n, v in numbers["parameters"].items()
    )
    squares = ", ".join(f"{w2:.6g}" for w2 in numbers["omega_squared"])
    lines = [
        f"    at {at}: {'squared angular frequencies' if words else 'ω² ='} {squares}"
        + unit(OMEGA_SQUARED)
    ]
    if any(w is not None for w in numbers["omega"]):
        omega = ", ".join("-" if w is None else f"{w:.6g}" for w in numbers["omega"])
        periods = ", ".join("-" if p is None else f"{p:.6g}" for p in numbers["periods"])
        lines.append(
            f"      {'angular frequencies' if words else 'ω ='} {omega}{unit(OMEGA)};  "
            f"periods {periods}{unit(PERIOD)}"
        )
    if numbers.get("mode_shapes"):
        shapes = ", ".join(
            "(" + ", ".join(f"{x:.4g}" for x in shape) + ")" for shape in numbers["mode_shapes"]
        )
        lines.append(f"      mode shapes: {shapes}")
    return lines


def _numbers(shape) -> str:
    """A mode shape as ``(1, -0.8702, 0.3451)``: numbers to four digits, else as printed."""
    return "(" + ", ".join(f"{float(x):.4g}" if x.is_number else str(x) for x in shape) + ")"


def _verdict(e, show, at: str = AT_DEFAULTS) -> str:
    """'stable', or 'stable at the default parameter values; stable iff 2 a g > ω²'."""
    verdict = e.modes.stability.value
    if getattr(e, "at_defaults", False):
        verdict += f" {at}"
        condition = getattr(e, "stability_condition", None)
        if condition is not None:
            verdict += "; stable iff " + _relation(condition, show)
    return verdict


def _relation(condition, show, latex: bool = False) -> str:
    """``a > b`` (and ``a > b and c > d``) written with ``show`` for each side."""
    import sympy

    parts = condition.args if isinstance(condition, sympy.And) else (condition,)
    joiner = r" \wedge " if latex else " and "
    return joiner.join(f"{show(p.lhs)} > {show(p.rhs)}" for p in parts)


def latex_analysis(analysis: Analysis, *, values_given: bool = False) -> str:
    """The conserved quantities, H, equilibria and V_eff as one ``align*`` block
    (``values_given`` as for :func:`format_analysis`)."""
    at = AT_GIVEN if values_given else AT_DEFAULTS
    system = analysis.equations.system
    show = _readable(latex_printer(system))
    conserved = analysis.conservation.conserved if analysis.conservation is not None else ()
    rows = [row for row in (latex_units_row(system),) if row is not None]
    rows += [
        rf"{_latex_quantity(q.name)} &= {show(q.expression)}"
        + _latex_unit(expression_unit(system, q.expression))
        for q in conserved
    ]
    if analysis.hamiltonian is not None:
        unit = _latex_unit(expression_unit(system, analysis.hamiltonian.expression))
        rows.append(rf"H &= {show(analysis.hamiltonian.expression)}{unit}")
    for e in analysis.equilibria:
        point = ", ".join(f"{latex_name(k)} = {show(v)}" for k, v in e.point.items())
        squares = ", ".join(show(w2) for w2 in e.modes.omega_squared)
        remarks = []
        if getattr(e, "free", ()):
            remarks.append("a family, free: " + ", ".join(f"${latex_name(n)}$" for n in e.free))
        if getattr(e, "family_dimension", 0):
            remarks.append(f"a family of up to {e.family_dimension} free directions")
        if getattr(e, "degenerate", ()):
            names = ", ".join(f"${latex_name(n)}$" for n in e.degenerate)
            remarks.append(f"{names} degenerate: the regular directions")
        remark = "".join(rf"\ \text{{({r})}}" for r in remarks)
        rows.append(
            rf"&{point}: \ \omega^2 \in \{{{squares}\}}"
            + (_latex_unit(OMEGA_SQUARED) if system.units is not None else "")
            + rf"\ \text{{({e.modes.stability.value})}}"
            + remark
        )
        multipliers = getattr(e, "multipliers", None)
        if multipliers:  # the constraint forces that hold a constrained point
            forces = ", ".join(f"{latex_name(k)} = {show(v)}" for k, v in multipliers.items())
            rows.append(rf"&\quad\text{{constraint forces at rest: }} {forces}")
        numbers = modes_at_values(e.modes, system) if system.units is not None else None
        if numbers is not None:  # the text's "at g = 9.81 m/s^2: ω² = ..." with its units
            rows.append(latex_mode_numbers(numbers, system))
        if getattr(e, "at_defaults", False):
            row = rf"&\quad\text{{stability {at}}}"
            if e.stability_condition is not None:
                condition = _relation(e.stability_condition, show, latex=True)
                row += rf"\text{{; stable iff }} {condition}"
            rows.append(row)
    if analysis.reduction is not None:
        rows.append(rf"V_{{\mathrm{{eff}}}} &= {show(analysis.reduction.effective_potential)}")
    for u in analysis.undecided:  # out of time: said, not left out silently
        rows.append(rf"&\text{{{u.stage}: {u.reason}}}")
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def _latex_unit(unit: str | None) -> str:
    r"""``\quad [\mathrm{J}]`` after a quantity of a dimensioned model, else nothing."""
    return rf"\quad [{latex_unit(unit)}]" if unit else ""


def _name(name: str) -> str:
    return unicode_name(name) if name.startswith("p_") else name


def _latex_quantity(name: str) -> str:
    if name.startswith("p_"):
        return f"p_{{{latex_name(name[2:])}}}"
    return {"energy": "h"}.get(name, latex_name(name))  # one naming rule for every name
