"""One run of heyoka's integrator in chunks of steps: no Python per step.

A Python callback per step (as ``watch`` and the last finite state were kept before)
cost 5-10 us a step where heyoka's step of the double pendulum takes 0.5 us: the
method ran at 15x heyoka's own time (issue 36).  Here heyoka propagates
``chunk`` steps per call (``max_steps``) and Python runs between chunks only:

- without output times every step is kept, from heyoka's continuous output of the
  chunk (``c_output=True``): the order-0 Taylor coefficient of a step is the state at
  its start, exactly the state the step before ended on, and the chunk's last state is
  the integrator's;
- with output times (``t_eval``), heyoka's ``propagate_grid`` over the times the chunk
  reaches (its dense output evaluated inside heyoka), the current time put first as the
  grid must begin there, and its row dropped.

Between chunks ``watch`` is told the time (a progress bar, a time budget: an exception
it raises ends the run), a run that keeps every step is checked to fit in memory
(:func:`~lagrangian.integrate.memory.check_kept_steps`), and the next chunk is sized
to take about :data:`CHUNK_SECONDS` of CPU, at most :data:`CHUNK_BYTES` of Taylor
coefficients (a continuous output object costs about a millisecond to make, so
chunks are thousands of steps).  Where heyoka stops at a state that is not finite it
leaves NaN in its state; the last finite state, which names where the run failed, is
found by taking the last good step again from its start, which the chunk's continuous
output holds (for a grid, which keeps none, the failed chunk is run again with it).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .compiled_events import StepEvents
from .memory import check_kept_steps

#: Steps in the first chunk; later chunks are sized by the CPU time a step took.
FIRST_CHUNK = 4096
#: CPU seconds a chunk aims at: how often ``watch`` hears of the run.
CHUNK_SECONDS = 0.25
#: The most bytes of Taylor coefficients one chunk's continuous output holds.
CHUNK_BYTES = 1 << 25


@dataclass(frozen=True)
class Propagation:
    """What a run reached: its outputs (``values`` (2n, T)), heyoka's steps and outcome,
    and the last finite (time, state)."""

    times: np.ndarray
    values: np.ndarray
    steps: int
    outcome: object
    last_t: float
    last_y: np.ndarray
    stopped: bool = False  # by a terminal event, at the last output


def propagate(
    integrator,
    t1: float,
    t_eval: np.ndarray | None,
    watch: Callable[[float], None] | None,
    events: StepEvents | None = None,
) -> Propagation:
    """Propagate ``integrator`` (time and state set) to ``t1``, or over ``t_eval``, with
    ``events`` located on the way where given."""
    if events is not None or t_eval is None:
        return _by_steps(integrator, t1, t_eval, watch, events)
    grid = np.asarray(t_eval, dtype=float)
    # heyoka's grid must increase strictly; t_eval may repeat a time (it is sorted)
    times, inverse = np.unique(grid, return_inverse=True)
    reached = _on_grid(integrator, times, watch)
    kept = inverse < reached.times.shape[0]  # a prefix, as t_eval is sorted
    return dataclasses.replace(reached, times=grid[kept], values=reached.values[:, inverse[kept]])


def _by_steps(integrator, t1: float, t_eval, watch, events: StepEvents | None) -> Propagation:
    """Every step of each chunk (its ends from the chunk's continuous output), each step's
    end handed to ``events`` where given, which locates crossings on that output; the run
    stops at a terminal one.  With ``t_eval`` the output times are the continuous output
    evaluated there, chunk by chunk, and a terminal event's state is the last output."""
    import heyoka as hy

    t0, y0 = float(integrator.time), np.array(integrator.state, dtype=float)
    size = y0.shape[0]
    grid = None if t_eval is None else np.asarray(t_eval, dtype=float)
    times, states, reached = [np.array([t0])], [y0[None, :]], 0
    if grid is not None:
        reached = int(np.searchsorted(grid, t0, side="right"))  # outputs at t0 itself
        times, states = [grid[:reached]], [np.repeat(y0[None, :], reached, axis=0)]
    largest = _largest_chunk(integrator, size)
    chunk, steps, last_t, last_y, stopped = min(FIRST_CHUNK, largest), 0, t0, y0, False
    while True:
        started, start_time = time.process_time(), float(integrator.time)
        outcome, _, _, taken, output, _ = integrator.propagate_until(
            t1, max_steps=chunk, c_output=True
        )
        spent = time.process_time() - started
        steps += taken
        if taken:
            step_times = np.array(output.times, dtype=float)
            ends = np.array(output.tcs[1:, :, 0], dtype=float)
            if outcome in (hy.taylor_outcome.time_limit, hy.taylor_outcome.step_limit):
                end = np.array(integrator.state, dtype=float)
            else:
                start = np.array(output.tcs[-1, :, 0], dtype=float)
                end = _step_from(integrator, float(step_times[-2]), start, t1)
            ts = step_times[1:] if end is not None else step_times[1:-1]
            ys = np.vstack([ends, end[None, :]]) if end is not None else ends
            hit = (
                None if events is None else events.located(start_time, ts, ys, _interpolant(output))
            )
            if hit is not None:
                k, (t_stop, y_stop) = hit
                ts, ys, stopped = np.append(ts[:k], t_stop), np.vstack([ys[:k], y_stop]), True
            if grid is None:
                times.append(ts)
                states.append(ys)
            elif ts.size:
                upto = int(np.searchsorted(grid, ts[-1], side="right"))
                inside = grid[reached:upto]
                times.append(inside)
                states.append(np.array(output(inside), dtype=float).reshape(-1, size))
                reached = upto
                if stopped and (not inside.size or inside[-1] < t_stop):
                    times.append(np.array([t_stop]))
                    states.append(y_stop[None, :])
            if ts.size:
                last_t, last_y = float(ts[-1]), ys[-1]
        if stopped or outcome != hy.taylor_outcome.step_limit:
            break
        if grid is None:
            check_kept_steps(
                "taylor", size, steps, (float(integrator.time), t1),
                (taken, float(integrator.time) - start_time),
            )  # fmt: skip
        if watch is not None:
            watch(float(integrator.time))
        chunk = _next_chunk(spent, taken, largest)
    if stopped:
        outcome = hy.taylor_outcome.time_limit  # a run that ended as asked
    return Propagation(
        np.concatenate(times), np.concatenate(states).T, steps, outcome, last_t, last_y, stopped
    )


def _interpolant(output):
    """``StepEvents.located``'s interpolant of every step of a chunk: its continuous
    output (the state at a time within it, as a copy)."""

    def state(t: float) -> np.ndarray:
        return np.array(output(float(t)), dtype=float).ravel()

    return lambda k, t_old, t: state


def _on_grid(integrator, grid: np.ndarray, watch) -> Propagation:
    import heyoka as hy

    t_last, y_last = float(integrator.time), np.array(integrator.state, dtype=float)
    rows, reached, chunk, steps = [], 0, FIRST_CHUNK, 0
    while True:
        rest = grid[reached:]
        t_start, y_start = float(integrator.time), np.array(integrator.state, dtype=float)
        lead = rest.size == 0 or rest[0] != t_start  # the grid must begin at the time
        chunk_grid = np.concatenate([[t_start], rest]) if lead else rest
        started = time.process_time()
        outcome, _, _, taken, _, values = integrator.propagate_grid(chunk_grid, max_steps=chunk)
        spent = time.process_time() - started
        steps += taken
        values = np.asarray(values, dtype=float)[1 if lead else 0 :]
        rows.append(values)
        reached += values.shape[0]
        if reached == grid.shape[0]:  # every output made: the run is complete
            outcome = hy.taylor_outcome.time_limit
        if outcome != hy.taylor_outcome.step_limit:
            break
        if watch is not None:
            watch(float(integrator.time))
        chunk = _next_chunk(spent, taken, 1 << 40)
    if outcome not in (hy.taylor_outcome.time_limit, hy.taylor_outcome.step_limit):
        t_last, y_last = _last_finite(integrator, t_start, y_start, grid[-1], chunk)
    values = np.concatenate(rows) if rows else np.empty((0, y_last.shape[0]))
    return Propagation(grid[:reached], values.T, steps, outcome, t_last, y_last)


def _step_from(integrator, t: float, y: np.ndarray, t1: float) -> np.ndarray | None:
    """The state one step of heyoka from (``t``, ``y``) ends on, or None where it is not
    finite.  A step depends only on where it starts, so this is the step the run took:
    the state it reached, which heyoka's continuous output cannot give near a
    singularity (its polynomial, evaluated at the step's end, is not the state there to
    the last digits where the derivatives are huge)."""
    import heyoka as hy

    integrator.time = t
    integrator.state[:] = y
    outcome, _ = integrator.step(max_delta_t=t1 - t)
    end = np.array(integrator.state, dtype=float)
    if outcome not in (hy.taylor_outcome.success, hy.taylor_outcome.time_limit):
        return None
    return end if np.all(np.isfinite(end)) else None


def _last_finite(integrator, t: float, y: np.ndarray, t1: float, chunk: int):
    """The last finite (time, state) of a chunk that failed, found by running it again
    from its start (``t``, ``y``) with continuous output, then its last step again."""
    integrator.time = t
    integrator.state[:] = y
    _, _, _, taken, output, _ = integrator.propagate_until(t1, max_steps=chunk, c_output=True)
    if not taken:
        return t, y
    start_t, start = float(output.times[-2]), np.array(output.tcs[-1, :, 0], dtype=float)
    end = _step_from(integrator, start_t, start, t1)
    if end is None:
        return start_t, start
    return float(output.times[-1]), end


def _largest_chunk(integrator, size: int) -> int:
    """The most steps whose Taylor coefficients fit in CHUNK_BYTES (at least 64: a
    100-link chain's 200 states at order 20 keep 33 kB a step)."""
    return max(64, CHUNK_BYTES // (8 * size * (integrator.order + 1)))


def _next_chunk(spent: float, taken: int, largest: int) -> int:
    """Steps for about CHUNK_SECONDS of CPU at the pace of the last chunk."""
    if taken == 0 or spent <= 0:  # no pace measured (a clock tick is 1-10 ms)
        return largest
    return int(min(max(CHUNK_SECONDS * taken / spent, min(FIRST_CHUNK, largest)), largest))
