"""The systems the numeric tests run on, derived and compiled once, and random points.

Points are drawn by name with ``helpers.random_point`` (away from the
coordinate singularities of each example); :func:`arguments` turns one into
the ``(t, y, params)`` of the compiled functions.
"""

from __future__ import annotations

import random
from functools import cache

import numpy as np
import sympy

import lagrangian as lg
from helpers import random_point
from lagrangian.examples import example_names
from lagrangian.numeric import DEFAULT_BAUMGARTE, CompiledSystem, compile_equations

EXAMPLES = example_names()
CONSTRAINED = ("cartesian_pendulum", "rolling_disc", "four_bar", "four_bar_driven", "slider_crank")

#: The unspecified functions of velocity_dependent_potential, as text for the compiler ...
DEFINITIONS = {
    "velocity_dependent_potential": {
        "V": "x^2/2 + y*z + cos(z)",
        "A": "-y*z/2 + sin(x*y)",
        "B": "x*z/2 + exp(-z^2)",
        "C": "x*y*z/3 + cos(x)",
    }
}
#: ... and the same functions as SymPy callables for the oracle (helpers.evaluate).
ORACLE_FUNCTIONS = {
    "velocity_dependent_potential": {
        "V": lambda x, y, z: x**2 / 2 + y * z + sympy.cos(z),
        "A": lambda x, y, z: -y * z / 2 + sympy.sin(x * y),
        "B": lambda x, y, z: x * z / 2 + sympy.exp(-(z**2)),
        "C": lambda x, y, z: x * y * z / 3 + sympy.cos(x),
    }
}
#: The linkages' loops near their closed configuration (far off them, projecting onto them
#: is a slow Gauss-Newton iteration whose stopping differs between a batch and one state).
_FOUR_BAR = {
    "a": (0.28, 0.32), "b": (0.95, 1.05), "c": (0.75, 0.85), "d": (0.95, 1.05),
    "theta_crank": (0.95, 1.05), "theta_coupler": (0.55, 0.65), "theta_rocker": (1.5, 1.6),
}  # fmt: skip
#: Where points are drawn: away from r = 0 and the poles theta = 0, pi.
RANGES = {
    "four_bar": _FOUR_BAR,
    "four_bar_driven": _FOUR_BAR,
    "slider_crank": {
        "r": (0.09, 0.11),
        "l": (0.38, 0.42),
        "theta": (0.45, 0.55),
        "x": (0.46, 0.5),
        "phi": (-0.14, -0.1),
    },
    "central_force": {"r": (0.5, 2.0)},
    "free_particle_spherical": {"r": (0.5, 2.0), "theta": (0.3, 2.8)},
    "spherical_pendulum": {"theta": (0.3, 2.8)},
    "cartesian_pendulum": {"x": (0.3, 1.5), "y": (-1.5, -0.3)},
}


@cache
def equations(name: str) -> lg.EquationsOfMotion:
    return lg.load(name).equations_of_motion()


@cache
def compiled(name: str, baumgarte: float = DEFAULT_BAUMGARTE) -> CompiledSystem:
    return compile_equations(
        equations(name), definitions=DEFINITIONS.get(name), baumgarte=baumgarte
    )


def point(name: str, rng: random.Random) -> dict[str, float]:
    return random_point(equations(name).system, rng, RANGES.get(name))


def arguments(
    system: CompiledSystem, values: dict[str, float]
) -> tuple[float, np.ndarray, np.ndarray]:
    """(t, y, params) of a point given by name."""
    names = [*system.coordinate_names, *(f"{c}_dot" for c in system.coordinate_names)]
    y = np.array([values[name] for name in names])
    params = np.array([values[name] for name in system.parameter_names])
    return values["t"], y, params


def assert_arrays_close(actual, expected, rtol: float, what: str = "", floor: float = 1e-12):
    """max |actual - expected| <= rtol * max(max |expected|, floor): relative, norm-wise."""
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    scale = max(float(np.max(np.abs(expected), initial=0.0)), floor)
    error = float(np.max(np.abs(actual - expected), initial=0.0))
    assert error <= rtol * scale, (
        f"{what}: relative error {error / scale:.3e} > {rtol:g}\n"
        f"got      {actual!r}\nexpected {expected!r}"
    )
