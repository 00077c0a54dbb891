"""The pictures of a worked solution: a phase portrait and the normal modes.

The phase portrait is ``plot --kind phase``'s: a run of the model from its initial state
(for one conservative coordinate, with a family of motions below and above the
separatrix); the modes are ``plot --kind modes``'s, about the first stable equilibrium
(else one stable apart from a free motion).  A picture that cannot be made (no run without
the model's functions, no stable equilibrium) is a sentence saying why, never missing
silently.
"""

from __future__ import annotations

from collections.abc import Mapping

from ...algebra import as_expression
from ...analysis import Analysis
from ...errors import LagrangianError
from ...model import System
from ..notation import latex_name
from .document import Math, Paragraph, Picture, joined, parts


def phase_pictures(
    system: System, given: bool, definitions: Mapping[str, str] | None = None
) -> tuple:
    """The phase portrait of a run of ``system`` (or a sentence saying why there is none)."""
    from ...simulation import simulate_system
    from ..phase import conservative_one_dof, phase_family, plot_phase_portrait

    try:
        run = simulate_system(system, definitions=definitions)
        if run.status == "failed":
            raise LagrangianError(run.dataset.attrs.get("message", "the integration failed"))
        runs = [run]
        family = conservative_one_dof(system) and not given
        if family:
            runs = [*phase_family(system), run]
        figure = plot_phase_portrait(runs if family else run, system)
    except LagrangianError as error:
        return (Paragraph(parts(f"No phase portrait: {error}.")),)
    start = [
        parts(Math(f"{latex_name(name)} = {value:g}"))
        for name in (*run.coordinates, *run.velocities)
        if (value := float(run.dataset[name][0])) != 0
    ]
    said = parts(" from ", *joined(start)) if start else parts(" from rest at the origin")
    t_end = float(run.dataset["t"][-1])
    caption = (
        f"Phase portrait: each coordinate's velocity against the coordinate along a run of"
        f" {t_end:g} s"
    )
    text = parts(
        "The motion in the phase plane of each coordinate, along a run of ",
        f"{t_end:g} s",
        *said,
        "; the colour follows the time."
        if not family
        else "; grey: levels of the energy, red: the separatrix, and motions at energies"
        " below and above it.",
    )
    return (Paragraph(text), Picture("phase", caption, figure))


def mode_pictures(system: System, analysis: Analysis, values_said: str, show) -> tuple:
    """The normal modes about the first stable equilibrium, drawn (or why not)."""
    from ..mode_shapes import plot_normal_modes

    # drawn: a mode shape per coordinate and a point that oscillates (every omega^2 = 0, as
    # for a free particle, shows nothing); a constrained system's shapes are tangent to its
    # constraint surface, and q0 + A s cos(phi) would be drawn off it (a stretched rod)
    drawable = [
        e
        for e in analysis.equilibria
        if e.point
        and not system.constraints
        and e.modes.shapes
        and len(e.modes.shapes[0]) == len(system.coordinates)
        and _oscillates(e.modes, system)
    ]
    stable = [e for e in drawable if e.stable]
    marginal = [e for e in drawable if e.modes.stability.value == "marginal" and not e.free]
    chosen = (stable or marginal or [None])[0]
    if chosen is None:
        return (Paragraph(parts(_why_no_modes(system, analysis))),)
    at = dict(getattr(chosen, "representative", None) or chosen.point)
    try:
        figure = plot_normal_modes(system, at, modes=chosen.modes)
    except (LagrangianError, ValueError, TypeError) as error:
        return (Paragraph(parts(f"The mode shapes were not drawn: {error}.")),)
    point = joined([parts(Math(f"{latex_name(k)} = {show(v)}")) for k, v in at.items()])
    caption = f"The normal modes at {values_said}"
    text = parts(
        "Each normal mode alone, about ",
        *point,
        f", at {values_said}: the mechanism at a few phases of the oscillation,"
        " the equilibrium dashed.",
    )
    return (Paragraph(text), Picture("modes", caption, figure))


def _oscillates(modes, system: System) -> bool:
    """Whether some omega^2 of ``modes`` is positive at the system's parameter values."""
    values = system.parameter_values
    at = {p.symbol: values[p.name] for p in system.parameters if p.name in values}
    for w2 in modes.omega_squared:
        try:
            if complex(as_expression(w2).subs(at)).real > 0:
                return True
        except TypeError:  # a parameter without a value
            continue
    return False


def _why_no_modes(system: System, analysis: Analysis) -> str:
    if not analysis.equilibria:
        return "No equilibrium: no normal modes to draw."
    if system.constraints:
        return (
            "The normal modes of a constrained system are not drawn (its mode shapes lie in"
            " the directions the constraints allow, not along each coordinate)."
        )
    return "No equilibrium about which the system oscillates: no normal modes to draw."
