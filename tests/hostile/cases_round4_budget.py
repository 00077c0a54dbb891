"""Budgets that must hold on hostile input (issue 37, items 1-3): a time-out deep in a
derivation leaves nothing armed, expansions too large for memory are refused before they
start, and a run's budget counts every part of it."""

from hostile.case import HostileCase

# A time-out inside a large derivation: the tidied solve for q'' runs out of its 5 s while
# SymPy expands the 8th power of 39 sines; its error unwinds for longer than the deadline's
# repeat, which escaped the clean-up and killed the process by SIGPROF (exit 155) after the
# error line.  The untidied route then decides q''.
SINES = "+".join(f"sin({k}*x)" for k in range(1, 40))
LARGE_DERIVATION = f"""coordinates = ["x", "y"]
lagrangian = "(x_dot+y_dot)^2/2 + (x_dot*y_dot)^2*({SINES})^8"
"""

# Expansions too large to make (item 2): SymEngine's expand runs in C++, out of reach of
# every deadline (the power ran 200 s to 6.8 GB and on); the terms are counted first.
VELOCITIES = " + ".join(f"q{i}_dot" for i in range(20))
COORDINATES = ",".join(f"q{i}" for i in range(20))
COORDINATE_LIST = ", ".join(f'"q{i}"' for i in range(20))
POWER_OF_A_SUM = f"""coordinates = [{COORDINATE_LIST}]
lagrangian = "({VELOCITIES})^20/2"
"""
PRODUCT_OF_SUMS = "*".join(
    f"(q{i}_dot + q{(i + 1) % 20}_dot + q{(i + 2) % 20}_dot)" for i in range(20)
)
NESTED_POWERS = f"(({' + '.join(f'q{i}_dot' for i in range(10))})^4 + 1)^5"
POSITION_POWER = f"""coordinates = [{COORDINATE_LIST}]

[[particles]]
name = "bead"
mass = "1"
position = ["({" + ".join(f"q{i}" for i in range(20))})^20", "0"]
"""
# A run's budget counts all of it (item 3): the watch was told only after each interval
# and after the whole transient, so y' = NaN at the start (the step shrinking without
# end) and a transient of 1e12 both ran on past --timeout.
UNDEFINED_AT_START = (
    'coordinates = ["x"]\nlagrangian = "x_dot^2/2 - sqrt(x)"\n\n[initial]\nx = -1.0\n'
)
NOT_FINITE = r"the right-hand side is not finite at t = 0 \(x = -1, x_dot = 0\)"

TOO_LARGE = r"lagrangian: expanded, it makes more than 2,000,000 terms .*too large to derive"

CASES = [
    HostileCase(
        "derive-time-out-inside-a-large-derivation-is-cleared",
        ("derive", "{dir}/model.toml"),
        exit_code=0,
        output=r"Accelerations:",
        model=LARGE_DERIVATION,
        slow=True,
    ),
    HostileCase(
        "derive-power-of-a-sum-too-large-to-expand",
        ("derive", "--lagrangian", f"({VELOCITIES})^20/2", "--coordinates", COORDINATES),
        error=TOO_LARGE,
    ),
    *(
        HostileCase(
            f"{command}-power-of-a-sum-too-large-to-expand",
            (command, "{dir}/model.toml", *extra),
            error=TOO_LARGE,
            model=POWER_OF_A_SUM,
        )
        for command, extra in [
            ("analyze", ()),
            ("simulate", ("--t-end", "1")),
            ("page", ("--out", "{dir}/page.html", "--no-cache")),
            ("export", ("--to", "c")),
        ]
    ),
    HostileCase(
        "derive-product-of-sums-too-large-to-expand",
        ("derive", "--lagrangian", PRODUCT_OF_SUMS, "--coordinates", COORDINATES),
        error=TOO_LARGE,
    ),
    HostileCase(
        "derive-nested-powers-too-large-to-expand",
        ("derive", "--lagrangian", NESTED_POWERS, "--coordinates", COORDINATES),
        error=TOO_LARGE,
    ),
    HostileCase(
        "derive-particle-position-too-large-to-expand",
        ("derive", "{dir}/model.toml"),
        error=TOO_LARGE.replace("lagrangian: ", r"particles\[0\]\.position\[0\]: "),
        model=POSITION_POWER,
    ),
    *(
        HostileCase(
            f"lyapunov-right-hand-side-not-finite-at-start{suffix}",
            ("lyapunov", "{dir}/model.toml", "--t-end", "5", "--timeout", "5", *extra),
            error=NOT_FINITE,
            model=UNDEFINED_AT_START,
        )
        for suffix, extra in [
            ("", ()),
            ("-largest", ("--largest",)),
            ("-numpy", ("--backend", "numpy")),
        ]
    ),
    HostileCase(
        "lyapunov-transient-past-the-budget",
        ("lyapunov", "henon_heiles", "--transient", "1e12", "--timeout", "5"),
        error=r"(would take about|did not finish within 5 s).* of 1e\+12, a transient of 1e\+12",
        slow=True,
    ),
]
