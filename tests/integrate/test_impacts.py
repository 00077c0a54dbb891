"""Runs with contacts: impact times and velocities against closed forms, the impact law's
invariants, chattering into a held contact, its release, and Newton's cradle."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import lagrangian as lg
from helpers import slow_where
from lagrangian.model.impacts import Impact
from lagrangian.numeric import compile_equations
from lagrangian.simulation import simulate_system


def ball(e: float = 0.9, h0: float = 1.0, **options) -> lg.System:
    return lg.System.from_energies(
        "m*y_dot**2/2", "m*g*y", coordinates=["y"],
        parameters={"m": 1.0, "g": 9.81, "e": e},
        impacts=(Impact(gap="y", restitution="e", name="floor"),),
        initial={"y": h0}, **options,
    )  # fmt: skip


def analytic_times(count: int, e: float, h0: float, g: float) -> np.ndarray:
    """t_1 = sqrt(2 h0 / g), t_{k+1} = t_k + 2 e^k v0 / g with v0 = sqrt(2 g h0)."""
    v0 = math.sqrt(2 * g * h0)
    times = [math.sqrt(2 * h0 / g)]
    for k in range(1, count):
        times.append(times[-1] + 2 * e**k * v0 / g)
    return np.array(times)


def test_the_first_bounces_of_the_ball_are_the_analytic_ones():
    trajectory = simulate_system(ball(0.9), t_end=3.0, backend="llvm")
    times = np.array([r.t for r in trajectory.impacts])
    assert times.size == 4
    np.testing.assert_allclose(times, analytic_times(4, 0.9, 1.0, 9.81), rtol=0, atol=1e-12)


@pytest.mark.parametrize("backend", slow_where(["llvm", "numba"], lambda name: name == "numba"))
def test_the_bouncing_ball_follows_the_analytic_sequence_into_a_held_contact(backend):
    e, h0, g = 0.9, 1.0, 9.81
    trajectory = simulate_system(ball(e, h0), t_end=12.0, backend=backend)
    impacts = trajectory.impacts
    times = np.array([r.t for r in impacts])
    expected = analytic_times(len(impacts), e, h0, g)
    speeds = np.array([-r.velocities_before[0] for r in impacts])
    fast = speeds > 1e-3  # every impact but the last few tens before the contact is held
    assert fast.sum() > 60
    np.testing.assert_allclose(times[fast], expected[fast], rtol=0, atol=1e-9)
    np.testing.assert_allclose(times, expected, rtol=0, atol=5e-9)
    # heights h_n = e^(2n) h0 from the speeds after each impact, and each impact's energy law
    after = np.array([r.velocities_after[0] for r in impacts])
    n = np.arange(1, len(impacts) + 1)
    heights = after**2 / (2 * g)
    bounces = slice(0, -1)  # the last impact is plastic: the contact is held from there
    np.testing.assert_allclose(heights[bounces], e ** (2 * n[bounces]) * h0, rtol=0, atol=1e-12)
    energy_before = np.array([r.energy_before for r in impacts])
    energy_after = np.array([r.energy_after for r in impacts])
    np.testing.assert_allclose(
        energy_after[bounces], e**2 * energy_before[bounces], rtol=0, atol=1e-12
    )
    assert after[-1] == 0.0 and energy_after[-1] < 1e-9
    # the chattering ends in a held contact from just before the accumulation time to t_end
    t_rest = expected[0] + 2 * e * math.sqrt(2 * g * h0) / g / (1 - e)
    (hold,) = trajectory.summary()["held_contacts"]
    assert hold["contact"] == "floor" and hold["t_to"] == 12.0
    assert t_rest - 1e-3 < hold["t_from"] < t_rest
    assert abs(trajectory.final_state["y"]) < 1e-12
    assert abs(trajectory.final_state["y_dot"]) < 1e-12
    assert trajectory.status == "success"
    assert "impacts take energy" in trajectory.energy_not_conserved


def test_energy_is_conserved_between_impacts():
    trajectory = simulate_system(ball(0.8), t_end=3.0, backend="llvm")
    impacts = trajectory.impacts
    t, energy = trajectory.t, trajectory["energy"]
    edges = [0.0, *(r.t for r in impacts), 3.0]
    levels = [impacts[0].energy_before, *(r.energy_after for r in impacts)]
    for start, end, level in zip(edges, edges[1:], levels, strict=False):
        inside = (t > start) & (t < end)
        assert inside.any()
        np.testing.assert_allclose(energy[inside], level, rtol=1e-9)


def test_outputs_on_a_grid_are_the_grid_and_impacts_are_kept_apart():
    trajectory = simulate_system(ball(0.9), t_end=2.0, n_out=41, backend="llvm")
    np.testing.assert_array_equal(trajectory.t, np.linspace(0, 2, 41))
    assert len(trajectory.impacts) == 3
    assert np.all(trajectory["y"] >= -1e-12)


def oblique(e: float) -> lg.System:
    """A particle under gravity in the plane above the inclined floor n . r >= 0, with
    n = (sin b, cos b) (a wall not along the coordinate axes)."""
    return lg.System.from_energies(
        "m*(x_dot**2 + y_dot**2)/2", "m*g*y", coordinates=["x", "y"],
        parameters={"m": 2.0, "g": 9.81, "e": e, "b": 0.3},
        impacts=(Impact(gap="x*sin(b) + y*cos(b)", restitution="e"),),
        initial={"x": 0.2, "y": 1.0, "x_dot": 0.7},
    )  # fmt: skip


@pytest.mark.parametrize("e", [1.0, 0.6])
def test_an_oblique_impact_reflects_the_normal_velocity_and_keeps_the_tangential(e):
    trajectory = simulate_system(oblique(e), t_end=0.6, backend="llvm")
    first = trajectory.impacts[0]
    normal = np.array([math.sin(0.3), math.cos(0.3)])
    tangent = np.array([math.cos(0.3), -math.sin(0.3)])
    before, after = first.velocities_before, first.velocities_after
    # the textbook law for a point mass, written independently of the mass metric
    expected = before - (1 + e) * (normal @ before) * normal
    np.testing.assert_allclose(after, expected, rtol=1e-12, atol=1e-12)
    assert after @ tangent == pytest.approx(before @ tangent, rel=1e-12)
    kinetic = lambda v: 2.0 * (v @ v) / 2  # noqa: E731
    lost = kinetic(before) - kinetic(after)
    assert lost == pytest.approx((1 - e**2) * 2.0 * (normal @ before) ** 2 / 2, abs=1e-10)
    assert first.energy_before - first.energy_after == pytest.approx(lost, abs=1e-10)


def test_the_law_in_a_non_diagonal_metric_keeps_the_momenta_orthogonal_to_the_contact():
    """A double pendulum whose lower bob hits a wall x = d: the mass matrix couples the
    angles, so the impulse is along M^-1 G^T, not along G."""
    system = lg.System.from_particles(
        coordinates=["a", "b"],
        particles=(
            lg.Particle("p", "m1", ("l*sin(a)", "-l*cos(a)")),
            lg.Particle("q", "m2", ("l*sin(a) + l*sin(b)", "-l*cos(a) - l*cos(b)")),
        ),
        gravity=lg.Gravity("g"),
        parameters={"m1": 1.0, "m2": 0.5, "l": 1.0, "g": 9.81, "e": 0.5, "d": 1.2},
        impacts=(Impact(gap="d - l*sin(a) - l*sin(b)", restitution="e"),),
        initial={"a": 0.3, "b": 0.2, "a_dot": 1.5, "b_dot": 2.5},
    )
    trajectory = simulate_system(system, t_end=0.5, backend="llvm")
    first = trajectory.impacts[0]
    # at the impact: the configuration from the gap, the law's invariants checked directly
    compiled = compile_equations(system.equations_of_motion())
    p = compiled.parameter_vector()
    k = int(np.argmin(np.abs(trajectory.t - first.t)))
    q = np.array([trajectory["a"][k], trajectory["b"][k]])
    mass = compiled.mass_matrix(first.t, q, first.velocities_before, p)
    gradient = np.array([-math.cos(q[0]), -math.cos(q[1])])
    assert gradient @ first.velocities_after == pytest.approx(
        -0.5 * (gradient @ first.velocities_before), rel=1e-6
    )
    orthogonal = np.array([gradient[1], -gradient[0]])  # G u = 0
    momentum = lambda v: orthogonal @ (mass @ v)  # noqa: E731
    assert momentum(first.velocities_after) == pytest.approx(
        momentum(first.velocities_before), rel=1e-6
    )


def cradle(e: float = 1.0) -> lg.System:
    """Three equal balls of radius r on a line; the last two touch at rest."""
    return lg.System.from_energies(
        "m*(x1_dot**2 + x2_dot**2 + x3_dot**2)/2", "0", coordinates=["x1", "x2", "x3"],
        parameters={"m": 1.0, "r": 0.5, "e": e},
        impacts=(
            Impact(gap="x2 - x1 - 2*r", restitution="e", name="left"),
            Impact(gap="x3 - x2 - 2*r", restitution="e", name="right"),
        ),
        initial={"x1": -1.0, "x2": 1.0, "x3": 2.0, "x1_dot": 2.0},
    )  # fmt: skip


def test_newtons_cradle_passes_the_momentum_through_the_touching_balls():
    trajectory = simulate_system(cradle(1.0), t_end=2.0, backend="llvm")
    final = trajectory.final_state
    assert [final[f"x{i}_dot"] for i in (1, 2, 3)] == pytest.approx([0.0, 0.0, 2.0], abs=1e-12)
    assert [r.contact for r in trajectory.impacts] == ["left", "right"]
    assert trajectory.impacts[0].t == pytest.approx(0.5, abs=1e-12)
    momentum = sum(final[f"x{i}_dot"] for i in (1, 2, 3))
    assert momentum == pytest.approx(2.0, rel=1e-14)
    assert trajectory.impacts[-1].energy_after == pytest.approx(2.0, rel=1e-14)
    assert final["x3"] == pytest.approx(2.0 + 2.0 * 1.5, rel=1e-12)


def test_a_held_contact_is_released_when_its_multiplier_would_pull():
    """A block resting on the floor, pulled up by a force A t: the floor pushes with
    lambda = m g - A t, and lets go at t = m g / A."""
    system = lg.System.from_energies(
        "m*y_dot**2/2",
        "m*g*y",
        coordinates=["y"],
        parameters={"m": 1.0, "g": 9.81, "A": 4.0, "e": 0.5},
        forces={"y": "A*t"},
        impacts=(Impact(gap="y", restitution="e", name="floor"),),
    )
    trajectory = simulate_system(system, t_end=4.0, backend="llvm")
    (hold,) = trajectory.summary()["held_contacts"]
    assert hold["t_from"] == 0.0
    assert hold["t_to"] == pytest.approx(9.81 / 4.0, rel=1e-9)
    # free afterwards: y = A (t^3 - t0^3)/6 - ... integrated from rest at t0 = m g / A
    t0, t = 9.81 / 4.0, 4.0
    expected = 4.0 * (t**3 - t0**3) / 6 - 4.0 * t0**2 * (t - t0) / 2 - 9.81 * (t - t0) ** 2 / 2
    assert trajectory.final_state["y"] == pytest.approx(expected, rel=1e-8)
    assert trajectory.impacts == []


def test_the_impacts_are_in_simulate_json_and_survive_a_netcdf_file(tmp_path, capsys):
    import json

    from lagrangian.cli import main
    from lagrangian.trajectory import Trajectory

    path = tmp_path / "ball.nc"
    status = main(["simulate", "bouncing_ball", "--t-end", "2", "--json", "--out", str(path)])
    document = json.loads(capsys.readouterr().out)
    assert status == 0
    impacts = document["impacts"]
    assert [entry["contact"] for entry in impacts] == ["floor"] * 3
    np.testing.assert_allclose(
        [entry["t"] for entry in impacts], analytic_times(3, 0.9, 1.0, 9.81), atol=1e-12
    )
    for entry in impacts:
        assert set(entry) == {"t", "contact", "energy_before", "energy_after"}
        # the ball's horizontal motion keeps its energy: only the vertical part is scaled
        vertical = entry["energy_before"] - 0.3**2 / 2
        assert entry["energy_after"] - 0.3**2 / 2 == pytest.approx(0.81 * vertical, rel=1e-12)
    assert document["held_contacts"] == []
    loaded = Trajectory.load(path)
    assert loaded.contacts == ("floor",)
    assert [r.t for r in loaded.impacts] == [entry["t"] for entry in impacts]
    np.testing.assert_allclose(
        loaded.impacts[0].velocities_after, [0.3, 0.9 * math.sqrt(2 * 9.81)], rtol=1e-12
    )


def test_a_model_without_contacts_keeps_its_json():
    trajectory = simulate_system(lg.load("harmonic_oscillator"), t_end=1.0)
    assert "impacts" not in trajectory.summary()
    assert trajectory.impacts == [] and trajectory.contacts == ()


@pytest.mark.slow
def test_the_rocking_block_switches_corners_by_the_closed_form_and_comes_to_rest():
    """Before a corner lands (theta = 0) the block turns about the other one, y' = b theta'
    (x is fixed: no horizontal force on a frictionless floor).  The landing corner stops
    (e = 0): the impulse P at it changes m y' by P and I theta' by b P, and
    y'+ + b theta'+ = 0 gives theta'+ = theta'- (I - m b^2) / (I + m b^2), the old pivot
    lifting with g' = -2 b theta'+ > 0 (derived by hand, independently of the mass metric)."""
    system = lg.load("rocking_block")
    trajectory = simulate_system(system, t_end=1.0, backend="llvm")
    m, b, h = 1.0, 0.2, 0.6
    inertia = m * (b**2 + h**2) / 3
    ratio = (inertia - m * b**2) / (inertia + m * b**2)
    holds = trajectory.summary()["held_contacts"]
    pivots = [hold["contact"] for hold in holds[:8]]
    assert pivots == ["left", "right"] * 4  # the pivot alternates
    switches = [r for r in trajectory.impacts if abs(r.velocities_before[1]) > 1e-3]
    assert len(switches) >= 4
    for record in switches:
        (y_before, theta_before), (y_after, theta_after) = (
            record.velocities_before,
            record.velocities_after,
        )
        assert theta_after == pytest.approx(ratio * theta_before, rel=1e-9)
        side = 1.0 if record.contact == "right" else -1.0  # the landing corner at x = side b
        assert y_before - side * b * theta_before == pytest.approx(0.0, abs=1e-9)  # the pivot
        assert y_after + side * b * theta_after == pytest.approx(0.0, abs=1e-9)  # it stops
        assert y_after - side * b * theta_after > 0  # and the old pivot lifts
        assert record.energy_after < record.energy_before
    # at rest flat on both corners once the rocking has died away
    assert {hold["contact"] for hold in holds[-2:]} == {"left", "right"}
    assert holds[-1]["t_to"] == 1.0 and holds[-1]["t_from"] < 0.6
    assert trajectory.final_state["y"] == pytest.approx(h, abs=1e-12)
    assert abs(trajectory.final_state["theta"]) < 1e-12


@pytest.mark.parametrize("enumerated", [8, 0])
def test_many_contacts_resting_at_once_are_held_without_trying_every_set(enumerated, monkeypatch):
    """Above MAX_ENUMERATED resting contacts (2^k sets) the held set is found greedily; on
    the rocking block (forced there with a limit of 0) it is the set every try finds.  The
    outputs skip a held segment (the right corner from 0.195 to 0.359 s)."""
    from lagrangian.integrate import impacts

    monkeypatch.setattr(impacts, "MAX_ENUMERATED", enumerated)
    trajectory = simulate_system(lg.load("rocking_block"), t_end=0.45, n_out=2, backend="llvm")
    np.testing.assert_array_equal(trajectory.t, [0.0, 0.45])
    holds = trajectory.summary()["held_contacts"]
    assert [hold["contact"] for hold in holds[:3]] == ["left", "right", "left"]
    assert holds[1]["t_from"] == pytest.approx(0.19536929697786376, abs=1e-12)


def test_the_text_summary_counts_the_impacts_and_the_held_contacts(capsys):
    from lagrangian.cli import main

    assert main(["simulate", "bouncing_ball", "--t-end", "10"]) == 0
    out = capsys.readouterr().out
    count = re.search(r"^impacts: (\d+), the first at t = 0\.451524 \(floor\)$", out, re.M)
    assert count is not None and int(count[1]) > 100  # t_1 = sqrt(2 / 9.81)
    assert re.search(r"^  held: floor from t = 8\.578\d* to 10$", out, re.M)  # t_inf 8.5789
