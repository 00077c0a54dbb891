"""The equations `lagrangian derive` prints are those it printed before the derivation and
the model's checks were made faster (issue 36, item 4): the sha256 (first 16 hex digits)
of the JSON document and of the text of every example and of 3-, 7- and 20-link chains
(the readable route and the SymEngine route), as main printed them at 74b85bc (the
examples added since, at 538748f).

The digests hold for the libraries they were taken with (SymPy 1.14.0, SymEngine
0.15.0): another version may print the same equations otherwise, and the test is
skipped there.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest
import symengine
import sympy

import lagrangian.examples
from lagrangian.cli import ExitStatus, main

# Each test derives and prints a model twice in this process: 1-10 s each on two cores.
pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        (sympy.__version__, symengine.__version__) != ("1.14.0", "0.15.0"),
        reason="the digests were taken with SymPy 1.14.0 and SymEngine 0.15.0",
    ),
]

DIGESTS = {
    "cart_pole --json": "f8a17cab5e4d0b0d",
    "cart_pole --text": "dea4cec67d3ceccd",
    "cartesian_pendulum --json": "77a3d96395e93dce",
    "cartesian_pendulum --text": "57b919102199eb06",
    "central_force --json": "3ab4cf5518f41c53",
    "central_force --text": "f863ecab0c1e73b1",
    "double_pendulum --json": "28908f05e6a3b7f3",
    "double_pendulum --text": "78f7f74a868a583d",
    "driven_damped_pendulum --json": "c01eb99ebcf8aaeb",
    "driven_damped_pendulum --text": "ec3e642476bfda5e",
    "free_particle_spherical --json": "71248f29efd5388a",
    "free_particle_spherical --text": "4d84f61cfb0774fa",
    "harmonic_oscillator --json": "acdba759b6d51c79",
    "harmonic_oscillator --text": "720670432da7e421",
    "heavy_top --json": "59e8beb226af95dc",
    "heavy_top --text": "37ac139b33f8f426",
    "henon_heiles --json": "e94d5f39d439b390",
    "henon_heiles --text": "8ee0a354e4622590",
    "planar_particle_forces --json": "e174c82eb6612a5b",
    "planar_particle_forces --text": "f691c3366934ad92",
    "rolling_disc --json": "b3bb55d90adbb50e",
    "rolling_disc --text": "a8df27e9bda3ea63",
    "rotating_wire_bead --json": "692bef4ba7495225",
    "rotating_wire_bead --text": "d7dd93a082389af9",
    "simple_pendulum --json": "84d48e8d22d7e8d7",
    "simple_pendulum --text": "71f52a18adecf83d",
    "spherical_pendulum --json": "992078dae79dedd9",
    "spherical_pendulum --text": "c0c9ecb5de70e214",
    "velocity_dependent_potential --json": "5277d71bc0ac136e",
    "velocity_dependent_potential --text": "f65bf7edf6c3121e",
    "vertical_spring --json": "b007b8143cf39e77",
    "vertical_spring --text": "50955f6364aa99d5",
    # examples added after 74b85bc (impacts, linkages), as main printed them at 538748f
    "bouncing_ball --json": "b8750edc5354386a",
    "bouncing_ball --text": "1be70b0e684038a8",
    "four_bar --json": "dba0496c88c4ece6",
    "four_bar --text": "f435cf1f74e036fe",
    "four_bar_driven --json": "9bc3fef1d3897ebf",
    "four_bar_driven --text": "55106beaacd6956f",
    "impact_oscillator --json": "6f154f1bb132bab9",
    "impact_oscillator --text": "f47e02826890ee7f",
    "rocking_block --json": "c0482660fc43dc19",
    "rocking_block --text": "cf6f6cf212ca6d32",
    "slider_crank --json": "ce8cf59fcbd1bd32",
    "slider_crank --text": "4846a14836292276",
    "c3 --json": "12b0fe90dfa984a5",
    "c3 --text": "6911a4f02e46a6bb",
    "c7 --json": "1b28a783536eb8a2",
    "c7 --text": "6d0c258ce213cc6a",
    "c20 --json": "07d30c46bd148796",
    "c20 --text": "bcd3ef21adce0d2c",
}
EXAMPLES = sorted(p.stem for p in Path(lagrangian.examples.__file__).parent.glob("*.toml"))


def chain_model(n: int) -> str:
    """The n-link pendulum's model file as benchmarks/cli.py writes it."""
    coordinates = ", ".join(f'"theta{i}"' for i in range(1, n + 1))
    lines = [f'name = "{n}-link pendulum"', f"coordinates = [{coordinates}]", "", "[parameters]"]
    lines += [f"m{i} = 1.0" for i in range(1, n + 1)]
    lines += [f"l{i} = 1.0" for i in range(1, n + 1)]
    lines += ["g = 9.81", ""]
    x, y = "0", "0"
    for i in range(1, n + 1):
        x += f" + l{i}*sin(theta{i})"
        y += f" - l{i}*cos(theta{i})"
        lines += ["[[particles]]", f'name = "bob{i}"', f'mass = "m{i}"']
        lines += [f'position = ["{x}", "{y}"]', ""]
    lines += ["[gravity]", 'g = "g"', "direction = [0, -1]", "", "[initial]", "theta1 = 0.5", ""]
    return "\n".join(lines)


def printed(capsys, model: str, *options: str) -> str:
    assert main(["derive", model, *options]) == ExitStatus.SUCCESS
    return hashlib.sha256(capsys.readouterr().out.encode()).hexdigest()[:16]


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_examples_equations_are_printed_as_before(name, capsys):
    assert printed(capsys, name, "--json") == DIGESTS[f"{name} --json"]
    assert printed(capsys, name) == DIGESTS[f"{name} --text"]


@pytest.mark.parametrize("links", [3, 7, 20])
def test_the_chains_equations_are_printed_as_before(links, tmp_path, capsys):
    model = tmp_path / f"c{links}.toml"
    model.write_text(chain_model(links))
    assert printed(capsys, str(model), "--json") == DIGESTS[f"c{links} --json"]
    assert printed(capsys, str(model)) == DIGESTS[f"c{links} --text"]
