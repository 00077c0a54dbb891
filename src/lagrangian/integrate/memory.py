"""Memory a run will hold, estimated before anything is allocated, and refused when it cannot fit.

A fixed-step run keeps every step (``--dt 1e-7 --t-end 1000`` is 10^10 of them) and an
ensemble keeps every member's results (a 10^4 x 10^4 grid is 10^8 members); without a
look ahead either fills the memory and the machine swaps or kills the process, hours
later.  The drivers call :func:`check_fits` with an estimate first, and stop with one
line giving it in GB and what to change.  The estimates count the arrays the code
makes (see the ``*_BYTES`` constants below), not the interpreter's own memory.
"""

from __future__ import annotations

import math
import os

from ..errors import ModelError

#: Bytes a single run holds per step it keeps, beyond 8 per state entry: the step lists
#: (a float and an array object per step, about 150 bytes), the time arrays.
STEP_OVERHEAD_BYTES = 160
#: Copies of each stored state entry (8 bytes): the stacked steps, the outputs, the
#: trajectory, and the temporaries of the energy check and of the trajectory's columns.
STATE_COPIES = 4


def available_memory() -> int | None:
    """Bytes the system can give without swapping (Linux: MemAvailable), or None if unknown.

    Elsewhere the free physical pages (``os.sysconf``), which undercounts the
    reclaimable cache: a refusal there can only be a little too strict.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024  # the kernel writes kB
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, OSError, ValueError):
        return None


def check_fits(estimate: float, what: str, advice: str) -> None:
    """ModelError when ``estimate`` bytes exceed the memory available (unknown: no check)."""
    available = available_memory()
    if available is None or estimate <= available:
        return
    raise ModelError(
        f"{what} needs about {_gigabytes(estimate)} GB of memory, more than the "
        f"{_gigabytes(available)} GB available: {advice}"
    )


def run_bytes(state_size: int, steps: int, outputs: int = 0) -> float:
    """Bytes of a single run of states of ``state_size`` (2n) entries that keeps ``steps``
    steps and makes ``outputs`` further output times (dense output)."""
    per_state = 8 * (state_size + 2) * STATE_COPIES
    return float(steps) * (STEP_OVERHEAD_BYTES + per_state) + float(outputs) * per_state


def step_count(t0: float, t1: float, dt: float) -> int:
    """N = ceil((t1 - t0)/dt) steps (the fixed-step grid's count), computed without the grid."""
    return max(1, math.ceil((t1 - t0) / dt - 1e-9))


def count_text(count: int) -> str:
    """A count as read: 10,000,000 (beyond 10^15, 1e+300)."""
    return f"{count:,}" if count < 10**15 else f"{float(count):.3g}"


def _gigabytes(size: float) -> str:
    """24.8, 2,880, 2.88e+294."""
    gigabytes = size / 1e9
    return f"{gigabytes:,.0f}" if 100 <= gigabytes < 1e15 else f"{gigabytes:.3g}"
