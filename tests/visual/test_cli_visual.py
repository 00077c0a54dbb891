"""The drawing commands, run in-process: plot, animate, demo."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image, ImageSequence

from lagrangian.cli import ExitStatus, main
from visual.pictures import PENDULUM_WITH_BOB


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def picture(path) -> np.ndarray:
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB")).astype(int)


def drawn(path) -> bool:
    """A picture with something on it: varied pixels, a fair share of ink."""
    image = picture(path)
    return image.std() > 20 and (np.abs(image - 255).sum(axis=-1) > 60).mean() > 0.01


@pytest.mark.slow
def test_demo_writes_its_files_and_says_where(capsys, tmp_path):
    folder = tmp_path / "demo"
    status, out, err = run(capsys, "demo", "--out-dir", folder)
    assert status == ExitStatus.SUCCESS, err
    files = sorted(p.name for p in folder.iterdir())
    assert files == ["double_pendulum.gif", "energy.png", "modes.png", "phase.png"]
    with Image.open(folder / "double_pendulum.gif") as gif:
        durations = [frame.info["duration"] for frame in ImageSequence.Iterator(gif)]
    assert len(durations) == 250 and sum(durations) == 10_000  # 10 s, played in 10 s
    for name in ("energy.png", "modes.png", "phase.png"):
        assert drawn(folder / name), name
    assert str(folder.resolve()) in out
    for name in files:
        assert name in out
    assert "θ₁:  l₁ θ̈₁ (m₁ + m₂)" in out  # the derived equations
    assert "mode 1: ω = 2.3972 rad/s" in out and "mode 2: ω = 5.7874 rad/s" in out


def test_plot_a_model(capsys, tmp_path):
    out_file = tmp_path / "phase.png"
    status, out, err = run(
        capsys, "plot", "simple_pendulum", "--kind", "phase", "--t-end", "2", "--out", out_file
    )
    assert status == ExitStatus.SUCCESS, err
    assert out == f"wrote {out_file}\n" and drawn(out_file)


def test_plot_a_trajectory_file(capsys, tmp_path):
    csv = tmp_path / "run.csv"
    assert run(capsys, "simulate", "harmonic_oscillator", "--t-end", "3", "--out", csv)[0] == 0
    for kind in ("timeseries", "energy", "phase"):
        out_file = tmp_path / f"{kind}.png"
        status, _, err = run(capsys, "plot", csv, "--kind", kind, "--out", out_file)
        assert status == ExitStatus.SUCCESS, err
        assert drawn(out_file), kind


def test_plot_errors_are_one_line(capsys, tmp_path):
    csv = tmp_path / "run.csv"
    run(capsys, "simulate", "harmonic_oscillator", "--t-end", "1", "--out", csv)
    cases = [
        (("plot", csv, "--kind", "modes", "--out", tmp_path / "m.png"), "needs a MODEL"),
        (("plot", "simple_pendulum", "--kind", "poincare"), "two or more coordinates"),
        (("plot", "simple_pendulum", "--out", tmp_path / "x.gif"), ".png, .pdf or .svg"),
        (("plot", tmp_path / "missing.nc"), "no such file"),
    ]
    for argv, text in cases:
        status, _, err = run(capsys, *argv)
        assert status == ExitStatus.BAD_INPUT, argv
        assert err.count("\n") == 1 and text in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.csv"]


def test_animate_a_model_file(capsys, tmp_path):
    model = tmp_path / "pendulum.toml"
    model.write_text(PENDULUM_WITH_BOB)
    out_file = tmp_path / "pendulum.gif"
    status, out, err = run(capsys, "animate", model, "--t-end", "0.4", "--out", out_file)
    assert status == ExitStatus.SUCCESS, err
    assert out == f"wrote {out_file}: 10 frames at 25 fps, real time\n"
    with Image.open(out_file) as gif:
        assert gif.n_frames == 10


def test_mp4_without_ffmpeg_is_one_line_and_exit_2(capsys, tmp_path, monkeypatch):
    import matplotlib

    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", "no-such-ffmpeg-here")
    status, out, err = run(capsys, "animate", "double_pendulum", "--out", tmp_path / "x.mp4")
    assert status == ExitStatus.BAD_INPUT
    assert err == "lagrangian: error: MP4 needs ffmpeg; write .gif or .html\n"
    assert out == "" and list(tmp_path.iterdir()) == []


def test_animate_a_model_without_geometry_draws_its_coordinates(capsys, tmp_path):
    # 2 s (50 frames), not the model's t_end = 20 (500 frames): every frame is drawn alike
    status, out, err = run(
        capsys, "animate", "harmonic_oscillator", "--t-end", "2", "--out", tmp_path / "x.gif"
    )
    assert status == ExitStatus.SUCCESS, err
    assert (tmp_path / "x.gif").stat().st_size > 0 and "wrote" in out
