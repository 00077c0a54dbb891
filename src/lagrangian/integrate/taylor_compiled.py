"""Taylor's method by our own code generation, compiled by numba: where heyoka is not installed.

The system's Taylor coefficients come from :mod:`lagrangian.codegen.taylor_numba` (its
tape of elementary operations and their recurrences, printed as a numba module per system,
kept in the code cache), the step loop from :mod:`.numba_taylor` (a template, its
machine code kept per system).  The order and the step follow the tolerance as heyoka's
do (Jorba and Zou's rule, :mod:`.numba_taylor`): order ceil(-ln(tol) / 2 + 1), 13 at
1e-10, 20 at machine epsilon.  A tape of more than :data:`COMPACT_OPERATIONS` operations is
walked as data by one loop for every system (:mod:`.numba_taylor_tape`, as heyoka's compact
mode), as numba would take minutes over its printed text.  The run goes in chunks of steps
with Python between them only (``watch`` told the time, a run that keeps every step
checked to fit in memory), as the compiled DOP853's.  Outputs are every step's end, or
with ``t_eval`` each step's Taylor polynomial at the times it covers.  Events are located
as the compiled DOP853 and heyoka's path locate them (:class:`.compiled_events.StepEvents`):
g at every step's end, a sign change found by Brent's method on that step's Taylor
polynomial, which the loop keeps for each step of a chunk.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..codegen.cache import built, built_already, filled_template, package_text
from ..errors import ModelError
from .memory import PROJECT_AFTER_STEPS, check_kept_steps

if TYPE_CHECKING:
    from types import ModuleType

    from ..codegen.taylor_tape import Tape
    from ..numeric.compiled import CompiledSystem
    from .base import Run
    from .compiled_events import StepEvents

#: Steps per call of the loop: the first chunk, and the most (it doubles).
FIRST_CHUNK, LARGEST_CHUNK = 256, 8192
#: Tapes of more operations than this are walked as data, not printed (compact mode):
#: numba compiles a printed tape in about 0.13 s per operation (the double pendulum's 25
#: in 2 s, a 3-link chain's 66 in 8.8 s, a 4-link chain's 131 in 19 s), the compact mode's
#: walk once per machine (4 s), which then runs 2.5-4x slower (the 3- and 4-link chains).
COMPACT_OPERATIONS = 40
#: The largest order the loop is asked for (tolerances down to 1e-300 would ask for 346);
#: below the printed table's row length, codegen.taylor_numba.STRIDE (64).
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
    program: np.ndarray  # the compact mode's tape as data (empty otherwise)
    exponents: np.ndarray

    def constants(self, params: np.ndarray) -> np.ndarray:
        """The tape's constants for the parameters ``params`` (inf or NaN where they are
        not finite: the run reports it)."""
        if compact(self.tape):
            return constant_values(self.tape, params)
        c = np.zeros(max(len(self.tape.constants), 1))
        self.system.constants(np.ascontiguousarray(params, dtype=float), c)
        return c


#: The operations' kinds, numbered as :mod:`.numba_taylor_tape` reads them.
KINDS = ("add", "sub", "mul", "square", "div", "neg", "sqrt", "pow", "exp", "log", "sincos",
         "sinhcosh")  # fmt: skip
_NO_PROGRAM = np.zeros((0, 4), dtype=np.int64)
_CONSTANT_FUNCTIONS = {
    "add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
    "div": lambda a, b: a / b, "neg": lambda a: -a, "square": lambda a: a * a,
    "sqrt": np.sqrt, "exp": np.exp, "log": np.log, "sin": np.sin, "cos": np.cos,
    "sinh": np.sinh, "cosh": np.cosh,
}  # fmt: skip


def constant_values(tape: Tape, params: np.ndarray) -> np.ndarray:
    """The tape's constants computed in NumPy's floating point (the printed ``constants``
    of a small system computes the same operations in the same order)."""
    values = np.zeros(max(len(tape.constants), 1))
    with np.errstate(all="ignore"):
        for j, entry in enumerate(tape.constants):
            if entry.kind == "number":
                values[j] = entry.number
            elif entry.kind == "parameter":
                values[j] = params[entry.index]
            elif entry.kind == "pow":
                values[j] = np.float64(values[entry.args[0]]) ** entry.number
            else:
                arguments = [np.float64(values[i]) for i in entry.args]
                values[j] = _CONSTANT_FUNCTIONS[entry.kind](*arguments)
    return values


def _program(tape: Tape) -> tuple[np.ndarray, np.ndarray]:
    """The compact mode's ``program`` and ``exponents`` of ``tape`` (see
    :mod:`.numba_taylor_tape`)."""

    def where(arg: tuple[str, int]) -> int:
        return arg[1] if arg[0] == "s" else -1 - arg[1]

    rows = []
    for op in tape.ops:
        a = where(op.args[0])
        b = where(op.args[1]) if len(op.args) > 1 else 0
        rows.append([KINDS.index(op.kind), op.rows[0], a, b])
    rows += [[where(rate), 0, 0, 0] for rate in tape.rates]
    rows.append([tape.size, int(tape.uses_time), tape.size, 0])
    exponents = np.array([op.exponent for op in tape.ops] or [0.0])
    return np.array(rows, dtype=np.int64), exponents


def taylor_loop(compiled: CompiledSystem) -> TaylorLoop:
    """The loop of ``compiled``: built once per process, machine code from the code cache."""
    build = lambda: _build(compiled)  # noqa: E731
    return built(compiled.forms.fingerprint, "taylor-numba", build, COMPACT_OPERATIONS)


def what_is_compiled(compiled: CompiledSystem) -> str:
    """What making the loop compiles now, in words, for the run's summary."""
    if built_already(compiled.forms.fingerprint, "taylor-numba", COMPACT_OPERATIONS):
        return "nothing: the Taylor loop was made earlier in this process"
    cached = loop_ready(compiled)
    loop = taylor_loop(compiled)
    mode = "walked as data, " if compact(loop.tape) else ""
    what = f"{len(loop.tape.ops)} operations, {mode}Taylor's method by numba"
    return f"nothing: {what} from the code cache" if cached else f"the loop of {what}"


def tape_problem(compiled: CompiledSystem) -> str | None:
    """Why the equations of ``compiled`` cannot be made into a tape (a function without a
    Taylor recurrence, named), or None."""
    from ..codegen.taylor_tape import UnsupportedFunction, tape_of

    try:
        tape_of(compiled.forms)
    except UnsupportedFunction as error:
        return f"cannot differentiate {error.function}"
    except ModelError:
        return "cannot take these equations"
    return None


def loop_ready(compiled: CompiledSystem) -> bool:
    """Whether the loop of ``compiled`` is built in this process or its machine code is in
    the code cache (a run then loads it in a fraction of a second instead of compiling)."""
    from ..codegen.cache import compiled_on_disk

    if built_already(compiled.forms.fingerprint, "taylor-numba", COMPACT_OPERATIONS):
        return True
    try:
        loop_text = _texts(compiled)[2]
    except ModelError:  # a function the tape cannot take: the run says which
        return False
    return compiled_on_disk(loop_text[0], "advance")


def _texts(compiled: CompiledSystem):
    """(the tape, (sha256, text) of the coefficients' module, of the loop's module)."""
    from ..codegen.cache import module_name, usable_directory
    from ..codegen.taylor_numba import module_text
    from ..codegen.taylor_tape import tape_of

    tape = tape_of(compiled.forms)
    if compact(tape):
        digest, text = package_text(Path(__file__).with_name("numba_taylor_tape.py"))
    else:
        digest, text = module_text(tape)
    name = module_name(usable_directory() / f"{digest}.py")
    generated = [f"from {name} import coefficients"]
    loop = filled_template(Path(__file__).with_name("numba_taylor.py"), generated)
    return tape, (digest, text), loop


def compact(tape: Tape) -> bool:
    """Whether the tape is walked as data (:mod:`.numba_taylor_tape`) rather than printed."""
    return len(tape.ops) > COMPACT_OPERATIONS


def _build(compiled: CompiledSystem) -> TaylorLoop:
    from ..codegen.cache import load_text

    tape, system_text, loop_text = _texts(compiled)
    system = load_text(*system_text)  # loaded first: the loop's text imports it
    program, exponents = _program(tape) if compact(tape) else (_NO_PROGRAM, np.zeros(0))
    loop = TaylorLoop(load_text(*loop_text), system, tape, program, exponents)
    _compile(loop)
    return loop


def _compile(loop: TaylorLoop) -> None:
    """Compile (or load from the code cache) the loop and the coefficients now, for the types
    :func:`propagate` calls them with, by a call that takes no step: what the build costs
    is then the run's ``compile_time``."""
    size = loop.tape.size
    tc = table(loop.tape, 2)
    loop.method.advance(
        size, loop.constants(np.ones(loop.tape.parameters)), 2, 1.0, np.zeros(1), tc,
        tc.reshape(-1), np.empty((size, 1)), np.zeros(0), np.empty((size, 0)), np.empty(0),
        np.empty((0, size)), np.zeros(3, dtype=np.int64), 0, True, loop.program, loop.exponents,
        np.empty((0, size, 3)),
    )  # fmt: skip


def table(tape: Tape, order: int) -> np.ndarray:
    """The zeroed table of Taylor coefficients (rows of the tape, orders 0..``order``): a
    printed system's coefficients take rows of its fixed length ``STRIDE``, and spare
    rows after the tape's."""
    from ..codegen.taylor_numba import STRIDE, table_rows

    if compact(tape):
        return np.zeros((tape.rows, order + 1))
    return np.zeros((table_rows(tape), STRIDE))


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
    stopped: bool = False  # by a terminal event, at the last output


def propagate(loop: TaylorLoop, run: Run, tol: float, events: StepEvents | None = None) -> Reached:
    """Taylor's method at ``tol`` over ``run`` by the compiled loop, ``events`` located on
    each step's Taylor polynomial (a terminal one ends the run there)."""
    t0, t1, t_eval, watch = run.t0, run.t1, run.t_eval, run.watch
    y0 = np.array(run.y0, dtype=float)
    size, order = y0.shape[0], order_for(tol)
    c = loop.constants(run.params)
    tc = table(loop.tape, order)
    tc[:size, 0] = y0
    work = np.empty((size, 1))
    clock = np.array([t0])
    counts = np.zeros(3, dtype=np.int64)
    keep = t_eval is None or events is not None  # the steps' ends: outputs, or for events
    grid = np.zeros(0) if t_eval is None else np.ascontiguousarray(t_eval, dtype=float)
    out = np.empty((size, grid.shape[0]))
    counts[2] = np.searchsorted(grid, t0, side="right")  # outputs at t0 itself
    out[:, : counts[2]] = y0[:, None]
    times, states = [np.array([t0])], [y0[None, :]]
    chunk, status, projected_at, stop = FIRST_CHUNK, 0, PROJECT_AFTER_STEPS, None
    while status == 0:
        ts, ys = np.empty(chunk if keep else 0), np.empty((chunk if keep else 0, size))
        kept = np.empty((chunk if events is not None else 0, size, order + 1))
        t_before, counts[1] = float(clock[0]), 0
        status = loop.method.advance(
            size, c, order, t1, clock, tc, tc.reshape(-1), work, grid, out, ts, ys, counts,
            chunk, keep, loop.program, loop.exponents, kept,
        )  # fmt: skip
        if keep:
            taken = int(counts[1])
            ts, ys = ts[:taken], ys[:taken]
            if events is not None:
                stop = events.located(t_before, ts, ys, _interpolant(kept))
                if stop is not None:  # the steps beyond it are not the run's
                    k, (t_stop, y_stop) = stop
                    ts, ys = np.append(ts[:k], t_stop), np.vstack([ys[:k], y_stop])
                    counts[0] -= taken - (k + 1)
            if t_eval is None:
                times.append(ts)
                states.append(ys)
            if t_eval is None and counts[0] >= projected_at:
                check_kept_steps(
                    "taylor", size, int(counts[0]), (float(clock[0]), t1),
                    (taken, float(clock[0]) - t_before),
                )  # fmt: skip
                projected_at = 2 * int(counts[0])
        if stop is not None:
            break
        if status == 0 and watch is not None:
            watch(float(clock[0]))
        chunk = min(2 * chunk, LARGEST_CHUNK)
    last_y = tc[:size, 0].copy()
    if t_eval is None:
        t_out, y_out = np.concatenate(times), np.concatenate(states).T
    else:
        done = int(counts[2])
        t_out, y_out = grid[:done], out[:, :done]
    if stop is None:
        return Reached(t_out, y_out, int(counts[0]), int(status), float(clock[0]), last_y)
    _, (t_stop, y_stop) = stop
    if t_eval is not None:  # the outputs up to the event, and its state last
        before = t_out < t_stop
        t_out = np.append(t_out[before], t_stop)
        y_out = np.concatenate([y_out[:, before], y_stop[:, None]], axis=1)
    return Reached(t_out, y_out, int(counts[0]), 1, t_stop, y_stop, stopped=True)


def _interpolant(kept: np.ndarray):
    """``StepEvents.located``'s interpolant of the steps of a chunk: step k's Taylor
    polynomial (its coefficients ``kept[k]``, rows of the state) at a time within it."""

    def at(k: int, t_old: float):
        def state(t: float) -> np.ndarray:
            coefficients, h = kept[k], float(t) - t_old
            value = coefficients[:, -1].copy()
            for j in range(coefficients.shape[1] - 2, -1, -1):
                value = value * h + coefficients[:, j]
            return value

        return state

    return lambda k, t_old, t: at(k, t_old)
