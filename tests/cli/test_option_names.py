"""Messages name only options the command has (issue 37 item 13): the library's settings
are spelled per command, and a deadline no stage caught suggests --timeout only where
the command has one."""

from __future__ import annotations

import importlib

import pytest

from lagrangian import facade
from lagrangian.budget import OutOfTime
from lagrangian.cli import ExitStatus, command_flags, main
from lagrangian.cli.app import FLAGS, app

#: The module (``lagrangian.cli.app`` as an attribute is the click group of that name).
cli_app = importlib.import_module("lagrangian.cli.app")


def out_of_time(*args, **kwargs):
    raise OutOfTime("derive", 5.0)


@pytest.mark.parametrize(
    ("argv", "hint"),
    [
        (["derive", "harmonic_oscillator"], "lagrangian derive has no --timeout"),
        (
            ["page", "harmonic_oscillator", "--out", "{dir}/p.html", "--no-cache"],
            "lagrangian page has no --timeout",
        ),
        (["export", "harmonic_oscillator", "--to", "c"], "lagrangian export has no --timeout"),
        (["analyze", "harmonic_oscillator"], "allow more time with --timeout SECONDS"),
        (["simulate", "harmonic_oscillator"], "allow more time with --timeout SECONDS"),
    ],
)
def test_a_deadline_no_stage_caught_suggests_only_an_option_that_exists(
    capsys, monkeypatch, tmp_path, argv, hint
):
    monkeypatch.setattr(cli_app, "_load", out_of_time)
    monkeypatch.setattr(facade, "load", out_of_time)
    argv = [argument.replace("{dir}", str(tmp_path)) for argument in argv]
    assert main(argv) == ExitStatus.BAD_INPUT
    err = capsys.readouterr().err
    ending = ": the budgets of its stages are fixed)" if "no --timeout" in hint else ")"
    assert err == f"lagrangian: error: derive: not decided within 5 s ({hint}{ending}\n"


def test_each_command_spells_only_the_settings_it_has_an_option_for():
    assert command_flags(app.commands["simulate"])["timeout"] == "--timeout SECONDS"
    assert "timeout" not in command_flags(app.commands["derive"])
    assert "grid" not in command_flags(app.commands["bifurcation"])
    assert command_flags(app.commands["bifurcation"])["vary"] == "--vary"
    assert command_flags(None) == FLAGS  # no command (a usage error before one)


def test_every_flag_of_a_setting_is_an_option_of_some_command():
    options = {name for command in app.commands.values() for p in command.params for name in p.opts}
    assert {flag.split()[0] for flag in FLAGS.values()} <= options


def test_remedies_without_an_option_on_this_command_are_left_out():
    from lagrangian.errors import PYTHON_SPELLING, choices, setting, spelled

    text = "give " + choices(
        f"a shorter {setting('t_end')}", f"a looser {setting('rtol')}", f"a larger {setting('dt')}"
    )
    assert spelled(text, PYTHON_SPELLING) == "give a shorter t_end, a looser rtol or a larger dt"
    plot = command_flags(app.commands["plot"])  # has --t-end, not --rtol nor --dt
    assert spelled(text, plot) == "give a shorter --t-end"
    lyapunov = command_flags(app.commands["lyapunov"])  # --rtol, no --dt
    assert spelled(text, lyapunov) == "give a shorter --t-end or a looser --rtol"
    assert spelled(choices("fewer members", f"a faster {setting('backend')}"), {}) == (
        "fewer members"
    )
