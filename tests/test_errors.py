"""The kinds of errors: each is the built-in exception a Python caller expects, one line each."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.errors import FileError, LagrangianError, MissingDependencyError, ModelError


def test_a_model_error_is_a_value_error():
    with pytest.raises(ValueError, match=r"^model\.toml: m: must be positive in '-1'$"):
        raise ModelError("must be positive", source="model.toml", field="m", text="-1")
    assert issubclass(ModelError, LagrangianError)


def test_a_missing_dependency_is_an_import_error_naming_the_extra():
    error = MissingDependencyError("method 'taylor'", "heyoka", "taylor")
    assert isinstance(error, ImportError) and isinstance(error, LagrangianError)
    assert not isinstance(error, ModelError)
    assert str(error) == (
        "method 'taylor' needs heyoka: pip install \".[taylor]\" in a clone of lagrangian"
    )
    bare = MissingDependencyError("to_control()", "python-control")
    assert str(bare) == "to_control() needs python-control: pip install python-control"


def test_file_errors_stay_their_own_kind():
    assert not issubclass(FileError, ValueError)
    assert str(FileError("run.csv", "no such file")) == "run.csv: no such file"


def test_a_bad_value_in_the_api_is_caught_as_a_value_error():
    system = lg.load("simple_pendulum")
    with pytest.raises(ValueError, match=r"^unknown parameter .nonsense. \(parameters: m, l, g\)$"):
        system.simulate(t_end=0.1, params={"nonsense": 1.0})


def test_messages_name_settings_as_python_does_and_the_cli_as_its_flags(capsys):
    from lagrangian.cli import main

    system = lg.System.from_lagrangian("m*x_dot^2/2 - k*x^2/2", coordinates=["x"])
    with pytest.raises(lg.ModelError) as error:
        system.simulate(t_end=1.0, method="rk4", rtol=1e-6)
    assert str(error.value) == "rtol does not apply to method 'rk4' (a fixed-step method: give dt)"
    status = main(["simulate", "harmonic_oscillator", "--method", "rk4", "--rtol", "1e-6"])
    assert status == 2
    assert capsys.readouterr().err == (
        "lagrangian: error: --rtol does not apply to method 'rk4' "
        "(a fixed-step method: give --dt)\n"
    )


def test_no_library_message_names_a_flag_of_the_command_line():
    # the CLI spells settings as flags (lagrangian.cli.FLAGS); the library never does
    import re
    from pathlib import Path

    source = Path(lg.__file__).parent
    flags = "set|dt|rtol|atol|t-end|timeout|define|grid|at|to|out|backend|method|output"
    flags += "|allow-remote|host|port"
    flag = re.compile(rf"""["'](?:[^"'\n]*\s)?--({flags})\b""")
    found = [
        f"{path.relative_to(source)}:{number}"
        for path in source.rglob("*.py")
        if path.parts[len(source.parts)] != "cli"
        for number, line in enumerate(path.read_text().splitlines(), start=1)
        if flag.search(line) and not line.lstrip().startswith("#")
    ]
    assert found == []
