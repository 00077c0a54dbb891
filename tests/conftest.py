"""Test-wide setup: seeded random number generators and the shared helpers.

Two tiers: ``pytest`` runs the quick one (every test not marked ``slow``, a few minutes on
two cores); ``pytest --slow`` runs every test, ``pytest -m slow`` the slow tier alone (CI
runs both tiers).  A test is marked slow when it takes more than about 1.5 s by itself on
such a machine (``benchmarks/suite_tiers.py`` measures the tiers and lists the tests on the
wrong side); a file named on the command line runs all its tests.

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


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--slow",
        action="store_true",
        help="run the slow tier too (tests marked slow; without it they are deselected)",
    )


def _quick_tier_only(config: pytest.Config) -> bool:
    return not (config.getoption("--slow") or config.getoption("markexpr"))


def pytest_report_header(config: pytest.Config) -> str:
    if _quick_tier_only(config):
        return "the quick tier: the tests marked slow are left out (pytest --slow runs them too)"
    return ""


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if not _quick_tier_only(config):
        return
    named = {
        Path(argument.split("::")[0]).resolve()
        for argument in config.args
        if argument.split("::")[0].endswith(".py")
    }
    slow = [i for i in items if i.get_closest_marker("slow") and i.path not in named]
    if slow:
        left_out = set(slow)
        items[:] = [item for item in items if item not in left_out]
        config.hook.pytest_deselected(items=slow)


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
