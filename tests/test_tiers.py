"""The two tiers of the suite (tests/conftest.py): plain ``pytest`` leaves the tests marked
slow out and says so, ``--slow`` and ``-m`` choose for themselves, a file named runs whole."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SAMPLE = """
import pytest

def test_quick():
    pass

@pytest.mark.slow
def test_slow():
    pass
"""


@pytest.fixture(scope="module")
def suite(tmp_path_factory) -> Path:
    """A suite of two files with one quick and one slow test each, and this conftest."""
    folder = tmp_path_factory.mktemp("suite")
    shutil.copy(Path(__file__).with_name("conftest.py"), folder / "conftest.py")
    (folder / "pytest.ini").write_text("[pytest]\nmarkers =\n    slow: slow\n")
    for name in ("test_a.py", "test_b.py"):
        (folder / name).write_text(SAMPLE)
    return folder


#: Collect only, in one process, without the plugins this suite loads that take a second,
#: in the files' order (pytest-randomly would shuffle the lists compared).
PYTEST = ["-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", "-p", "no:xdist"]
PYTEST += ["-p", "no:hypothesispytest", "-p", "no:randomly", "--strict-markers"]


def collected(suite: Path, *arguments: str) -> tuple[list[str], str]:
    done = subprocess.run(
        [sys.executable, *PYTEST, *arguments], cwd=suite, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return [line for line in done.stdout.splitlines() if "::" in line], done.stdout


def test_plain_pytest_leaves_the_slow_tier_out(suite):
    tests, output = collected(suite)
    assert tests == ["test_a.py::test_quick", "test_b.py::test_quick"]
    assert "2 deselected" in output


def test_the_slow_option_runs_every_test(suite):
    tests, _ = collected(suite, "--slow")
    assert len(tests) == 4


def test_a_marker_expression_chooses_for_itself(suite):
    tests, _ = collected(suite, "-m", "slow")
    assert tests == ["test_a.py::test_slow", "test_b.py::test_slow"]


def test_a_file_named_runs_all_its_tests(suite):
    tests, _ = collected(suite, "test_a.py", "test_b.py::test_quick")
    assert tests == ["test_a.py::test_quick", "test_a.py::test_slow", "test_b.py::test_quick"]
