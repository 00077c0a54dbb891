"""3-D bodies in the animation: the outline's shape from the inertia, its place and
orientation in space (R(q) applied to the body-frame points, R typed from SymPy's
rotation matrices), the stem of a top, and the files written."""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy
from PIL import Image, ImageSequence

import lagrangian as lg
from lagrangian.output.animation import animate, mechanism_view
from lagrangian.output.geometry import geometry, solid_pivots
from lagrangian.output.solids import solid_shape
from visual.pictures import color_mask

BOX = """
coordinates = ["x", "a", "b", "c"]
[parameters]
m = 6.0
[[bodies]]
name = "brick"
mass = "m"
position = ["x", "0", "1"]
inertia = [26, 20, 10]
orientation = {euler = ["a", "b", "c"], convention = "zyx"}
[initial]
x_dot = 0.3
a_dot = 1.0
b_dot = 0.5
"""


def zxz(phi, theta, psi):
    r = sympy.rot_axis3(phi).T * sympy.rot_axis1(theta).T * sympy.rot_axis3(psi).T
    return np.array(r, dtype=float)


def test_a_box_has_the_half_sides_of_the_uniform_box_with_the_moments():
    # half-sides 1, 2, 3 and mass 6: I = m (b^2 + c^2) / 3 ... = 26, 20, 10
    shape = solid_shape(6.0, np.diag([26.0, 20.0, 10.0]))
    assert shape.kind == "box"
    assert np.allclose(np.sort(np.abs(shape.points), axis=0), [[1, 2, 3]] * 8)
    assert len(shape.paths) == 12
    lengths = sorted(np.linalg.norm(shape.points[i] - shape.points[j]) for i, j in shape.paths)
    assert np.allclose(lengths, [2] * 4 + [4] * 4 + [6] * 4)


def test_a_thin_disc_is_drawn_as_a_disc_of_its_radius():
    mass, radius = 2.0, 0.5
    moments = np.diag([mass * radius**2 / 4, mass * radius**2 / 4, mass * radius**2 / 2])
    shape = solid_shape(mass, moments)
    assert shape.kind == "disc"
    rim = shape.points[:-1]
    assert np.allclose(np.linalg.norm(rim, axis=1), radius)
    assert np.allclose(rim[:, 2], 0)  # in the plane across the symmetry axis (body z)


def test_the_outline_is_the_rotated_body_frame_outline(rng):
    system = lg.load("heavy_top")
    scene = geometry(system)
    times = np.array([0.0, 0.5, 1.0])
    q = np.array([[rng.uniform(-3, 3) for _ in times] for _ in range(3)])
    positions = scene.at(times, q)
    (outline,) = scene.solid_outlines(positions)
    (shape,) = scene.solid_shapes
    l = system.parameter_values["l"]
    for k in range(len(times)):
        phi, theta, psi = q[:, k]
        rotation = zxz(phi, theta, psi)
        center = l * rotation[:, 2]  # the centre of mass on the symmetry axis
        assert np.allclose(outline[:, :, k], center + shape.points @ rotation.T)
    assert solid_pivots(positions) == (0,)


@pytest.mark.slow
def test_a_brick_is_drawn_with_its_corners_where_the_rotation_puts_them():
    system = lg.loads(BOX)
    run = system.simulate(t_end=1.0, n_out=11)
    view, _ = mechanism_view(run, system, fps=10)
    assert view.stems == ()  # its centre moves: no fixed point
    k = 5
    j = k * 4  # OVERSAMPLE samples per frame
    t = view.positions.t[j]
    a, b, c = (np.interp(t, run.t, run[n]) for n in "abc")
    rotation = np.array(
        sympy.rot_axis3(a).T * sympy.rot_axis2(b).T * sympy.rot_axis1(c).T, dtype=float
    )
    x = np.interp(t, run.t, run["x"])
    expected = np.array([x, 0, 1]) + view.geometry.solid_shapes[0].points @ rotation.T
    assert np.allclose(view.outlines[0][:, :, j], expected, atol=1e-5)
    view.update(k)
    side = view._panels[0]
    lines = side["solids"][0]
    for line, path in zip(lines, view.geometry.solid_shapes[0].paths, strict=True):
        xs, zs = line.get_data()
        assert np.allclose(xs, expected[list(path), 0], atol=1e-5)
        assert np.allclose(zs, expected[list(path), 2], atol=1e-5)


@functools.cache
def heavy_top_run():
    """The heavy top and a run of 0.4 s, made once for both files (the first run of a
    system derives its equations and analyses them: seconds; animate only reads the run)."""
    system = lg.load("heavy_top")
    return system, system.simulate(t_end=0.4, n_out=41)


@pytest.mark.parametrize("suffix", [".gif", ".html"])
def test_the_top_is_animated_to_a_file(tmp_path, suffix):
    system, run = heavy_top_run()
    result = animate(run, system, tmp_path / f"top{suffix}", fps=10, size=3.0, dpi=50)
    assert result.path.stat().st_size > 1000
    if suffix == ".gif":
        with Image.open(result.path) as gif:
            frames = [frame.convert("RGB") for frame in ImageSequence.Iterator(gif)]
        assert len(frames) == result.plan.frames == 4
        from lagrangian.output.mechanism import SOLID_COLOR

        assert color_mask(np.asarray(frames[0]).astype(int), SOLID_COLOR).sum() > 20
    else:
        assert "<html>" in result.path.read_text()
