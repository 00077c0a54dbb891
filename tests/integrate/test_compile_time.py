"""A run's ``compile_time`` holds the first call of its y' (integrate.simulate): the code
that call makes (the llvm backend's JIT, NumPy's functions, LAPACK loaded) is paid in the
compile phase on every path, not in the run.  Measured by the test itself: each of L, M
and y' wrapped, the CPU time of its first call recorded, and the call of ``solve`` timed;
no absolute time limit, only quantities of the same process compared."""

from __future__ import annotations

import dataclasses
import importlib.util
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.codegen.llvm import llvm_available
from lagrangian.integrate import simulate
from lagrangian.integrate.base import AbstractIntegrator
from lagrangian.integrate.compiled_loop import CompiledLoop
from lagrangian.integrate.registry import method_class
from lagrangian.numeric import compile_equations
from lagrangian.numeric.compile import default_backend

#: A model no other test compiles, so that its code is made here: ``{n}`` differs between
#: the tests (code is made once per process, or per cache, for each set of equations).
COUPLED = """
name = "coupled pair {n}"
coordinates = ["x", "y"]
parameters = {{ m = 1.0, k = 1.5 }}
kinetic = "m*(x_dot^2 + y_dot^2)/2 + x_dot*y_dot*cos(x - y)/3"
potential = "k*(x^2 + y^2)/2 + x^2*y/{n}"
[initial]
x = 0.3
y = -0.2
"""


class FirstCall:
    """``function`` of (t, state..., params) with the CPU seconds of its first call at one
    state kept (``seconds``): the call that makes its code (a batch of states goes to the
    NumPy functions on the llvm backend, code of its own)."""

    def __init__(self, function):
        self.function, self.seconds = function, None

    def __call__(self, *args):
        if self.seconds is not None or np.ndim(args[1]) != 1:
            return self.function(*args)
        began = time.process_time()
        try:
            return self.function(*args)
        finally:
            self.seconds = time.process_time() - began


def _timed(monkeypatch, cls, name: str) -> list:
    """The CPU seconds of each call of ``cls.name`` (a method), kept in the list returned."""
    seconds = []
    method = getattr(cls, name)

    def timed(self, *args, **keywords):
        began = time.process_time()
        try:
            return method(self, *args, **keywords)
        finally:
            seconds.append(time.process_time() - began)

    monkeypatch.setattr(cls, name, timed)
    return seconds


def _runs(monkeypatch, system: lg.System, backend: str, method):
    """(first trajectory, second, CPU of the first call of simulate, CPU in its solve, CPU
    of the first calls of L, M and y' and of the integrator's prepare) of two runs of a new
    system in this process."""
    compiled = compile_equations(system.equations_of_motion(), backend=backend)
    wrapped = {
        name: FirstCall(getattr(compiled, name)) for name in ("lagrangian", "mass_matrix", "rhs")
    }
    compiled = dataclasses.replace(compiled, **wrapped)
    cls = type(method) if isinstance(method, AbstractIntegrator) else method_class(method)
    preparing = _timed(monkeypatch, cls, "prepare")
    solving = _timed(monkeypatch, AbstractIntegrator, "solve")
    began = time.process_time()
    first = simulate(compiled, t_end=0.5, method=method)
    total = time.process_time() - began
    second = simulate(compiled, t_end=0.5, method=method)
    assert first.status == second.status == "success"
    assert wrapped["rhs"].seconds > 0.0  # y' was called at one state: its first call timed
    made = sum(w.seconds for w in wrapped.values()) + preparing[0]
    return first, second, total, solving[0], made


def _check(first, second, total, solving, made):
    compile_time = first.attrs["compile_time"]
    # the first calls (y''s too) and the preparation lie inside the timed compile phase
    assert compile_time >= made
    # the compile phase and the solve are parts of the call, neither counted twice
    assert compile_time + solving <= total
    # the second run makes nothing: its compile phase is a small part of the first's
    assert second.attrs["compile_time"] < made / 10


LLVM = pytest.mark.skipif(not llvm_available(), reason="SymEngine without LLVM")


@pytest.mark.parametrize(
    ("n", "backend", "method"),
    [
        pytest.param(3, "llvm", "dop853", marks=LLVM, id="llvm-scipy-dop853"),
        pytest.param(5, "llvm", "rk4", marks=LLVM, id="llvm-rk4-step-from-the-motion"),
        (7, "numpy", "dop853"),
        (11, "numpy", "radau"),
    ],
)
def test_the_first_call_of_y_prime_is_compile_time(monkeypatch, n, backend, method):
    _check(*_runs(monkeypatch, lg.loads(COUPLED.format(n=n)), backend, method))


@LLVM
@pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="numba not installed")
@pytest.mark.slow  # numba compiles the DOP853 method module once per cache: 7 s of CPU
def test_the_linked_loop_counts_the_first_call_of_y_prime_too(monkeypatch):
    # DOP853's compiled loop over the LLVM code of M and f (the CLI's choice for a new
    # system): its own y' steps, and compiled.rhs is called once, at the start check
    linked = dataclasses.replace(method_class("dop853").configure(t_span=(0.0, 0.5)), linked=True)
    first, *rest = _runs(monkeypatch, lg.loads(COUPLED.format(n=13)), "llvm", linked)
    assert first.attrs["compiled"]  # the loop ran
    _check(first, *rest)


@pytest.mark.skipif(importlib.util.find_spec("heyoka") is None, reason="heyoka not installed")
def test_a_taylor_run_counts_the_first_call_of_y_prime_besides_heyokas_build(monkeypatch):
    system = lg.loads(COUPLED.format(n=17))
    first, *rest = _runs(monkeypatch, system, default_backend(), "taylor")
    assert first.attrs["compiled"].startswith("heyoka's Taylor integrator")
    _check(first, *rest)


def check_the_double_pendulum() -> None:
    """The checks on the double pendulum's default run (dop853, on the default backend),
    for a fresh interpreter (test below): nothing of it made before."""
    with pytest.MonkeyPatch.context() as monkeypatch:
        system = lg.load("double_pendulum")
        _check(*_runs(monkeypatch, system, default_backend(), "dop853"))


@pytest.mark.slow  # a fresh interpreter derives and compiles the double pendulum
def test_in_a_fresh_process_the_first_call_of_y_prime_is_compile_time():
    tests = str(Path(__file__).resolve().parents[1])
    code = (
        f"import sys; sys.path.insert(0, {tests!r}); "
        "from integrate.test_compile_time import check_the_double_pendulum as check; check()"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]


@pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="numba not installed")
@pytest.mark.slow  # numba compiles a new system's functions and loops: seconds of CPU
@pytest.mark.parametrize(("n", "method"), [(19, "rk4"), (23, "variational")])
def test_a_fixed_step_loop_is_made_before_the_run_on_the_numba_backend(monkeypatch, n, method):
    """The generated loop of a single rk4 or variational run (integrate.compiled_loop) is
    compiled by the integrator's prepare, not by its first march: the first run's march
    costs about what the second's does (the same steps), and compile_time holds the rest."""
    marching = _timed(monkeypatch, CompiledLoop, "march")
    first, second, total, solving, made = _runs(
        monkeypatch, lg.loads(COUPLED.format(n=n)), "numba", method
    )
    _check(first, second, total, solving, made)
    assert len(marching) == 2  # each run marched in the compiled loop
    assert marching[0] < 3 * marching[1] + made / 100
