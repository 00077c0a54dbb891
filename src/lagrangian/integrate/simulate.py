"""`simulate`: one motion of a compiled system, from the initial state to a `Trajectory`.

The driver reads the method's declared capabilities before running: the
settings that apply (``dt`` for fixed-step methods, ``rtol``/``atol`` for
adaptive ones; one that does not apply is an error, a missing one takes the
method's documented default), and ``check(compiled)`` (a variational method
refuses constraints).  It then builds y0 and params
(``compiled.state_vector`` / ``parameter_vector``: a missing parameter value
is an error), moves y0 of a constrained system onto its constraints (:mod:`.start`), runs
the method, and evaluates the energy, the conserved quantities and the
multipliers at the output times.

Defaults (all echoed in the trajectory's attributes): method ``dop853``
(rtol 1e-10, atol 1e-12; its loop compiled on the numba backend, see
:mod:`.compiled_dop853`; :mod:`.choice` picks method and backend for runs of the CLI
and ``System.simulate``); ``radau`` rtol 1e-8, atol 1e-10; ``rk4`` and
``variational`` dt from the motion's time scale (:mod:`.step_size`: a fixed
fraction of its period, at most t_end / 1000; a given dt past the method's
stability limit is refused, a coarse one warned about).  Outputs: ``t_eval`` if given, else
``n_out`` equally spaced times from 0 to t_end, else every ``dt_out`` from 0 (and t_end),
else every step of the method; the last output is the state at ``t_end`` (or where a terminal event
or a failure stopped the run).
"""

from __future__ import annotations

import contextlib
import json
import math
import time
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError, choices, setting
from ..numeric.impacts import contact_functions
from ..trajectory import Trajectory
from .base import AbstractIntegrator, IntegrationResult, check_time_span
from .events import Event
from .fixed_step import AbstractFixedStepIntegrator
from .guard import parameter_problem
from .impacts import ImpactRun
from .linkage_outputs import reactions_along
from .memory import check_fits, count_text, run_bytes
from .registry import method_class
from .start import constrained_start
from .step_size import fixed_step_for

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

DEFAULT_METHOD = "dop853"


def simulate(
    compiled: CompiledSystem,
    *,
    t_end: float,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    method: str | AbstractIntegrator = DEFAULT_METHOD,
    dt: float | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    events: Sequence[Event] = (),
    n_out: int | None = None,
    t_eval: Sequence[float] | np.ndarray | None = None,
    dt_out: float | None = None,
    watch: Callable[[float], None] | None = None,
    choice: str | None = None,
) -> Trajectory:
    """Integrate ``compiled`` from t = 0 to ``t_end``; see the module docstring.

    ``initial`` maps names ``q`` / ``q_dot`` to values (missing: the model's
    ``[initial]`` table, else 0); ``params`` overrides parameter defaults;
    ``method`` is a registered name or a configured integrator instance (then
    ``dt``/``rtol``/``atol`` must be left out); ``watch`` is told the time reached
    at every step (see :meth:`AbstractIntegrator.solve`); ``choice``: why this method and
    backend run (:mod:`.choice`), kept in the trajectory's attributes.
    """
    t_span = check_time_span((0.0, t_end))
    if isinstance(method, AbstractIntegrator):
        if any(value is not None for value in (dt, rtol, atol)):
            raise ModelError("give dt/rtol/atol to the integrator instance, not to simulate")
        integrator = method
    else:
        integrator = method_class(method).configure(t_span=t_span, dt=dt, rtol=rtol, atol=atol)
    integrator.check(compiled)
    y0 = compiled.state_vector(initial)
    p = compiled.parameter_vector(params)
    if compiled.has_constraints and compiled.project is not None:
        y0 = constrained_start(compiled, t_span[0], y0, p)
    began = time.process_time()  # the first calls of L, M and y' make their code (or load it)
    problem = parameter_problem(compiled, t_span[0], y0, p)
    if problem is None:
        _make_y_prime(compiled, t_span[0], y0, p)
    compile_time = time.process_time() - began
    if problem is not None:
        raise ModelError(problem)
    if isinstance(integrator, AbstractFixedStepIntegrator) and not isinstance(
        method, AbstractIntegrator
    ):  # the step from the motion's time scale, or a given one checked against it
        integrator = fixed_step_for(type(integrator), compiled, t_span, dt, y0, p)
    requested = {"n_out": n_out, "t_eval": t_eval, "dt_out": dt_out}
    _check_memory(integrator, t_span, 2 * compiled.n, output_count(t_span, **requested))
    outputs = output_times(t_span, **requested)
    if watch is not None:  # the budget's clock starts before a compile, which counts
        watch(t_span[0])
    began = time.process_time()
    compiled_now = integrator.prepare(compiled, y0, p)
    compile_time += time.process_time() - began
    # Non-finite values are found and reported (integrate.guard): NumPy's warnings about
    # them would only repeat that, several lines long.
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        start = time.perf_counter()
        contacts = contact_functions(compiled)
        impacts = None
        if contacts is None:
            result = integrator.solve(
                compiled, t_span, y0, p, t_eval=outputs, events=events, watch=watch
            )
        else:  # segments between impacts (integrate.impacts)
            run = ImpactRun(integrator, compiled, contacts, p, t_span, events, watch)
            result = run.run(y0, outputs)
            impacts = (run.pieces.impacts, run.pieces.holds)
        wall_time = time.perf_counter() - start
        values = dict(zip(compiled.parameter_names, p.tolist(), strict=True))
        trajectory = trajectory_of(
            compiled, result, p, parameters=values, wall_time=wall_time, impacts=impacts
        )
    if choice is not None:
        trajectory.attrs["choice"] = choice
    trajectory.attrs["compile_time"] = compile_time
    if compiled_now is not None:
        trajectory.attrs["compiled"] = compiled_now
    return trajectory


def _make_y_prime(compiled: CompiledSystem, t: float, y: np.ndarray, p: np.ndarray) -> None:
    """Call y' once, so that the work of its first call (the llvm backend's JIT, NumPy's
    code made, LAPACK loaded: 0.1 s for the double pendulum) is the run's compile_time, not
    its run time, on every path (each method's solve calls y' first at the start).  What
    the call gives or raises is left to that start check, which reports it as before."""
    with np.errstate(all="ignore"), contextlib.suppress(Exception):
        compiled.rhs(t, y, p)


def _check_memory(integrator, t_span, state_size, outputs: int) -> None:
    """Refuse, before anything is allocated, a run whose steps and outputs cannot fit."""
    steps = integrator.kept_steps(t_span)
    settings = integrator.settings()
    if steps is not None:
        check_fits(
            run_bytes(state_size, steps, outputs),
            f"{settings['method']} with dt = {settings['dt']:g} to t_end = {t_span[1]:g} "
            f"({count_text(steps)} steps, every one kept)",
            "give " + choices(f"a larger {setting('dt')}", f"a shorter {setting('t_end')}"),
        )
    check_fits(
        run_bytes(state_size, 0, outputs),
        f"{count_text(outputs)} output times",
        f"ask for fewer output times ({setting('n_out')}, {setting('dt_out')}, t_eval)",
    )


def output_count(
    t_span: tuple[float, float], *, n_out: int | None = None, t_eval=None, dt_out=None
) -> int:
    """How many output times are asked for (0: the method's steps), found before any is
    made: a tiny ``dt_out`` is refused by the memory check, not by an allocation."""
    requested = {"n_out": n_out, "t_eval": t_eval, "dt_out": dt_out}
    given = [name for name, value in requested.items() if value is not None]
    if len(given) > 1:
        raise ModelError(f"give {' or '.join(map(setting, given))}, not both")
    if n_out is not None:
        if not float(n_out).is_integer() or n_out < 2:
            raise ModelError(f"{setting('n_out')} must be a whole number >= 2, not {n_out!r}")
        return int(n_out)
    if dt_out is not None:
        if not (math.isfinite(dt_out) and dt_out > 0):
            raise ModelError(f"{setting('dt_out')} must be a time step > 0, not {dt_out!r}")
        return math.floor((t_span[1] - t_span[0]) / dt_out) + 2  # at most: t_end added
    return 0 if t_eval is None else len(t_eval)


def output_times(
    t_span: tuple[float, float], *, n_out: int | None = None, t_eval=None, dt_out=None
) -> np.ndarray | None:
    """The requested output times (None: the method's steps); checked to lie in ``t_span``.

    ``dt_out`` gives 0, dt_out, 2 dt_out, ... and t_end itself (the last row is always the
    state at t_end), the last step shortened rather than a time within 1e-9 dt_out of it.
    """
    output_count(t_span, n_out=n_out, t_eval=t_eval, dt_out=dt_out)
    if n_out is not None:
        return np.linspace(t_span[0], t_span[1], int(n_out))
    if dt_out is not None:
        times = t_span[0] + dt_out * np.arange(output_count(t_span, dt_out=dt_out) - 1)
        times = times[times < t_span[1] - 1e-9 * dt_out]
        return np.append(times, t_span[1])
    if t_eval is None:
        return None
    times = np.asarray(t_eval, dtype=float)
    if times.ndim != 1 or times.size == 0 or np.any(np.diff(times) < 0):
        raise ModelError("t_eval must be a non-empty increasing sequence of times")
    if times[0] < t_span[0] or times[-1] > t_span[1] or not np.all(np.isfinite(times)):
        raise ModelError(f"t_eval must lie between {t_span[0]:g} and t_end = {t_span[1]:g}")
    return times


def trajectory_of(
    compiled: CompiledSystem,
    result: IntegrationResult,
    params: np.ndarray,
    *,
    parameters: Mapping[str, float] | None = None,
    wall_time: float = 0.0,
    impacts: tuple[list, list] | None = None,
) -> Trajectory:
    """A Trajectory of one result (y (2n, T)): energy, invariants and multipliers added;
    ``impacts``: (the impact records, the held contacts' spans) of a run with contacts."""
    t, y = result.t, result.y
    causes, conserved_here = _causes_at(compiled, params)
    invariants = {name: along(f, t, y, params) for name, f in compiled.invariants.items()}
    for name in conserved_here.keys() - {"energy"}:
        invariants[name] = along(compiled.conditional_invariants[name], t, y, params)
    multipliers = {}
    if compiled.has_constraints and compiled.multipliers is not None:
        values = along(compiled.multipliers, t, y, params).reshape(-1, t.shape[0])
        multipliers = dict(zip(compiled.constraint_names, values, strict=True))
    reactions = reactions_along(compiled, t, y, params, multipliers)
    system = getattr(compiled.equations, "system", None)
    attrs: dict[str, object] = {
        "model": getattr(system, "name", ""),
        **result.settings,
        "backend": compiled.backend,
        "status": result.status.value,
        "message": result.message,
        "steps": result.steps,
        "rhs_evaluations": result.rhs_evaluations,
        "jacobian_evaluations": result.jacobian_evaluations,
        "wall_time": wall_time,
        "parameters": dict(parameters or {}),
        **causes,
    }
    if impacts is not None:
        attrs["holds"] = json.dumps(impacts[1])
        lost = sum(r.energy_before - r.energy_after for r in impacts[0])
        scale = max((abs(r.energy_before) for r in impacts[0]), default=0.0)
        if "energy_not_conserved" not in attrs and lost > 1e-9 * max(scale, 1e-300):
            attrs["energy_not_conserved"] = "the impacts take energy (restitution below 1)"
    return Trajectory.build(
        t=t,
        coordinates=compiled.coordinate_names,
        y=y,
        energy=along(compiled.energy, t, y, params),
        invariants=invariants,
        multipliers=multipliers,
        reactions=reactions,
        events=result.events,
        attrs=attrs,
        system=compiled.equations.system,
        impacts=None if impacts is None else impacts[0],
    )


def _causes_at(
    compiled: CompiledSystem, params: np.ndarray
) -> tuple[dict[str, str], dict[str, str]]:
    """Why the energy changes along the run (its attribute), and the quantities conserved in
    this run though not in general (name -> the general causes).

    Where the energy is not conserved (forces, inputs, dissipation, L depending on t) its
    change is physics, not the method's drift.  Causes that vanish at the run's parameter
    values (an input F = 0, an amplitude 0) do not act in it: the energy, or a momentum whose
    only force is such an input, is conserved in the run, and its drift is reported."""
    general = dict(compiled.not_conserved)
    if not general:
        return {}, {}
    here = general
    if compiled.not_conserved_at is not None and np.ndim(params) == 1:
        values = dict(zip(compiled.parameter_names, map(float, params), strict=True))
        here = dict(compiled.not_conserved_at(values))
    conditional = {"energy", *compiled.conditional_invariants}
    conserved_here = {
        name: general[name]
        for name in sorted(general, key=lambda name: name != "energy")  # the energy first
        if name not in here and name in conditional
    }
    attrs = {}
    if "energy" in here:
        attrs["energy_not_conserved"] = here["energy"]
    if conserved_here:
        attrs["conserved_here"] = json.dumps(conserved_here)
    return attrs, conserved_here


def along(function: Callable, t: np.ndarray, y: np.ndarray, params: np.ndarray) -> np.ndarray:
    """``function(t, y, params)`` at every output time: the times are the batch axis.

    The compiled functions are vectorised over a trailing batch axis; the
    output times are passed as that batch (t an array of shape (T,)).  A
    function that cannot take t as an array (or gives another shape) is
    evaluated time by time instead.
    """
    count = t.shape[0]
    if count == 0:
        return np.empty(0)
    try:
        values = np.asarray(function(t, y, params), dtype=float)
        if values.shape and values.shape[-1] == count:
            return values
    except (TypeError, ValueError, IndexError):
        pass
    columns = [np.asarray(function(float(tk), y[:, k], params), float) for k, tk in enumerate(t)]
    return np.stack(columns, axis=-1)
