"""A Lyapunov run keeps to its budget (issue 37, item 3).

The watch (the run's time budget) was told the time only after each interval and after
the whole transient: ``--transient 1e12`` was one solve that never reported back, and
y' = NaN at the start shrank the step without end inside the first interval; both ran
past ``--timeout`` for minutes.  The watch is now told as the steps go, and a start
where the equations have no finite value is refused as ``simulate`` refuses it.
"""

from __future__ import annotations

import importlib.util

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate.lyapunov import lyapunov_spectrum
from lagrangian.integrate.pace import RunTooLong
from lagrangian.numeric import compile_equations

BACKENDS = ["numpy"] + (["numba"] if importlib.util.find_spec("numba") else [])


class Told(Exception):
    """Raised by a watch: where the run was when the watch was first told."""


def _first_told(t: float) -> None:
    raise Told(t)


@pytest.fixture(scope="module")
def henon_heiles():
    return lg.load("henon_heiles")


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_watch_is_told_during_the_transient(henon_heiles, backend):
    compiled = compile_equations(henon_heiles.equations_of_motion(), backend=backend)
    with pytest.raises(Told) as told:
        lyapunov_spectrum(compiled, t_end=1.0, transient=400.0, watch=_first_told)
    assert 0.0 <= told.value.args[0] < 400.0  # it was told at the end of the transient alone


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_watch_is_told_during_an_interval(henon_heiles, backend):
    compiled = compile_equations(henon_heiles.equations_of_motion(), backend=backend)
    with pytest.raises(Told) as told:
        lyapunov_spectrum(compiled, t_end=400.0, interval=400.0, count=1, watch=_first_told)
    assert 0.0 <= told.value.args[0] < 400.0


def test_a_transient_too_long_for_the_budget_is_refused_by_its_pace(henon_heiles):
    with pytest.raises(RunTooLong) as refused:
        henon_heiles.lyapunov(transient=1e12, t_end=10, count=1, timeout=1)
    # refused by its pace, or at the end of its budget on a machine slow to compile
    assert "t = 1e+12" not in str(refused.value)
    assert " of 1e+12, a transient of 1e+12 and then t_end = 10" in str(refused.value)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_start_without_a_finite_right_hand_side_is_refused_as_simulate_refuses_it(backend):
    system = lg.System.from_lagrangian("x_dot^2/2 - sqrt(x)", coordinates=["x"])
    expected = "the right-hand side is not finite at t = 0 (x = -1, x_dot = 0)"
    with pytest.raises(ModelError, match=r"^the right-hand side is not finite at t = 0 \("):
        system.lyapunov(t_end=5, initial={"x": -1.0}, backend=backend, timeout=5)
    simulated = system.simulate(t_end=5, initial={"x": -1.0})
    assert simulated.status == "failed"
    assert expected in simulated.dataset.attrs["message"]
