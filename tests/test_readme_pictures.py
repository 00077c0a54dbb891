"""The README's chaos lines, run as written, draw what their comments promise.

tests/test_docs.py runs every documented line, smaller, to check that it runs; these
tests run the lines at their full size and count the points in the picture each one
writes (read back from the figure as it is saved, and from the CSV where the line writes
one): a section needs hundreds of points an orbit to show its curves and its chaotic sea,
an attractor a thousand, a diagram its points for every value of the parameter.  The
strange attractor's line alone runs shorter (a tenth of its t_end): it draws one point per
strobe time, so its full size is counted from its options.
"""

from __future__ import annotations

import csv
import math
import re
import shlex
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from lagrangian.cli import ExitStatus, main

README = Path(__file__).resolve().parents[1] / "README.md"

pytestmark = pytest.mark.slow  # full-size runs: about 40 s of CPU together


def readme_line(start: str) -> str:
    """The command line of the README's shell blocks that starts with ``start``
    (continuation lines joined), exactly one."""
    text = README.read_text(encoding="utf-8")
    blocks = re.findall(r"^```sh\n(.*?)^```", text, re.S | re.M)
    joined = "\n".join(blocks).replace("\\\n", " ")
    found = [line.strip() for line in joined.splitlines() if line.strip().startswith(start)]
    assert len(found) == 1, f"{len(found)} README lines start with {start!r}"
    return found[0]


def drawn_points(figure: Figure) -> np.ndarray:
    """Every point drawn in ``figure`` (scatter offsets, marker lines), NaN ones left out."""
    parts = [np.empty((0, 2))]
    for axis in figure.axes:
        parts += [np.asarray(c.get_offsets(), dtype=float) for c in axis.collections]
        parts += [line.get_xydata() for line in axis.get_lines() if line.get_marker() != "None"]
    points = np.concatenate(parts)
    return points[np.all(np.isfinite(points), axis=1)]


def drawn_picture(line: str, folder: Path, monkeypatch) -> Figure:
    """The README line through the CLI in ``folder``: the one figure it saved."""
    saved: list[Figure] = []
    save = Figure.savefig

    def recorded(figure, *args, **kwargs):
        saved.append(figure)
        return save(figure, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", recorded)
    monkeypatch.chdir(folder)
    argv = shlex.split(line, comments=True)
    assert argv[0] == "lagrangian"
    assert main(argv[1:]) == ExitStatus.SUCCESS
    (figure,) = saved
    return figure


def test_the_henon_heiles_section_draws_hundreds_of_points_an_orbit(tmp_path, monkeypatch):
    line = readme_line("lagrangian poincare henon_heiles")
    picture = drawn_picture(line, tmp_path, monkeypatch)
    with open(tmp_path / "section.csv", newline="") as file:
        rows = list(csv.DictReader(file))
    per_orbit = Counter(row["orbit"] for row in rows)
    assert len(per_orbit) == 12
    assert min(per_orbit.values()) >= 200, per_orbit  # at t_end 200: about 30 each
    assert len(drawn_points(picture)) == len(rows)
    assert (tmp_path / "section.png").is_file()


def option(line: str, name: str) -> str:
    """The value of the option ``name`` in the command ``line`` (given once)."""
    argv = shlex.split(line, comments=True)
    assert argv.count(name) == 1, f"{name} is given {argv.count(name)} times in {line!r}"
    return argv[argv.index(name) + 1]


def strobe_times(period: float, transient: float, t_end: float) -> int:
    """How many t = k * period (k = 0, 1, ...) lie in [transient, t_end]."""
    return math.floor(t_end / period) - math.ceil(transient / period) + 1


def test_the_driven_pendulums_strobe_draws_its_strange_attractor(tmp_path, monkeypatch):
    line = readme_line("lagrangian poincare driven_damped_pendulum")
    period, transient, t_end = (
        float(option(line, o)) for o in ("--strobe", "--transient", "--t-end")
    )
    # as written: t_end 10000, 1051 strobe times (at the model's t_end, 300: 21)
    assert strobe_times(period, transient, t_end) >= 1000
    # run to a tenth of that t_end (15 s of CPU less): a point drawn for every strobe time
    shorter = line.replace(f"--t-end {option(line, '--t-end')}", f"--t-end {t_end / 10:g}")
    assert shorter != line
    points = drawn_points(drawn_picture(shorter, tmp_path, monkeypatch))
    assert (tmp_path / "attractor.png").is_file()
    assert len(points) == strobe_times(period, transient, t_end / 10) == 96
    # chaos, not a periodic response (which strobes to a few points): all points differ
    # (at A = 1.07, period 2, the same 96 times give 33 distinct points)
    assert len(np.unique(np.round(points, 6), axis=0)) == len(points)


def test_the_bifurcation_from_a_section_draws_turning_points_for_every_drive(tmp_path, monkeypatch):
    line = readme_line(
        "lagrangian bifurcation driven_damped_pendulum --vary A=1.35:1.5:400 --section"
    )
    points = drawn_points(drawn_picture(line, tmp_path, monkeypatch))
    assert (tmp_path / "turning.png").is_file()  # the line wrote nothing before
    drives = np.unique(points[:, 0])
    assert len(drives) == 400  # every run crossed θ̇ = 0 downwards after its transient
    assert np.all(np.abs(points[:, 1]) <= np.pi)  # θ, wrapped


def test_the_lab_fit_draws_data_fit_and_residuals(tmp_path, monkeypatch):
    # the README's lab example (issue 33): the two panels its picture promises, every
    # measured frame kept but the two the tracker lost, the fit through them, and
    # residuals the size of the tracker's noise (0.3 degrees)
    line = readme_line("lagrangian fit docs/lab/damped_pendulum.toml")
    lab = tmp_path / "docs" / "lab"
    lab.mkdir(parents=True)
    for name in ("damped_pendulum.toml", "pendulum.csv"):
        (lab / name).write_bytes((README.parent / "docs" / "lab" / name).read_bytes())
    picture = drawn_picture(line, tmp_path, monkeypatch)
    assert (tmp_path / "lab_fit.png").is_file()
    data_axis, residual_axis = picture.axes
    (points, fit) = data_axis.get_lines()
    assert len(points.get_xdata()) == 499 and len(fit.get_xdata()) == 499  # 501 frames, 2 lost
    assert fit.get_marker() == "None" and points.get_marker() == "."
    residuals = residual_axis.get_lines()[0].get_ydata()
    assert len(residuals) == 499
    assert 0.8 < np.std(residuals) / np.radians(0.3) < 1.2


def test_the_basin_map_colours_every_start_by_one_of_two_period_two_attractors(
    tmp_path, monkeypatch
):
    line = readme_line("lagrangian basins driven_damped_pendulum")
    figure = drawn_picture(line, tmp_path, monkeypatch)
    assert (tmp_path / "basins.png").is_file()
    (image,) = figure.axes[0].get_images()
    colours = np.asarray(image.get_array())
    assert colours.shape == (200, 200)
    # label + 1 per start: 1 and 2, both attractors' basins large, no start unlabelled (0)
    values, counts = np.unique(colours, return_counts=True)
    assert values.tolist() == [1, 2] and counts.min() > 0.3 * colours.size
    legend = [text.get_text() for text in figure.axes[0].get_legend().get_texts()]
    assert [entry.split(",")[0] for entry in legend] == ["0: period 2", "1: period 2"]
    # the two orbits' points, marked: 2 + 2
    assert len(drawn_points(figure)) == 4
