"""`lagrangian simulate`: the summary, the files, and analytic truth through the CLI."""

from __future__ import annotations

import csv
import json
import math

import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.trajectory import Trajectory


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_json_summary_has_the_contract_fields(capsys):
    status, out, _ = run(capsys, "simulate", "double_pendulum", "--t-end", "2", "--json")
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert set(summary["final_state"]) == {"theta1", "theta2", "theta1_dot", "theta2_dot"}
    assert summary["method"] == "dop853"
    assert summary["rtol"] > 0 and summary["atol"] > 0
    assert summary["steps"] > 0 and summary["wall_time"] >= 0
    assert summary["invariants"]["energy"] < 1e-7


def test_set_changes_parameters_and_initial_state(capsys):
    # x'' = -(k/m) x with k = 4, m = 1, x(0) = 0.5, x'(0) = 1: x = 0.5 cos 2t + 0.5 sin 2t
    status, out, _ = run(
        capsys, "simulate", "harmonic_oscillator", "--t-end", "3", "--set", "k=4",
        "--set", "x=0.5", "--set", "x_dot=1", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    final = json.loads(out)["final_state"]
    assert final["x"] == pytest.approx(0.5 * math.cos(6) + 0.5 * math.sin(6), abs=1e-8)


def test_rotating_wire_follows_cosh(capsys, tmp_path):
    out_file = tmp_path / "bead.csv"
    status, _, _ = run(
        capsys, "simulate", "rotating_wire_bead", "--t-end", "2", "--set", "omega=1.5",
        "--set", "r=0.2", "--set", "r_dot=0.1", "--out", str(out_file),
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    with out_file.open() as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0])[:4] == ["t", "r", "r_dot", "energy"]
    assert float(rows[-1]["t"]) == pytest.approx(2.0)
    for row in rows[:: max(1, len(rows) // 10)]:
        t = float(row["t"])
        exact = 0.2 * math.cosh(1.5 * t) + (0.1 / 1.5) * math.sinh(1.5 * t)
        assert float(row["r"]) == pytest.approx(exact, rel=1e-8)


@pytest.mark.slow
def test_netcdf_round_trip(capsys, tmp_path):
    out_file = tmp_path / "run.nc"
    status, _, _ = run(
        capsys, "simulate", "spherical_pendulum", "--t-end", "1", "--method", "variational",
        "--dt", "0.001", "--out", str(out_file),
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    trajectory = Trajectory.load(out_file)
    assert trajectory.dataset.attrs["method"] == "variational"
    assert trajectory.drift("p_phi") < 1e-12


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--set", "k"], "expected NAME=NUMBER"),
        (["--set", "nope=1"], "'nope' is neither a parameter"),
        (["--method", "euler"], "Invalid value for '--method'"),
        (["--dt", "0.1"], "does not apply"),
        (["--out", "result.txt"], "must end in .csv or .nc"),
    ],
)
def test_bad_simulate_input(capsys, tmp_path, monkeypatch, argv, fragment):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, "simulate", "harmonic_oscillator", "--t-end", "1", *argv)
    assert out == ""
    assert status == ExitStatus.BAD_INPUT
    assert fragment in err and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("method", ["dop853", "rk4", "variational"])
def test_progress_reaches_the_end(method):
    import lagrangian as lg
    from lagrangian.simulation import simulate_system

    seen = []
    options = {"dt": 0.01} if method != "dop853" else {}
    simulate_system(
        lg.load("simple_pendulum"), t_end=2.0, method=method, progress=seen.append, **options
    )
    assert seen and max(seen) == pytest.approx(1.0) and min(seen) >= 0.0


def test_define_gives_unspecified_functions(capsys):
    # a charge in a uniform field B = 1 along z (A = (-y/2, x/2, 0)) and a harmonic trap:
    # the energy (x'^2 + y'^2 + z'^2)/2 + V is conserved and Lz-like motion stays planar
    base = ["simulate", "velocity_dependent_potential", "--t-end", "3", "--set", "x=1"]
    status, _, err = run(capsys, *base)
    assert status == ExitStatus.BAD_INPUT and "--define" in err
    status, out, _ = run(
        capsys, *base, "--define", "V=(x^2 + y^2 + z^2)/2", "--define", "A=-y/2",
        "--define", "B=x/2", "--define", "C=0", "--set", "y_dot=0.5", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["invariants"]["energy"] < 1e-8
    assert summary["final_state"]["z"] == 0.0


def test_numba_backend_gives_the_numpy_run(capsys):
    pytest.importorskip("numba")
    finals = {}
    for backend in ("numpy", "numba"):
        status, out, _ = run(
            capsys, "simulate", "harmonic_oscillator", "--t-end", "3", "--set", "x=0.5",
            "--backend", backend, "--json",
        )  # fmt: skip
        assert status == ExitStatus.SUCCESS
        finals[backend] = json.loads(out)["final_state"]
    for name, value in finals["numpy"].items():
        assert finals["numba"][name] == pytest.approx(value, abs=1e-12)


SINGULAR_AT_START = """
name = "Bead whose inertia vanishes at x = 0"
coordinates = ["x"]
kinetic = "m*x^2*x_dot^2/2"
potential = "k*x^2/2"
[parameters]
m = 1.0
k = 1.0
[initial]
x = 0
x_dot = 1
"""


@pytest.mark.parametrize("method", ["dop853", "radau", "rk4", "variational"])
@pytest.mark.parametrize(
    ("model", "where"),
    [("bead", "at t = 0 (x = 0)"), ("spherical_pendulum", "at t = 0 (theta = 0, phi = 0)")],
)
def test_a_singular_mass_matrix_on_the_way_is_one_line(capsys, tmp_path, method, model, where):
    if model == "bead":
        model = tmp_path / "bead.toml"
        model.write_text(SINGULAR_AT_START, encoding="utf-8")
        extra = []
    else:
        extra = ["--set", "theta=0", "--set", "phi=0"]
    out_file = tmp_path / "run.csv"
    status, out, err = run(
        capsys, "simulate", str(model), "--t-end", "1", "--method", method, *extra,
        "--out", str(out_file),
    )  # fmt: skip
    assert status == ExitStatus.BAD_INPUT and out == ""
    assert err.strip().splitlines() == [
        f"lagrangian: error: the mass matrix is singular {where}: the coordinates are "
        "degenerate there (an angle at a pole, a collision); start the motion away from "
        "that state"
    ]
    assert not out_file.exists()


@pytest.mark.parametrize(
    ("sampling", "times"),
    [
        (("--samples", "5"), [0.0, 0.25, 0.5, 0.75, 1.0]),
        (("--dt-out", "0.3"), [0.0, 0.3, 0.6, 0.9, 1.0]),  # and t_end: the last row
        (("--dt-out", "0.25"), [0.0, 0.25, 0.5, 0.75, 1.0]),  # t_end once, not twice
    ],
)
def test_output_sampling(capsys, tmp_path, sampling, times):
    out = tmp_path / "run.csv"
    argv = ("simulate", "simple_pendulum", "--t-end", "1", "--out", str(out), *sampling)
    status, _, _ = run(capsys, *argv)
    assert status == ExitStatus.SUCCESS
    with out.open() as file:
        rows = list(csv.DictReader(file))
    assert [float(row["t"]) for row in rows] == pytest.approx(times, abs=1e-12)


def test_a_forced_run_says_the_energy_is_not_conserved_and_why(capsys):
    # cart-pole pushed by F = 0.5: the energy grows, which is physics, not the method's drift
    argv = ("simulate", "cart_pole", "--t-end", "2", "--set", "F=0.5")
    status, out, _ = run(capsys, *argv, "--json")
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert "energy" not in summary["invariants"]
    energy = summary["not_conserved"]["energy"]
    assert energy["reason"] == "Q_x does work" and energy["change"] > 0.1
    status, out, _ = run(capsys, *argv)
    assert "energy is not conserved (Q_x does work): it changed by 9." in out
    assert "drift along the run" not in out  # nothing conserved to drift


def test_time_dependent_lagrangian_energy_not_conserved(capsys):
    # a pendulum in a gravity that varies in time: L depends on t
    shaken = "x_dot^2/2 + (1 + a*cos(w*t))*cos(x)"
    status, out, _ = run(
        capsys, "simulate", "--lagrangian", shaken, "--coordinates", "x", "--set", "a=0.5",
        "--set", "w=3", "--set", "x=0.3", "--t-end", "2", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["invariants"] == {}
    assert summary["not_conserved"]["energy"]["reason"] == "L depends on t"


SHAKEN = """
name = "Pendulum on a shaken pivot, with a torque"
coordinates = ["th"]
[parameters]
m = 1.0
l = 1.0
g = 9.81
w = 3.0
a = 0.0
u = 0.0
[[particles]]
name = "bob"
mass = "m"
position = ["l*sin(th)", "a*cos(w*t) - l*cos(th)"]
[gravity]
g = "g"
direction = [0, -1]
[forces]
th = "u"
[initial]
th = 0.5
"""


@pytest.mark.parametrize(
    ("values", "reason"),
    [
        ((), None),
        (("--set", "a=0.2"), "L depends on t"),
        (("--set", "u=0.1"), "Q_th does work"),
        (("--set", "a=0.2", "--set", "u=0.1"), "L depends on t; Q_th does work"),
    ],
)
def test_the_energy_is_conserved_in_a_run_where_its_causes_vanish(capsys, tmp_path, values, reason):
    # a pivot shaken with amplitude a and a torque u: in general L depends on t and Q_th does
    # work; with a = 0 and u = 0 neither acts in the run, whose energy is then conserved
    model = tmp_path / "shaken.toml"
    model.write_text(SHAKEN, encoding="utf-8")
    argv = ("simulate", str(model), "--t-end", "2", *values)
    status, out, _ = run(capsys, *argv, "--json")
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    if reason is None:
        assert summary["invariants"]["energy"] < 1e-8
        general = "L depends on t; Q_th does work"
        assert summary["conserved_in_this_run"] == {"energy": {"reason_in_general": general}}
        assert "not_conserved" not in summary
        _, text, _ = run(capsys, *argv)
        assert (
            f"energy is conserved in this run: not in general ({general}), but that vanishes "
            "at these parameter values"
        ) in text
    else:
        assert summary["not_conserved"]["energy"]["reason"] == reason
        assert summary["not_conserved"]["energy"]["change"] > 1e-3
        assert "energy" not in summary["invariants"] and "conserved_in_this_run" not in summary


@pytest.mark.parametrize("force", [0.0, 0.5])
def test_a_momentum_is_conserved_in_a_run_where_its_force_vanishes(capsys, force):
    # the cart-pole's x is cyclic, but the input F pushes the cart: p_x is conserved in a run
    # with F = 0 only, where its drift is reported like a conserved quantity's
    argv = ("simulate", "cart_pole", "--t-end", "2", "--set", f"F={force}")
    status, out, _ = run(capsys, *argv, "--json")
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    if force:
        assert "p_x" not in summary["invariants"] and "conserved_in_this_run" not in summary
        return
    assert summary["invariants"]["p_x"] < 1e-9
    assert list(summary["conserved_in_this_run"]) == ["energy", "p_x"]
    assert summary["conserved_in_this_run"]["p_x"] == {
        "reason_in_general": "the generalized force Q_x acts on it"
    }
    _, text, _ = run(capsys, *argv)
    assert "p_x is conserved in this run: not in general (the generalized force Q_x" in text
