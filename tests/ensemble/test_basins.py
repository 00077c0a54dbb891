"""Basins of attraction (lagrangian.ensemble.basins) against independently computed ones."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lagrangian.derive import derive
from lagrangian.ensemble.basins import basins_of_attraction
from lagrangian.facade import load
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

#: A damped particle in the double well V = -x^2/2 + x^4/4: two point attractors x = +-1,
#: the basins' boundary the stable manifold of the saddle at 0 (not a model of the project).
DOUBLE_WELL = """
name = "Damped double well"
coordinates = ["x"]
kinetic = "x_dot^2/2"
potential = "-x^2/2 + x^4/4"

[parameters]
d = 0.3

[forces]
x = "-d*x_dot"

[initial]
x = 0.1

[simulate]
t_end = 100.0
"""


@pytest.fixture(scope="module")
def well(tmp_path_factory):
    path = tmp_path_factory.mktemp("well") / "double_well.toml"
    path.write_text(DOUBLE_WELL)
    return compile_equations(derive(load(str(path))))


@functools.cache  # both parametrisations read the same starts: integrate them once
def _reference_wells(xs: tuple, vs: tuple, d=0.3, t_end=200.0):
    """The well each start (x, v) of the grid ends in (+1 or -1, indexed [x, v]), by
    scipy's DOP853 of the equations written by hand (x'' = x - x^3 - d x'), integrated
    long after every start has settled: all starts as one system (one solve_ivp, NumPy
    arrays), tolerances tightened by sqrt(size) below a single start's (rtol 1e-10, atol
    1e-12) because the error is measured as the root mean square over the whole system."""
    x0, v0 = np.meshgrid(np.asarray(xs), np.asarray(vs), indexing="ij")
    size = x0.size

    def slopes(t, y):
        x, v = y[:size], y[size:]
        return np.concatenate([v, x - x**3 - d * v])

    tighter = np.sqrt(2 * size)
    solution = solve_ivp(
        slopes, (0.0, t_end), np.concatenate([x0.ravel(), v0.ravel()]), method="DOP853",
        rtol=1e-10 / tighter, atol=1e-12 / tighter, t_eval=[t_end],
    )  # fmt: skip
    x, v = solution.y[:size, -1], solution.y[size:, -1]
    # settled: every start is below the barrier's energy (0, at the saddle x = 0), so no
    # start can cross to the other well later
    assert np.all(v**2 / 2 - x**2 / 2 + x**4 / 4 < -0.2)
    return np.sign(x).reshape(x0.shape)


@pytest.mark.slow
@pytest.mark.parametrize("basin_hits", [10, 3])
def test_double_well_basins_match_long_scipy_runs(well, basin_hits):
    grid = {"x": (-2.0, 2.0, 40), "x_dot": (-2.0, 2.0, 40)}
    basins = basins_of_attraction(well, grid=grid, interval=1.0, basin_hits=basin_hits)
    assert basins.settings["basin_hits"] == basin_hits
    assert [a.kind for a in basins.attractors] == ["fixed point", "fixed point"]
    wells = {a.label: np.sign(a.points[0, 0]) for a in basins.attractors}
    for a in basins.attractors:  # the equilibria (+-1, 0), to the cells' resolution at least
        assert abs(abs(a.points[0, 0]) - 1.0) < 1e-3 and abs(a.points[1, 0]) < 1e-3
    assert sorted(wells.values()) == [-1.0, 1.0]
    assert basins.counts()[-1] == 0
    xs, vs = basins.axes
    reference = _reference_wells(tuple(xs), tuple(vs))
    agree = np.count_nonzero(np.vectorize(wells.get)(basins.labels) == reference)
    assert agree / basins.labels.size >= 0.995
    # the map is symmetric under (x, v) -> (-x, -v): so must the basins be, where the
    # grid is (it is symmetric about 0)
    flipped = np.vectorize(wells.get)(basins.labels[::-1, ::-1])
    assert np.mean(np.vectorize(wells.get)(basins.labels) == -flipped) >= 0.995


@pytest.mark.slow
def test_starts_that_leave_the_box_get_minus_one(well):
    # both attractors (+-1, 0) lie outside the box |x| <= 0.6: every start is lost
    grid = {"x": (-0.6, 0.6, 8), "x_dot": (-0.6, 0.6, 8)}
    basins = basins_of_attraction(well, grid=grid, interval=1.0)
    assert basins.attractors == ()
    assert np.all(basins.labels == -1) and basins.counts() == {-1: 64}


@pytest.mark.slow
def test_driven_pendulum_period_two_attractors_repeat_under_scipy():
    compiled = compile_equations(derive(load("driven_damped_pendulum")))
    period = 3 * np.pi  # the drive's, omega = 2/3
    grid = {"theta": (-np.pi, np.pi, 16), "theta_dot": (-3.0, 3.0, 16)}
    basins = basins_of_attraction(compiled, grid=grid, period=period, params={"A": 1.073})
    assert [(a.kind, a.period) for a in basins.attractors] == [("periodic", 2)] * 2
    for attractor in basins.attractors:
        start = attractor.points[:, 0]
        solution = solve_ivp(
            lambda t, y: [y[1], -np.sin(y[0]) - 0.5 * y[1] + 1.073 * np.cos(2 * t / 3)],
            (0.0, 2 * period), start, method="DOP853", rtol=1e-11, atol=1e-12,
            t_eval=[period, 2 * period],
        )  # fmt: skip
        turned = np.angle(np.exp(1j * (solution.y[0] - start[0])))
        assert abs(turned[1]) < 1e-3 and abs(solution.y[1, 1] - start[1]) < 1e-3
        assert abs(turned[0]) > 0.05  # not a fixed point: period 2


@pytest.mark.slow
def test_attractors_of_period_four_are_found_while_many_starts_share_them():
    """At A = 1.081 (past the second period doubling) the driven pendulum has two attractors
    of period 4 and one of period 3.  A period as long as the chunk of iterations labelled at
    a time (4) left the starts converging together on one orbit wiping each other's marks:
    before the earliest start kept its marks, 36 % of a 60 x 60 grid ended at -1 and one
    period-4 attractor was never found.  Each start's label is checked against its own
    scipy run of 300 periods."""
    compiled = compile_equations(derive(load("driven_damped_pendulum")))
    period = 3 * np.pi
    grid = {"theta": (-np.pi, np.pi, 24), "theta_dot": (-3.0, 3.0, 24)}
    basins = basins_of_attraction(compiled, grid=grid, period=period, params={"A": 1.081})
    assert sorted(a.period for a in basins.attractors) == [3, 4, 4]
    assert basins.counts()[-1] == 0

    def attractors_of(starts):
        """Where each start ends after 296 periods, all integrated as one system (the error
        norm is an RMS over the 2k components: the tolerance divided by sqrt(2k))."""
        k = len(starts)

        def flow(t, y):
            theta, speed = y[:k], y[k:]
            return np.concatenate([speed, -np.sin(theta) - 0.5 * speed + 1.081 * np.cos(2 * t / 3)])

        tol = 1e-10 / np.sqrt(2 * k)
        solution = solve_ivp(
            flow, (0.0, 296 * period), np.concatenate([starts[:, 0], starts[:, 1]]),
            method="DOP853", rtol=tol, atol=tol, t_eval=[296 * period],
        )  # fmt: skip
        ends = solution.y[:, 0].reshape(2, k).T
        found = []
        for end in ends:  # the attractor whose orbit passes through the end point
            gaps = [
                np.hypot(np.angle(np.exp(1j * (a.points[0] - end[0]))), a.points[1] - end[1])
                for a in basins.attractors
            ]
            near = [
                a.label
                for a, gap in zip(basins.attractors, gaps, strict=True)
                if np.min(gap) < 0.02
            ]
            found.append(near[0] if near else -1)
        return found

    # the basins are intertwined finely (at (-0.137, -0.652) rk4 with 100, 200 and 400 steps
    # a period ends on three different attractors): a few starts may go either way
    starts = basins.table()
    sample = starts[np.random.default_rng(3).choice(len(starts), 20, replace=False)]
    same = [a == int(row[2]) for a, row in zip(attractors_of(sample[:, :2]), sample, strict=True)]
    assert sum(same) >= 18, same


#: m x'' = -d x' + x - x^3 + F cos(w t): at these values two attractors of period 1 of the
#: strobe map coexist, one in each well (not a model of the project).
DRIVEN_DUFFING = """
name = "Driven double-well Duffing oscillator"
coordinates = ["x"]
kinetic = "x_dot^2/2"
potential = "-x^2/2 + x^4/4"

[parameters]
d = 0.3
F = 0.2
w = 1.2

[forces]
x = "F*cos(w*t) - d*x_dot"

[initial]
x = 0.1
"""


@pytest.mark.slow
def test_driven_duffing_basins_match_long_scipy_runs(tmp_path):
    """A driven system that is not the pendulum: each start's label against where scipy's
    DOP853 (the equations written by hand; all starts as one system, the tolerance
    divided by sqrt(2k) for the RMS norm) puts it after 100 drive periods."""
    path = tmp_path / "duffing.toml"
    path.write_text(DRIVEN_DUFFING)
    compiled = compile_equations(derive(load(str(path))))
    period = 2 * np.pi / 1.2
    grid = {"x": (-2.0, 2.0, 40), "x_dot": (-2.0, 2.0, 40)}
    basins = basins_of_attraction(compiled, grid=grid, period=period)
    assert [(a.kind, a.period) for a in basins.attractors] == [("fixed point", 1)] * 2
    assert basins.counts()[-1] == 0
    x0, v0 = np.meshgrid(*basins.axes, indexing="ij")
    k = x0.size

    def flow(t, y):
        x, v = y[:k], y[k:]
        return np.concatenate([v, x - x**3 - 0.3 * v + 0.2 * np.cos(1.2 * t)])

    tol = 1e-9 / np.sqrt(2 * k)
    end = 100 * period
    solution = solve_ivp(
        flow, (0.0, end), np.concatenate([x0.ravel(), v0.ravel()]), method="DOP853",
        rtol=tol, atol=tol, t_eval=[end],
    )  # fmt: skip
    x, v = solution.y[:k, -1], solution.y[k:, -1]
    reference = np.full(k, -1)
    for attractor in basins.attractors:  # a fixed point of the strobe map: one point
        point_x, point_v = attractor.points[:, 0]
        reference[np.hypot(x - point_x, v - point_v) < 0.05] = attractor.label
    assert np.all(reference >= 0)  # every start settled on one of the two
    assert np.mean(reference == basins.labels.ravel()) >= 0.995


@pytest.mark.slow
def test_pendulum_labels_are_where_the_labellers_own_map_takes_the_starts():
    """At A = 1.073 the two basins are intertwined below the cells' size, and rounding alone
    moves about 0.8 % of the starts to the other attractor, so a peer of other arithmetic
    cannot check each label.  The labeller's own map can: the same loop over the same
    times, iterated 300 periods (every start then lies within 0.05 of an attractor
    point).  Before basin hits counted only in cells passed by starts of one attractor,
    1 of these 600 starts was labelled otherwise than its own map takes it (chunk 4)."""
    from lagrangian.ensemble import basins as walk
    from lagrangian.ensemble.numba_backend import tabulated_kernel

    compiled = compile_equations(derive(load("driven_damped_pendulum")))
    period = 3 * np.pi
    grid = {"theta": (-np.pi, np.pi, 150), "theta_dot": (-3.0, 3.0, 150)}
    basins = basins_of_attraction(compiled, grid=grid, period=period, params={"A": 1.073})
    table = basins.table()
    sample = table[np.random.default_rng(35).choice(len(table), 600, replace=False)]
    loop = tabulated_kernel(compiled, range(len(compiled.parameter_names)))
    p = np.asarray(compiled.parameter_vector({"A": 1.073}), dtype=float)
    times = period * (np.arange(walk.CHUNK * walk.STEPS + 1) / walk.STEPS)
    rows = loop.table(times, p)
    states = np.ascontiguousarray(sample[:, :2])
    final = np.empty_like(states)
    for _ in range(300 // walk.CHUNK):  # chunk after chunk, θ wrapped between, as the walk
        loop.run(states, np.repeat(p[None, :], len(states), axis=0), times, rows, 0, final,
                 np.empty((1, 1, 1)))  # fmt: skip
        states = final.copy()
        states[:, 0] = np.mod(states[:, 0] + np.pi, 2 * np.pi) - np.pi
    gaps = np.array([
        np.min(np.hypot(np.angle(np.exp(1j * (states[:, :1] - a.points[0]))),
                        states[:, 1:] - a.points[1]), axis=1)
        for a in basins.attractors
    ])  # fmt: skip
    assert np.all(np.min(gaps, axis=0) < 0.05)
    assert np.array_equal(np.argmin(gaps, axis=0), sample[:, 2].astype(int))


def test_a_grid_must_cover_the_state(well):
    from lagrangian.errors import ModelError

    with pytest.raises(ModelError, match=r"the grid must cover the whole state \(x, x_dot\)"):
        basins_of_attraction(well, grid={"x": (-1.0, 1.0, 4)}, interval=1.0)


@pytest.mark.slow
def test_a_start_kept_out_of_an_earlier_starts_cells_still_stops_at_max_iterations():
    """The labeller's paths that go on to the next point (a cell an earlier start still
    searching owns, a run in basin cells) skipped the iteration limit: a start that only
    ever met such cells was never labelled and the walk would not end."""
    from lagrangian.ensemble import basins_numba as walk

    cells = np.full(10, -1, dtype=np.int64)
    cells[3] = -(0 + 2)  # the mark of the start taken first, still searching
    status = np.array([walk.SEARCHING], dtype=np.int64)
    counters = np.zeros((1, 8), dtype=np.int64)
    settings = np.array([40, 3, 20, 5, 200, 10], dtype=np.int64)  # max_iterations 5
    walk.label(
        np.full((1, 1, 10), 3.0), np.array([1], dtype=np.int64), status, counters, cells,
        np.array([0]), np.array([0.0]), np.array([1.0]), np.array([10]), np.array([False]),
        np.array([0.0]), settings, np.zeros(1, dtype=np.int64), np.zeros((4, 200, 1)),
        np.arange(4, dtype=np.int64), np.full(2, -2, dtype=np.int64),
        np.full(10, walk.UNSEEN, dtype=np.int16), np.zeros((1, 32), dtype=np.int64),
    )  # fmt: skip
    assert status[0] == -1 and counters[0, 0] == 6
    assert cells[3] == -2  # the earlier start's mark is left alone


@pytest.mark.slow
def test_cells_passed_by_starts_of_two_attractors_label_no_start():
    """A cell of a fractal basin boundary holds points of both basins.  Before, the first
    start labelled that passed a cell made it its attractor's basin for good, and a later
    start that ran through such cells basin_hits times in a row took that label, wherever
    it went on.  Now a start passing a cell where starts of two attractors passed (MIXED)
    counts no basin hit there: the third start below ends on attractor 1's cells and is
    labelled 1 (before: 0, from the first start's cells 2, 3, 4)."""
    from lagrangian.ensemble import basins_numba as walk

    cells = np.full(10, -1, dtype=np.int64)
    cells[8], cells[9] = 0, 1  # the cells of attractors 0 and 1, found before
    paths = np.array([[2, 3, 4, 8, 8, 8, 8], [2, 3, 4, 9, 9, 9, 9], [2, 3, 4, 2, 9, 9, 9]])
    status = np.full(3, walk.SEARCHING, dtype=np.int64)
    counters = np.zeros((3, 8), dtype=np.int64)
    seen = np.full(10, walk.UNSEEN, dtype=np.int16)
    done = np.full(3, -2, dtype=np.int64)
    settings = np.array([40, 3, 20, 2000, 200, 4], dtype=np.int64)  # basin hits 4
    for b in range(3):  # one start after another, each done before the next, as the walk does
        walk.label(
            paths[b : b + 1, None, :].astype(float), np.array([b], dtype=np.int64),
            status[b : b + 1], counters[b : b + 1], cells, np.array([0]), np.array([0.0]),
            np.array([1.0]), np.array([10]), np.array([False]), np.array([0.0]), settings,
            np.array([2], dtype=np.int64), np.zeros((4, 200, 1)), np.arange(4, dtype=np.int64),
            done, seen, np.zeros((1, 32), dtype=np.int64),
        )  # fmt: skip
        done[b] = status[b]
    assert status.tolist() == [0, 1, 1]
    assert seen[[2, 3, 4]].tolist() == [walk.MIXED] * 3 and seen[8] == 0 and seen[9] == 1
