"""One hostile command-line case: the argv, the files it needs, and the one-line error expected.

Each ``cases_<area>.py`` beside this file lists its cases in ``CASES``.  The
suite (``test_cases.py``) runs every case in-process through
:func:`lagrangian.cli.main` under a hard alarm; ``benchmarks/hostile.py``
runs the same cases as real ``lagrangian`` processes and prints the worst
wall time.  ``{dir}`` in an argument is the case's own empty folder, after
``setup`` has put its files there (``model.toml`` from ``model``, when given).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class HostileCase:
    """``lagrangian *argv`` exits with ``exit_code``; with 2, one stderr line matching ``error``."""

    name: str
    argv: tuple[str, ...]
    error: str = ""  # a regular expression searched in the one stderr line (exit 2)
    model: str | bytes | None = None  # written to {dir}/model.toml
    setup: Callable[[Path], None] | None = None  # makes special files in {dir}
    exit_code: int = 2
    output: str = ""  # for exit 0: a regular expression searched in stdout
    warning: str = ""  # a regular expression searched in stderr (warnings with exit 0)
    env: tuple[tuple[str, str], ...] = ()  # extra environment variables ({dir} replaced)
    slow: bool = False  # seconds of symbolic work: in the slow tier (pytest --slow)

    def prepare(self, folder: Path) -> list[str]:
        """Write the case's files into ``folder`` and return the argv to run."""
        if self.model is not None:
            data = self.model if isinstance(self.model, bytes) else self.model.encode()
            (folder / "model.toml").write_bytes(data)
        if self.setup is not None:
            self.setup(folder)
        return [argument.replace("{dir}", str(folder)) for argument in self.argv]

    def environment(self, folder: Path) -> dict[str, str]:
        """The extra environment variables of the case, ``{dir}`` being ``folder``."""
        return {name: value.replace("{dir}", str(folder)) for name, value in self.env}

    def check(self, status: int, stdout: str, stderr: str) -> None:
        """Assert the outcome: the exit status, one error line, no traceback or warning noise."""
        assert status == self.exit_code, f"{self.name}: exit {status}, stderr {stderr!r}"
        assert "Traceback" not in stderr, f"{self.name}: traceback on stderr"
        if self.exit_code == 2:
            lines = stderr.strip().splitlines()
            assert len(lines) == 1, f"{self.name}: expected one stderr line, got {lines!r}"
            assert lines[0].startswith("lagrangian: error: "), lines[0]
            assert re.search(self.error, lines[0]), f"{self.name}: {lines[0]!r} !~ {self.error!r}"
        if self.output:
            assert re.search(self.output, stdout), f"{self.name}: stdout {stdout[:500]!r}"
        if self.warning:
            assert re.search(self.warning, stderr), f"{self.name}: stderr {stderr!r}"


def all_cases() -> list[HostileCase]:
    """Every case of every ``cases_*.py`` module beside this file, in file order."""
    import importlib

    found = []
    for path in sorted(Path(__file__).parent.glob("cases_*.py")):
        module = importlib.import_module(f"hostile.{path.stem}")
        found.extend(module.CASES)
    names = [case.name for case in found]
    duplicated = {name for name in names if names.count(name) > 1}
    assert not duplicated, f"hostile case names used twice: {sorted(duplicated)}"
    return found
