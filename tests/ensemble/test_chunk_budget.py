"""An ensemble keeps its time budget: chunks sized by measured time, on a clock the test
moves (each member costs a fixed amount of it), never the wall clock: numpy (CPU time),
cuda (its kernel built for the CPU, timed on the wall clock as on a GPU) and dask (its
tasks run in this process by a stand-in for ``distributed``, each timed on its worker's
wall clock).  jax compiles per chunk size: its chunks keep one size."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import core, dask_backend, ensemble_of_system, run_ensemble
from lagrangian.ensemble.chunk import Chunks
from lagrangian.ensemble.cuda_cpu import CudaOnCpuBackend, compiler
from lagrangian.ensemble.jax_backend import JaxBackend
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


class _InProcessDistributed:
    """A ``distributed`` whose tasks run here when submitted, on one worker of
    ``threads`` threads; ``as_completed`` hands them back in order, taking more."""

    class KilledWorker(Exception):
        pass

    def __init__(self, threads: int):
        self.threads, self.in_flight = threads, []

    def LocalCluster(self, **options):
        return self

    def Client(self, *args, **options):
        return self

    def close(self):
        pass

    def scatter(self, payload, broadcast):
        return payload

    def nthreads(self):
        return {"worker": self.threads}

    def scheduler_info(self):
        return {"workers": {"worker": {}}}

    def submit(self, function, *args, pure=True, key=None):
        # as dask does, a future given as an argument reaches the task as its result
        args = [a.result() if isinstance(a, _Done) else a for a in args]
        self.in_flight.append(object())
        return _Done(function(*args))

    def as_completed(self, futures):
        return _Completing(futures)


class _Done:
    def __init__(self, value):
        self.value = value

    def result(self):
        return self.value


class _Completing:
    def __init__(self, futures):
        self.queue = list(futures)

    def __iter__(self):
        while self.queue:
            yield self.queue.pop(0)

    def add(self, future):
        self.queue.append(future)


def _charging(monkeypatch, clock, backend):
    """Every chunk ``backend`` integrates is charged to ``clock``, which stands for the
    CPU time here and the wall clock of runs elsewhere (a GPU, the dask workers)."""
    integrate = backend.integrate

    def charged(self, chunk, progress=None):
        clock.sizes.append(chunk.count)
        result = integrate(self, chunk, progress)
        clock.now += clock.per_member * chunk.count
        return result

    monkeypatch.setattr(backend, "integrate", charged)
    for module, name in ((core, "cpu_seconds"), (core, "wall_seconds"), (pace, "cpu_seconds")):
        monkeypatch.setattr(module, name, clock)
    monkeypatch.setattr(dask_backend, "task_seconds", clock)


def _cuda_on_cpu(monkeypatch):
    if compiler() is None:
        pytest.skip("no C compiler (gcc) for the CPU build of the cuda kernel")
    backends = dict(core.ENSEMBLE_BACKENDS) | {"cuda": CudaOnCpuBackend}
    monkeypatch.setattr(core, "ENSEMBLE_BACKENDS", backends)
    return "cuda", CudaOnCpuBackend


def _dask_in_process(monkeypatch):
    cloudpickle = pytest.importorskip("cloudpickle")
    pytest.importorskip("distributed")
    fake = _InProcessDistributed(threads=2)
    monkeypatch.setattr(dask_backend, "_distributed", lambda: (fake, cloudpickle))
    return "dask", NumpyBackend  # the task integrates its chunk with the numpy backend


OTHER_BACKENDS = {
    "cuda": _cuda_on_cpu,
    "dask": _dask_in_process,
}


@pytest.mark.parametrize("which", list(OTHER_BACKENDS))
def test_every_backend_sizes_its_chunks_by_time_and_keeps_the_budget(monkeypatch, which):
    # as the numpy backend above: 15 s of work for a budget of 10 s, checked between
    # chunks of about 1.5 % of it
    backend, integrating = OTHER_BACKENDS[which](monkeypatch)
    clock = CostClock(per_member=1e-3)
    _charging(monkeypatch, clock, integrating)
    system = lg.load("harmonic_oscillator")
    grid = {"x": np.linspace(-1.0, 1.0, 15_000)}
    with pytest.raises(RunTooLong, match="did not finish within 10 s"):
        ensemble_of_system(
            system, initial=grid, t_end=0.1, dt=0.05, timeout=10.0, backend=backend,
            method="rk4",
        )  # fmt: skip
    assert 10.0 < clock.now <= 10.0 * 1.03
    untimed = 2 if which == "dask" else 1  # made before a first chunk's time is known
    assert set(clock.sizes[:untimed]) == {256} and max(clock.sizes[untimed:]) <= 150


class _Sized:
    def __init__(self, count: int):
        self.count = count


def _sizes(seconds: float, latency: float, per_member: float, *, count=500_000, **options):
    """The chunk sizes of a run whose chunks take ``latency + per_member * members``."""
    made = Chunks(lambda start, stop: stop - start, count, 65_536, seconds=seconds, **options)
    for size in made:
        made.took(_Sized(size), latency + per_member * size)
    return made.sizes


def test_jax_chunks_keep_one_size(monkeypatch, oscillator):
    # each new batch size would cost a compile (seconds): chunks of chunk_size, budget or not
    pytest.importorskip("jax")
    clock = CostClock(per_member=1e-3)
    _charging(monkeypatch, clock, JaxBackend)
    grid = {"x": np.linspace(-1.0, 1.0, 2_000)}
    kw = dict(initial=grid, t_end=0.1, dt=0.05, backend="jax", chunk_size=700)
    run_ensemble(oscillator, chunk_seconds=0.5, **kw)
    assert clock.sizes == [700, 700, 600]


def test_chunks_grow_past_a_latency_as_on_a_gpu():
    # 0.1 s whatever the size (a GPU thread runs the whole loop) plus 10 us a member:
    # the first chunk looks like 0.4 ms a member, the second tells the latency apart, and
    # the chunks then spend the 0.4 s left of 0.5 on 40,000 members
    sizes = _sizes(0.5, 0.1, 1e-5)
    assert sizes[:3] == [256, 1248, 9984]
    assert all(39_990 <= size <= 40_000 for size in sizes[3:-1])
    # a latency over half the time asked: as long again on the members (at least half
    # of the time goes to the work): 0.3 s, 30,000 members; 1 s, 100,000 (the largest)
    assert all(29_990 <= size <= 30_000 for size in _sizes(0.5, 0.3, 1e-5)[4:-1])
    # 1 s: the first chunk (256 in 1 s) asks fewer, 127, which take as long: then growth
    assert _sizes(0.5, 1.0, 1e-5)[:6] == [256, 127, 1016, 8128, 65024, 65_536]
