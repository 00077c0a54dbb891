"""Runs and ensembles that cannot fit in memory are refused before anything is allocated,
with the estimate in GB and what to change (integrate.memory)."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import run_ensemble
from lagrangian.errors import ModelError
from lagrangian.integrate import memory, simulate
from lagrangian.numeric import compile_equations

GB = 1e9


@pytest.fixture(scope="module")
def pendulum():
    return compile_equations(lg.load("double_pendulum").equations_of_motion())


@pytest.fixture
def available(monkeypatch):
    """Pretend the machine has this many bytes available."""

    def set_available(size: float | None) -> None:
        monkeypatch.setattr(memory, "available_memory", lambda: size)

    return set_available


def test_available_memory_is_read_from_the_system():
    size = memory.available_memory()
    assert size is None or size > 0


def test_a_fixed_step_run_of_too_many_steps_is_refused_with_its_estimate(pendulum):
    # 10^10 steps of 4 numbers: more than any machine has, whatever it is
    with pytest.raises(ModelError) as error:
        simulate(pendulum, t_end=1000.0, method="rk4", dt=1e-7)
    expected = memory.run_bytes(4, 10**10) / GB
    assert str(error.value).startswith(
        "rk4 with dt = 1e-07 to t_end = 1000 (10,000,000,000 steps, every one kept) needs "
        f"about {expected:,.0f} GB of memory, more than the "
    )
    assert str(error.value).endswith("GB available: give a larger dt or a shorter t_end")


def test_the_estimate_counts_every_kept_step(pendulum, available):
    steps = 1000
    needed = memory.run_bytes(4, steps)
    available(needed * 1.01)
    assert simulate(pendulum, t_end=1.0, method="variational", dt=1e-3).status == "success"
    available(needed * 0.99)
    with pytest.raises(ModelError, match=r"^variational with dt = 0.001 to t_end = 1 \(1,000 "):
        simulate(pendulum, t_end=1.0, method="variational", dt=1e-3)


def test_output_times_count_for_adaptive_methods(pendulum, available):
    available(memory.run_bytes(4, 0, 10**6) * 0.99)
    with pytest.raises(ModelError, match=r"^1,000,000 output times needs about .*: ask for fewer"):
        simulate(pendulum, t_end=1.0, n_out=10**6)


def test_unknown_memory_is_not_a_reason_to_refuse(pendulum, available):
    available(None)
    assert simulate(pendulum, t_end=0.1, method="rk4").status == "success"


def test_an_ensemble_too_large_is_refused_before_its_members_are_made(pendulum):
    grid = np.linspace(-3, 3, 100_000)  # 10^10 members of a 100,000 x 100,000 grid
    with pytest.raises(ModelError) as error:
        run_ensemble(pendulum, t_end=1.0, initial={"theta1": grid[:, None], "theta2": grid})
    assert str(error.value).startswith(
        "an ensemble of 10,000,000,000 members (1,000 steps) needs about "
    )
    assert str(error.value).endswith(
        "GB available: use fewer members (fewer points per grid axis), or fewer steps (a larger dt)"
    )


def test_the_ensemble_estimate_counts_members_paths_and_steps(pendulum, available):
    from lagrangian.ensemble.core import ensemble_bytes

    names = ("final_state",)
    small = ensemble_bytes(pendulum, 100, 1000, names, None, 65536)
    assert ensemble_bytes(pendulum, 200, 1000, names, None, 65536) > small
    with_paths = ensemble_bytes(pendulum, 100, 1000, names, 10, 65536)
    assert with_paths - small == pytest.approx(8 * 100 * 3 * 4 * 101)
    available(ensemble_bytes(pendulum, 5, 100, names, 10, 65536) * 0.99)
    with pytest.raises(ModelError, match=r"^an ensemble of 5 members, keeping 11 states each"):
        run_ensemble(
            pendulum, t_end=1.0, dt=0.01, initial={"theta1": np.linspace(0, 1, 5)}, save_every=10
        )


def test_the_address_space_limit_counts_what_is_in_use(tmp_path):
    import resource

    status = tmp_path / "status"
    status.write_text("Name:\tpython\nVmSize:\t 1000000 kB\nVmRSS:\t 1000 kB\n")
    limit = 3 * 1024**3

    def limited(which):
        assert which == resource.RLIMIT_AS
        return limit, resource.RLIM_INFINITY

    assert memory.address_space_left(limited, status) == limit - 1000000 * 1024
    unlimited = lambda which: (resource.RLIM_INFINITY, resource.RLIM_INFINITY)  # noqa: E731
    assert memory.address_space_left(unlimited, status) is None


@pytest.mark.parametrize(
    ("files", "left"),
    [
        ({"memory.max": "2147483648\n", "memory.current": "1073741824\n"}, 1 << 30),
        ({"memory.max": "max\n", "memory.current": "1073741824\n"}, None),
        (
            {
                "memory/memory.limit_in_bytes": "2147483648\n",
                "memory/memory.usage_in_bytes": "536870912\n",
            },
            3 << 29,
        ),
        ({"memory/memory.limit_in_bytes": "9223372036854771712\n"}, None),
        ({}, None),
    ],
)
def test_the_cgroup_limit_is_read_from_v2_and_v1_files(tmp_path, files, left):
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text(text)
    assert memory.cgroup_left(tmp_path) == left


def test_the_smallest_limit_is_the_one_checked_and_named(monkeypatch):
    monkeypatch.setattr(memory, "system_available", lambda: 8 * 10**9)
    monkeypatch.setattr(memory, "address_space_left", lambda: 2 * 10**9)
    monkeypatch.setattr(memory, "cgroup_left", lambda: 4 * 10**9)
    assert memory.available_memory() == 2 * 10**9
    with pytest.raises(ModelError) as error:
        memory.check_fits(3e9, "the run", "do less")
    assert str(error.value) == (
        "the run needs about 3 GB of memory, more than the 2 GB available under the "
        "address-space limit (RLIMIT_AS): do less"
    )


def test_a_huge_grid_is_refused_before_its_values_are_made(pendulum):
    from lagrangian.ensemble.members import GridAxis

    axis = GridAxis(0.0, 1.0, 10**12)  # 8 TB of values if they were made
    with pytest.raises(ModelError, match=r"^an ensemble of 1,000,000,000,000 members"):
        run_ensemble(pendulum, initial={"theta1": axis}, t_end=1.0, dt=0.1)
