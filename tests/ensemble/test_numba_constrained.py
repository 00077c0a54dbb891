"""Ensembles of constrained systems on the numba backend (ensemble/numba_projected.py).

Each member is stepped by rk4 on the augmented equations and projected onto its
constraints after every step, in compiled code; checked member by member against the numpy
backend, which steps the batch with the NumPy functions and projects it with
``compiled.project`` (numeric/projection.py), and against the constraints themselves.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import run_ensemble
from lagrangian.errors import LagrangianWarning, ModelError
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")


@functools.cache
def compiled(name: str):
    return compile_equations(lg.load(name).equations_of_motion())


def both(name: str, **options) -> tuple:
    """(numba, numpy) ensembles of the same settings."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LagrangianWarning)  # a coarse dt is the point here
        return tuple(
            run_ensemble(compiled(name), backend=backend, **options)
            for backend in ("numba", "numpy")
        )


def test_pendulums_of_several_lengths_agree_with_numpy_member_by_member():
    lengths = np.linspace(0.5, 2.0, 6)
    angle = np.linspace(0.3, 2.5, 6)
    initial = {
        "x": lengths * np.sin(angle), "y": -lengths * np.cos(angle),
        "x_dot": 2 * np.cos(angle), "y_dot": 2 * np.sin(angle),
    }  # fmt: skip
    ours, numpy = both(
        "cartesian_pendulum", initial=initial, params={"l": lengths}, t_end=1.0, dt=0.002,
        save_every=50,
    )  # fmt: skip
    for name in ("x", "y", "x_dot", "y_dot"):
        np.testing.assert_allclose(ours.final_state[name], numpy.final_state[name], atol=1e-12)
        np.testing.assert_allclose(ours[f"path_{name}"], numpy[f"path_{name}"], atol=1e-12)
    final = ours.final_state
    # on each member's own circle, moving along it
    np.testing.assert_allclose(np.hypot(final["x"], final["y"]), lengths, rtol=0, atol=1e-14)
    radial = final["x"] * final["x_dot"] + final["y"] * final["y_dot"]
    np.testing.assert_allclose(radial, 0.0, atol=1e-13)


def test_the_rolling_disc_keeps_rolling_as_on_numpy():  # velocity-level constraints only
    rates = np.linspace(0.5, 2.0, 4)
    initial = {"theta_dot": rates, "x_dot": 0.5 * rates, "phi_dot": 0.5}
    ours, numpy = both("rolling_disc", initial=initial, t_end=4.0, dt=0.01)
    for name in ("x", "y", "phi", "theta", "x_dot", "y_dot"):
        np.testing.assert_allclose(ours.final_state[name], numpy.final_state[name], atol=1e-12)
    final = ours.final_state  # x' = R cos(phi) theta', y' = R sin(phi) theta', R = 0.5
    np.testing.assert_allclose(final["x_dot"], 0.5 * np.cos(final["phi"]) * rates, atol=1e-14)
    np.testing.assert_allclose(final["y_dot"], 0.5 * np.sin(final["phi"]) * rates, atol=1e-14)


def test_the_lyapunov_observable_is_refused_with_constraints():
    with pytest.raises(ModelError, match=r"^the lyapunov observable does not take constrained"):
        run_ensemble(
            compiled("cartesian_pendulum"), t_end=0.1, dt=0.001, backend="numba",
            observables=("lyapunov",),
        )  # fmt: skip
