"""The numerical path: equations without a finite value, singularities, values the model's
assumptions forbid, and runs too large for the memory (issue 10, part A)."""

from hostile.case import HostileCase

# V = k sqrt(x): undefined for x < 0; from x = 1 at rest the force is infinite at x = 0,
# reached at t = 4 sqrt(2) / 3 = 1.8856
SQRT = """coordinates = ["x"]
kinetic = "x_dot^2/2"
potential = "k*sqrt(x)"
[parameters]
k = 1.0
[initial]
x = 1.0
[simulate]
t_end = 3.0
"""

# V = -k/x: from x = 0.01 at rest the motion falls into x = 0 at t = 1.1e-3
COULOMB = """coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "-k/x"
[parameters]
m = 1.0
k = 1.0
[initial]
x = 0.01
"""

# the same fall, by a generalized force instead of a potential
FORCE = """coordinates = ["x"]
kinetic = "m*x_dot^2/2"
[parameters]
m = 1.0
k = 1.0
[forces]
x = "-k/x^2"
[initial]
x = 0.01
"""

# M = diag(x^2, 1): singular at x = 0
SINGULAR_MASS = """coordinates = ["x", "y"]
lagrangian = "x^2*x_dot^2/2 + y_dot^2/2 - y^2/2"
[initial]
y = 1.0
"""

OSCILLATOR = """coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
[parameters]
m = 1.0
k = 1.0
[initial]
x = 1.0
"""

THETA2_GRID = ("--grid", "theta2=-3:3:100000")
FAILED = r"^lagrangian: error: the integration failed: "
NAN_AT_START = (
    FAILED + r"the right-hand side is not finite at t = 0 \(x = -1, x_dot = 0\): "
    r"the equations of motion are undefined or infinite there .*; nothing was written$"
)
# a step of 1e-3, stable at the start (omega dt = 1.4), crosses x = 0 in its second step (the
# default step resolves the fall: 100,000 steps, seconds, to the same failure)
ENERGY_JUMP = (
    FAILED + r"the energy jumped from [-0-9.e+]+ to [-0-9.e+]+ in the step from t = [0-9.e-]+ "
    r"\(x = [0-9.e-]+, x_dot = [-0-9.e+]+\): the motion passes a singularity there"
)


def _positive(name: str, value: str) -> str:
    return (
        rf"parameter {name} = {value} breaks the model's assumption that {name} is positive "
        rf"\(the equations were derived with it\): give a value > 0, or declare {name} = "
    )


CASES = [
    *(
        HostileCase(
            f"simulate-nan-at-start-{method}",
            ("simulate", "{dir}/model.toml", "--set", "x=-1", "--method", method),
            error=NAN_AT_START,
            model=SQRT,
        )
        for method in ("dop853", "radau", "rk4", "variational")
    ),
    HostileCase(
        "simulate-nan-at-start-numba",
        ("simulate", "{dir}/model.toml", "--set", "x=-1", "--backend", "numba"),
        error=NAN_AT_START,
        model=SQRT,
    ),
    *(
        HostileCase(
            f"simulate-infinite-force-midrun-{method}",
            ("simulate", "{dir}/model.toml", "--method", method),
            error=FAILED + r"the right-hand side is not finite just after t = 1\.885",
            model=SQRT,
        )
        for method in ("dop853", "radau")
    ),
    *(
        HostileCase(
            f"simulate-nan-midrun-{method}",
            ("simulate", "{dir}/model.toml", "--method", method),
            error=FAILED + r"the state is not finite after t = 1\.8[0-9]* \(x = ",
            model=SQRT,
        )
        for method in ("rk4", "variational")
    ),
    *(
        HostileCase(
            f"simulate-step-across-singularity-{method}",
            ("simulate", "{dir}/model.toml", "--method", method, "--dt", "1e-3"),
            error=ENERGY_JUMP,
            model=COULOMB,
        )
        for method in ("rk4", "variational")
    ),
    HostileCase(
        "simulate-step-across-singular-force-rk4",
        ("simulate", "{dir}/model.toml", "--method", "rk4", "--dt", "1e-3"),
        error=ENERGY_JUMP,
        model=FORCE,
    ),
    *(
        HostileCase(
            f"simulate-singular-mass-matrix-{backend}",
            ("simulate", "{dir}/model.toml", "--backend", backend),
            error=r"^lagrangian: error: the mass matrix is singular at t = 0 \(x = 0, y = 1\): "
            r"the coordinates are degenerate there",
            model=SINGULAR_MASS,
        )
        for backend in ("numpy", "numba")
    ),
    *(
        HostileCase(
            f"simulate-parameter-breaks-its-sign-m={value}",
            ("simulate", "{dir}/model.toml", "--set", f"m={value}"),
            error=_positive("m", value),
            model=OSCILLATOR,
        )
        for value in ("-1", "0")
    ),
    *(
        HostileCase(
            f"simulate-parameter-not-finite-m={value}",
            ("simulate", "{dir}/model.toml", "--set", f"m={value}"),
            error=rf"parameter m = {value} is not a finite number$",
            model=OSCILLATOR,
        )
        for value in ("inf", "nan")
    ),
    HostileCase(
        "simulate-initial-velocity-not-finite",
        ("simulate", "{dir}/model.toml", "--set", "x_dot=-inf"),
        error=r"initial x_dot = -inf is not a finite number$",
        model=OSCILLATOR,
    ),
    HostileCase(
        "ensemble-grid-breaks-a-parameter-sign",
        ("ensemble", "{dir}/model.toml", "--grid", "m=-1:1:5"),
        error=_positive("m", "-1"),
        model=OSCILLATOR,
    ),
    HostileCase(
        "simulate-too-many-steps-for-the-memory",
        ("simulate", "{dir}/model.toml", "--method", "rk4", "--dt", "1e-7", "--t-end", "1000"),
        error=r"rk4 with dt = 1e-07 to t_end = 1000 \(10,000,000,000 steps, every one kept\) "
        r"needs about [0-9,]+ GB of memory, more than the [0-9.]+ GB available: "
        r"give a larger --dt or a shorter --t-end$",
        model=OSCILLATOR,
    ),
    HostileCase(
        "ensemble-too-many-members-for-the-memory",
        ("ensemble", "double_pendulum", "--grid", "theta1=-3:3:100000", *THETA2_GRID),
        error=r"an ensemble of 10,000,000,000 members \(1,000 steps\) needs about [0-9,]+ GB "
        r"of memory, more than the [0-9.]+ GB available: use fewer members",
    ),
]

# Runs that would take hours end at once with their projected time: an adaptive run's cost
# is not known before it starts (integrate.pace)
CASES += [
    HostileCase(
        "simulate-t-end-1e12-refused-by-its-pace",
        # 1e12 (not 1e9): the compiled default loop would finish 1e9 in minutes on a quiet machine
        # --samples: every step kept, the memory they would need is refused first
        ("simulate", "harmonic_oscillator", "--t-end", "1e12", "--samples", "100"),
        error=r"at its pace so far the run would take about [\d,]+ (minutes|hours|days|years)",
    ),
    HostileCase(
        "simulate-over-its-timeout",
        # 1000 s of it may now finish in 0.3 s (the default compiles dop853's loop)
        (
            "simulate",
            "double_pendulum",
            "--t-end",
            "100000",
            "--timeout",
            "0.3",
            "--samples",
            "100",
        ),
        error=r"did not finish within 0\.3 s: it reached t = ",
    ),
    HostileCase(
        "simulate-timeout-must-be-positive",
        ("simulate", "harmonic_oscillator", "--timeout", "0"),
        error=r"--timeout",
    ),
]
CASES += [
    HostileCase(
        "ensemble-over-its-timeout",
        (
            "ensemble",
            "double_pendulum",
            "--grid",
            "theta1=0:1:2000",
            "--t-end",
            "100",
            "--timeout",
            "0.3",
        ),
        error=r"did not finish within 0\.3 s: it reached [\d.]+ % of the runs; give fewer",
    ),
    HostileCase(
        "ensemble-timeout-must-be-positive",
        ("ensemble", "double_pendulum", "--grid", "theta1=0:1:2", "--timeout", "-1"),
        error=r"--timeout",
    ),
]
CASES += [
    HostileCase(
        # SciPy raised it to 2.2e-14 in a warning, and the summary reported 1e-300
        "simulate-rtol-below-double-precision",
        ("simulate", "harmonic_oscillator", "--rtol", "1e-300"),
        error=r"rtol = 1e-300 is below what dop853 can deliver in double precision",
    ),
]
