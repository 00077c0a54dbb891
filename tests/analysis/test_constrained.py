"""Equilibria on constraint surfaces: rest points, constraint forces and small oscillations."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis import Stability, constrained_equilibria


def by_height(equilibria, system):
    return sorted(equilibria, key=lambda e: float(e.point["y"].subs(system.symbol("l"), 1)))


def test_cartesian_pendulum_tension_and_frequency():
    system = lg.load("cartesian_pendulum")
    bottom, top = by_height(constrained_equilibria(system.equations_of_motion()), system)
    m, g, l = (system.symbol(n) for n in ("m", "g", "l"))
    assert bottom.point == {"x": 0, "y": -l}
    assert sympy.simplify(-2 * l * bottom.multipliers["lambda1"] - m * g) == 0  # tension m g
    assert bottom.modes.stability is Stability.STABLE
    assert sympy.simplify(bottom.omega_squared[0] - g / l) == 0
    assert top.modes.stability is Stability.UNSTABLE


def test_bead_on_a_parabolic_wire():
    # y = a x^2 under gravity: omega^2 = 2 a g at the bottom, the wire pushes with m g
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bead", "m", ("x", "y"))],
        gravity=lg.Gravity("g"),
        constraints=["y - a*x^2"],
    )
    (bottom,) = constrained_equilibria(system.equations_of_motion())
    a, g, m = (system.symbol(n) for n in ("a", "g", "m"))
    assert bottom.point == {"x": 0, "y": 0}
    assert sympy.simplify(bottom.omega_squared[0] - 2 * a * g) == 0
    assert sympy.simplify(bottom.multipliers["lambda1"] - m * g) == 0


@pytest.mark.slow
def test_two_masses_on_a_rigid_rod_hanging_from_a_spring():
    # a dumbbell (rod of length d between two masses) hanging vertically from a spring
    system = lg.System.from_particles(
        ["x1", "y1", "x2", "y2"],
        [lg.Particle("a", "m", ("x1", "y1")), lg.Particle("b", "m", ("x2", "y2"))],
        gravity=lg.Gravity("g"),
        springs=[lg.Spring("k", ends=("a", (0, 0)))],
        constraints=["(x1 - x2)^2 + (y1 - y2)^2 - d^2"],
        parameters={"m": 1.0, "g": 9.81, "k": 50.0, "d": 0.5},
    )
    equilibria = constrained_equilibria(system.equations_of_motion())
    stable = [e for e in equilibria if e.modes.stability is Stability.STABLE]
    assert len(stable) == 1
    (rest,) = stable
    # the spring carries both weights: y1 = -2 m g / k, the second mass hangs d below
    defaults = {p.symbol: p.default for p in system.parameters}
    assert float(rest.point["y1"].subs(defaults)) == pytest.approx(-2 * 9.81 / 50.0)
    assert float(rest.point["y2"].subs(defaults)) == pytest.approx(-2 * 9.81 / 50.0 - 0.5)
    assert len(rest.omega_squared) == 3  # 4 coordinates, 1 constraint


def test_analyze_reports_constrained_equilibria():
    from lagrangian.analysis import analyze
    from lagrangian.output.analysis import analysis_document

    document = analysis_document(analyze(lg.load("cartesian_pendulum").equations_of_motion()))
    assert {tuple(e["point"].values()) for e in document["equilibria"]} == {("0", "-l"), ("0", "l")}
    assert all("lambda1" in e["multipliers"] for e in document["equilibria"])


def test_nonholonomic_constraints_are_refused():
    with pytest.raises(lg.ModelError, match="linear in the velocities"):
        constrained_equilibria(lg.load("rolling_disc").equations_of_motion())


def test_text_says_equilibria_not_computed_rather_than_none_found():
    from lagrangian.output.analysis import format_analysis

    text = format_analysis(lg.load("rolling_disc").analyze())
    block = text.split("Equilibria (at rest, staying at rest):")[1].split("\n\n")[0]
    assert "none found" not in block
    assert "not computed: equilibria with constraints linear in the velocities" in block
