"""Values given in place of the defaults (params=, at=, --set, --at, an ensemble's grid) pass
the model file's own checks: the parameter's assumed sign and the 3-D bodies' inertia."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.model.values import check_parameter_expressions, check_parameter_values

TRIANGLE = r"^bodies\[0\]\.inertia: the principal moments .* violate the triangle inequality"


@pytest.fixture(scope="module")
def top():
    return lg.load("heavy_top")  # inertia [I1, I1, I3], I1 = 0.01, I3 = 0.02


def test_the_file_refuses_what_a_value_given_later_is_refused_for(top):
    text = (
        'coordinates = ["phi", "theta", "psi"]\n[parameters]\nI1 = 0.01\nI3 = 1.0\n'
        '[[bodies]]\nmass = "1"\nposition = ["0", "0", "0"]\ninertia = ["I1", "I1", "I3"]\n'
        'orientation = {euler = ["phi", "theta", "psi"], convention = "zxz"}\n'
    )
    with pytest.raises(ModelError, match=r"bodies\[0\]\.inertia: the principal moments"):
        lg.loads(text)
    with pytest.raises(ModelError, match=TRIANGLE + r".*\(with I3 = 1\)$"):
        check_parameter_values(top, {"I3": 1.0})


def test_good_values_pass_and_arrays_are_checked_member_by_member(top):
    check_parameter_values(top, {"I1": 0.5, "I3": 0.9, "M": 2.0})
    check_parameter_values(top, {"I3": np.linspace(0.001, 0.02, 50)})
    with pytest.raises(ModelError, match=TRIANGLE + r".*\(with I1 = 0\.01, I3 = 0\.03\)$"):
        check_parameter_values(top, {"I1": [[0.01], [0.02]], "I3": [0.02, 0.03]})


def test_sign_finiteness_and_names(top):
    with pytest.raises(ModelError, match=r"^parameter M = -1 breaks the model's assumption"):
        check_parameter_values(top, {"M": -1.0})
    with pytest.raises(ModelError, match=r"^parameter l = nan is not a finite number$"):
        check_parameter_values(top, {"l": np.nan})
    with pytest.raises(ModelError, match=r"^unknown parameter 'nope'"):
        check_parameter_values(top, {"nope": 1.0})


def test_an_expression_is_judged_at_the_other_values(top):
    import sympy

    M, g = top.symbol("M"), top.symbol("g")
    check_parameter_expressions(top, {"M": 2 * g})
    with pytest.raises(ModelError, match=r"^parameter M = -9\.81 breaks"):
        check_parameter_expressions(top, {"M": -g})
    check_parameter_expressions(top, {"M": sympy.Symbol("free") * M})  # no number: left alone


def test_every_entry_point_with_values_checks_them(top):
    with pytest.raises(ModelError, match=TRIANGLE):
        top.simulate(t_end=0.1, params={"I3": 1.0})
    with pytest.raises(ModelError, match=TRIANGLE):
        top.state_space(at={"theta": 0, "I3": 1.0})
    pendulum = lg.load("simple_pendulum")
    with pytest.raises(ModelError, match=r"^parameter l = -1 breaks"):
        pendulum.linearize({"theta": 0, "l": -1.0})
    with pytest.raises(ModelError, match=r"^parameter l = -1 breaks"):
        pendulum.state_space(at={"theta": 0, "l": "-1"})


@pytest.mark.parametrize(
    "name, error",
    [
        ("bad name", r"^outputs: invalid output name 'bad name'"),
        ("sin", r"^outputs\.sin: 'sin' is a built-in name"),
        ("E", r"^outputs\.E: 'E' is a built-in name"),
        ("theta", r"^outputs\.theta: 'theta' is a coordinate"),
        ("theta_ddot", r"^outputs\.theta_ddot: 'theta_ddot' is an acceleration"),
        ("l", r"^outputs\.l: 'l' is a parameter"),
    ],
)
def test_an_output_is_named_by_an_identifier_that_means_nothing_else(name, error):
    pendulum = lg.load("simple_pendulum")
    with pytest.raises(ModelError, match=error):
        pendulum.state_space(at={"theta": 0}, outputs={name: "theta"})
    assert pendulum.state_space(at={"theta": 0}, outputs={"tip": "l*sin(theta)"}) is not None


def test_a_mass_of_two_parameters_among_others_is_checked_at_their_defaults(tmp_path):
    # the check puts in only the parameters the mass holds (k is not in it)
    model = tmp_path / "bead.toml"
    model.write_text(
        'name = "bead"\ncoordinates = ["x"]\n\n[parameters]\nm1 = 1.0\nm2 = 2.0\nk = 3.0\n\n'
        '[[particles]]\nname = "bob"\nmass = "m1 - m2"\nposition = ["x", "0"]\n'
    )
    with pytest.raises(ModelError, match=r"the mass of 'bob' \(particles\[0\]\.mass = m1 - m2\) "
                       r"is -1 with m1 = 1, m2 = 2: it must be > 0$"):  # fmt: skip
        lg.load(model)
    model.write_text(model.read_text().replace("m1 - m2", "m2 - m1"))
    assert lg.load(model).parameter_values["k"] == 3.0


def test_the_masses_are_checked_against_the_defaults_made_once(monkeypatch):
    """A large model has a mass per parameter or two: the defaults are gathered once for
    all its masses (before: once per mass, O(n^2) for a chain), and a bad mass among
    many is still named."""
    from lagrangian.model import system as system_module
    from lagrangian.model.values import check_masses

    n = 12
    particles = [lg.Particle(f"bob{i}", mass=f"m{i}", position=[f"x*l{i}", "0"]) for i in range(n)]
    model = lg.System.from_particles(coordinates=["x"], particles=particles)
    read: list[int] = []
    defaults = system_module.System.parameter_values

    def counted(self):
        read.append(1)
        return defaults.fget(self)

    monkeypatch.setattr(system_module.System, "parameter_values", property(counted))
    check_masses(model)
    assert len(read) == 1
    negative = {"m7": -2.0}
    with pytest.raises(ModelError, match=r"the mass of 'bob7' \(particles\[7\]\.mass = m7\) is -2"):
        check_masses(model, negative)
