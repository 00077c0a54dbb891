"""`lagrangian lyapunov`: text, JSON, the convergence plot and one-line errors."""

from __future__ import annotations

import json

import pytest

from lagrangian.cli import ExitStatus, main


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_lyapunov_json_has_the_spectrum_and_settings(capsys):
    status, out, _ = run(
        capsys, "lyapunov", "driven_damped_pendulum", "--t-end", "20", "--transient", "5",
        "--set", "b=0.4", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert len(summary["exponents"]) == 2
    assert summary["sum"] == pytest.approx(-0.4, abs=1e-6)  # the divergence -b / (m l^2)
    assert summary["transient"] == 5.0 and summary["interval"] == 1.0
    assert summary["parameters"]["b"] == 0.4
    assert summary["reorthonormalisations"] == 20


def test_lyapunov_text_and_plot(capsys, tmp_path):
    picture = tmp_path / "convergence.png"
    status, out, _ = run(
        capsys, "lyapunov", "henon_heiles", "--t-end", "4", "--largest", "--plot", str(picture)
    )
    assert status == ExitStatus.SUCCESS
    assert out.startswith("Henon-Heiles system: largest Lyapunov exponent over t = 4")
    assert "lambda1 =" in out and "lambda2" not in out
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["cartesian_pendulum", "--t-end", "1"],
            "Lyapunov exponents of constrained systems are not supported",
        ),
        (["henon_heiles", "--count", "5"], "must be from 1 to 4 (twice the coordinates), not 5"),
        (["henon_heiles", "--plot", "x.pdf"], "the picture must be a .png file"),
        (["henon_heiles", "--largest", "--count", "2"], "--largest is --count 1"),
        (["henon_heiles", "--set", "q=1"], "'q' is neither a parameter nor a coordinate"),
    ],
)
def test_lyapunov_errors_are_one_line(capsys, argv, message):
    status, out, err = run(capsys, "lyapunov", *argv)
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert len(err.strip().splitlines()) == 1 and out == ""
