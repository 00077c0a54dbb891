"""Taylor's method by our own code generation, compiled by numba: where heyoka is not installed.

The system's Taylor coefficients come from :mod:`lagrangian.codegen.taylor_numba` (its
tape of elementary operations and their recurrences, printed as a numba module per system,
kept in the code cache), the step loop from :mod:`.numba_taylor` (one module for every
system, compiled once per machine, calling the system's coefficients through a function
pointer).  The order and the step follow the tolerance as heyoka's do (Jorba and Zou's
rule, :mod:`.numba_taylor`): order ceil(-ln(tol) / 2 + 1), 13 at 1e-10, 20 at machine
epsilon.  The run goes in chunks of steps with Python between them only (``watch`` told
the time, a run that keeps every step checked to fit in memory), as the compiled DOP853's.
Outputs are every step's end, or with ``t_eval`` each step's Taylor polynomial at the
times it covers.  Not handled: events (their detection is heyoka's path and dop853's).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..codegen.cache import built, built_already, filled_template
from .memory import PROJECT_AFTER_STEPS, check_kept_steps

if TYPE_CHECKING:
    from types import ModuleType

    from ..codegen.taylor_tape import Tape
    from ..numeric.compiled import CompiledSystem
    from .base import Run

#: Steps per call of the loop: the first chunk, and the most (it doubles).
FIRST_CHUNK, LARGEST_CHUNK = 256, 8192
#: The largest order the loop is asked for (tolerances down to 1e-300 would ask for 346).
MAX_ORDER = 60


def order_for(tol: float) -> int:
    """Jorba and Zou's order for tolerance ``tol``, as heyoka takes it: ceil(-ln(tol)/2 + 1)."""
    return min(max(math.ceil(-math.log(tol) / 2.0 + 1.0), 2), MAX_ORDER)


@dataclass(frozen=True)
class TaylorLoop:
    """The step loop of one system (:mod:`.numba_taylor` over its coefficients)."""

    method: ModuleType
    system: ModuleType
    tape: Tape

    def constants(self, params: np.ndarray) -> np.ndarray:
        c = np.zeros(max(len(self.tape.constants), 1))
        with np.errstate(all="ignore"):
            self.system.constants(np.ascontiguousarray(params, dtype=float), c)
        return c


def taylor_loop(compiled: CompiledSystem) -> TaylorLoop:
    """The loop of ``compiled``: built once per process, machine code from the code cache."""
    return built(compiled.forms.fingerprint, "taylor-numba", lambda: _build(compiled))


def what_is_compiled(compiled: CompiledSystem) -> str:
    """What making the loop compiles now, in words, for the run's summary."""
    if built_already(compiled.forms.fingerprint, "taylor-numba"):
        return "nothing: the Taylor loop was made earlier in this process"
    loop = taylor_loop(compiled)
    return f"the Taylor coefficients by numba ({len(loop.tape.ops)} operations)"


def _build(compiled: CompiledSystem) -> TaylorLoop:
    from ..codegen.cache import load_text, module_name, usable_directory
    from ..codegen.taylor_numba import module_text
    from ..codegen.taylor_tape import tape_of

    tape = tape_of(compiled.forms)
    digest, text = module_text(tape)
    system = load_text(digest, text)  # loaded first: the loop's text imports it
    name = module_name(usable_directory() / f"{digest}.py")
    generated = [f"from {name} import coefficients"]
    method = load_text(*filled_template(Path(__file__).with_name("numba_taylor.py"), generated))
    return TaylorLoop(method, system, tape)


@dataclass(frozen=True)
class Reached:
    """What a run reached: outputs (``values`` (size, T)), steps, the loop's status (1 the end,
    2 a step below 10 ulp, 3 not finite) and the last (time, state) it took."""

    times: np.ndarray
    values: np.ndarray
    steps: int
    status: int
    last_t: float
    last_y: np.ndarray


def propagate(loop: TaylorLoop, run: Run, tol: float) -> Reached:
    """Taylor's method at ``tol`` over ``run`` (no events) by the compiled loop."""
    t0, t1, t_eval, watch = run.t0, run.t1, run.t_eval, run.watch
    y0 = np.array(run.y0, dtype=float)
    size, order = y0.shape[0], order_for(tol)
    c = loop.constants(run.params)
    tc = np.zeros((loop.tape.rows, order + 1))
    tc[:size, 0] = y0
    work = np.empty((size, 1))
    clock = np.array([t0])
    counts = np.zeros(3, dtype=np.int64)
    keep = t_eval is None
    grid = np.zeros(0) if keep else np.ascontiguousarray(t_eval, dtype=float)
    out = np.empty((size, grid.shape[0]))
    counts[2] = np.searchsorted(grid, t0, side="right")  # outputs at t0 itself
    out[:, : counts[2]] = y0[:, None]
    times, states = [np.array([t0])], [y0[None, :]]
    chunk, status, projected_at = FIRST_CHUNK, 0, PROJECT_AFTER_STEPS
    while status == 0:
        ts, ys = np.empty(chunk if keep else 0), np.empty((chunk if keep else 0, size))
        t_before, counts[1] = float(clock[0]), 0
        status = loop.method.advance(
            size, c, order, t1, clock, tc, work, grid, out, ts, ys, counts,
            chunk, keep,
        )  # fmt: skip
        if keep:
            kept = int(counts[1])
            times.append(ts[:kept])
            states.append(ys[:kept])
            if counts[0] >= projected_at:
                check_kept_steps(
                    "taylor", size, int(counts[0]), (float(clock[0]), t1),
                    (kept, float(clock[0]) - t_before),
                )  # fmt: skip
                projected_at = 2 * int(counts[0])
        if status == 0 and watch is not None:
            watch(float(clock[0]))
        chunk = min(2 * chunk, LARGEST_CHUNK)
    last_y = tc[:size, 0].copy()
    if keep:
        t_out, y_out = np.concatenate(times), np.concatenate(states).T
    else:
        done = int(counts[2])
        t_out, y_out = grid[:done], out[:, :done]
    return Reached(t_out, y_out, int(counts[0]), int(status), float(clock[0]), last_y)
