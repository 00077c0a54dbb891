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

The tests run in a random order (pytest-randomly, of the ``test`` extra): no test may
depend on another having run before it.  The summary's last line names the order's seed
(``pytest -n 0 --randomly-seed=N`` runs that order again, in one process, where the
xdist workers shared it out; ``-p no:randomly`` keeps the files' order);
each test's seeding stays the one above (randomly's own reseeding is turned off).

Every cache of the package (generated modules and their numba files, kept pages) goes to
one temporary folder made for the run and removed after it, ``$LAGRANGIAN_CACHE``, shared
by the xdist workers and inherited by every command a test runs: the user's cache is never
written (tests/test_suite_hygiene.py checks it).  ``LAGRANGIAN_TEST_SUITE_CACHE=FOLDER``
names a folder to use instead and keep, so that numba's machine code survives the run.
"""

from __future__ import annotations

import os
import random
import shutil
import sys
import tempfile
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


#: The variable that names the folder of every cache of the package (codegen/cache.py).
CACHE_VARIABLE = "LAGRANGIAN_CACHE"
#: The suite's cache folder: set by the run that made it (xdist's workers inherit it), or
#: given to keep the caches between runs (numba's machine code, compiled again otherwise).
SUITE_CACHE_VARIABLE = "LAGRANGIAN_TEST_SUITE_CACHE"


def pytest_configure(config: pytest.Config) -> None:
    if config.pluginmanager.hasplugin("randomly"):
        config.option.randomly_reset_seed = False  # the per-test seeding below stays ours
    folder = os.environ.get(SUITE_CACHE_VARIABLE)
    if not folder:
        folder = tempfile.mkdtemp(prefix="lagrangian-test-cache-")
        config.stash[_made_cache] = folder
    os.makedirs(folder, mode=0o700, exist_ok=True)
    os.environ[CACHE_VARIABLE] = os.environ[SUITE_CACHE_VARIABLE] = folder


_made_cache = pytest.StashKey[str]()


def pytest_unconfigure(config: pytest.Config) -> None:
    folder = config.stash.get(_made_cache, None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)


def _randomly_seed(config: pytest.Config) -> int | None:
    if not config.pluginmanager.hasplugin("randomly"):
        return None
    return config.getoption("randomly_seed", None)


def pytest_report_header(config: pytest.Config) -> list[str]:
    lines = []
    if _quick_tier_only(config):
        lines.append(
            "the quick tier: the tests marked slow are left out (pytest --slow runs them too)"
        )
    kept = "" if config.stash.get(_made_cache, None) else ", kept"
    lines.append(f"the package's caches: {os.environ[CACHE_VARIABLE]}{kept}")
    return lines


def pytest_terminal_summary(
    terminalreporter: pytest.TerminalReporter, config: pytest.Config
) -> None:
    seed = _randomly_seed(config)
    if seed is not None and config.getoption("randomly_reorganize", True):
        terminalreporter.write_line(
            f"the tests ran in a random order: -n 0 --randomly-seed={seed} repeats it"
        )


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


@pytest.fixture(scope="session")
def browser():
    """One headless Chromium for the run's browser tests (tests/output/browser.py), in each
    xdist worker: a test opens its pages (each in a context of its own) and closes them.
    A launch costs about 1.5 s of CPU: it was paid once per module and worker, and once per
    test in two files (about 15 times a run)."""
    from output.browser import chromium

    with chromium() as launched:
        yield launched
