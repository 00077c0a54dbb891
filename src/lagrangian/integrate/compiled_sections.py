"""Poincaré sections at compiled speed: a motion's crossings found inside DOP853's loop.

SciPy's ``solve_ivp`` evaluates an event in Python after every step, and the compiled
loop of :mod:`.compiled_dop853` hands its steps back to Python to do the same: both
cost microseconds of interpreter per step, and a section of 50 orbits x 2000 crossings
takes millions of steps.  Here the section's g = 0 (user text, read by the safe parser
into a SymPy expression, :mod:`.section`) is generated as a numba kernel beside the
system's M and f, and the loop of :mod:`.numba_sections` evaluates it at every step's
end and locates each crossing on the step's interpolant as SciPy does (Brent's method
to 4 eps): the steps and the roots of SciPy's path, to rounding.  Python runs once per
chunk of steps (64, doubling to 4096), where ``watch`` sees the time.

A motion whose start or integration fails gives None: the caller runs it by SciPy's
path, which says why in SciPy's words.  :func:`section_loop` is None where the compiled
loops do not apply (numba missing, constraints, functions given by hand) or the section
cannot be printed for numba.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..codegen.cache import built
from ..errors import ModelError
from .compiled_dop853 import (
    FIRST_CHUNK,
    LARGEST_CHUNK,
    MIN_FACTOR,
    Loop,
    compiled_loop,
    first_step,
    loop_applies,
)
from .events import Event, scipy_event
from .guard import start_problem
from .section import Section

if TYPE_CHECKING:
    from types import ModuleType

    from ..numeric.compiled import CompiledSystem

#: Crossings kept per call of the loop before Python collects them.
FOUND_CAPACITY = 256
#: ``cross``'s status: steps taken, t_end reached, the found rows full.
MORE, REACHED, FULL = 0, 1, 4


def section_loop(compiled: CompiledSystem, section: Section) -> SectionLoop | None:
    """The jitted crossing loop of ``compiled`` and ``section`` (built once, machine code
    cached on disk), or None where it does not apply (see the module docstring)."""
    if not loop_applies(compiled):
        return None
    import sympy

    try:
        return built(
            compiled.forms.fingerprint, "dop853-section", lambda: _build(compiled, section),
            sympy.srepr(section.expression),
        )  # fmt: skip
    except ModelError:  # the section's expression has no numba form: SciPy's path reads it
        return None


@dataclass(frozen=True)
class SectionLoop:
    """The compiled crossing loop (:mod:`.numba_sections`, one for every system and
    section) with one system's DOP853 loop and one section's g (in a typed list of one)."""

    sections: ModuleType
    loop: Loop
    g: object

    def cross(self, *arguments: object) -> int:
        """The loop's ``cross`` on this system and section: its arguments after ``y_prime``,
        ``g``, ``n`` and ``tangent``."""
        loop = self.loop
        return self.sections.cross(loop.y_prime, self.g, loop.n, loop.tangent, *arguments)


def _build(compiled: CompiledSystem, section: Section) -> SectionLoop:
    from ..codegen.cache import filled_template, load_text
    from ..codegen.numba import load_functions

    loop = compiled_loop(compiled)  # the method's module and the system's y'
    kernel = load_functions(
        compiled.forms, "section", [("section", [("out", [section.expression])])]
    )
    generated = [
        f"from {loop.method.__name__} import (",
        "    accept, buffers, interpolate, interpolation, step, workspace,",
        ")",
    ]
    template = Path(__file__).with_name("numba_sections.py")
    sections = load_text(*filled_template(template, generated))
    return SectionLoop(sections, loop, sections.g(kernel.section))


def crossings(
    loop: SectionLoop,
    compiled: CompiledSystem,
    section: Section,
    y0: np.ndarray,
    params: np.ndarray,
    *,
    t_end: float,
    rtol: float,
    atol: float,
    watch: Callable[[float], None] | None = None,
) -> tuple[np.ndarray, np.ndarray] | None:
    """(times (K,), states (2n, K)) of the crossings of ``section`` by the motion from
    ``y0`` at t = 0 to ``t_end``, by DOP853 at ``rtol``/``atol``; None where the start or
    the integration failed."""
    t0 = 0.0
    y = np.array(y0, dtype=float)
    p = np.ascontiguousarray(params, dtype=float)
    if start_problem(compiled, t0, y, p) is not None:
        return None
    f = np.asarray(compiled.rhs(t0, y, p), dtype=float).copy()
    clock = np.array(
        [t0, first_step(lambda t, y: compiled.rhs(t, y, p), t0, y, f, t_end, rtol, atol)]
    )
    counts = np.array([2, 0, 0, 0, 0], dtype=np.int64)  # as advance's, then the rows found
    flags = np.zeros(1, dtype=np.int64)
    start = scipy_event(Event(section.function, section.direction), p, t0, y, f)(t0, y)
    level = np.array([start, t0, start])
    found_t, found_y = np.empty(FOUND_CAPACITY), np.empty((FOUND_CAPACITY, y.shape[0]))
    times, states = [], []
    budget, status = FIRST_CHUNK, MORE
    while status in (MORE, FULL):
        try:
            status = loop.cross(
                clock, y, f, p, t_end, rtol, atol, section.direction, level, budget,
                found_t, found_y, counts, flags,
            )  # fmt: skip
        except ZeroDivisionError:  # NumPy's inf: rejected, as SciPy rejects a NaN error
            flags[0], counts[3] = 1, 1
            clock[1] *= MIN_FACTOR
            continue
        found = int(counts[4])
        times.append(found_t[:found].copy())
        states.append(found_y[:found].copy())
        counts[4] = 0
        if watch is not None:
            watch(float(clock[0]))
        budget = min(2 * budget, LARGEST_CHUNK)
    if status != REACHED:
        return None
    return np.concatenate(times), np.concatenate(states).T
