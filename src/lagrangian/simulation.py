"""`System` -> `Trajectory` in one call: the model's [simulate] defaults, compile, integrate.

The CLI's ``simulate`` and :meth:`System.simulate` both come through here, so
both honour the model file's defaults the same way: an explicit argument wins,
then the model's ``[simulate]`` table, then the integrator's documented default.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .budget import RUN_SECONDS
from .derive import EquationsOfMotion, derive
from .errors import ModelError, setting
from .integrate import method_class, simulate
from .integrate.base import transient_setting
from .integrate.choice import choose_run
from .integrate.continuation import DEFAULT_DOUBLINGS, Continuation, continue_orbits
from .integrate.lyapunov import DEFAULT_INTERVAL, LyapunovSpectrum, lyapunov_spectrum
from .integrate.orbits import MAX_STARTS, OrbitSearch, periodic_orbits
from .integrate.pace import RunPace, watching
from .integrate.poincare import MAX_ORBITS, PoincareSection, poincare_section, shell_starts
from .integrate.section import parse_section
from .integrate.sensitivity import DEFAULT_POINTS, Sensitivities, sensitivities
from .model import System
from .model.impacts import refuse_impacts
from .model.values import check_parameter_values
from .numeric import compile_equations, default_backend
from .trajectory import Trajectory

#: Used when neither the caller nor the model gives an end time.
DEFAULT_T_END = 10.0


def split_assignments(
    system: System,
    assignments: Mapping[str, float] | None,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
) -> tuple[dict[str, float], dict[str, float]]:
    """(initial, params) with the NAME=VALUE ``assignments`` put where their names belong,
    the parameter values checked (before the derivation: a bad value fails at once)."""
    initial = dict(initial or {})
    params = dict(params or {})
    state_names = set(system.coordinate_names) | {f"{c}_dot" for c in system.coordinate_names}
    for name, value in (assignments or {}).items():
        if name in system.parameter_names:
            params[name] = value
        elif name in state_names:
            initial[name] = value
        else:
            raise ModelError(
                f"'{name}' is neither a parameter nor a coordinate or velocity",
                field=setting("params"),
            )
    check_parameter_values(system, params)
    return initial, params


def simulate_system(
    system: System,
    *,
    t_end: float | None = None,
    method: str | None = None,
    dt: float | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    assignments: Mapping[str, float] | None = None,
    progress: Callable[[float], None] | None = None,
    definitions: Mapping[str, str] | None = None,
    backend: str | None = None,
    timeout: float | None = RUN_SECONDS,
    equations: Callable[[], EquationsOfMotion] | None = None,
    **options: object,
) -> Trajectory:
    """Simulate ``system``; ``assignments`` are NAME=VALUE pairs that may name a parameter
    or an initial coordinate / velocity (the CLI's ``--set``); ``progress`` is called with
    the fraction of the time span done (often: throttle it); ``definitions`` give the
    unspecified functions as expressions of their arguments ({"V": "x^2 + y^2"});
    ``method`` and ``backend`` (the compiled code's,
    :func:`~lagrangian.numeric.compile_equations`) left out are chosen for the run by
    :func:`~lagrangian.integrate.choice.choose_run`: dop853 in SciPy's loop on ``llvm``
    for short runs, its compiled loop (numba) or heyoka's taylor for long ones;
    ``timeout``: seconds the integration may take (None: no limit), a run that would
    take longer ends with :class:`~lagrangian.integrate.pace.RunTooLong` as soon as
    its pace shows it (:mod:`lagrangian.integrate.pace`); ``equations`` gives the system's
    equations of motion (``System.simulate``: the ones it keeps, derived once), asked for
    where ``derive(system)`` runs without it: after the values are checked."""
    settings = dict(system.simulate_settings)
    initial, params = split_assignments(system, assignments, initial, params)
    method = method or settings.get("method")
    # The model's defaults apply where they fit the method; the caller's settings always
    # go through, so a misfit (--dt for an adaptive method) is reported, not ignored.  A
    # method left to choose is adaptive (dop853 or taylor, integrate.choice).
    adaptive = method is None or method_class(method).adaptive
    if adaptive:
        rtol = rtol if rtol is not None else settings.get("rtol")
        atol = atol if atol is not None else settings.get("atol")
    else:
        dt = dt if dt is not None else settings.get("dt")
    t_final = _model_t_end(system, t_end)
    derived = equations() if equations is not None else derive(system)
    run = choose_run(
        derived, t_end=t_final, method=method, backend=backend, rtol=rtol, atol=atol,
        initial=initial, params=params, events=options.get("events", ()), definitions=definitions,
        every_step=options.get("t_eval") is None and options.get("n_out") is None,
    )  # fmt: skip
    chosen = {"t_end": t_final, "method": run.method, "dt": dt, "rtol": run.rtol, "atol": run.atol}
    if run.linked:  # dop853's compiled loop on the llvm backend: an integrator so configured
        chosen = {"t_end": t_final, "method": run.integrator(t_final, dt)}
    chosen = {key: value for key, value in chosen.items() if value is not None}
    return simulate(
        run.compiled, initial=initial, params=params, watch=_watch(t_final, progress, timeout),
        choice=run.reason, **chosen, **options,
    )  # fmt: skip


def _watch(t_final: float, progress, timeout, describe=None):
    """The watch of a run from 0 to ``t_final``: its pace and progress."""
    pace = None if timeout is None else RunPace((0.0, t_final), timeout, describe=describe)
    share = None if progress is None else (lambda t: progress(min(1.0, t / t_final)))
    return watching(pace, share)


def _model_t_end(system: System, t_end: float | None) -> float:
    """``t_end``, or the model's [simulate] t_end, or :data:`DEFAULT_T_END`."""
    return float(
        t_end if t_end is not None else system.simulate_settings.get("t_end", DEFAULT_T_END)
    )


@dataclass(frozen=True)
class RunSettings:
    """The settings that :func:`lyapunov_of_system` and :func:`poincare_of_system` take
    besides their own (as keywords), with the meaning they have for
    :func:`simulate_system`: tolerances (None: the run's documented default), the
    ``initial`` state and ``params``, NAME=VALUE ``assignments`` of either, a
    ``progress`` callback, ``definitions`` of unspecified functions, the compiled code's
    ``backend`` and the ``timeout`` in seconds (None: no limit)."""

    rtol: float | None = None
    atol: float | None = None
    initial: Mapping[str, float] | None = None
    params: Mapping[str, float] | None = None
    assignments: Mapping[str, float] | None = None
    progress: Callable[[float], None] | None = None
    definitions: Mapping[str, str] | None = None
    backend: str | None = None
    timeout: float | None = RUN_SECONDS

    def values(self, system: System) -> tuple[dict[str, float], dict[str, float]]:
        """(initial, params) with the assignments put in, checked (:func:`split_assignments`);
        a model with contacts is refused (these runs do not stop at impacts)."""
        refuse_impacts(system, "this command (Lyapunov, sensitivities, sections, orbits, fit)")
        return split_assignments(system, self.assignments, self.initial, self.params)

    def compiled(self, system: System, t_final: float, describe=None):
        """(the compiled equations, the watch of a run from 0 to ``t_final``: its pace and
        progress; ``describe`` says how far a run got, see :class:`RunPace`)."""
        compiled = compile_equations(
            derive(system), backend=self.backend or default_backend(), definitions=self.definitions
        )
        return compiled, _watch(t_final, self.progress, self.timeout, describe)


def lyapunov_of_system(
    system: System,
    *,
    t_end: float | None = None,
    count: int | None = None,
    transient: float = 0.0,
    interval: float | None = None,
    **settings: Any,
) -> LyapunovSpectrum:
    """The ``count`` largest Lyapunov exponents of ``system`` (all 2n by default) along the
    motion from its initial state, averaged over ``t_end`` (default: the model's t_end)
    after ``transient``; see :mod:`lagrangian.integrate.lyapunov`.  ``settings``: the
    keywords of :class:`RunSettings` (rtol, atol, initial, params, assignments, progress,
    definitions, backend, timeout)."""
    run = RunSettings(**settings)
    transient = transient_setting(transient)  # before the compilation
    initial, params = run.values(system)
    t_end = _model_t_end(system, t_end)
    total = transient + t_end  # the transient is integrated too: it counts in the budget

    def reached(t: float) -> str:
        return f"t = {t:.6g} of {total:g}, a transient of {transient:g} and then t_end = {t_end:g}"

    compiled, watch = run.compiled(system, total, describe=reached if transient else None)
    interval = DEFAULT_INTERVAL if interval is None else interval
    return lyapunov_spectrum(
        compiled, t_end=t_end, count=count, initial=initial, params=params,
        transient=transient, interval=interval, rtol=run.rtol, atol=run.atol, watch=watch,
    )  # fmt: skip


def sensitivities_of_system(
    system: System,
    *,
    wrt: Sequence[str],
    t_end: float | None = None,
    points: int = DEFAULT_POINTS,
    **settings: Any,
) -> Sensitivities:
    """d(q, q')(t)/dw along the motion of ``system`` from its initial state, for each name
    w in ``wrt`` (a parameter, or a coordinate or velocity for its initial value), at
    ``points`` times from 0 to ``t_end`` (default: the model's t_end); see
    :mod:`lagrangian.integrate.sensitivity`.  ``settings``: the keywords of
    :class:`RunSettings`; with ``backend="numba"`` the equations run in the compiled
    DOP853 loop (:mod:`lagrangian.integrate.compiled_sensitivity`)."""
    run = RunSettings(**settings)
    initial, params = run.values(system)
    t_end = _model_t_end(system, t_end)
    compiled, watch = run.compiled(system, t_end)
    return sensitivities(
        compiled, wrt=wrt, t_end=t_end, initial=initial, params=params, points=points,
        rtol=run.rtol, atol=run.atol, watch=watch,
    )  # fmt: skip


#: Orbits of a section sampled on an energy shell, unless told.
DEFAULT_ORBITS = 10


def poincare_of_system(
    system: System,
    *,
    axes: tuple[str, str],
    section: str | None = None,
    direction: str = "+",
    strobe: float | None = None,
    phase: float | None = None,
    transient: float = 0.0,
    energy: float | None = None,
    orbits: int | None = None,
    spread: Mapping[str, tuple[float, float]] | None = None,
    t_end: float | None = None,
    **settings: Any,
) -> PoincareSection:
    """The Poincaré section of ``system`` (see :mod:`lagrangian.integrate.poincare`):
    crossings of ``section`` ("x = 0") in ``direction``, or with ``strobe`` the state at
    t = ``phase`` + k ``strobe`` (default phase 0) after ``transient``, drawn on ``axes``
    (coordinates, velocities or momenta p_q).  The orbits start on the energy shell
    ``energy`` (``orbits`` of them, default 10, see
    :func:`~lagrangian.integrate.poincare.shell_starts`), or from the initial state with
    one value ``spread`` {name: (low, high)} over ``orbits`` starts, or, with neither,
    from the initial state alone.  Each runs to ``t_end`` (default: the
    model's t_end).  ``settings``: the keywords of :class:`RunSettings`."""
    run = RunSettings(**settings)
    transient = transient_setting(transient)  # before the compilation
    initial, params = run.values(system)
    if energy is not None and spread:
        raise ModelError("give an energy or a spread of start values, not both")
    t_end = _model_t_end(system, t_end)
    compiled, watch = run.compiled(
        system, 1.0, describe=lambda done: f"{100 * done:.3g} % of the orbits"
    )
    parsed = None if section is None else parse_section(compiled, section, direction)
    count = DEFAULT_ORBITS if orbits is None else int(orbits)
    if not 1 <= count <= MAX_ORBITS:
        raise ModelError(f"give from 1 to {MAX_ORBITS:,} orbits, not {orbits}")
    if energy is not None:
        if parsed is None:
            raise ModelError("sampling an energy shell needs a section 'coordinate = number'")
        starts = shell_starts(
            compiled, parsed, float(energy), count, axes[0], initial=initial, params=params
        )
    else:
        starts = _spread_starts(compiled, initial, spread or {}, count)
    return poincare_section(
        compiled, starts, axes=axes, t_end=t_end, section=parsed, strobe=strobe,
        phase=phase, transient=transient, params=params, rtol=run.rtol, atol=run.atol, watch=watch,
    )  # fmt: skip


def _spread_starts(compiled, initial, spread: Mapping[str, tuple[float, float]], count: int):
    """The initial state, with each ``spread`` value going from low to high over ``count``
    starts (2n, count); the initial state alone (2n, 1) without a spread."""
    base = compiled.state_vector(initial)
    if not spread:
        return base[:, None]
    starts = np.repeat(base[:, None], count, axis=1)
    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    for name, (low, high) in spread.items():
        if name not in names:
            raise ModelError(f"'{name}' is not a coordinate or velocity", field="spread")
        values = np.linspace(float(low), float(high), count)
        if not np.all(np.isfinite(values)):  # HI - LO overflows: +-1e308 gives nan starts
            raise ModelError(
                f"'{name}' from {float(low):g} to {float(high):g}: the spread is not a range "
                "of finite numbers (its width overflows)",
                field="spread",
            )
        starts[names.index(name)] = values
    return starts


def orbits_of_system(
    system: System,
    *,
    period: int,
    strobe: float | None = None,
    phase: float | None = None,
    section: str | None = None,
    direction: str = "+",
    energy: float | None = None,
    t_end: float | None = None,
    grid: Mapping[str, object] | None = None,
    attractor: int = 20,
    transient: float | None = None,
    **settings: Any,
) -> OrbitSearch:
    """The periodic orbits of ``system``'s strobe map (t = ``phase`` + k ``strobe``) of
    period dividing ``period``, by Newton's method from ``attractor`` strobe points of
    the motion from the initial state after ``transient`` (default 50 periods) and from
    the starts of ``grid`` ({name: values} of coordinates or velocities, a value array or
    a grid axis each, all combinations; the rest from the initial state); see
    :mod:`lagrangian.integrate.orbits`.  Or, for an autonomous system, through the
    ``section`` ("q = c", ``direction``) on the shell h = ``energy``, from ``attractor``
    starts spread over the shell, returning within ``period`` crossings found up to
    ``t_end`` (default: the model's): :mod:`lagrangian.integrate.shell_orbits`.
    ``settings``: the keywords of :class:`RunSettings`."""
    if (strobe is None) == (section is None):
        raise ModelError("give a strobe period or a section (one of them)")
    run = RunSettings(**settings)
    if transient is not None:
        transient = transient_setting(transient)  # before the compilation
    initial, params = run.values(system)
    compiled, watch = run.compiled(
        system, 1.0, describe=lambda done: f"{100 * done:.3g} % of the starts"
    )
    if section is not None:
        return _shell_orbits(
            compiled, section, direction, energy, period, attractor, _model_t_end(system, t_end),
            initial, params, run, watch,
        )  # fmt: skip
    return periodic_orbits(
        compiled, strobe=strobe, period=period, phase=phase,
        starts=_grid_starts(compiled, initial, grid or {}), attractor=attractor,
        transient=transient, initial=initial, params=params, rtol=run.rtol, atol=run.atol,
        watch=watch,
    )  # fmt: skip


def continuation_of_system(
    system: System,
    *,
    vary: Mapping[str, tuple[float, float, int]],
    strobe: float,
    period: int = 1,
    phase: float | None = None,
    max_doublings: int = DEFAULT_DOUBLINGS,
    grid: Mapping[str, object] | None = None,
    attractor: int = 20,
    transient: float | None = None,
    **settings: Any,
) -> Continuation:
    """The branches of ``system``'s periodic orbits (period dividing ``period``, found at
    the low end as :func:`orbits_of_system` finds them) followed over ``vary`` ({parameter:
    (low, high, count)}) by pseudo-arclength continuation, the period doublings followed
    to ``max_doublings``; see :mod:`lagrangian.integrate.continuation`."""
    if len(vary) != 1:
        raise ModelError("vary one parameter: {name: (low, high, count)}", field=setting("vary"))
    ((parameter, (low, high, count)),) = vary.items()
    run = RunSettings(**settings)
    if transient is not None:
        transient = transient_setting(transient)  # before the compilation
    initial, params = run.values(system)
    compiled, _ = run.compiled(system, 1.0)
    pace = None if run.timeout is None else RunPace(
        (0.0, 1.0), run.timeout, describe=lambda done: f"{100 * done:.3g} % of the branches",
        advice=f"give a shorter range or fewer values in {setting('vary')}, or allow more "
        f"time with {setting('timeout')}",
    )  # fmt: skip
    watch = watching(pace, run.progress)
    return continue_orbits(
        compiled, parameter=parameter, low=low, high=high, count=count, strobe=strobe,
        period=period, phase=phase, max_doublings=max_doublings,
        starts=_grid_starts(compiled, initial, grid or {}), attractor=attractor,
        transient=transient, initial=initial, params=params, rtol=run.rtol, atol=run.atol,
        watch=watch,
    )  # fmt: skip


def _shell_orbits(
    compiled, text, direction, energy, period, count, t_end, initial, params, run, watch
) -> OrbitSearch:
    """The orbits through the section ``text`` on the energy shell (see orbits_of_system)."""
    from .integrate.shell_orbits import check_autonomous, shell_orbits

    if energy is None:
        raise ModelError("periodic orbits through a section need the energy of their shell")
    check_autonomous(
        compiled, compiled.state_vector(initial)[:, None], compiled.parameter_vector(params)
    )
    if compiled.n < 2:
        raise ModelError(
            "periodic orbits through a section need two or more coordinates (with one, every "
            "motion on an energy shell is periodic)"
        )
    section = parse_section(compiled, text, direction)
    if section.coordinate is None:
        raise ModelError(f"the section must be 'coordinate = number', not {text!r}")
    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    axis = next(n for n in names if n not in (section.coordinate, f"{section.coordinate}_dot"))
    starts = shell_starts(
        compiled, section, float(energy), int(count), axis, initial=initial, params=params
    )
    return shell_orbits(
        compiled, section=section, energy=float(energy), period=period, starts=starts,
        t_end=t_end, params=params, rtol=run.rtol, atol=run.atol, watch=watch,
    )  # fmt: skip


def _grid_starts(compiled, initial, grid: Mapping[str, object]) -> np.ndarray:
    """The start states (2n, N) of every combination of the ``grid``'s values, the other
    values from the initial state; (2n, 0) without a grid."""
    if not grid:
        return np.empty((2 * compiled.n, 0))
    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    for name in grid:
        if name not in names:
            raise ModelError(f"'{name}' is not a coordinate or velocity", field="grid")
    axes = [np.asarray(values, dtype=float) for values in grid.values()]
    if len(axes) > 1 and all(axis.ndim <= 1 for axis in axes):  # plain lists: all pairs
        axes = list(np.meshgrid(*axes, indexing="ij"))
    values = np.broadcast_arrays(*axes)
    count = values[0].size
    if not 1 <= count <= MAX_STARTS:
        raise ModelError(f"give from 1 to {MAX_STARTS:,} starts, not {count:,}", field="grid")
    starts = np.repeat(compiled.state_vector(initial)[:, None], count, axis=1)
    for name, column in zip(grid, values, strict=True):
        starts[names.index(name)] = column.ravel()
    if not np.all(np.isfinite(starts)):
        raise ModelError("the grid's starts are not all finite numbers", field="grid")
    return starts
