"""SymPy's solve of G = 0 in a forked child process, ended after a CPU-time budget.

SymPy cannot be interrupted safely from outside a pure-Python call that holds
no checkpoints (``solve`` on a hard system may run for minutes), so the solve
runs in a child process that ends when its time is up.  The time is the child's
own CPU time (its ``ITIMER_PROF``), as every budget (:mod:`lagrangian.budget`),
so a busy machine gives the same answer as a quiet one; waiting for the child
costs the parent no CPU, so the child's time is charged to the parent's deadlines
once it has been waited for (:func:`lagrangian.budget.recount`).  The parent also
stops waiting after ``WALL_FACTOR`` times the budget in wall time: a backstop for
a child that makes no progress at all (stopped, or starved of CPU), never reached
at the loads the budgets are sized for.  While the child solves, the parent may do other
work that does not need the answer (the numerical search for equilibria): the two then run
side by side on two cores.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import multiprocessing
import os
import pickle
import signal
import time
import warnings

import sympy

from ..budget import recount

#: Largest number of factor combinations solved symbolically.
MAX_COMBINATIONS = 64
#: Wall time the parent waits, in multiples of the child's CPU budget (plus WALL_EXTRA
#: seconds): a child beside 18 busy processes on two cores gets a tenth of a core.
WALL_FACTOR, WALL_EXTRA = 30.0, 5.0


def solve_factored(
    equations: list[sympy.Expr], unknowns: list[sympy.Symbol], *, simplify: bool = True
) -> list[dict]:
    """Solutions of the equations, each split into its factors (a product is zero
    when one factor is), with those that make a denominator vanish dropped; ``simplify``:
    SymPy's own simplification of each solution (3/4 of its time on a slider-crank's
    pinned loop closures: off where the caller tidies what it keeps)."""
    options = []
    denominators = []
    for equation in equations:
        numerator, denominator = sympy.fraction(sympy.together(equation))
        if not numerator.has(*unknowns):
            return []  # a condition on the parameters alone: no solution for generic values
        denominators.append(denominator)
        factors = [f for f, _ in sympy.factor_list(numerator)[1] if f.has(*unknowns)]
        options.append(factors or [numerator])
    if math.prod(len(o) for o in options) > MAX_COMBINATIONS:
        options = [[sympy.fraction(sympy.together(e))[0]] for e in equations]
    solutions: list[dict] = []
    for combination in itertools.product(*options):
        for solution in sympy.solve(list(combination), unknowns, dict=True, simplify=simplify):
            if any(d.xreplace(solution).is_zero for d in denominators):
                continue
            if solution and solution not in solutions:
                solutions.append(solution)
    return solutions


def in_child(function, arguments: tuple, timeout: float, *, meanwhile=None):
    """``function(*arguments)`` in a forked process; None on error or after ``timeout``
    CPU seconds of the child.

    ``meanwhile()``, when given, runs in this process while the child works (the two
    share the machine's cores: the numerical search for equilibria beside SymPy's solve);
    an error it raises ends the child.
    """
    if "fork" not in multiprocessing.get_all_start_methods():
        if meanwhile is not None:
            meanwhile()
        return None
    context = multiprocessing.get_context("fork")
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(
        target=_child, args=(sender, function, arguments, timeout), daemon=True
    )
    try:
        with warnings.catch_warnings(), _deadlines_held():
            # JAX warns at every fork that its threads may hold locks.  The child runs only
            # SymPy (pure Python), never XLA, and glibc's malloc is fork-safe; a fork server
            # or spawn would re-run the user's __main__ script, which is worse.
            warnings.filterwarnings(
                "ignore", message=r"os\.fork\(\) was called", category=RuntimeWarning
            )
            process.start()
        sender.close()
        patience = time.monotonic() + WALL_FACTOR * timeout + WALL_EXTRA
        if meanwhile is not None:
            meanwhile()
        return _received(receiver, max(0.0, patience - time.monotonic()))
    finally:
        sender.close()
        receiver.close()
        if process.is_alive():
            process.kill()
        if process.pid is not None:
            process.join()
        recount()  # the child's CPU time is on the clock now: charge it to the deadlines


@contextlib.contextmanager
def _deadlines_held():
    """The deadlines' signal held back while the block runs (delivered after it).

    A deadline raises from its signal handler wherever the main thread is; inside fork's
    handlers (logging's, releasing its lock after the fork) the error would be lost and
    the lock left taken.  Held across the fork, it is raised after it, here."""
    if not hasattr(signal, "pthread_sigmask") or not hasattr(signal, "SIGPROF"):
        yield
        return
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGPROF})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGPROF})


def _received(receiver, wait: float):
    """What the child sent within ``wait`` seconds (wall), or None."""
    try:
        if receiver.poll(wait):
            ok, result = receiver.recv()
            return result if ok else None
        return None
    except (EOFError, OSError, pickle.UnpicklingError, AttributeError, TypeError):
        return None  # the child died or sent something unreadable: use the numerical route


def _child(sender, function, arguments, seconds: float) -> None:
    if hasattr(signal, "pthread_sigmask"):  # the mask is inherited: the parent held SIGPROF
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGPROF})
    if hasattr(signal, "ITIMER_PROF"):  # timers are not inherited across fork: arm ours
        signal.signal(signal.SIGPROF, _out_of_time)
        signal.setitimer(signal.ITIMER_PROF, max(seconds, 1e-6))
    try:
        result = (True, function(*arguments))
    except Exception:
        result = (False, None)
    if hasattr(signal, "ITIMER_PROF"):  # decided within the budget: sending it is not cut
        signal.setitimer(signal.ITIMER_PROF, 0)
    try:
        sender.send(result)
    except Exception:
        sender.send((False, None))
    finally:
        sender.close()


def _out_of_time(signum, frame) -> None:
    os._exit(0)  # nothing sent: the parent reads the closed pipe as "no result"
