"""Symbolic stages within their budgets: analyze says what it could not decide in time."""

from hostile.case import HostileCase

TOP_KINETIC = (
    "(I1*(phi_dot*sin(theta)*sin(psi) + theta_dot*cos(psi))**2"
    " + I2*(phi_dot*sin(theta)*cos(psi) - theta_dot*sin(psi))**2"
    " + I3*(phi_dot*cos(theta) + psi_dot)**2)/2"
)
ASYMMETRIC_TOP = f"""name = "Asymmetric top"
coordinates = ["phi", "theta", "psi"]
kinetic = "{TOP_KINETIC}"
potential = "0"

[parameters]
I1 = 1.0
I2 = 2.0
I3 = 3.0
"""

DISC_KINETIC = (
    "m*((x_dot + R*(cos(theta)*sin(phi)*theta_dot + sin(theta)*cos(phi)*phi_dot))**2"
    " + (y_dot - R*(cos(theta)*cos(phi)*theta_dot - sin(theta)*sin(phi)*phi_dot))**2"
    " + R**2*sin(theta)**2*theta_dot**2)/2"
    " + m*R**2*(theta_dot**2 + phi_dot**2*cos(theta)**2)/8"
    " + m*R**2*(psi_dot + phi_dot*sin(theta))**2/4"
)
LEANING_DISC = f"""name = "Leaning rolling disc"
coordinates = ["x", "y", "theta", "phi", "psi"]
kinetic = "{DISC_KINETIC}"
potential = "m*g*R*cos(theta)"
constraints = ["x_dot - R*psi_dot*cos(phi)", "y_dot - R*psi_dot*sin(phi)"]

[parameters]
m = 1.0
R = 1.0
g = 9.81
"""

CASES = [
    HostileCase(
        "analyze-asymmetric-top-reports-undecided",
        ("analyze", "{dir}/model.toml", "--timeout", "0.1"),
        exit_code=0,
        output=r"(?s)Undecided \(out of time.*: not decided within 0\.1 s",
        model=ASYMMETRIC_TOP,
        slow=True,
    ),
    HostileCase(
        "analyze-asymmetric-top-json-undecided",
        ("analyze", "{dir}/model.toml", "--timeout", "0.1", "--json"),
        exit_code=0,
        output=r'"undecided": \[\s*\{\s*"stage": ',
        model=ASYMMETRIC_TOP,
        slow=True,
    ),
    HostileCase(
        "analyze-timeout-must-be-positive",
        ("analyze", "{dir}/model.toml", "--timeout", "0"),
        error=r"--timeout",
        model=ASYMMETRIC_TOP,
    ),
    HostileCase(
        "derive-leaning-rolling-disc",
        ("derive", "{dir}/model.toml"),
        exit_code=0,
        output=r"Lagrange multipliers",
        model=LEANING_DISC,
        slow=True,
    ),
]


def _one_coordinate(lagrangian: str) -> str:
    return f'coordinates = ["x"]\nlagrangian = "{lagrangian}"\n'


# Values beyond double precision: SymPy's own evaluation at sample points asked mpmath for
# numbers of 10^17 digits (a hang in analyze, an OverflowError in derive)
EXP_TOWER = "exp(exp(exp(exp(exp(x)))))"

CASES += [
    HostileCase(
        "derive-exp-tower-in-the-mass",
        ("derive", "{dir}/model.toml"),
        exit_code=0,
        output=r"ẍ = ",
        model=_one_coordinate(f"{EXP_TOWER}*x_dot^2/2 - x^2"),
    ),
    HostileCase(
        "analyze-exp-tower-in-the-mass",
        ("analyze", "{dir}/model.toml"),
        exit_code=0,
        output=r"(?s)Conserved:\s+energy.*overflow double precision",
        model=_one_coordinate(f"{EXP_TOWER}*x_dot^2/2 - x^2"),
    ),
    HostileCase(
        "analyze-exp-tower-potential",
        ("analyze", "{dir}/model.toml", "--timeout", "1"),
        exit_code=0,
        output=r"(?s)Conserved:\s+energy",
        model=_one_coordinate(f"x_dot^2/2 - {EXP_TOWER}"),
    ),
    HostileCase(
        "simulate-exp-tower-overflows-at-the-start",
        ("simulate", "{dir}/model.toml"),
        error=r"not finite at t = 0",
        model=_one_coordinate(f"{EXP_TOWER}*x_dot^2/2 - x^2"),
    ),
    HostileCase(
        # the trigonometric tidying expanded the power: a thousand terms of 300-digit numbers
        "derive-power-1000-of-a-sum",
        ("derive", "{dir}/model.toml"),
        exit_code=0,
        output=r"ẍ = -998 ẋ cos\(x\)/999 \+ sin\(x\) cos\(x\)/999",
        model=_one_coordinate("(sin(x) + x_dot)^1000"),
    ),
]


def _dense_coupling(n: int) -> str:
    """n coordinates all coupled through the kinetic energy: H has M's full inverse."""
    coordinates = ", ".join(f'"x{i}"' for i in range(n))
    momentum = " + ".join(f"(1 + x{i}^2)*x{i}_dot" for i in range(n))
    own = " + ".join(f"x{i}_dot^2*cos(x{(i + 1) % n})^2" for i in range(n))
    potential = " + ".join(f"sin(x{i}*x{(i + 1) % n})" for i in range(n))
    return (
        f'coordinates = [{coordinates}]\nkinetic = "({momentum})^2/2 + {own}"\n'
        f'potential = "{potential}"\n'
    )


CASES += [
    HostileCase(
        # printing its Hamiltonian (SymPy's term ordering) took 100 s after the stages ended
        "analyze-dense-six-coordinates-prints-in-time",
        ("analyze", "{dir}/model.toml", "--timeout", "1"),
        exit_code=0,
        output=r"H = too long to print; analyze --json gives it",
        model=_dense_coupling(6),
        slow=True,
    ),
]
