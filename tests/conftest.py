"""Test-wide setup: seeded random number generators and the shared helpers.

Every test starts with ``random`` and NumPy's global generator seeded from its
own node id, so a failure reproduces exactly when the test is run alone; the
``rng`` fixture is a ``random.Random`` seeded the same way.  Shared helpers
live in ``tests/helpers.py`` (``import helpers``).
"""

from __future__ import annotations

import random
import shutil
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

TESTS = Path(__file__).resolve().parent
if str(TESTS) not in sys.path:
    sys.path.insert(0, str(TESTS))


def _seed_of(request: pytest.FixtureRequest) -> int:
    return zlib.crc32(request.node.nodeid.encode("utf-8"))


@pytest.fixture(autouse=True)
def _seed_random_generators(request: pytest.FixtureRequest) -> None:
    seed = _seed_of(request)
    random.seed(seed)
    np.random.seed(seed % 2**32)


@pytest.fixture(autouse=True)
def _no_kept_pages(monkeypatch: pytest.MonkeyPatch) -> None:
    """``lagrangian page`` makes every page anew in the tests (tests/cli/test_page_cache.py
    turns the cache of pages on in a folder of its own): a test that changes how a page is
    made must see the change, and the user's cache stays untouched."""
    monkeypatch.setenv("LAGRANGIAN_NO_CACHE", "1")


@pytest.fixture(scope="session")
def compiler() -> str:
    """The C compiler (cc or gcc); the test is skipped where there is none."""
    found = shutil.which("cc") or shutil.which("gcc")
    if found is None:
        pytest.skip("no C compiler (cc or gcc) on this machine")
    return found


@pytest.fixture
def rng(request: pytest.FixtureRequest) -> random.Random:
    """A ``random.Random`` seeded from the test's node id."""
    return random.Random(_seed_of(request))


@pytest.fixture
def np_rng(request: pytest.FixtureRequest) -> np.random.Generator:
    """A NumPy generator seeded from the test's node id."""
    return np.random.default_rng(_seed_of(request))
