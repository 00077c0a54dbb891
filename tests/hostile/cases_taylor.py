"""Method taylor (heyoka): tolerances it cannot use, a mass matrix its elimination without
pivoting cannot take, failures named by their state; and a parameter value that leaves L
without a value at the start (every method)."""

import importlib.util

from hostile.case import HostileCase
from hostile.cases_simulate import SQRT  # V = k sqrt(x): infinite force at x = 0, t = 1.8856

# M = [[0, 1], [1, 0]]: indefinite, the first pivot is zero
CROSS = """coordinates = ["x", "y"]
lagrangian = "x_dot*y_dot - x*y"
[initial]
x = 1.0
y = 0.5
"""

# M = [[a, 1], [1, -1]]: indefinite, a tiny first pivot (the elimination loses 9 digits)
SMALL_PIVOT = """coordinates = ["x", "y"]
lagrangian = "a*x_dot^2/2 + x_dot*y_dot - y_dot^2/2 - x^2/2 - y^2/2"
[parameters]
a = 1e-9
[initial]
x = 1.0
"""


ZERO_MASS = """coordinates = ["x"]
lagrangian = "x_dot^2/(2*m) - x^2/2"
[parameters]
m = 0.0
[initial]
x = 1.0
"""

BELOW = r"is below what taylor can deliver in double precision: give --{name} 2\.22e-16 or more$"
INDEFINITE = (
    r"method 'taylor' solves M q'' = f without pivoting, which needs a definite mass "
    r"matrix M .* M at the initial state is not \(eigenvalues from .*\): use dop853$"
)

CASES = [
    HostileCase(
        "taylor-rtol-1e-300-refused-before-the-build",
        ("simulate", "double_pendulum", "--method", "taylor", "--rtol", "1e-300"),
        error=r"rtol = 1e-300 " + BELOW.format(name="rtol"),
    ),
    HostileCase(
        "taylor-atol-1e-20-refused",
        ("simulate", "double_pendulum", "--method", "taylor", "--atol", "1e-20"),
        error=r"atol = 1e-20 " + BELOW.format(name="atol"),
    ),
    *(
        HostileCase(
            f"taylor-{name}-{text}-refused",
            ("simulate", "double_pendulum", "--method", "taylor", f"--{name}", text),
            error=rf"{name} must be a finite number > 0, not",
        )
        for name, text in (("rtol", "0"), ("atol", "0"), ("rtol", "-1e-12"), ("rtol", "inf"))
    ),
    *(
        HostileCase(
            f"simulate-zero-mass-parameter-{method}",
            ("simulate", "{dir}/model.toml", "--method", method, "--json"),
            error=r"parameter m = 0 leaves the Lagrangian or the mass matrix undefined or "
            r"infinite at the initial state \(x = 1, x_dot = 0\), .*: give m another value$",
            model=ZERO_MASS,
        )
        for method in ("dop853", "rk4", "variational")
    ),
]

if importlib.util.find_spec("heyoka") is not None:  # optional: pip install 'lagrangian[taylor]'
    CASES += [
        HostileCase(
            "taylor-json-reports-its-tolerance",
            ("simulate", "harmonic_oscillator", "--method", "taylor", "--rtol", "1e-12", "--json"),
            exit_code=0,
            output=r'"rtol": 1e-12,\s+"atol": 1e-12,',
        ),
        HostileCase(
            "taylor-zero-pivot-refused",
            ("simulate", "{dir}/model.toml", "--method", "taylor"),
            error=INDEFINITE,
            model=CROSS,
        ),
        HostileCase(
            "taylor-small-pivot-indefinite-refused",
            ("simulate", "{dir}/model.toml", "--method", "taylor"),
            error=INDEFINITE,
            model=SMALL_PIVOT,
        ),
        HostileCase(
            "taylor-failure-names-the-state",
            ("simulate", "{dir}/model.toml", "--method", "taylor"),
            error=r"the integration failed: the state is not finite after t = 1\.8856\d "
            r"\(x = [-0-9.e]+, x_dot = -1\.4142\d\): the equations of motion are undefined",
            model=SQRT,
        ),
        HostileCase(
            "taylor-failure-at-the-start-names-the-state",
            ("simulate", "{dir}/model.toml", "--method", "taylor", "--set", "x=-1"),
            error=r"the integration failed: the right-hand side is not finite at t = 0 "
            r"\(x = -1, x_dot = 0\): the equations of motion are undefined",
            model=SQRT,
        ),
        HostileCase(
            "simulate-zero-mass-parameter-taylor",
            ("simulate", "{dir}/model.toml", "--method", "taylor", "--json"),
            error=r"parameter m = 0 leaves the Lagrangian or the mass matrix undefined",
            model=ZERO_MASS,
        ),
    ]
