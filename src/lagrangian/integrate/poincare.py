"""Poincaré sections: where many motions cross a surface, or where they are every period.

For each start state one motion is integrated by DOP853 (rtol 1e-10, atol 1e-12 unless
told) from t = 0 to ``t_end``; its crossings of the section g = 0
(:mod:`lagrangian.integrate.section`) are the roots of g along the method's 7th-order
dense output, located by SciPy's event finder to the integration tolerance
(:func:`lagrangian.integrate.events.scipy_event`); where numba is installed, the same
steps and roots are taken in DOP853's compiled loop with g generated beside the
equations (:mod:`lagrangian.integrate.compiled_sections`).  A stroboscopic section instead
keeps the state at t = phase + k * period after the transient, from the same dense
output: the Poincaré map of a system driven with that period, the same map whatever
the transient (:mod:`lagrangian.integrate.strobe`).

Start states are given, or sampled on an energy shell (:func:`shell_starts`): for a
section ``q_c = c`` the other values of the start are the model's initial state, the
first axis is spread over the range the energy allows, and q_c' is solved from
h(q, q') = E (h is quadratic in q_c': its three coefficients are read from h at
q_c' = -1, 0, 1), the root of the crossing direction.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LagrangianWarning, ModelError, setting
from ..files import write_atomically, write_csv
from ..provided import Provided
from .base import Status, check_time_span, transient_setting
from .compiled_sections import crossings, section_loop
from .events import Event
from .memory import check_fits, count_text, run_bytes
from .scipy_methods import Dop853
from .section import Section, axis_values, state_names
from .start import constrained_start
from .strobe import Strobe

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: The most orbits of one section (each is a run of its own: more would take days).
MAX_ORBITS = 100_000
#: Steps (of 1e-3 of the first axis' scale) searched for each end of an energy shell,
#: and how many are tried at once.
SHELL_SPAN, SHELL_CHUNK = 100_000, 1000


@dataclass(frozen=True)
class PoincareSection:
    """The points of a section: ``values`` (V, K) of ``variables`` (the state, then any
    momentum axes) at K crossings (or strobe times) ``times``, of orbit ``orbits`` (K,)."""

    # drawn by output/, given by the facade (see lagrangian.provided)
    plot = Provided()

    variables: tuple[str, ...]
    values: np.ndarray
    times: np.ndarray
    orbits: np.ndarray
    axes: tuple[str, str]
    starts: np.ndarray  # (2n, N): the orbits' start states
    energies: np.ndarray  # (K,): h at each point (the energy function)
    settings: Mapping[str, object] = field(default_factory=dict)
    name: str = ""
    system: object = field(default=None, repr=False, compare=False)  # the model, if known

    def __getitem__(self, variable: str) -> np.ndarray:
        return self.values[self.variables.index(variable)]

    @property
    def count(self) -> int:
        return int(self.times.shape[0])

    @property
    def orbit_count(self) -> int:
        return int(self.starts.shape[1])

    def columns(self) -> tuple[str, ...]:
        """The columns of the files: orbit, t, the variables, energy."""
        return ("orbit", "t", *self.variables, "energy")

    def table(self) -> np.ndarray:
        """(K, columns) of the points, in the order of :meth:`columns`."""
        return np.column_stack([self.orbits, self.times, *self.values, self.energies])

    def unit(self, name: str) -> str | None:
        """The SI unit of the column ``name`` for a dimensioned model (``rad``, ``m/s``,
        ``J``), else None."""
        units = getattr(self.system, "units", None)
        return None if units is None else units.column_unit(name)

    def to_csv(self, path: str | os.PathLike) -> Path:
        """The points as CSV (orbit numbered from 0, full float precision), atomically; a
        column with a unit is headed ``name [unit]``, as simulate's CSV."""
        headers = [
            f"{name} [{unit}]" if (unit := self.unit(name)) else name for name in self.columns()
        ]
        return write_csv(path, self.table(), headers)

    def to_netcdf(self, path: str | os.PathLike) -> Path:
        """The points as netCDF-3 (dimension ``point``; the starts and settings in
        attributes), atomically."""
        import xarray

        data = {name: ("point", self.values[i]) for i, name in enumerate(self.variables)}
        data |= {"orbit": ("point", self.orbits), "energy": ("point", self.energies)}
        attrs = {
            "model": self.name,
            "axes": ",".join(self.axes),
            **{key: str(value) for key, value in self.settings.items()},
        }
        dataset = xarray.Dataset(data, coords={"t": ("point", self.times)}, attrs=attrs)
        for name in dataset.variables:  # CF conventions: a units attribute where known
            unit = self.unit(str(name))
            if unit is not None:
                dataset[name].attrs["units"] = unit
        return write_atomically(path, lambda target: dataset.to_netcdf(target, engine="scipy"))

    def save(self, path: str | os.PathLike) -> Path:
        """``to_csv`` or ``to_netcdf`` by the suffix of ``path`` (.csv, .nc)."""
        suffix = Path(path).suffix
        writers = {".csv": self.to_csv, ".nc": self.to_netcdf}
        if suffix not in writers:
            raise ModelError(f"the points are written to .csv or .nc, not {suffix or path!r}")
        return writers[suffix](path)


def poincare_section(
    compiled: CompiledSystem,
    starts: np.ndarray,
    *,
    axes: Sequence[str],
    t_end: float,
    section: Section | None = None,
    strobe: float | None = None,
    phase: float | None = None,
    transient: float = 0.0,
    params: Mapping[str, float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    watch: Callable[[float], None] | None = None,
) -> PoincareSection:
    """The section's points of the motions from ``starts`` (2n, N): the crossings of
    ``section``, or with ``strobe`` the states at t = ``phase`` + k ``strobe`` (phase
    default 0, taken modulo the period) after ``transient``.

    The crossings before ``transient`` are dropped as well.  ``watch`` is told the
    fraction of the work done (0 to 1) at every step.
    """
    if (section is None) == (strobe is None):
        raise ModelError("give a section or a strobe period (one of them)")
    if phase is not None and strobe is None:
        raise ModelError("a phase goes with a strobe period, not with a section")
    transient = transient_setting(transient)
    axes = tuple(axes)
    if len(axes) != 2:
        raise ModelError(f"give two axes, e.g. 'y,p_y', not {len(axes)}", field="axes")
    t0, t1 = check_time_span((0.0, t_end))
    if transient >= t1:
        raise ModelError(
            f"the transient ({transient:g}) leaves no time before t_end = {t1:g}: give a "
            f"shorter transient or a longer {setting('t_end')}"
        )
    p = compiled.parameter_vector(params)
    n = compiled.n
    axis_values(compiled, axes, np.empty(0), np.empty((2 * n, 0)), p)  # an unknown axis: now
    integrator = Dop853.configure(t_span=(t0, t1), rtol=rtol, atol=atol)
    events = ()
    t_eval = None
    starts = np.asarray(starts, dtype=float).reshape(2 * n, -1)
    if compiled.has_constraints and compiled.project is not None:
        starts = constrained_start(compiled, t0, starts, p)  # as a single run's start
    strobed = None if strobe is None else Strobe.of(strobe, phase)
    if strobed is not None:
        times = max(0.0, (t1 - transient) / strobed.period)
        check_fits(
            run_bytes(2 * n, 0, min(times, 1e300) * starts.shape[1]),
            f"{count_text(math.floor(min(times, 1e300)))} strobe times per orbit",
            f"give a longer strobe period or a shorter {setting('t_end')}",
        )
        t_eval = strobed.times(transient, t1)
        if t_eval.size == 0:
            raise ModelError(
                f"no strobe time ({strobed.describe()}) after the transient {transient:g} "
                f"and before t_end = {t1:g}"
            )
    else:
        events = (Event(section.function, section.direction, name="section"),)
    loop = None if section is None else section_loop(compiled, section)
    times, states, orbits = [], [], []
    count = starts.shape[1]
    for k in range(count):
        told = None if watch is None else (lambda t, k=k: watch((k + t / t1) / count))
        found = None
        if loop is not None:  # the same points as SciPy's path, to rounding
            found = crossings(
                loop, compiled, section, starts[:, k], p, t_end=t1, rtol=integrator.rtol,
                atol=integrator.atol, watch=told,
            )  # fmt: skip
        if found is None:  # SciPy's path, which also says why a motion failed
            result = integrator.solve(
                compiled, (t0, t1), starts[:, k], p, t_eval=t_eval, events=events, watch=told
            )
            if result.status is Status.FAILED:
                raise ModelError(f"the integration of orbit {k + 1} failed: {result.message}")
            record = result.events[0] if strobe is None else None
            found = (result.t, result.y) if record is None else (record.times, record.states)
        found_t, found_y = found
        kept = found_t >= transient
        found_t, found_y = found_t[kept], found_y[:, kept]
        times.append(found_t)
        states.append(found_y)
        orbits.append(np.full(found_t.shape, k))
    if section is not None:
        _warn_uncrossed(section, [found_t.size for found_t in times], transient, t1)
    t = np.concatenate(times)
    y = np.concatenate(states, axis=1) if states else np.empty((2 * n, 0))
    names = state_names(compiled)
    extra = [name for name in axes if name not in names]
    values = np.vstack([y, axis_values(compiled, extra, t, y, p)])
    energies = np.asarray(compiled.energy(t, y, p), dtype=float).reshape(-1)
    settings = {
        **integrator.settings(),
        "t_end": t1,
        "section": None if section is None else section.text,
        "direction": None if section is None else section.direction,
        "strobe": None if strobed is None else strobed.period,
        "phase": None if strobed is None else strobed.phase,
        "transient": transient,
    }
    return PoincareSection(
        variables=(*names, *extra),
        values=values,
        times=t,
        orbits=np.concatenate(orbits).astype(int),
        axes=(axes[0], axes[1]),
        starts=starts,
        energies=energies,
        settings=settings,
        name=compiled.equations.system.name if compiled.derived else "",
        system=compiled.equations.system if compiled.derived else None,
    )


def _warn_uncrossed(section: Section, counts: Sequence[int], transient: float, t1: float):
    """Say when orbits never cross the section: their points (none) are no result."""
    missing = sum(1 for count in counts if count == 0)
    if not missing:
        return
    span = f"between t = {transient:g} and {t1:g}" if transient else f"up to t = {t1:g}"
    which = (
        f"none of the {len(counts)} orbits crosses" if missing == len(counts) and missing > 1
        else "the orbit does not cross" if len(counts) == 1
        else f"{missing} of the {len(counts)} orbits do not cross"
    )  # fmt: skip
    warnings.warn(
        LagrangianWarning(
            f"{which} the section {section.text} (direction {section.direction_name}) {span}"
            + (": no points" if missing == len(counts) else ": they have no points")
        ),
        stacklevel=3,
    )


def shell_starts(
    compiled: CompiledSystem,
    section: Section,
    energy: float,
    count: int,
    axis: str,
    *,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
) -> np.ndarray:
    """``count`` start states (2n, count) on the section q_c = c at energy ``energy``: the
    initial state with q_c = c, ``axis`` spread evenly over the interval about its initial
    value where h = E has a solution for q_c', and q_c' solved."""
    if section.coordinate is None or section.value is None:
        raise ModelError(
            f"sampling an energy shell needs a section 'coordinate = number', not {section.text!r}"
        )
    names = state_names(compiled)
    c = names.index(section.coordinate)
    velocity = compiled.n + c
    if axis not in names or names.index(axis) in (c, velocity):
        raise ModelError(
            f"the energy shell is spread along the first axis: a coordinate or velocity "
            f"other than {section.coordinate} and its velocity, not {axis!r}",
            field="axes",
        )
    if not (np.isfinite(energy) and 1 <= int(count) <= MAX_ORBITS):
        raise ModelError(
            f"give a finite energy and from 1 to {MAX_ORBITS:,} orbits, not {energy}, {count}"
        )
    p = compiled.parameter_vector(params)
    base = compiled.state_vector(initial)
    base[c] = section.value
    index = names.index(axis)

    root = -1.0 if section.direction < 0 else 1.0

    def solved(values: np.ndarray, check: bool = False) -> np.ndarray:
        """q_c' on the shell with the axis at each of ``values``, NaN where none is real."""
        values = np.asarray(values, dtype=float)
        y = np.repeat(base[:, None, None], 4, axis=1) * np.ones(values.shape)
        y[index] = values
        y[velocity] = np.array([-1.0, 0.0, 1.0, 2.0])[:, None]
        h = np.asarray(compiled.energy(0.0, y.reshape(len(base), -1), p), dtype=float)
        h = h.reshape(4, -1)
        a = (h[0] + h[2]) / 2 - h[1]
        b = (h[2] - h[0]) / 2
        if check and not (
            a[0] > 0 and np.isclose(4 * a[0] + 2 * b[0] + h[1, 0], h[3, 0], rtol=1e-9, atol=1e-12)
        ):
            raise ModelError(
                f"the energy is not a convex quadratic in {names[velocity]}: "
                "it cannot be solved on the shell"
            )
        with np.errstate(invalid="ignore"):
            return (-b + root * np.sqrt(b * b - 4 * a * (h[1] - energy))) / (2 * a)

    start = float(base[index])
    if np.isnan(solved(np.array([start]), check=True)[0]):
        raise ModelError(
            f"the energy {energy:g} is below the energy of the section's start "
            f"({axis} = {start:g} at rest across the section)"
        )
    low, high = (_shell_end(solved, start, sign) for sign in (-1.0, 1.0))
    starts = np.repeat(base[:, None], int(count), axis=1)
    starts[index] = low + (np.arange(int(count)) + 0.5) * (high - low) / int(count)
    starts[velocity] = solved(starts[index])
    return starts


def _shell_end(solved: Callable[[np.ndarray], np.ndarray], start: float, sign: float) -> float:
    """The end of the shell's interval from ``start`` in direction ``sign``: the first
    value without a solution on a grid of steps of 1e-3 (of max(1, |start|)) out to
    :data:`SHELL_SPAN` of them, then bisection to 1e-12 relative."""
    scale = max(1.0, abs(start))
    step = 1e-3 * scale
    for first in range(0, SHELL_SPAN, SHELL_CHUNK):
        grid = start + sign * step * np.arange(first + 1, first + SHELL_CHUNK + 1)
        outside = np.flatnonzero(np.isnan(solved(grid)))
        if outside.size:
            break
    else:
        raise ModelError(
            "the energy shell reaches beyond "
            f"{SHELL_SPAN * 1e-3:g} x the first axis' scale: give the starts instead"
        )
    k = int(outside[0])
    inside, outside = (grid[k - 1] if k else start), grid[k]
    while abs(outside - inside) > 1e-12 * scale:
        middle = (inside + outside) / 2
        if np.isnan(solved(np.array([middle]))[0]):
            outside = middle
        else:
            inside = middle
    return float(inside)
