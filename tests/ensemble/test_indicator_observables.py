"""The ensemble observables sali and gali<k>: a regular and a chaotic orbit, agreement
with the lyapunov observable's classification, refusals."""

from __future__ import annotations

import importlib.util
import re

import numpy as np
import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.derive import derive
from lagrangian.ensemble import run_ensemble
from lagrangian.errors import ModelError
from lagrangian.facade import load
from lagrangian.integrate.indicators import SALI_BELOW
from lagrangian.numeric import compile_equations

#: Two uncoupled oscillators of incommensurate frequencies 1 and sqrt(2): integrable, every
#: orbit on a torus (not a model of the project).
OSCILLATORS = """
name = "Two oscillators"
coordinates = ["x", "y"]
kinetic = "(x_dot^2 + y_dot^2)/2"
potential = "x^2/2 + y^2"

[initial]
x = 0.3
y = 0.2
"""


#: The compiled backend where numba is installed (its loops are compiled once per test
#: session, in the suite's code cache), else numpy's.
FAST = "numba" if importlib.util.find_spec("numba") else "numpy"


@pytest.fixture(scope="module")
def henon_heiles():
    return compile_equations(derive(load("henon_heiles")))


def _shell(y, py, energy=0.125):
    """Starts on x = 0 of the energy shell of Hénon–Heiles (x' > 0 from the energy)."""
    y, py = np.asarray(y, dtype=float), np.asarray(py, dtype=float)
    kinetic = 2 * (energy - (y**2 / 2 - y**3 / 3)) - py**2
    return {"x": 0 * y, "y": y, "x_dot": np.sqrt(kinetic), "y_dot": py}


def test_sali_stays_of_order_one_on_an_integrable_system(tmp_path):
    path = tmp_path / "oscillators.toml"
    path.write_text(OSCILLATORS)
    compiled = compile_equations(derive(load(str(path))))
    result = run_ensemble(
        compiled, initial={"x": [0.3, 1.0], "y": [0.2, -0.5]}, t_end=100.0, dt=0.05,
        observables=("sali", "gali2"),
    )  # fmt: skip
    dataset = result.dataset
    assert np.all(dataset["sali"].values > 0.05) and not np.any(dataset["sali_chaotic"].values)
    assert np.all(dataset["gali2"].values > 0.05)


@pytest.mark.slow
def test_sali_decays_on_the_chaotic_orbit_and_not_on_the_regular_one(henon_heiles):
    # y = -0.25 is in the chaotic sea at E = 1/8 (largest exponent ~0.047), y = 0.1,
    # p_y = 0.3 on a torus around an island.  Asked alone, sali stops each member at its
    # first step below SALI_BELOW: the chaotic one after a few hundred time units (SALI
    # falls like exp(-0.047 t), below 1e-4 near t = 200), with its SALI then just below
    # 1e-4 (one step earlier it was above: a step changes it by a few percent at most),
    # where running on would take it to rounding (1e-16) by t = 800
    # (on the compiled backend where there is one: the numpy backend stops its members
    # at the same steps, test_the_numba_backend_gives_the_numpy_backends_indicators)
    starts = _shell([-0.25, 0.1], [0.0, 0.3])
    result = run_ensemble(
        henon_heiles, initial=starts, t_end=500.0, dt=0.05, observables="sali", backend=FAST
    )
    dataset = result.dataset
    chaotic, regular = 0, 1
    assert 150.0 < dataset["sali_time"].values[chaotic] < 450.0
    assert 0.8 * SALI_BELOW < dataset["sali"].values[chaotic] < SALI_BELOW
    assert np.isnan(dataset["sali_time"].values[regular])
    assert dataset["sali"].values[regular] > 1e-2
    assert dataset["sali_chaotic"].values.tolist() == [True, False]
    # w_1 is the lyapunov observable's displacement: its exponent is that of a lyapunov run
    both = run_ensemble(
        henon_heiles, initial=starts, t_end=20.0, dt=0.05, observables=("sali", "lyapunov")
    )
    alone = run_ensemble(henon_heiles, initial=starts, t_end=20.0, dt=0.05, observables="lyapunov")
    assert np.allclose(alone.dataset["lyapunov"], both.dataset["lyapunov"], rtol=1e-12)


#: Starts on the benchmark's grid (benchmarks/indicators.py --size 16: y, p_y indices) whose
#: class the exponent at t = 4000 and at t = 10000 agree on (benchmarks/README.md): four
#: regular ones, SALI's lowest by t = 1200 from 9e-4 to 2e-2; three weakly chaotic ones
#: (exponents 0.019, 0.049, 0.053 at t = 4000) whose SALI falls below 1e-4 only at
#: t = 505, 583 and 712; two in the chaotic sea (crossing at t = 164 and 133)
REGULAR = ((13, 11), (6, 11), (5, 3), (4, 4))
WEAKLY_CHAOTIC = ((3, 1), (4, 1), (5, 5))
CHAOTIC = ((7, 2), (4, 9))


@pytest.mark.slow
def test_the_sali_and_gali3_maps_agree_with_the_lyapunov_map(henon_heiles):
    # the rule: SALI below 1e-4 at some step up to t_end (800 here, a fifth of the
    # exponent's run); the value at t_end below 1e-8, the rule before, misses the weakly
    # chaotic starts.  GALI_3 at t_end below 1e-8.  All on the compiled backend (the
    # numpy backend's values to rounding: the test above); one loop (3 vectors) for both.
    indices = np.array([*REGULAR, *WEAKLY_CHAOTIC, *CHAOTIC])
    y_grid, py_grid = np.linspace(-0.45, 0.7, 16), np.linspace(-0.5, 0.5, 16)
    starts = _shell(y_grid[indices[:, 0]], py_grid[indices[:, 1]])
    settings = {"initial": starts, "dt": 0.05, "backend": FAST}
    lyapunov = run_ensemble(
        henon_heiles, t_end=4000.0, observables=("lyapunov", "gali3"), **settings
    ).dataset["lyapunov"].values  # fmt: skip
    chaotic = lyapunov > 0.01
    assert chaotic.tolist() == [False] * len(REGULAR) + [True] * (len(indices) - len(REGULAR))
    indicators = run_ensemble(
        henon_heiles, t_end=800.0, observables=("sali", "gali3"), **settings
    ).dataset
    assert indicators["sali_chaotic"].values.tolist() == chaotic.tolist()
    assert indicators["gali3_chaotic"].values.tolist() == chaotic.tolist()
    # SALI at t_end of the first weakly chaotic start is back above 1e-5 (3e-5 at t = 750
    # in the study, after 8.6e-6): the old rule, SALI at t_end below 1e-8, calls it regular
    assert indicators["sali"].values[len(REGULAR)] > 1e-8


@pytest.mark.slow
def test_the_numba_backend_gives_the_numpy_backends_indicators(henon_heiles):
    # the k displacements of codegen.steps.rk4_tangent, renormalised in the numba loop,
    # against the numpy backend's TangentFlows: the same rk4 steps from the same starting
    # vectors, so the same values to rounding (a chaotic, a regular and two more starts)
    pytest.importorskip("numba")
    starts = _shell([-0.25, 0.1, 0.0, 0.3], [0.0, 0.3, 0.1, -0.2])
    names = ("sali", "gali2", "gali4", "lyapunov", "final_state")
    numpy = run_ensemble(henon_heiles, initial=starts, t_end=40.0, dt=0.05, observables=names)
    numba = run_ensemble(
        henon_heiles, initial=starts, t_end=40.0, dt=0.05, observables=names, backend="numba"
    )
    for name in ("sali", "gali2", "gali4", "lyapunov", "final_x", "final_y_dot"):
        np.testing.assert_allclose(numba.dataset[name], numpy.dataset[name], rtol=1e-10)
    # four different values, none at a limit (orthogonal, aligned)
    assert np.all((numpy.dataset["gali4"].values > 1e-9) & (numpy.dataset["sali"].values < 1.4))
    assert len(set(np.round(numpy.dataset["sali"].values, 6))) == 4
    # sali alone: each member stops at its first step below 1e-4, at the same step on
    # both backends (the first and the last start cross before t = 200)
    numpy = run_ensemble(henon_heiles, initial=starts, t_end=200.0, dt=0.05, observables="sali")
    numba = run_ensemble(
        henon_heiles, initial=starts, t_end=200.0, dt=0.05, observables="sali", backend="numba"
    )
    crossing = numpy.dataset["sali_time"].values
    assert np.isfinite(crossing[[0, 3]]).all() and np.isnan(crossing[1])  # the regular one
    np.testing.assert_array_equal(numba.dataset["sali_time"].values, crossing)
    np.testing.assert_allclose(numba.dataset["sali"], numpy.dataset["sali"], rtol=1e-8)


def test_indicators_are_refused_where_they_are_not_computed(henon_heiles):
    with pytest.raises(
        ModelError, match=r"^observable sali runs on backend numpy, numba, not jax$"
    ):
        run_ensemble(henon_heiles, t_end=1.0, observables=("sali",), backend="jax")
    with pytest.raises(ModelError, match=r"^the chaos indicator observable needs an explicit"):
        run_ensemble(henon_heiles, t_end=1.0, observables=("sali",), method="variational")
    pendulum = compile_equations(derive(load("simple_pendulum")))
    with pytest.raises(
        ModelError,
        match=r"^observable gali3 needs 3 deviation vectors: the state of 1 coordinates has 2 "
        r"dimensions$",
    ):
        run_ensemble(pendulum, t_end=1.0, observables=("gali3",))


def run(capsys, *argv):
    status = main(list(argv))
    return status, capsys.readouterr().err


@pytest.mark.parametrize(
    ("model", "grid", "error"),
    [
        # 1 degree of freedom: a regular orbit's vectors are sheared together too
        ("simple_pendulum", "theta=0:1:3",
         r"Hamiltonian systems of 2 or more degrees of freedom; this one has 1 \(theta\)"),
        # forces: SALI falls on an attractor whether the motion on it is chaotic or not
        ("planar_particle_forces", "x=0:1:3",
         r"Hamiltonian systems; this one has forces or dissipation \(Q - dF/dq' on x: F_x, "
         r"y: F_y\)"),
    ],
)  # fmt: skip
def test_sali_on_a_system_it_cannot_classify_is_one_line(capsys, model, grid, error):
    status, err = run(capsys, "ensemble", model, "--grid", grid, "--observable", "sali")
    assert status == ExitStatus.BAD_INPUT
    assert len(err.strip().splitlines()) == 1
    expected = r"lagrangian: error: observable sali classifies orbits of " + error
    assert re.fullmatch(expected, err.strip())
