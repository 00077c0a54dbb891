"""Names that look like slips: warned of where they become parameters, suggested where refused;
and constants that are not real, refused in SymPy input too."""

from __future__ import annotations

import warnings

import pytest
import sympy

import lagrangian as lg
from lagrangian.errors import LagrangianWarning, LikelyTypoWarning, ModelError
from lagrangian.parsing.suggest import likely_meant

KNOWN = ["x", "x_dot", "x_ddot", "theta", "theta_dot", "theta_ddot", "theta1", "theta1_dot"]


@pytest.mark.parametrize(
    "name, meant",
    [
        ("xdot", "x_dot"), ("x_dott", "x_dot"), ("x_d", "x_dot"), ("dx", "x_dot"),
        ("xd", "x_dot"), ("thetadot", "theta_dot"), ("thetaDot", "theta_dot"),
        ("dtheta", "theta_dot"), ("theta_dto", "theta_dot"), ("theta1dot", "theta1_dot"),
        ("xddot", "x_ddot"), ("x_dd", "x_ddot"), ("ddx", "x_ddot"), ("thetta", "theta"),
        ("thta", "theta"),
    ],
)  # fmt: skip
def test_slips_for_coordinates_and_velocities(name, meant):
    assert likely_meant(name, KNOWN) == meant


@pytest.mark.parametrize("name", ["k", "m", "y", "xx", "theta0", "theta2", "Theta", "l", "omega"])
def test_other_names_are_not_slips(name):
    assert likely_meant(name, KNOWN) is None


def caught_warnings(build) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        build()
    return [str(w.message) for w in caught if issubclass(w.category, LikelyTypoWarning)]


def test_an_undeclared_velocity_slip_is_warned_of():
    messages = caught_warnings(
        lambda: lg.System.from_lagrangian("m*xdot**2/2 - k*x**2/2", coordinates=["x"])
    )
    assert messages == [
        "parameters.xdot: 'xdot' is not declared and became a parameter (a constant); "
        "did you mean 'x_dot'?"
    ]
    assert issubclass(LikelyTypoWarning, LagrangianWarning)


def test_slips_are_warned_of_in_every_constructor():
    assert caught_warnings(
        lambda: lg.System.from_energies("m*thetadot**2/2", "m*g*cos(theta)", coordinates=["theta"])
    ) == [
        "parameters.thetadot: 'thetadot' is not declared and became a parameter (a constant); "
        "did you mean 'theta_dot'?"
    ]
    particle = lg.Particle(name="p", mass="m", position=("x", "x_dott"))
    messages = caught_warnings(lambda: lg.System.from_particles(["x"], [particle]))
    assert len(messages) == 1 and "'x_dott'" in messages[0] and "'x_dot'" in messages[0]


def test_a_declared_parameter_named_like_a_velocity_is_warned_of(tmp_path):
    path = tmp_path / "model.toml"
    path.write_text('coordinates = ["x"]\nlagrangian = "xdot**2"\n[parameters]\nxdot = 1.0\n')
    messages = caught_warnings(lambda: lg.load(path))
    assert messages == [
        f"{path}: parameters.xdot: 'xdot' is declared as a parameter (a constant); "
        "did you mean 'x_dot'?"
    ]


def test_ordinary_models_give_no_warning():
    assert not caught_warnings(
        lambda: lg.System.from_lagrangian(
            "m*x_dot**2/2 - k*x**2/2 + theta0*x + a*x_ddot*0", coordinates=["x"]
        )
    )
    assert not caught_warnings(lambda: lg.load("double_pendulum"))


def test_an_unknown_name_in_a_model_file_suggests_the_likely_one(tmp_path):
    path = tmp_path / "model.toml"
    path.write_text('coordinates = ["x"]\nlagrangian = "m*x_dott**2/2"\n[parameters]\nm = 1.0\n')
    with pytest.raises(ModelError) as caught:
        lg.load(path)
    assert str(caught.value) == (
        f"{path}: lagrangian: unknown symbol 'x_dott' (did you mean 'x_dot'?) at position 3 "
        "in 'm*x_dott**2/2'"
    )


def test_sympy_input_with_a_constant_that_is_not_real_is_refused():
    x, x_dot = sympy.symbols("x x_dot", real=True)
    with pytest.raises(ModelError) as caught:
        lg.System.from_lagrangian(x_dot**2 / 2 + sympy.acos(2) * x, coordinates=["x"])
    assert str(caught.value).startswith("lagrangian: acos(2) is not a real number in ")
    with pytest.raises(ModelError, match=r"forces\.x: I is not a real number"):
        lg.System.from_lagrangian("x_dot**2", coordinates=["x"], forces={"x": sympy.I * x})
