"""The JavaScript target: the ES module, run by node, agrees with our compiled right-hand side,
mass matrix and forcing at random states to 1e-12, for the double pendulum, a model with inputs
and explicit time (the shaken cart-pole) and a constrained one (the Cartesian pendulum, with
multipliers and Baumgarte's stabilisation); the model's free text stays in comments."""

from __future__ import annotations

import copy
import json
import shutil
import subprocess

import pytest

import lagrangian as lg
from export.test_export import SHAKEN_CART_POLE, close, random_cases
from lagrangian.export import LANGUAGES, export_code, write_code
from lagrangian.numeric import compile_equations

SYSTEMS = {
    "double_pendulum": lambda: lg.load("double_pendulum"),
    "shaken_cart_pole": lambda: lg.loads(SHAKEN_CART_POLE),
    "cartesian_pendulum": lambda: lg.load("cartesian_pendulum"),
}

#: Reads cases [t, y, params, u] as JSON on stdin, prints [rhs, M, f] of each as JSON.
DRIVER = """
import * as model from "./model.mjs";
let text = "";
process.stdin.on("data", (chunk) => (text += chunk));
process.stdin.on("end", () => {
  const results = JSON.parse(text).map(([t, y, p, u]) => [
    model.rhs(t, y, p, u), model.mass_matrix(t, y, p, u), model.forcing(t, y, p, u),
  ]);
  process.stdout.write(JSON.stringify(results));
});
"""


@pytest.fixture(scope="module")
def node():
    found = shutil.which("node")
    if found is None:
        pytest.skip("node is not installed: the generated JavaScript cannot be run")
    return found


def test_javascript_is_an_export_language():
    assert "javascript" in LANGUAGES


@pytest.mark.parametrize("name", SYSTEMS)
def test_javascript_matches_our_compiled_rhs(name, node, tmp_path, np_rng):
    system = SYSTEMS[name]()
    write_code(system, "javascript", tmp_path / "model.mjs")
    (tmp_path / "driver.mjs").write_text(DRIVER)
    compiled = compile_equations(system.equations_of_motion())
    cases = list(random_cases(system, np_rng))
    payload = [[t, y.tolist(), params.tolist(), u.tolist()] for t, y, params, u, _ in cases]
    run = subprocess.run(
        [node, str(tmp_path / "driver.mjs")],
        input=json.dumps(payload), capture_output=True, text=True, check=True, timeout=60,
    )  # fmt: skip
    n = len(system.coordinates)
    for (t, y, _, _, ours), (rhs, mass, forcing) in zip(cases, json.loads(run.stdout), strict=True):
        vector = compiled.parameter_vector(ours)
        assert close(rhs, compiled.rhs(t, y, vector))
        assert close(mass, compiled.mass_matrix(t, y[:n], y[n:], vector))
        assert close(forcing, compiled.forcing(t, y[:n], y[n:], vector))


def test_javascript_reports_a_singular_mass_matrix(node, tmp_path):
    system = lg.loads(
        'name = "Free"\ncoordinates = ["x"]\nkinetic = "m*x_dot^2/2"\n[parameters]\nm = 1.0\n'
    )
    write_code(system, "javascript", tmp_path / "model.mjs")
    script = (
        'import {rhs} from "./model.mjs";'
        " try { rhs(0, [0, 0], [0]); } catch (e) { console.log(e.message); }"
    )
    (tmp_path / "driver.mjs").write_text(script)
    run = subprocess.run([node, str(tmp_path / "driver.mjs")], capture_output=True, text=True)
    assert run.stdout.strip() == "singular mass matrix"


def test_free_text_stays_in_comments():
    """A name or description that got past the model's check (a System refuses these
    characters as model files do) cannot end the header's comments: every JavaScript line
    break starts a new comment line."""
    system = copy.copy(lg.load("double_pendulum"))
    object.__setattr__(system, "name", "a\u2028b(); //")
    object.__setattr__(system, "description", "c\nd();\u2029e();")
    text = export_code(system, "javascript")
    code = [line for line in text.splitlines() if not line.startswith("//")]
    assert not any(call in line for line in code for call in ("b();", "d();", "e();"))
    assert not any(mark in text for mark in ("\u2028", "\u2029"))
