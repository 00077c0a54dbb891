"""`analyze`: everything the analysis stage can say about a system, in one frozen object.

Each stage (conserved quantities, Hamiltonian, equilibria, their modes, Routh's
reduction, steady motions) runs under its own deadline (:mod:`lagrangian.budget`,
``timeout`` seconds of CPU time each; the modes, a linearization that always
ends, at least :data:`~lagrangian.budget.ENDING_SECONDS`).  A stage that runs
out of time is abandoned whole and listed in ``undecided``; what it would have
said is ``None`` (or empty), never a half-made answer.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass

from ..budget import STAGE_SECONDS, Undecided, attempt, checked_seconds, generous
from ..derive import EquationsOfMotion
from ..errors import ModelError
from ..provided import Provided
from ..symbols import momentum_name
from .conserved import Conservation, conserved_quantities
from .constrained import surface_rest_points
from .equilibria import Equilibrium, rest_points, with_modes
from .hamiltonian import Hamiltonian, hamiltonian
from .modes import NormalModes
from .routh import Reduction, cyclic_coordinates, reduce, steady_motions_of

#: CPU seconds for SymPy's solve of the steady motions within the stage (the heavy top's
#: takes 2.1 s to find that it has no isolated solution).
STEADY_SOLVE_SECONDS = 10.0

#: The stages in the order they run (the names used in ``undecided``).
STAGES = (
    "conserved quantities",
    "Hamiltonian",
    "equilibria",
    "modes",
    "Routh reduction",
    "steady motions",
)


@dataclass(frozen=True, eq=False)
class Analysis:
    """Conserved quantities, H, equilibria with their small oscillations, Routh's reduction.

    ``notes`` say what was not computed and why (a part that does not apply is
    ``None`` or empty, never silently wrong); ``undecided`` lists the stages that
    ran out of time (their parts are ``None`` or empty, and say nothing).
    """

    # the text and LaTeX of output/, given by the facade (see lagrangian.provided)
    __repr__ = Provided()
    _repr_latex_ = Provided()

    equations: EquationsOfMotion
    conservation: Conservation | None
    hamiltonian: Hamiltonian | None
    equilibria: tuple[Equilibrium, ...]
    reduction: Reduction | None
    steady_motions: tuple[Equilibrium, ...] = ()  # equilibria of the reduced system
    notes: tuple[str, ...] = ()
    undecided: tuple[Undecided, ...] = ()

    def decided(self, stage: str) -> bool:
        """Whether ``stage`` (one of ``STAGES``) finished within its time."""
        return all(u.stage != stage for u in self.undecided)


def analyze(
    eom: EquationsOfMotion,
    *,
    timeout: float | None = STAGE_SECONDS,
    momenta: Mapping[str, float] | None = None,
    stages: Collection[str] = STAGES,
) -> Analysis:
    """Run every analysis that applies to ``eom``, each stage within ``timeout`` seconds.

    ``timeout=None`` runs every stage to its end.  ``momenta`` gives values to
    cyclic momenta (``{"p_phi": 1.0}``): the steady motions are then found for
    them, numerically where SymPy cannot.  ``stages`` (some of :data:`STAGES`) are
    those to run; the others are not attempted (their parts are ``None`` or empty, and
    no note or undecided entry speaks of them).
    """
    unknown = sorted(set(stages) - set(STAGES))
    if unknown:
        raise ValueError(f"unknown analysis stages {unknown} (stages: {', '.join(STAGES)})")
    if timeout is not None:
        timeout = checked_seconds(timeout, "timeout")
    if momenta:
        known = {momentum_name(name) for name in cyclic_coordinates(eom)}
        unknown = sorted(set(momenta) - known)
        if unknown:
            raise ModelError(
                f"not momenta of cyclic coordinates: {', '.join(unknown)}"
                f" (cyclic momenta: {', '.join(sorted(known)) or 'none'})"
            )
    notes: list[str] = []
    undecided: list[Undecided] = []

    def stage(name: str, work, *arguments, seconds: float | None = timeout):
        """``work(*arguments)`` within ``seconds``; None with a note when it does not apply
        (and None, silently, for a stage not asked for)."""
        if name not in stages:
            return None
        result, missing = attempt(name, seconds, lambda: _or_note(notes, name, work, *arguments))
        if missing is not None:
            undecided.append(missing)
        return result

    conservation = stage("conserved quantities", conserved_quantities, eom)
    if conservation is not None:
        notes.extend(conservation.notes)
    constrained = eom.constraints is not None
    h = None
    if constrained and "Hamiltonian" in stages:
        notes.append("Hamiltonian: not computed for systems with constraints")
    else:
        h = stage("Hamiltonian", hamiltonian, eom)
    points: tuple[Equilibrium, ...] = ()
    if constrained:
        on_surface = stage("equilibria", surface_rest_points, eom)
        if on_surface is not None:
            points = on_surface.points
            notes += on_surface.notes
    else:
        rest = stage("equilibria", rest_points, eom)
        if rest is not None:
            points = _with_modes(eom, rest, stage, generous(timeout))
            notes += [_singularity_note(e) for e in points if e.coordinate_singularity]
            points = tuple(e for e in points if not e.coordinate_singularity)
            if not points and not eom.system.is_autonomous:
                notes.append("equilibria: none in general, the system depends explicitly on t")
    reduction, steady = None, ()
    if not constrained and cyclic_coordinates(eom):
        reduction = stage("Routh reduction", lambda: reduce(eom, momenta=momenta))
    if reduction is not None:
        steady = stage("steady motions", _steady, reduction, notes) or ()
    return Analysis(eom, conservation, h, points, reduction, steady, tuple(notes), tuple(undecided))


def _singularity_note(e: Equilibrium) -> str:
    """What a point where G = 0 only by the coordinates' names is, said apart."""
    point = ", ".join(f"{name} = {value}" for name, value in e.point.items())
    names = ", ".join(e.degenerate)
    return (
        f"equilibria: {point} is a singular point of the coordinates ({names} degenerate "
        f"there), not an equilibrium: the same configuration under other values of {names} "
        "is not at rest"
    )


def _or_note(notes: list[str], name: str, work, *arguments):
    """``work(*arguments)``, or None with a note when it says it does not apply (ModelError)."""
    try:
        return work(*arguments)
    except ModelError as error:
        notes.append(f"{name}: {error.message}")
        return None


def _with_modes(eom: EquationsOfMotion, rest, stage, seconds) -> tuple[Equilibrium, ...]:
    """The equilibria with their modes; past the modes' deadline, the rest undetermined."""
    done: list[Equilibrium] = []

    def all_modes() -> None:
        for point in rest[len(done) :]:
            done.append(with_modes(eom, point))

    if stage("modes", all_modes, seconds=seconds) is None and len(done) < len(rest):
        note = "the normal modes were not decided in time"
        for point in rest[len(done) :]:
            done.append(Equilibrium(point.point, point.numeric, NormalModes.undetermined(note)))
    return tuple(done)


def _steady(reduction: Reduction, notes: list[str]) -> tuple[Equilibrium, ...]:
    # SymPy's solve gets part of the stage: without values for the momenta the
    # numerical search cannot follow, and a hard solve (a top's two momenta)
    # should end in a note, not in an undecided stage
    steady = steady_motions_of(reduction, timeout=STEADY_SOLVE_SECONDS)
    if not steady:
        momenta = ", ".join(str(p) for p in reduction.momenta.values())
        notes.append(
            f"steady motions: none found symbolically; for a numeric search give {momenta}"
            " values: System.steady_motions(momenta={...})"
        )
    return steady
