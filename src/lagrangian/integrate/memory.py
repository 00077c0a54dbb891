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
from collections.abc import Callable
from pathlib import Path

from ..errors import ModelError, choices, setting

#: Bytes a single run holds per step it keeps, beyond 8 per state entry: the step lists
#: (a float and an array object per step, about 150 bytes), the time arrays.
STEP_OVERHEAD_BYTES = 160
#: Copies of each stored state entry (8 bytes): the stacked steps, the outputs, the
#: trajectory, and the temporaries of the energy check and of the trajectory's columns.
STATE_COPIES = 4


#: A limit at or above this many bytes means "no limit" (cgroup v1 writes 2^63 rounded down).
NO_LIMIT = 1 << 60


def available_memory() -> int | None:
    """Bytes this process can still allocate, or None if unknown: the smallest of the
    memory the system can give without swapping (:func:`system_available`), what the
    address-space limit leaves (:func:`address_space_left`, ``ulimit -v``) and what the
    process's cgroup leaves (:func:`cgroup_left`, a container's memory limit)."""
    limits = [limit for limit, _ in memory_limits()]
    return min(limits) if limits else None


def memory_limits() -> list[tuple[int, str]]:
    """(bytes left, where the limit comes from) of every limit that applies; smallest first."""
    found = [
        (system_available(), ""),
        (address_space_left(), " under the address-space limit (RLIMIT_AS)"),
        (cgroup_left(), " in this process's cgroup"),
    ]
    return sorted((size, source) for size, source in found if size is not None)


def system_available() -> int | None:
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


def address_space_left(
    getrlimit: Callable[[int], tuple[int, int]] | None = None,
    status: str | os.PathLike = "/proc/self/status",
) -> int | None:
    """RLIMIT_AS (soft) minus the address space in use (VmSize), or None without a limit.

    ``getrlimit`` (default :func:`resource.getrlimit`) and ``status`` are for tests."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not on Windows
        return None
    try:
        soft, _ = (getrlimit or resource.getrlimit)(resource.RLIMIT_AS)
    except (OSError, ValueError):
        return None
    if soft == resource.RLIM_INFINITY or soft < 0 or soft >= NO_LIMIT:
        return None
    used = _status_kilobytes(status, "VmSize:")
    return max(0, soft - (used or 0))


def cgroup_left(root: str | os.PathLike = "/sys/fs/cgroup") -> int | None:
    """The cgroup's memory limit minus its usage, or None without a limit.

    cgroup v2: ``memory.max`` and ``memory.current``; v1: ``memory/memory.limit_in_bytes``
    and ``memory/memory.usage_in_bytes`` (the folders as mounted in a container, where
    the process's own cgroup is the root; ``root`` is for tests)."""
    base = Path(root)
    for limit_file, usage_file in (
        (base / "memory.max", base / "memory.current"),
        (base / "memory" / "memory.limit_in_bytes", base / "memory" / "memory.usage_in_bytes"),
    ):
        limit = _number(limit_file)
        if limit is None:
            continue
        if limit >= NO_LIMIT:
            return None
        return max(0, limit - (_number(usage_file) or 0))
    return None


def _number(path: Path) -> int | None:
    """The integer in a one-line file; NO_LIMIT for "max"; None if unreadable."""
    try:
        text = path.read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError):
        return None
    if text == "max":
        return NO_LIMIT
    try:
        return int(text)
    except ValueError:
        return None


def _status_kilobytes(path: str | os.PathLike, field: str) -> int | None:
    try:
        with open(path, encoding="ascii") as status:
            for line in status:
                if line.startswith(field):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def check_fits(estimate: float, what: str, advice: str) -> None:
    """ModelError when ``estimate`` bytes exceed the memory available (unknown: no check),
    naming the limit that is smallest when it is not the system's memory."""
    available = available_memory()
    if available is None or estimate <= available:
        return
    source = next((where for size, where in memory_limits() if size == available), "")
    raise ModelError(
        f"{what} needs about {_gigabytes(estimate)} GB of memory, more than the "
        f"{_gigabytes(available)} GB available{source}: {advice}"
    )


#: Steps an adaptive run keeps before its memory is first projected (its step size has
#: settled by then); projected again each time the steps kept double.
PROJECT_AFTER_STEPS = 8192
KEEPING_ADVICE = "give " + choices(
    f"{setting('n_out')} N (N output times)",
    f"a shorter {setting('t_end')}",
    f"a looser {setting('rtol')}",
)


def check_kept_steps(
    method: str, state_size: int, kept: int, t_span: tuple[float, float], pace: tuple[int, float]
) -> None:
    """ModelError once an adaptive run that keeps every step shows it cannot fit: ``kept``
    steps so far, and ``pace`` = (steps, time span) of its latest stretch projected to
    t_end.  An adaptive method's steps are known only as it goes (an oscillator to
    ``t_end = 1e7`` keeps 10^8 of them, 8 GB); the first projection comes after
    ``PROJECT_AFTER_STEPS`` steps, milliseconds into the run."""
    steps, span = pace
    if span <= 0:
        return
    projected = kept + steps * max(t_span[1] - t_span[0], 0.0) / span
    check_fits(
        run_bytes(state_size, projected),
        f"{method} to t_end = {t_span[1]:g} keeping every step (about "
        f"{count_text(int(min(projected, 1e300)))} at the pace so far)",
        KEEPING_ADVICE,
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
