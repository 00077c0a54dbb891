"""The method and backend of a single run, when the user names neither: the fastest at the
requested accuracy for the run's length.

Three ways to run the default accuracy (DOP853's rtol 1e-10, atol 1e-12, or the
tolerances given) differ in what they cost before the first step and per step
(measured, benchmarks/user_paths.py; figures in benchmarks/README.md):

- ``dop853`` in SciPy's loop on the ``llvm`` backend: code in milliseconds, then
  about 100 us of Python per step around 12 evaluations of the right-hand side;
- ``dop853`` with its loop compiled (:mod:`.compiled_dop853`, backend ``numba``):
  seconds of numba compilation the first time a system runs (its machine code is
  then cached on disk and loads in a fraction of a second), then about 1 us per
  step for small systems: 100-400x SciPy's loop;
- the same compiled loop over the ``llvm`` backend's code of M and f
  (:func:`.compiled_dop853.linked_loop`): nothing compiled for the system but
  SymEngine's code (milliseconds), the loop loaded from the code cache (it is compiled
  once on a machine), then 1.2-1.4x the steps' time of the loop above: a new system's
  long run starts at once, and the system's own loop is compiled only for a run long
  enough to pay for it (millions of steps);
- ``taylor`` (heyoka, where installed and applicable: no constraints, a definite mass
  matrix; events are located on its continuous output as the compiled loop locates
  them on its interpolant), at tol = min(rtol, atol): its import and build take a
  fraction of a second for small systems, more for large ones, and it then runs
  2x faster than the compiled DOP853 for two coordinates with errors 30-200x
  smaller, but 3-5x slower for a 10-link chain (heyoka's compact mode).

So the run's length decides, and to know it the first :data:`PROBE_STEPS` steps of
SciPy's DOP853 are taken (a few milliseconds): the step size they reach, over the
time span, estimates the steps of the whole run; each way's cost is its start-up
plus that many steps at its pace (the constants below, per coordinate count n).  A run
SciPy's loop ends within :data:`SWITCH_MARGIN` times the compiled loop's start from the
code cache stays in SciPy's loop without looking further.
The estimate is deterministic for a given system, state and tolerance, except that a
loop found in the code cache costs less to start.  The cheapest runs; the reason is
one line, echoed in the run's summary (``choice``).  Where a way does not apply
(constraints: the SciPy loop integrates the stabilised equations; numba or heyoka
not installed; constraints for heyoka), that line says so.  A constrained system
runs in SciPy's loop on the stabilised equations, or in the compiled loop, which projects
every step onto its constraints as well (:mod:`.compiled_dop853`).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LagrangianWarning, ModelError
from .compiled_dop853 import (
    compiled_loop,
    compiled_ready,
    linked_applies,
    method_ready,
    numba_installed,
)
from .guard import start_problem
from .scipy_methods import MIN_RTOL, Dop853
from .start import constrained_start

if TYPE_CHECKING:
    from ..derive import EquationsOfMotion
    from ..numeric.compiled import CompiledSystem
    from .base import AbstractIntegrator
    from .events import Event

#: SciPy steps taken to estimate the step size of the run.
PROBE_STEPS = 40


def scipy_step_seconds(n: int) -> float:
    """Seconds per step of SciPy's DOP853 on the llvm backend: about 0.75 ms of Python and
    NumPy calls around 12 evaluations (0.8 s for the double pendulum's 819 steps to t = 20,
    0.6 s for a 10-link chain's 828 to t = 10)."""
    return 7.5e-4 + 12 * 2.5e-7 * n * n


def compiled_step_seconds(n: int) -> float:
    """Seconds per step of the compiled DOP853 loop (12 evaluations of generated code)."""
    return 12 * (1e-7 + 2e-8 * n * n)


def numba_start_seconds(n: int, cached: bool, method_cached: bool = True) -> float:
    """Seconds before the compiled loop's first step: load the machine code from the code
    cache, or generate and compile the system's y' (2.2 s for the double pendulum, 5.2 s
    for a 10-link chain, numba's start included), and the first time on a machine the
    method shared by every system too (5 s more)."""
    if cached:
        return 0.8
    return (2.0 if method_cached else 7.0) + 0.035 * n * n


def linked_step_seconds(n: int) -> float:
    """Seconds per step of the compiled loop over the llvm backend's M and f: the values
    and entries copied, the solve for any n (2.1 against 1.5 us for the double pendulum,
    17 against 14 us for a 10-link chain, benchmarks/first_run.py)."""
    return 1.3 * compiled_step_seconds(n)


def linked_start_seconds(n: int, method_cached: bool = True) -> float:
    """Seconds before that loop's first step: the method loaded from the code cache (as
    the system's own loop loads, 0.25-0.3 s quiet) and SymEngine's code (milliseconds,
    0.05 s for a 10-link chain); the first time on a machine the method compiled too."""
    return (0.8 if method_cached else 6.0) + 0.0005 * n * n


def taylor_start_seconds(n: int) -> float:
    """CPU seconds to import heyoka and build its integrator in a new process: 0.29-0.33 s
    for the double pendulum, 0.73-0.85 s for a 10-link chain (benchmarks/taylor_path.py's
    notes, issue 36; 0.6 + 0.015 n^2 before, from wall clocks under load)."""
    return 0.25 + 0.006 * n * n


#: heyoka's integration time relative to the compiled DOP853 at the same tolerance, CPU:
#: its code for two coordinates (0.44 for the double pendulum at 1e-10, 0.36-0.45 at 1e-15),
#: and in the compact mode it is built in for more (5.2: a 10-link chain at 1e-10, 3 at
#: 1e-15; benchmarks/taylor_path.py, adaptive.py).
TAYLOR_PACE, TAYLOR_COMPACT_PACE = 0.45, 5.0
#: CPU seconds per taylor step where every step is an output (no t_eval / n_out): taken
#: from heyoka's continuous output a chunk at a time (0.3 us; 20 us with a Python call a
#: step before issue 36), for about as many steps as DOP853's at 1e-10 (18,563 against
#: 18,961 for the double pendulum).
TAYLOR_STEP_OUTPUT = 3e-7


#: Our Taylor method's integration time (backend numba, :mod:`.taylor_compiled`) relative
#: to the compiled DOP853 at the same tolerance, CPU: 0.3 for the double pendulum at 1e-10
#: (0.0132 s against DOP853's 19,446 steps at 2.16 us; its printed coefficients, 0.4 before
#: their flat table of round 8), 3.5 for a 3-link chain and 12 for a 10-link chain (8.2 s
#: against 0.68 s) in the compact mode that larger systems take
#: (benchmarks/taylor_numba.py): only two coordinates pay.  Every step kept costs little
#: more (the loop writes each step's end: 0.014 s).
TAYLOR_NUMBA_PACE = 0.3


def taylor_numba_compact_pace(n: int) -> float:
    """The compact mode's pace relative to the compiled DOP853 for n > 2 coordinates: 1.2 n
    (3.6 for 3, 12 for 10: the measured 3.5 and 12 above)."""
    return 1.2 * n


def taylor_numba_start_seconds(n: int, cached: bool) -> float:
    """CPU seconds before our Taylor method's first step: the tape and its module made
    (milliseconds), then numba's compile of the printed coefficients and the loop (3.3 s
    for the double pendulum under load; the compact mode's walk of larger systems 3.4 s
    once per machine), or the machine code loaded from the code cache (0.6-0.75 s;
    benchmarks/taylor_numba.py, ``prepare`` in a fresh process)."""
    if cached:
        return 0.7
    return 3.3 if n <= 2 else 4.0


def taylor_numba_seconds(n: int, steps: float, cached: bool) -> float:
    """Our Taylor method's estimate for a run DOP853 takes ``steps`` for: start and pace."""
    relative = TAYLOR_NUMBA_PACE if n <= 2 else taylor_numba_compact_pace(n)
    return taylor_numba_start_seconds(n, cached) + relative * steps * compiled_step_seconds(n)


#: A way that must compile first is chosen over SciPy's loop only when its estimate is this
#: many times smaller: near a tie the estimates cannot tell, and SciPy's loop starts at once.
SWITCH_MARGIN = 1.5


@dataclass(frozen=True)
class RunChoice:
    """The compiled system to run, the method and tolerances to run it with, and why."""

    compiled: CompiledSystem
    method: str
    rtol: float | None
    atol: float | None
    reason: str
    linked: bool = False  # dop853's compiled loop over the llvm backend's M and f

    def integrator(self, t_end: float, dt: float | None = None) -> AbstractIntegrator:
        """The integrator the run takes: the method configured with the tolerances (and
        ``dt``) from 0 to ``t_end``, dop853 with its compiled loop over the llvm backend's
        code where :attr:`linked`."""
        from .registry import method_class

        integrator = method_class(self.method).configure(
            t_span=(0.0, t_end), dt=dt, rtol=self.rtol, atol=self.atol
        )
        return dataclasses.replace(integrator, linked=True) if self.linked else integrator


def choose_run(
    eom: EquationsOfMotion,
    *,
    t_end: float,
    method: str | None,
    backend: str | None,
    rtol: float | None,
    atol: float | None,
    initial: Mapping[str, float],
    params: Mapping[str, float],
    events: Sequence[Event] = (),
    definitions: Mapping[str, str] | None = None,
    every_step: bool = True,
) -> RunChoice:
    """The run's method and backend (see the module docstring); those given are kept.
    ``every_step``: the outputs are the method's steps (no ``t_eval`` / ``n_out``)."""
    from ..numeric import compile_equations, default_backend

    def compiled_on(name: str) -> CompiledSystem:
        return compile_equations(eom, backend=name, definitions=definitions)

    too_tight = rtol is not None and rtol < MIN_RTOL  # dop853 refuses it, saying why
    if method not in (None, "dop853") or backend is not None or too_tight:
        chosen = method or "dop853"
        compiled = compiled_on(backend or default_backend())
        how = " with its loop compiled" if _compiled_loop_applies(chosen, compiled) else ""
        if chosen == "taylor":  # Taylor's default backend: heyoka where installed
            how = " (heyoka)" if heyoka_installed() else " (numba)"
        asked = " and ".join(
            name for name, value in (("method", method), ("backend", backend)) if value
        )
        why = f"the {asked} asked for" if asked else "the default"
        return RunChoice(
            compiled, chosen, rtol, atol, f"{chosen}{how} on {compiled.backend}: {why}"
        )
    quick = compiled_on(default_backend())
    rtol = Dop853.rtol if rtol is None else rtol
    atol = Dop853.atol if atol is None else atol

    def scipy_loop(why: str) -> RunChoice:
        return RunChoice(
            quick, "dop853", rtol, atol, f"dop853 in SciPy's loop on {quick.backend}: {why}"
        )

    if quick.program is None:
        return scipy_loop("functions given by hand, no code to generate")
    y0, p = quick.state_vector(initial), quick.parameter_vector(params)
    if quick.has_constraints:  # the probe starts where the run will: on the constraints
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LagrangianWarning)  # the run itself says so
            y0 = constrained_start(quick, 0.0, y0, p)
    steps = estimated_steps(quick, (0.0, float(t_end)), y0, p, rtol, atol)
    n = quick.n
    costs = {"scipy": steps * scipy_step_seconds(n)}
    notes, fast = [], None
    # A run SciPy's loop ends in about the compiled loop's start stays there, heyoka or
    # not (it is under a second either way): a short run's numbers are the same on every
    # machine, and the optional package is not imported for it.
    quickest = numba_start_seconds(n, cached=True)
    if costs["scipy"] <= SWITCH_MARGIN * quickest:  # nothing that compiles can win: go now
        scipy = f"about {_count(steps)} steps: scipy ~{costs['scipy']:.2g} s"
        return scipy_loop(f"{scipy}, too short for a compiled way (start ~{quickest:.2g} s)")
    if numba_installed():
        fast = compiled_on("numba")
        ready, method_cached = compiled_ready(fast), method_ready()
        start = numba_start_seconds(n, ready, method_cached)
        costs["compiled loop"] = start + steps * compiled_step_seconds(n)
        if not ready and linked_applies(quick):  # the loop over the llvm backend's code
            start = linked_start_seconds(n, method_cached)
            costs["compiled loop on llvm"] = start + steps * linked_step_seconds(n)
    else:
        notes.append("numba is not installed (the compiled loop)")
    if method is None and not heyoka_installed() and numba_installed():
        problem = _taylor_problem(quick, y0, p)  # our Taylor method
        if problem is None:
            problem = taylor_compiled_problem(quick)
            problem = None if problem is None else f"(numba) {problem}"
        if problem is None:
            costs["taylor (numba)"] = taylor_numba_seconds(n, steps, taylor_compiled_ready(quick))
        else:
            notes.append(f"taylor {problem}")
    if method is None and heyoka_installed():
        problem = _taylor_problem(quick, y0, p)
        if problem is None:
            relative = TAYLOR_PACE if n <= 2 else TAYLOR_COMPACT_PACE  # taylor.py's modes
            pace = relative * steps * compiled_step_seconds(n)
            if every_step:  # each step's state copied from heyoka's continuous output
                pace += steps * TAYLOR_STEP_OUTPUT
            costs["taylor"] = taylor_start_seconds(n) + pace
        else:
            notes.append(f"taylor {problem}")
    best = min(costs, key=lambda way: costs[way] * (1.0 if way == "scipy" else SWITCH_MARGIN))
    estimates = ", ".join(f"{way} ~{costs[way]:.2g} s" for way in costs)
    why = f"about {_count(steps)} steps: {estimates}" + "".join(f"; {note}" for note in notes)
    if best == "scipy":
        return scipy_loop(why)
    if best == "compiled loop on llvm":
        how = "dop853 with its loop compiled (numba) over the llvm backend's M and f"
        return RunChoice(quick, "dop853", rtol, atol, f"{how}: {why}", linked=True)
    if best == "compiled loop":
        try:  # the loop's text is generated now (its compilation waits for the run)
            compiled_loop(fast)
        except ModelError as error:  # equations numba's printer cannot write
            return scipy_loop(f"{why}; the compiled loop cannot be generated: {error}")
        return RunChoice(
            fast, "dop853", rtol, atol, f"dop853 with its loop compiled (numba): {why}"
        )
    tol = min(rtol, atol)
    backend = "numba" if best == "taylor (numba)" else "heyoka"
    return RunChoice(quick, "taylor", rtol, atol, f"taylor ({backend}, tol {tol:g}): {why}")


def _compiled_loop_applies(method: str, compiled: CompiledSystem) -> bool:
    """Whether dop853 on ``compiled`` runs the compiled loop (without building it)."""
    return method == "dop853" and compiled.backend == "numba" and compiled.program is not None


def estimated_steps(
    compiled: CompiledSystem,
    t_span: tuple[float, float],
    y0: np.ndarray,
    params: np.ndarray,
    rtol: float,
    atol: float,
) -> float:
    """The steps DOP853 takes over ``t_span``: the first :data:`PROBE_STEPS`, then the rest
    at the mean size of the later half of them (1 where the start cannot be stepped from)."""
    from scipy.integrate import DOP853

    t0, t1 = t_span
    if start_problem(compiled, t0, np.asarray(y0, dtype=float), params) is not None:
        return 1.0  # SciPy's first step would be NaN and its loop endless; the run says why
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            solver = DOP853(
                lambda t, y: compiled.rhs(t, y, params), t0, np.array(y0, dtype=float), t1,
                rtol=max(rtol, MIN_RTOL), atol=atol,
            )  # fmt: skip
            times = [t0]
            if not math.isfinite(solver.h_abs):
                return 1.0
            while len(times) <= PROBE_STEPS and solver.status == "running":
                solver.step()
                times.append(solver.t)
        except (ArithmeticError, ValueError):
            return 1.0
    taken = len(times) - 1
    if solver.status != "running" or taken < 2:
        return float(max(taken, 1))
    half = taken // 2
    size = (times[-1] - times[half]) / (taken - half)
    if not math.isfinite(size) or size <= 0:
        return float(taken)
    return taken + (t1 - times[-1]) / size


def heyoka_installed() -> bool:
    """Whether heyoka can be imported (without importing it: 0.3 s)."""
    return importlib.util.find_spec("heyoka") is not None


def taylor_compiled_problem(compiled: CompiledSystem) -> str | None:
    """Why our Taylor method cannot take the equations of ``compiled``, or None."""
    from .taylor_compiled import tape_problem

    return tape_problem(compiled)


def taylor_compiled_ready(compiled: CompiledSystem) -> bool:
    """Whether our Taylor loop of ``compiled`` is built in this process or in the code cache."""
    from .taylor_compiled import loop_ready

    return loop_ready(compiled)


def _taylor_problem(compiled, y0, params) -> str | None:
    """Why the taylor method does not apply to this run, or None."""
    from .taylor import indefinite_mass

    if compiled.has_constraints:
        return "does not take constraints"
    if getattr(compiled.equations.system, "impacts", ()):
        return "does not stop at impacts"
    with np.errstate(all="ignore"):
        if indefinite_mass(compiled, 0.0, y0, params) is not None:
            return "needs a definite mass matrix"
    return None


def _count(steps: float) -> str:
    return f"{steps:,.0f}" if steps < 1e6 else f"{steps:.1e}"
