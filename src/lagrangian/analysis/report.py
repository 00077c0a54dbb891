"""`analyze`: everything the analysis stage can say about a system, in one frozen object."""

from __future__ import annotations

from dataclasses import dataclass

from ..derive import EquationsOfMotion
from ..errors import ModelError
from .conserved import Conservation, conserved_quantities
from .constrained import constrained_equilibria
from .equilibria import Equilibrium, equilibria
from .hamiltonian import Hamiltonian, hamiltonian
from .routh import Reduction, cyclic_coordinates, reduce


@dataclass(frozen=True, eq=False)
class Analysis:
    """Conserved quantities, H, equilibria with their small oscillations, Routh's reduction.

    ``notes`` say what was not computed and why (a part that does not apply is
    ``None`` or empty, never silently wrong).
    """

    equations: EquationsOfMotion
    conservation: Conservation
    hamiltonian: Hamiltonian | None
    equilibria: tuple[Equilibrium, ...]
    reduction: Reduction | None
    steady_motions: tuple[Equilibrium, ...] = ()  # equilibria of the reduced system
    notes: tuple[str, ...] = ()

    def _repr_latex_(self) -> str:
        from ..output.analysis import latex_analysis

        return latex_analysis(self)


def analyze(eom: EquationsOfMotion) -> Analysis:
    """Run every analysis that applies to ``eom``."""
    notes = []
    conservation = conserved_quantities(eom)
    constrained = eom.constraints is not None
    h = None
    if constrained:
        notes.append("Hamiltonian: not computed for systems with constraints")
    else:
        try:
            h = hamiltonian(eom)
        except ModelError as error:
            notes.append(f"Hamiltonian: {error.message}")
    points: tuple[Equilibrium, ...] = ()
    if constrained:
        try:
            points = constrained_equilibria(eom)
        except ModelError as error:
            notes.append(f"equilibria: {error.message}")
    else:
        try:
            points = equilibria(eom)
        except ModelError as error:
            notes.append(f"equilibria: {error.message}")
        if not points and not eom.system.is_autonomous:
            notes.append("equilibria: none in general, the system depends explicitly on t")
    reduction, steady = None, ()
    if not constrained and cyclic_coordinates(eom):
        try:
            reduction = reduce(eom)
            steady = equilibria(reduction.system.equations_of_motion())
            if not steady:
                momenta = ", ".join(str(p) for p in reduction.momenta.values())
                notes.append(
                    f"steady motions: none found symbolically; for a numeric search give {momenta}"
                    " values: lagrangian.analysis.steady_motions(eom, momenta={...})"
                )
        except ModelError as error:
            notes.append(f"Routh reduction: {error.message}")
    return Analysis(eom, conservation, h, points, reduction, steady, tuple(notes))
