"""What the page's Poincaré section panel (``page_assets/section.js``) needs from Python.

The panel integrates orbits in the browser with the page's DOP853 and locates each
crossing of the section on the step's 7th-order dense output, as ``lagrangian poincare``
does through SciPy (:mod:`lagrangian.integrate.poincare`): the extra stages and the
interpolant's coefficients (SciPy's ``A_EXTRA``, ``C_EXTRA`` and ``D``, shipped as data:
:mod:`lagrangian.output.page_dop853`) travel in the page's document beside the stepper's.

A section of an energy shell needs a model whose energy is conserved and whose state
is its coordinates and velocities: autonomous, without constraints, forces or
dissipation, and with two coordinates or more (a section of one degree of freedom is a
point).  Otherwise the panel says why in place of the controls.
"""

from __future__ import annotations

from ..model import System
from .page_dop853 import dense_coefficients


def section_document(system: System, constraints: int) -> dict:
    """``{"available": true, "dense": {...}}`` for the panel of ``system`` (with
    ``constraints`` multipliers in its page's code), or ``{"available": false, "why":
    text}``."""
    why = _unavailable(system, constraints)
    if why is not None:
        return {"available": False, "why": why}
    return {"available": True, "dense": dense_coefficients()}


def _unavailable(system: System, constraints: int) -> str | None:
    if len(system.coordinates) < 2:
        return "A Poincaré section needs two coordinates or more: this model has one."
    if not system.is_autonomous:
        return (
            "No Poincaré section of an energy shell here: the model depends on t (its energy "
            "is not conserved); lagrangian poincare --strobe PERIOD samples a driven motion."
        )
    if constraints or system.constraints:
        return "No Poincaré section here: the model has constraints (Lagrange multipliers)."
    if system.forces or system.dissipation != 0:
        return "No Poincaré section of an energy shell: forces or dissipation change the energy."
    return None
