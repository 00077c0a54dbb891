"""What the CLI prints around warnings: ours as one line each, library noise never on top of
an error, and only with LAGRANGIAN_DEBUG=1 after a success."""

from __future__ import annotations

import warnings

import pytest

from lagrangian import examples
from lagrangian.cli import ExitStatus, main
from lagrangian.errors import CacheWarning, LagrangianWarning, ModelError


class TypoWarning(LagrangianWarning):  # another part's category: a subclass is enough
    pass


def _examples_that(monkeypatch, *, warn=(), fail=False):
    """`lagrangian examples` made to raise ``warn`` (category, text) and then fail or list none."""

    def names():
        for category, text in warn:
            warnings.warn(text, category, stacklevel=1)
        if fail:
            raise ModelError("the model is broken", source="model.toml")
        return []

    monkeypatch.setattr(examples, "example_names", names)


NOISE = [
    (RuntimeWarning, "invalid value encountered in divide"),
    (DeprecationWarning, "xarray: this keyword is deprecated"),
    (UserWarning, "matplotlib: Attempting to set identical low and high xlims"),
]
OURS = [
    (CacheWarning, "the code cache /x cannot be used (not a directory); ..."),
    (TypoWarning, "'thetta' is not a coordinate;\n did you mean 'theta'?"),
]


def test_on_failure_only_the_error_line(monkeypatch, capsys):
    _examples_that(monkeypatch, warn=[*NOISE, *OURS], fail=True)
    assert main(["examples"]) == ExitStatus.BAD_INPUT
    assert capsys.readouterr().err == "lagrangian: error: model.toml: the model is broken\n"


def test_on_success_ours_one_line_each_and_no_library_noise(monkeypatch, capsys):
    monkeypatch.delenv("LAGRANGIAN_DEBUG", raising=False)
    _examples_that(monkeypatch, warn=[*NOISE, *OURS, *OURS])  # the same text twice: once
    assert main(["examples"]) == ExitStatus.SUCCESS
    assert capsys.readouterr().err.splitlines() == [
        "lagrangian: warning: the code cache /x cannot be used (not a directory); ...",
        "lagrangian: warning: 'thetta' is not a coordinate; did you mean 'theta'?",
    ]


def test_library_warnings_shown_with_debug(monkeypatch, capsys):
    monkeypatch.setenv("LAGRANGIAN_DEBUG", "1")
    _examples_that(monkeypatch, warn=NOISE[:1])
    assert main(["examples"]) == ExitStatus.SUCCESS
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith(
        "lagrangian: warning: RuntimeWarning: invalid value encountered in divide ("
    )


@pytest.mark.parametrize("run", [1, 2])
def test_each_command_shows_its_own_warnings(monkeypatch, capsys, run):
    # the registry of warnings already shown must not hide one in the next in-process run
    _examples_that(monkeypatch, warn=OURS[:1])
    assert main(["examples"]) == ExitStatus.SUCCESS
    assert capsys.readouterr().err.count("lagrangian: warning:") == 1


def test_warning_filters_are_restored(monkeypatch, capsys):
    before = list(warnings.filters)
    _examples_that(monkeypatch, warn=NOISE)
    main(["examples"])
    assert warnings.filters == before
