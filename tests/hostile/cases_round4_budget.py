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

CASES = [
    HostileCase(
        "derive-time-out-inside-a-large-derivation-is-cleared",
        ("derive", "{dir}/model.toml"),
        exit_code=0,
        output=r"Accelerations:",
        model=LARGE_DERIVATION,
        slow=True,
    ),
]
