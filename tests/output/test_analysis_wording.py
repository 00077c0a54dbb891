"""The words of analyze's text where they could mislead (issue 32, item 6): values given
with --set are not called the defaults, and a parameter written ω (a turning wire's rate)
is not confused with the modes' ω in one line."""

from __future__ import annotations

import pytest

from lagrangian.cli import ExitStatus, main

#: A bead on the parabola z = a r^2 turning at omega: stable iff 2 a g > omega^2.
PARABOLA = """
name = "bead on a turning parabola"
coordinates = ["r"]
kinetic = "m*(r_dot^2 + omega^2*r^2 + (2*a*r*r_dot)^2)/2"
potential = "m*g*a*r^2"
[parameters]
m = 1
g = 9.81
a = 1
omega = 2
"""


def _analyzed(model, *options, capsys) -> str:
    assert main(["analyze", str(model), *options]) == ExitStatus.SUCCESS
    return capsys.readouterr().out


@pytest.mark.slow  # three analyses
def test_a_verdict_at_values_given_says_so(tmp_path, capsys):
    model = tmp_path / "parabola.toml"
    model.write_text(PARABOLA, encoding="utf-8")
    defaults = _analyzed(model, capsys=capsys)
    assert "r = 0: stable at the default parameter values; stable iff 2 a g > ω²" in defaults
    given = _analyzed(model, "--set", "omega=5", capsys=capsys)  # 2 a g = 19.62 < 25
    assert "r = 0: unstable at the given values; stable iff 2 a g > ω²" in given
    assert "default" not in given
    latex = _analyzed(model, "--set", "omega=5", "--latex", capsys=capsys)
    assert r"\text{stability at the given values}" in latex


def test_a_parameter_named_omega_is_not_the_modes_omega(capsys):
    text = _analyzed("rotating_wire_bead", capsys=capsys)
    # was "at ω = 1: ω² = -1": one symbol for the wire's rate and the mode's frequency
    assert "at ω = 1: squared angular frequencies -1" in text
    assert "ω² = -1" not in text
