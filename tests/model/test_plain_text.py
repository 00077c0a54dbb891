"""Names and descriptions hold only what a model file can hold, however the system is made
(issue 37 item 14: a lone surrogate was accepted from Python, then no page or file of the
model could be written)."""

from __future__ import annotations

import dataclasses

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError

SURROGATE = r"lone surrogate U\+D800 not allowed in text \(it has no UTF-8 form\)$"


def _particle(name: str = "bob"):
    return lg.Particle(name=name, mass="m", position=["x", "0"])


MAKERS = {
    "from_lagrangian": lambda **text: lg.System.from_lagrangian(
        "x_dot**2/2", coordinates=["x"], **text
    ),
    "from_energies": lambda **text: lg.System.from_energies(
        "x_dot**2/2", "x**2/2", coordinates=["x"], **text
    ),
    "from_particles": lambda **text: lg.System.from_particles(
        ["x"], particles=[_particle()], **text
    ),
}


@pytest.mark.parametrize("maker", MAKERS)
@pytest.mark.parametrize("field", ["name", "description"])
def test_a_lone_surrogate_is_refused_by_every_constructor(maker, field):
    with pytest.raises(ModelError, match=rf"^{field}: {SURROGATE}"):
        MAKERS[maker](**{field: "a\ud800b"})


@pytest.mark.parametrize("character", ["\x1b", "\u202e", "\u2028", "\r"])
def test_control_characters_are_refused_as_the_model_file_refuses_them(character, tmp_path):
    code = f"U\\+{ord(character):04X}"
    with pytest.raises(ModelError, match=rf"^name: control character {code} not allowed in text$"):
        MAKERS["from_lagrangian"](name=f"a{character}b")
    path = tmp_path / "model.toml"
    escaped = f"\\u{ord(character):04x}"
    path.write_text(f'name = "a{escaped}b"\ncoordinates = ["x"]\nlagrangian = "x_dot^2/2"\n')
    with pytest.raises(ModelError, match=rf"name: control character {code} not allowed in text"):
        lg.load(path)


def test_a_description_keeps_its_line_breaks_and_tabs():
    system = MAKERS["from_lagrangian"](name="Free particle", description="one\n\ttwo")
    assert (system.name, system.description) == ("Free particle", "one\n\ttwo")


def test_a_replaced_name_is_checked_too():
    system = MAKERS["from_lagrangian"]()
    with pytest.raises(ModelError, match=rf"^name: {SURROGATE}"):
        dataclasses.replace(system, name="a\ud800b")


def test_a_component_name_is_checked():
    with pytest.raises(ModelError, match=rf"^particles\[0\]\.name: {SURROGATE}"):
        lg.System.from_particles(["x"], particles=[_particle("b\ud800")])
