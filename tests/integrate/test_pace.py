"""The time budget of one run (integrate.pace), on a clock the test moves."""

import pytest

import lagrangian as lg
from lagrangian.integrate import pace
from lagrangian.integrate.pace import RunPace, RunTooLong


class Clock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


@pytest.fixture
def clock(monkeypatch):
    fake = Clock()
    monkeypatch.setattr(pace, "cpu_seconds", fake)
    return fake


def test_a_run_that_keeps_its_pace_is_left_alone(clock):
    watch = RunPace((0.0, 100.0), seconds=10.0)
    for k in range(1, 101):  # 1 model second per 0.09 s: 9 s in all
        clock.now += 0.09
        watch(float(k))


def test_a_hopeless_pace_is_refused_after_the_probe_not_at_the_budget(clock):
    watch = RunPace((0.0, 1e9), seconds=300.0)
    watch(0.0)
    clock.now += 0.5
    watch(100.0)  # the pace is judged from here, once PROBE_SECONDS have passed
    clock.now += 0.9
    watch(190.0)
    clock.now += 0.2
    with pytest.raises(RunTooLong, match=r"would take about \d+ days \(t = 220 of t_end = 1e\+09"):
        watch(220.0)


def test_time_before_the_first_step_does_not_count_as_pace(clock):
    # a numba compile between the first call and the first step: 20 s at t = 0
    watch = RunPace((0.0, 10.0), seconds=60.0)
    watch(0.0)
    clock.now += 20.0
    watch(0.0)
    for k in range(1, 11):  # then 1 model second per second: 30 s in all, within 60
        clock.now += 1.0
        watch(float(k))


def test_the_budget_ends_a_run_whose_pace_looked_fine(clock):
    watch = RunPace((0.0, 10.0), seconds=5.0)
    watch(0.0)
    clock.now += 4.0
    watch(8.0)
    clock.now += 1.5  # then it slowed down
    with pytest.raises(RunTooLong, match=r"did not finish within 5 s: it reached t = 8\.5 of"):
        watch(8.5)


def test_system_simulate_stops_a_run_over_its_budget():
    system = lg.load("harmonic_oscillator")
    with pytest.raises(RunTooLong, match=r"did not finish within 0\.2 s"):
        system.simulate(t_end=1e4, method="rk4", dt=1e-3, timeout=0.2)
    with pytest.raises(lg.ModelError, match="seconds > 0"):
        system.simulate(t_end=1.0, timeout=0)


@pytest.mark.parametrize("method", ["dop853", "radau", "rk4", "variational"])
def test_every_method_tells_the_watch_the_time_reached(method):
    compiled = lg.compile_equations(lg.load("simple_pendulum").equations_of_motion())
    seen = []
    options = {"dt": 0.01} if method in ("rk4", "variational") else {}
    lg.simulate(compiled, t_end=1.0, method=method, watch=seen.append, **options)
    assert seen and max(seen) == pytest.approx(1.0, abs=0.02)
    assert seen == sorted(seen) or method in ("dop853", "radau")  # trial stages may step back


def test_the_budget_is_cpu_time_so_waiting_does_not_spend_it():
    """A run that waits (here: sleeps at every step, as on a machine busy with other work)
    spends no CPU: 0.3 s of waiting fit a budget of 0.05 s."""
    import time

    watch = RunPace((0.0, 3.0), seconds=0.05)
    for k in range(4):
        time.sleep(0.1)
        watch(float(k))


def test_a_run_computed_elsewhere_is_timed_on_a_given_clock(clock):
    watch = RunPace((0.0, 10.0), seconds=5.0, clock=lambda: clock.now * 2)
    watch(0.0)
    clock.now += 3.0  # 6 s on the given clock
    with pytest.raises(RunTooLong, match="did not finish within 5 s"):
        watch(1.0)


def test_a_pace_is_judged_once_it_has_settled(clock):
    # an ensemble on a GPU: every chunk takes 0.5 s whatever its size until it fills the
    # device, the chunks growing 8x: 256, 2048, ... members of a million; the pace from
    # the start projects 54 s after the first second (over twice the 10 s allowed), but
    # it is still improving 8x a chunk; once settled it projects 4.7 s, and the run ends
    # in 5.5 s
    watch = RunPace((0.0, 1.0), seconds=10.0, describe=lambda done: f"{done:.3g}")
    watch(0.0)
    done, size = 0, 256
    while done < 1_000_000:
        clock.now += 0.5
        done = min(1_000_000, done + size)
        watch(done / 1_000_000)
        size = min(8 * size, 131_072)
    # a steady hopeless pace is still refused a second after it settled
    watch = RunPace((0.0, 1.0), seconds=10.0, describe=lambda done: f"{done:.3g}")
    watch(0.0)
    with pytest.raises(RunTooLong, match="at its pace so far"):
        for _ in range(5):
            clock.now += 0.5
            watch(watch.reached + 0.001)


class WorkClock:
    """Seconds that the work moves (the test adds each call's cost); counts its reads."""

    def __init__(self):
        self.now, self.reads = 0.0, 0

    def __call__(self):
        self.reads += 1
        return self.now


def _run_until_refused(watch: RunPace, clock: WorkClock, cost) -> int:
    """Call ``watch`` as a run would, each call costing ``cost(calls)`` of the clock, until
    it refuses the run; the calls made."""
    calls = 0
    with pytest.raises(RunTooLong, match="did not finish within"):
        while True:
            watch(calls * 1e-3)
            calls += 1
            clock.now += cost(calls)
    return calls


def test_the_clock_is_read_every_few_milliseconds_not_at_every_call():
    # 5 us of work a call (a small system's right-hand side): half a second is 100,000
    # calls, of which under 1 % read the clock (2 us of system calls each); the budget
    # still ends the run within a read's time of it
    clock = WorkClock()
    watch = RunPace((0.0, 1e9), seconds=0.5, clock=clock)
    calls = _run_until_refused(watch, clock, lambda calls: 5e-6)
    assert calls > 99_000 and clock.reads == watch.reads < calls / 100
    assert 0.5 < clock.now <= 0.5 + pace.READ_SECONDS
    # calls that grow 8x dearer (an ensemble's chunks grow so): the stride follows at the
    # next read, the budget is overshot by 8 reads' time at most (just before it ends)
    for grown in (99_600, 99_700, 99_777):  # at about 0.498 s
        clock = WorkClock()
        watch = RunPace((0.0, 1e9), seconds=0.5, clock=clock)
        _run_until_refused(
            watch, clock, lambda calls, grown=grown: 5e-6 * (8 if calls > grown else 1)
        )
        assert 0.5 < clock.now <= 0.5 + 8 * pace.READ_SECONDS
    # a pause between two calls (2 ms here, a compile's seconds elsewhere) adds only itself
    clock = WorkClock()
    watch = RunPace((0.0, 1e9), seconds=0.5, clock=clock)
    calls = _run_until_refused(watch, clock, lambda calls: 5e-6 if calls % 10_000 else 2e-3)
    assert 0.5 < clock.now <= 0.5 + 2e-3 + pace.READ_SECONDS


@pytest.mark.parametrize("every", [1, 3])
def test_a_clock_moving_a_reads_time_a_call_is_read_at_every_call(clock, every):
    # the clocks of the tests above and of the ensemble's (moved after each chunk, not at
    # its steps): every call judged, as if each read the clock
    watch = RunPace((0.0, 100.0), seconds=10.0)
    for k in range(1, 301):
        if k % every == 0:
            clock.now += pace.READ_SECONDS * every
        watch(k / 3)
    assert watch.reads == watch.calls == 300
