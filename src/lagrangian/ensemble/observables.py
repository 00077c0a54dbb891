"""What an ensemble reports per member: a registry of observables.

Each observable is computed from the batched stepping of the single-run
integrator (the state of every member after every step), never from a second
implementation of the physics:

- ``final_state``: the state at t_end, one variable ``final_<name>`` per
  coordinate and velocity;
- ``energy_drift``: |E(t_end) - E(0)| / |E(0)| (absolute when |E(0)| <= 1e-12),
  the energy function h = q' . dL/dq' - L at both ends;
- ``flip_time``: the first step time at which some coordinate's |q| exceeds pi
  (0 when the initial state already does; NaN when it never happens).  For the
  double pendulum that is the time the first arm flips over.  It needs no
  state at t_end, so a run asking only for it stops each member when it has
  flipped;
- ``lyapunov``: the largest Lyapunov exponent, the mean logarithmic stretch per unit
  time of one displacement stepped with the state by the members' explicit method
  (the variational equations, :class:`~lagrangian.integrate.lyapunov.TangentFlow`),
  renormalised every step; the numpy, numba (the variational equations generated,
  :mod:`lagrangian.codegen.schemes`), jax and dask backends compute it;
- ``sali``, ``gali2``, ``gali3``, ``gali4``: fast chaos indicators from 2 (or k)
  deviation vectors stepped with the state (:mod:`lagrangian.integrate.indicators`);
  the numpy and numba backends compute them (rk4), for Hamiltonian systems of 2 or more
  degrees of freedom (:func:`indicator_refusal`).  ``sali``: SALI is checked after every
  step; ``sali_time`` is the first step time at which it is below
  :data:`~lagrangian.integrate.indicators.SALI_BELOW` (1e-4; NaN: never),
  ``sali_chaotic`` whether that happened, and ``sali`` its value at the member's last
  step.  Like ``flip_time`` it needs no state at t_end: a run asking for nothing else
  stops each member at its crossing.  ``gali<k>``: the value at t_end and
  ``gali<k>_chaotic``, whether it is below
  :data:`~lagrangian.integrate.indicators.CHAOTIC_BELOW` (1e-8).

Every run also reports ``failed``: the members whose state at the end (or where
they stopped) is not finite, NaN or overflowed.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Below this |E(0)| the energy drift is absolute, as in Trajectory.drift.
DRIFT_RELATIVE_FLOOR = 1e-12


@dataclass(frozen=True)
class Observable:
    """One registered observable: its name, what it is, and whether it needs t_end."""

    name: str
    description: str
    needs_end: bool  # False: a member may stop as soon as its value is known


OBSERVABLES: dict[str, Observable] = {
    o.name: o
    for o in (
        Observable("final_state", "the state at t_end (final_<q>, final_<q>_dot)", True),
        Observable("energy_drift", "|E(t_end) - E(0)| / |E(0)|", True),
        Observable("flip_time", "first time some |q| exceeds pi (NaN: never)", False),
        Observable("lyapunov", "largest Lyapunov exponent over the run (rk4; not cuda)", True),
        Observable(
            "sali",
            "SALI of 2 deviation vectors; sali_time (its first step below 1e-4), sali_chaotic",
            False,
        ),
        *(
            Observable(f"gali{k}", f"GALI_{k} of {k} deviation vectors; gali{k}_chaotic", True)
            for k in (2, 3, 4)
        ),
    )
}


def observable_names(names: str | Iterable[str]) -> tuple[str, ...]:
    """``names`` checked against the registry (one ModelError listing the valid names)."""
    chosen = (names,) if isinstance(names, str) else tuple(names)
    if not chosen:
        raise ModelError("give at least one observable (" + ", ".join(OBSERVABLES) + ")")
    for name in chosen:
        if name not in OBSERVABLES:
            valid = ", ".join(OBSERVABLES)
            raise ModelError(f"unknown observable '{name}' (observables: {valid})")
    return tuple(dict.fromkeys(chosen))


#: The chaos indicators (:mod:`lagrangian.integrate.indicators`) and the deviation
#: vectors each needs.
INDICATORS = {"sali": 2, "gali2": 2, "gali3": 3, "gali4": 4}


def indicator_vectors(names: tuple[str, ...]) -> int:
    """The deviation vectors the chaos indicators among ``names`` need (0: none asked)."""
    return max((INDICATORS[name] for name in names if name in INDICATORS), default=0)


def indicator_refusal(compiled: CompiledSystem, name: str) -> str | None:
    """Why the chaos indicator ``name`` would not classify this system's orbits (None:
    it does).  Their test, regular orbits keep the deviation vectors apart, holds for a
    Hamiltonian flow of 2 or more degrees of freedom: with 1, even a regular orbit's
    vectors are sheared together (SALI falls like 1/t, Skokos 2001), and dissipation
    aligns them on any attractor, a fixed point or a limit cycle too."""
    what = f"observable {name} classifies orbits of Hamiltonian systems"
    if compiled.n < 2:
        coordinate = compiled.coordinate_names[0]
        return f"{what} of 2 or more degrees of freedom; this one has 1 ({coordinate})"
    if compiled.has_constraints:
        return f"{what}, not of constrained ones"
    forms = compiled.forms
    if forms is None:
        return f"{what}: it needs derived equations (to check that), not given functions"
    if not forms.conservative:
        names, forces = compiled.coordinate_names, forms.nonconservative_forces
        acting = ", ".join(f"{q}: {f}" for q, f in zip(names, forces, strict=True) if f != 0)
        return f"{what}; this one has forces or dissipation (Q - dF/dq' on {acting})"
    return None


def indicator_values(
    vectors: np.ndarray, names: tuple[str, ...], sali_time: np.ndarray
) -> dict[str, np.ndarray]:
    """Each chaos indicator asked for from the unit deviation vectors at each member's last
    step (k, 2n, B), and ``<name>_chaotic``: for SALI, whether it fell below SALI_BELOW at
    some step (``sali_time``, the first such step's time, NaN: never, is reported too); for
    GALI_k, whether it is below CHAOTIC_BELOW at t_end."""
    from ..integrate.indicators import CHAOTIC_BELOW, gali, sali

    values = {}
    for name in names:
        if name == "sali":
            values["sali"] = sali(vectors)
            values["sali_time"] = np.asarray(sali_time, dtype=float)
            values["sali_chaotic"] = np.isfinite(sali_time)
        elif name in INDICATORS:
            values[name] = gali(vectors, INDICATORS[name])
            values[f"{name}_chaotic"] = values[name] < CHAOTIC_BELOW
    return values


#: The observables whose value is known once something happens: a flip, SALI's crossing.
SETTLING = ("flip_time", "sali")


def stops_early(names: tuple[str, ...]) -> bool:
    """Whether members may stop once every value asked for is known (flipped, SALI below
    SALI_BELOW): no observable needs the state at t_end."""
    return any(n in SETTLING for n in names) and not any(OBSERVABLES[n].needs_end for n in names)


def flipped(y: np.ndarray, n: int) -> np.ndarray:
    """Per member: does some coordinate's |q| exceed pi?  (y (2n, B))."""
    return np.any(np.abs(y[:n]) > np.pi, axis=0)


def finish(
    compiled: CompiledSystem,
    names: tuple[str, ...],
    *,
    t0: float,
    y0: np.ndarray,
    t1: float,
    y1: np.ndarray,
    params: np.ndarray,
    flip_time: np.ndarray | None,
) -> dict[str, np.ndarray]:
    """The observables' values (each of shape (B,)) from the start, the end and the flips,
    and ``failed`` (a state that is not finite at the end)."""
    values: dict[str, np.ndarray] = {"failed": ~np.all(np.isfinite(y1), axis=0)}
    state_names = (*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names))
    for name in names:
        if name == "final_state":
            for i, state in enumerate(state_names):
                values[f"final_{state}"] = np.array(y1[i], dtype=float)
        elif name == "energy_drift":
            start = np.asarray(compiled.energy(t0, y0, params), dtype=float)
            end = np.asarray(compiled.energy(t1, y1, params), dtype=float)
            deviation = np.abs(end - start)
            scale = np.abs(start)
            with np.errstate(divide="ignore", invalid="ignore"):
                values[name] = np.where(scale > DRIFT_RELATIVE_FLOOR, deviation / scale, deviation)
        elif name == "flip_time":
            values[name] = np.array(flip_time, dtype=float)
    return values
