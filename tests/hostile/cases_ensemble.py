"""Ensembles: grids too large to make, steps too large for the motion, members that fail,
dask clusters that cannot be reached (issue 21)."""

from hostile.case import HostileCase

CASES = [
    HostileCase(
        # the 74.5 GiB linspace of the grid was made before the memory check: MemoryError
        "ensemble-grid-of-10^10-points-refused-before-it-is-made",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0:1:10000000000"),
        error=r"an ensemble of 10,000,000,000 members \([0-9,]+ steps\) needs about [0-9,]+ GB "
        r"of memory, more than the [0-9.]+ GB available[^:]*: use fewer members",
    ),
    HostileCase(
        "ensemble-two-grids-of-10^5-points-refused-at-once",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0:1:100000", "--grid", "x_dot=0:1:100000"),
        error=r"an ensemble of 10,000,000,000 members \([0-9,]+ steps\) needs about [0-9,]+ GB "
        r"of memory, more than the [0-9.]+ GB available[^:]*: use fewer members",
    ),
]
