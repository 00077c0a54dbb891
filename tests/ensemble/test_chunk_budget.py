"""An ensemble keeps its time budget: chunks sized by measured CPU time, on a clock the
test moves (each member costs a fixed amount of it), never the wall clock."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import core, ensemble_of_system, run_ensemble
from lagrangian.ensemble.numpy_backend import NumpyBackend
from lagrangian.integrate import pace
from lagrangian.integrate.pace import RunTooLong
from lagrangian.numeric import compile_equations


class CostClock:
    """CPU seconds that advance by ``per_member`` for every member integrated."""

    def __init__(self, per_member: float):
        self.now, self.per_member, self.sizes = 0.0, per_member, []

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def costly(monkeypatch):
    """The clock, with every chunk the numpy backend integrates charged to it."""
    clock = CostClock(per_member=1e-3)
    integrate = NumpyBackend.integrate

    def charged(self, chunk, progress=None):
        clock.sizes.append(chunk.count)
        result = integrate(self, chunk, progress)
        clock.now += clock.per_member * chunk.count  # spent while integrating
        return result

    monkeypatch.setattr(NumpyBackend, "integrate", charged)
    monkeypatch.setattr(core, "cpu_seconds", clock)
    monkeypatch.setattr(pace, "cpu_seconds", clock)
    return clock


@pytest.fixture(scope="module")
def oscillator():
    return compile_equations(lg.load("harmonic_oscillator").equations_of_motion())


def test_chunks_sized_by_time_start_small_then_take_the_time_asked(costly, oscillator):
    # 1 ms a member, 0.5 s a chunk: 256 members first, then 500 at a time
    grid = {"x": np.linspace(-1.0, 1.0, 2_000)}
    timed = run_ensemble(oscillator, initial=grid, t_end=0.1, dt=0.05, chunk_seconds=0.5)
    assert costly.sizes == [256, 500, 500, 500, 244]
    costly.sizes.clear()
    fixed = run_ensemble(oscillator, initial=grid, t_end=0.1, dt=0.05, chunk_size=700)
    assert costly.sizes == [700, 700, 600]  # without a budget: the fixed count
    np.testing.assert_array_equal(timed.final_state["x"], fixed.final_state["x"])


def test_a_chunk_grows_at_most_eightfold_and_never_past_chunk_size(costly, oscillator):
    costly.per_member = 1e-6  # cheap members: the size asked would be 500,000
    grid = {"x": np.linspace(-1.0, 1.0, 30_000)}
    run_ensemble(oscillator, initial=grid, t_end=0.1, dt=0.05, chunk_seconds=0.5, chunk_size=9000)
    assert costly.sizes[:3] == [256, 2048, 9000]


def test_an_ensemble_over_its_budget_stops_within_a_few_percent_of_it(costly):
    # 15,000 members of 1 ms: 15 s of work, a pace within twice the budget of 10 s (not
    # refused early), so it runs until the budget is spent, checked between chunks of
    # 1.5 % of it (one chunk of 65,536 members was 65 s: 6.5 budgets)
    system = lg.load("harmonic_oscillator")
    grid = {"x": np.linspace(-1.0, 1.0, 15_000)}
    with pytest.raises(RunTooLong, match="did not finish within 10 s"):
        ensemble_of_system(system, initial=grid, t_end=0.1, dt=0.05, timeout=10.0)
    assert 10.0 < costly.now <= 10.0 * 1.03
    assert max(costly.sizes[1:]) <= 150
