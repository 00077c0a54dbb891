"""Periodic orbits as JSON and as text (``lagrangian orbits``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..integrate.floquet import as_json

if TYPE_CHECKING:
    from ..integrate.orbits import OrbitSearch, PeriodicOrbit


def orbits_json(search: OrbitSearch) -> dict[str, object]:
    """The search as JSON: the settings, and ``orbits``, a list of ``{period, points
    (name -> value maps, one per point), multipliers (a complex one as [re, im]), stable,
    kind, residual}``."""
    return {
        "model": search.name,
        **search.settings,
        "period": search.period,
        "starts": search.starts,
        "orbits": [
            {
                "period": orbit.period,
                "points": [
                    dict(zip(search.names, map(float, point), strict=True))
                    for point in orbit.points.T
                ],
                "multipliers": as_json(orbit.multipliers),
                "stable": orbit.stable,
                "kind": orbit.kind,
                "residual": orbit.residual,
                **({} if orbit.time is None else {"time": orbit.time}),
            }
            for orbit in search.orbits
        ],
    }


def orbits_text(search: OrbitSearch) -> str:
    """One line for the search, then one per orbit: its period, stability and kind, its
    multipliers and its points."""
    strobe = search.strobe
    if strobe is None:
        settings = search.settings
        where = f"the section {settings['section']} at energy {settings['energy']:.6g}"
    else:
        at = f" at phase {strobe.phase:.6g}" if strobe.phase else ""
        where = f"the strobe every {strobe.period:.6g}{at}"
    count = len(search.orbits)
    lines = [
        f"{search.name}: {count} periodic orbit{'s' if count != 1 else ''} of period "
        f"dividing {search.period} of {where}, from {search.starts} starts"
    ]
    names = ", ".join(search.names)
    lines += [f"  {_orbit_line(orbit)}; ({names}) at {_points(orbit)}" for orbit in search.orbits]
    return "\n".join(lines)


def _orbit_line(orbit: PeriodicOrbit) -> str:
    stability = "stable" if orbit.stable else "unstable"
    values = ", ".join(multiplier_text(value) for value in orbit.multipliers)
    time = "" if orbit.time is None else f" (time {orbit.time:.9g})"
    return f"period {orbit.period}{time}, {stability} {orbit.kind}, multipliers {values}"


def multiplier_text(value: complex) -> str:
    encoded = as_json([value])[0]
    if isinstance(encoded, list):
        return f"{encoded[0]:.6g}{encoded[1]:+.6g}i"
    return f"{encoded:.6g}"


def _points(orbit: PeriodicOrbit) -> str:
    return ", ".join(
        "(" + ", ".join(f"{value:.6g}" for value in point) + ")" for point in orbit.points.T
    )
