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
