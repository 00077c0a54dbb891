"""DOP853 with its whole step loop compiled: SciPy's method without Python per step.

SciPy's ``DOP853`` runs each step in Python: about 150 us of interpreter and NumPy
calls per step around 12 evaluations of a right-hand side that takes 0.1-2 us as
generated machine code, so a long run is almost all overhead (double pendulum,
t = 1000 at tol 1e-10: 12 s, where heyoka's Taylor method takes 0.025 s).  Here the
same method (SciPy's coefficients, initial step, error norm and step-size control,
:mod:`.numba_dop853`) runs as one numba loop over the system's generated M and f
(:mod:`lagrangian.codegen.numba`, solved in the loop by Gaussian elimination with
partial pivoting), so it takes the steps SciPy takes and gives its answers to
rounding.  The method is compiled once for every system (its machine code kept in the
code cache) and takes the system's y' as a function pointer: a new system compiles only
its own y', about a second, where the whole loop took 4-5 s more.  :func:`linked_loop`
compiles nothing for the system in numba: the method's ``linked_derivative`` calls the
code SymEngine's LLVM makes of M and f in milliseconds (the llvm backend's), at 1.2-1.4x
the time per step of the system's own y'; :mod:`.choice` takes it for a new system's
long run, and the system's own loop where it is in the code cache or the run is long
enough to pay for compiling it (benchmarks/README.md, "The first run of a new system").

Why this and not the other ways to an adaptive method without Python per step
(measured, benchmarks/user_paths.py, figures in benchmarks/README.md):

- heyoka's Taylor method (``method="taylor"``) is faster still for small systems at
  tight tolerances, but it is an optional 100 MB package that CI does not install and
  takes constraints nowhere (our events, Python functions of the state, it cannot
  detect itself: they are located on its continuous output, :mod:`.taylor_propagate`);
  where it is installed the default uses it for long runs that it can do
  (:mod:`.choice`).
- A compiled solver from PyPI (numbalsoda, NumbaLSODA's LSODA; nbkode) would add a
  dependency for what is 200 lines over code we generate already, and none of those
  maintained gives DOP853's dense output and events.

Events are located as SciPy locates them, in Python, on each step's interpolant
(Brent's method to 4 eps), from the step ends the loop hands back in chunks; a
terminal event discards the steps the chunk took beyond it.  ``watch`` is told the
time once per chunk (64 steps at first, doubling to 4096), so a time budget or a
progress bar still sees the run move.  Failures read as SciPy's path reads them
(:mod:`.scipy_methods`): a start where y' is not finite, a step size that falls
below the spacing of floating-point numbers (after a right-hand side that was not
finite, saying so), an accepted state that is not finite.

Constrained systems (:func:`compiled_loop` only; the linked loop, the sections,
sensitivities and variational equations refuse them) integrate the equations SciPy's loop
integrates, the augmented system with Baumgarte's stabilisation
(:mod:`lagrangian.codegen.numba_constrained`), and every accepted state and every output is
projected onto the constraint manifold in the loop (positions by Gauss-Newton in the mass
metric, velocities exactly, as :mod:`lagrangian.numeric.projection`): the residual stays at
rounding level however long the run, where SciPy's loop lets it wander at the tolerance.

Applies to systems with derived equations where numba is installed (:func:`compiled_loop`
returns None otherwise and SciPy's loop runs).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..codegen.cache import built, built_already, package_text
from .base import IntegrationResult, Run, Status
from .compiled_derivatives import derivative_text, jacobian_filler
from .compiled_events import StepEvents
from .guard import UNDEFINED, describe_state, state_problem
from .memory import PROJECT_AFTER_STEPS, check_kept_steps

if TYPE_CHECKING:
    from types import ModuleType

    from ..numeric.compiled import CompiledSystem

#: Steps per call of the compiled loop: the first chunk, and the most (it doubles).
FIRST_CHUNK, LARGEST_CHUNK = 64, 4096
#: SciPy's messages, so that both loops read the same.
REACHED = "The solver successfully reached the end of the integration interval."
TERMINATED = "A termination event occurred."
TOO_SMALL_STEP = "Required step size is less than spacing between numbers."
MIN_FACTOR = 0.2  # SciPy's smallest shrink of a rejected step


_NO_LINK = np.empty(0, dtype=np.int64)


@dataclass(frozen=True)
class Loop:
    """The compiled DOP853 method (:mod:`.numba_dop853`, one for every system) with one
    system's y' (in a typed list of one): its generated ``derivative`` of
    :mod:`.numba_derivative`, or the method's ``linked_derivative`` with the ``link``
    (address, user data, parameter count) of SymEngine's compiled M and f, ``code``, kept
    alive with the loop (:func:`linked_loop`)."""

    method: ModuleType
    y_prime: object
    n: int
    tangent: bool
    link: np.ndarray = field(default_factory=lambda: _NO_LINK)
    code: object = None

    def advance(self, *arguments: object) -> int:
        """The method's ``advance`` on this system: its arguments after ``y_prime``, ``n``,
        ``tangent`` and ``link``."""
        return self.method.advance(self.y_prime, self.n, self.tangent, self.link, *arguments)

    def slope(self, t: float, y: np.ndarray, p: np.ndarray, out: np.ndarray, flags) -> None:
        """out = y' at (t, y) (flags[0] = 1 where it is not finite)."""
        self.method.slope(self.y_prime, self.n, self.tangent, self.link, t, y, p, out, flags)

    def y_prime_at(self, t: float, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """y' at (t, y), a new array (inf or NaN where it is not finite)."""
        out = np.empty(y.shape[0])
        self.slope(t, np.ascontiguousarray(y, dtype=float), p, out, np.zeros(1, dtype=np.int64))
        return out

    def prepare(self, size: int, parameters: int) -> None:
        """Make (or load from the code cache) ``advance`` for a run of vectors of ``size``
        and ``parameters`` values, by a call that takes no step, so that its cost is paid,
        and measured, before the run."""
        empty, rows = np.zeros(0), np.zeros((0, size))
        self.advance(
            np.zeros(2), np.zeros(size), np.zeros(size), np.zeros(parameters), 0.0, 1.0, 1.0,
            True, empty, rows, empty, rows, rows, np.zeros((0, 7, size)),
            np.zeros(4, dtype=np.int64), np.zeros(1, dtype=np.int64),
        )  # fmt: skip


def compiled_loop(compiled: CompiledSystem) -> Loop | None:
    """The jitted DOP853 loop of ``compiled`` (built once, machine code cached on disk), or
    None where it does not apply: functions given by hand, numba missing.  A constrained
    system's loop projects onto its constraints (see the module docstring)."""
    if not loop_applies(compiled, constraints=True):
        return None
    fingerprint = compiled.forms.fingerprint
    return built(fingerprint, "dop853", lambda: _build(compiled), _alpha(compiled))


def _alpha(compiled: CompiledSystem) -> float:
    """Baumgarte's rate in the constrained loop's y' (the forms' fingerprint has it not)."""
    return compiled.baumgarte if compiled.has_constraints else 0.0


def tangent_loop(compiled: CompiledSystem) -> Loop | None:
    """The loop of the variational equations of ``compiled`` (the state followed by K
    displacements, any K, see :mod:`.numba_derivative`), or None as :func:`compiled_loop`."""
    if not loop_applies(compiled):
        return None
    return built(
        compiled.forms.fingerprint, "dop853-tangent", lambda: _build(compiled, tangent=True)
    )


def linked_loop(compiled: CompiledSystem) -> Loop | None:
    """The DOP853 loop of ``compiled`` with nothing compiled for the system by numba: the
    method's ``linked_derivative`` over SymEngine's LLVM code of M and f (made in
    milliseconds), or None where it does not apply (as :func:`compiled_loop`, or SymEngine
    cannot hold the equations).  The method's machine code is the same for every system."""
    if not loop_applies(compiled):
        return None
    return built(compiled.forms.fingerprint, "dop853-linked", lambda: _build_linked(compiled))


def linked_applies(compiled: CompiledSystem) -> bool:
    """Whether :func:`linked_loop` serves ``compiled``: as :func:`loop_applies`, on the llvm
    backend, with equations SymEngine's LLVM holds (its code is made now, in milliseconds,
    where the llvm backend's functions have not made it already)."""
    from ..codegen.llvm import llvm_blocks

    if compiled.backend != "llvm" or not loop_applies(compiled):
        return False
    return llvm_blocks(compiled.program) is not None


def _build_linked(compiled: CompiledSystem) -> Loop | None:
    from ..codegen.llvm import llvm_blocks

    code = llvm_blocks(compiled.program)
    if code is None:
        return None
    function, user_data = code.as_ctypes()
    address = ctypes.cast(function, ctypes.c_void_p).value
    parameters = len(compiled.forms.parameters)
    link = np.array([address, user_data.value, parameters], dtype=np.int64)
    method = method_module()
    return Loop(method, method.y_prime(method.linked_derivative), compiled.n, False, link, code)


def what_is_compiled(compiled: CompiledSystem, *, linked: bool) -> str:
    """What making the loop of ``compiled`` (:func:`linked_loop` with ``linked``, else
    :func:`compiled_loop`) compiles now, in words, for the run's summary."""
    fingerprint = compiled.forms.fingerprint if compiled.forms is not None else ""
    key = ("dop853-linked",) if linked else ("dop853", _alpha(compiled))
    if built_already(fingerprint, *key):
        return "nothing: the loop was made earlier in this process"
    if not linked and compiled_ready(compiled):
        return "nothing: the loop and the right-hand side from the code cache"
    right_hand_side = "the right-hand side by " + ("LLVM" if linked else "numba")
    if method_ready():
        return f"{right_hand_side} (the loop from the code cache)"
    return f"the DOP853 loop (its first run on this machine) and {right_hand_side}"


def method_module() -> ModuleType:
    """The DOP853 method's generated module (:mod:`.numba_dop853`, the same for every
    system)."""
    from ..codegen.cache import load_text

    return load_text(*_method_text())


def _method_text() -> tuple[str, str]:
    return package_text(Path(__file__).with_name("numba_dop853.py"))


def loop_applies(compiled: CompiledSystem, *, constraints: bool = False) -> bool:
    """Whether the compiled loops serve ``compiled``: derived equations, without constraints
    unless ``constraints`` (the DOP853 loop projects, the others do not), and numba
    installed."""
    if compiled.has_constraints and not constraints:
        return False
    return compiled.program is not None and numba_installed()


def numba_installed() -> bool:
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def compiled_ready(compiled: CompiledSystem) -> bool:
    """Whether the loop of ``compiled`` is built in this process or its machine code is in
    the code cache (a run then loads it in a fraction of a second instead of compiling)."""
    from ..codegen.cache import compiled_on_disk

    if compiled.program is None:
        return False
    if built_already(compiled.forms.fingerprint, "dop853", _alpha(compiled)):
        return True
    return method_ready() and compiled_on_disk(derivative_text(compiled)[0], "derivative")


def method_ready() -> bool:
    """Whether the method's machine code (the same for every system) is in the code cache:
    a new system then compiles only its y'."""
    from ..codegen.cache import compiled_on_disk

    return compiled_on_disk(_method_text()[0], "advance")


def _build(compiled: CompiledSystem, *, tangent: bool = False) -> Loop:
    from ..codegen.cache import load_text
    from ..codegen.numba import NumbaTarget

    method = method_module()
    if compiled.has_constraints:  # the fillers are loaded as its text is made
        system = load_text(*derivative_text(compiled))
        pointers = method.projected_y_prime(system.derivative, system.project)
        return Loop(method, pointers, compiled.n + len(compiled.constraint_names), False)
    NumbaTarget().load(compiled.program)  # the fillers' module, imported by the system's
    jacobian = jacobian_filler(compiled).__name__ if tangent else None
    system = load_text(*derivative_text(compiled, jacobian))
    return Loop(method, method.y_prime(system.derivative), compiled.n, tangent)


def solve_compiled(
    loop: Loop, compiled: CompiledSystem, run: Run, *, rtol: float, atol: float,
    settings: dict[str, object],
) -> IntegrationResult:  # fmt: skip
    """DOP853 on a checked ``run`` (a finite start with a finite y') by the compiled loop;
    the result reads as :class:`~lagrangian.integrate.scipy_methods.Dop853`'s."""
    t0, t1, params, t_eval, events, watch = (
        run.t0, run.t1, run.params, run.t_eval, run.events, run.watch
    )  # fmt: skip
    y = np.array(run.y0, dtype=float)
    p = np.ascontiguousarray(params, dtype=float)
    size = y.shape[0]
    f = loop.y_prime_at(t0, y, p)  # the loop's own y': its steps depend on its code only
    h = first_step(lambda t, y: loop.y_prime_at(t, y, p), t0, y, f, t1, rtol, atol)
    clock = np.array([t0, h])
    counts = np.array([2, 0, 0, 0], dtype=np.int64)  # f at t0 and in first_step, as SciPy
    flags = np.zeros(1, dtype=np.int64)
    dense = t_eval is not None or bool(events)
    grid = np.zeros(0) if t_eval is None else np.ascontiguousarray(t_eval, dtype=float)
    out = np.empty((grid.shape[0], size))
    watcher = StepEvents(events, params, t0, y, f) if events else None
    times, states = [np.array([t0])], [y[None, :].copy()]
    chunk, status = FIRST_CHUNK, 0
    taken, projected_at = 0, PROJECT_AFTER_STEPS  # steps taken; the next memory projection
    while status == 0:
        ts, ys = np.empty(chunk), np.empty((chunk, size))
        olds = np.empty((chunk if dense else 0, size))
        slopes = np.empty((chunk if dense else 0, 7, size))
        t_before, counts[1] = clock[0], 0
        while True:
            try:
                status = loop.advance(
                    clock, y, f, p, t1, rtol, atol, dense, grid, out, ts, ys, olds, slopes,
                    counts, flags,
                )  # fmt: skip
                break
            except ZeroDivisionError:  # NumPy's inf: rejected, as SciPy rejects a NaN error
                flags[0], counts[3] = 1, 1
                clock[1] *= MIN_FACTOR
        steps = int(counts[1])
        ts, ys = ts[:steps], ys[:steps]
        if watcher is not None:
            hit = watcher.steps(t_before, ts, ys, olds, slopes)
            if hit is not None:
                k, (t_stop, y_stop) = hit
                if compiled.project is not None:  # the interpolant's state, onto the manifold
                    y_stop = np.asarray(compiled.project(t_stop, y_stop, p), dtype=float)
                ts, ys = np.append(ts[:k], t_stop), np.vstack([ys[:k], y_stop])
                status = -1
        times.append(ts)
        states.append(ys)
        taken += ts.shape[0]
        if t_eval is not None:  # the outputs are on the grid: the last two steps suffice
            times, states = [np.concatenate(times)[-2:]], [np.concatenate(states)[-2:]]
        elif taken >= projected_at:  # every step kept: will they fit?
            check_kept_steps(
                "dop853", size, taken, (float(clock[0]), t1), (steps, clock[0] - t_before)
            )
            projected_at = 2 * taken
        if watch is not None:
            watch(float(clock[0]))
        chunk = min(2 * chunk, LARGEST_CHUNK)
    t_out, y_out = np.concatenate(times), np.concatenate(states).T
    result_status, message = Status.SUCCESS, REACHED
    if status == -1:
        result_status, message = Status.EVENT, TERMINATED
    elif status == 2:
        result_status = Status.FAILED
        where = f"t = {t_out[-1]:.6g} ({describe_state(compiled, y_out[:, -1])})"
        message = f"{TOO_SMALL_STEP.rstrip('.')} at {where}"
        if flags[0]:
            message = (
                f"the right-hand side is not finite just after {where}, so no step "
                f"size works: {UNDEFINED}, or the motion reaches a singularity"
            )
    elif status == 3:
        result_status = Status.FAILED
        message = state_problem(compiled, t_out[-2], y_out[:, -2], y_out[:, -1])
        t_out, y_out = t_out[:-1], y_out[:, :-1]
    steps = taken - (status == 3)  # the failed step's state is not kept
    if t_eval is not None:
        reached = grid <= t_out[-1]
        t_kept, y_kept = grid[reached], out[reached].T
        if result_status is not Status.SUCCESS and (not t_kept.size or t_kept[-1] < t_out[-1]):
            t_kept = np.append(t_kept, t_out[-1])
            y_kept = np.concatenate([y_kept, y_out[:, -1:]], axis=1)
        t_out, y_out = t_kept, y_kept
    return IntegrationResult(
        t=t_out,
        y=y_out,
        status=result_status,
        message=message,
        steps=steps,
        rhs_evaluations=int(counts[0]),
        jacobian_evaluations=0,
        events=watcher.records(size) if watcher is not None else (),
        settings=settings,
    )  # fmt: skip


def first_step(rhs, t0, y0, f0, t_end, rtol, atol) -> float:
    """SciPy's ``select_initial_step`` for DOP853 (error estimator order 7; Hairer,
    Norsett & Wanner, *Solving ODEs I*, II.4): one evaluation of y' = ``rhs(t, y)`` ahead
    of t0."""
    interval = abs(t_end - t0)
    scale = atol + np.abs(y0) * rtol
    d0, d1 = _rms(y0 / scale), _rms(f0 / scale)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, interval)
    f1 = np.asarray(rhs(t0 + h0, y0 + h0 * f0), dtype=float)
    d2 = _rms((f1 - f0) / scale) / h0
    flat = d1 <= 1e-15 and d2 <= 1e-15
    h1 = max(1e-6, h0 * 1e-3) if flat else (0.01 / max(d1, d2)) ** (1 / 8)
    return min(100 * h0, h1, interval)


def _rms(x: np.ndarray) -> float:
    return float(np.linalg.norm(x) / x.size**0.5)
