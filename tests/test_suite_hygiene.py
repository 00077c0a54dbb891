"""The suite's own promises (tests/conftest.py): each test seeded from its node id whatever
order the tests run in, and the package's caches kept in the run's own folder, never in
the user's."""

from __future__ import annotations

import os
import random
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

from lagrangian.codegen.cache import cache_directory, cache_root

ROOT = Path(__file__).resolve().parent.parent

#: Tests that compile generated code with numba into the default cache: in this process,
#: and in a ``lagrangian`` command run as a child.
CACHE_WRITERS = (
    "tests/numeric/test_numba_backend.py::test_batch_equals_loop_of_single_states",
    "tests/cli/test_simulate_cli.py::test_numba_backend_gives_the_numpy_run",
)


def test_a_test_starts_with_the_generators_seeded_from_its_node_id(request):
    """pytest-randomly would reseed them from its run's seed as the test starts: the
    suite's seeding stays, so a test run alone draws what it drew in the whole run."""
    seed = zlib.crc32(request.node.nodeid.encode("utf-8"))
    assert random.random() == random.Random(seed).random()
    assert np.random.random() == np.random.RandomState(seed % 2**32).random()


def test_the_package_caches_are_in_the_suites_folder(monkeypatch):
    folder = Path(os.environ["LAGRANGIAN_TEST_SUITE_CACHE"])
    assert folder.is_dir() and cache_root() == folder and cache_directory().parent == folder
    monkeypatch.delenv("LAGRANGIAN_CACHE")
    assert cache_root() != folder  # the user's cache, where the package keeps them for a user


@pytest.mark.slow
def test_a_run_writes_nothing_into_the_users_cache(tmp_path):
    """A run of tests that compile with numba, one of them through a ``lagrangian``
    command, leaves the cache folder of a fresh home as it was: absent."""
    home = tmp_path / "home"
    home.mkdir()
    environment = {
        name: value
        for name, value in os.environ.items()
        if name not in ("LAGRANGIAN_CACHE", "LAGRANGIAN_TEST_SUITE_CACHE", "XDG_CACHE_HOME")
    }
    environment |= {"HOME": str(home), "PYTHONPATH": os.pathsep.join(sys.path)}
    command = [sys.executable, "-m", "pytest", "-q", "-n", "0", "-p", "no:randomly"]
    command += ["-p", "no:cacheprovider", *CACHE_WRITERS]
    finished = subprocess.run(
        command, cwd=ROOT, env=environment, capture_output=True, text=True, check=False
    )
    assert finished.returncode == 0, finished.stdout + finished.stderr
    assert "2 passed" in finished.stdout
    assert not (home / ".cache" / "lagrangian").exists()
    assert not (home / ".cache" / "numba").exists()
