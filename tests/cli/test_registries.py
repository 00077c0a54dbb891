"""Every registered method, backend and language runs through every command that offers it.

The CLI's choice lists are read from the registries (a method added to the
registry is offered by every command at once): the choices are compared with
the registries, and each one is run on a small model.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys

import click
import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.cli.app import app
from lagrangian.ensemble import core as ensemble_core
from lagrangian.export import LANGUAGES
from lagrangian.integrate.registry import METHODS
from lagrangian.numeric.compile import RUN_BACKENDS

MODEL = "simple_pendulum"
SHORT = ("--t-end", "0.3")
#: Methods that run on optional packages (an extra CI does not install), any one of them:
#: taylor is heyoka's where it is installed, else ours compiled by numba.
METHOD_PACKAGES = {"taylor": ("heyoka", "numba")}


def _skip_without_package(method: str) -> None:
    packages = METHOD_PACKAGES.get(method, ())
    if packages and not any(importlib.util.find_spec(name) for name in packages):
        pytest.skip(f"method {method} needs one of {', '.join(packages)}")


def _without_heyoka(monkeypatch) -> None:
    """heyoka as if it were not installed (its import fails), in this process."""
    from lagrangian.integrate import choice

    monkeypatch.setattr(choice, "heyoka_installed", lambda: False)
    monkeypatch.setitem(sys.modules, "heyoka", None)


def _choices(command: str, option: str) -> list[str]:
    for parameter in app.commands[command].params:
        if f"--{option}" in parameter.opts:
            assert isinstance(parameter.type, click.Choice)
            return list(parameter.type.choices)
    raise AssertionError(f"{command} has no --{option}")


@pytest.mark.parametrize(
    ("command", "option", "registry"),
    [
        ("simulate", "method", METHODS),
        ("plot", "method", METHODS),
        ("animate", "method", METHODS),
        ("simulate", "backend", RUN_BACKENDS),
        ("ensemble", "method", ensemble_core.METHODS),
        ("ensemble", "backend", ensemble_core.BACKENDS),
        ("ensemble", "precision", ensemble_core.PRECISIONS),
        ("export", "to", LANGUAGES),
        ("lyapunov", "backend", RUN_BACKENDS),
        ("poincare", "backend", RUN_BACKENDS),
        ("bifurcation", "method", ensemble_core.METHODS),
        ("bifurcation", "backend", ensemble_core.BACKENDS),
    ],
)
def test_choices_are_the_registries(command, option, registry):
    assert sorted(_choices(command, option)) == sorted(registry)


def _run(capsys, *argv) -> str:
    status = main(list(argv))
    captured = capsys.readouterr()
    assert status == ExitStatus.SUCCESS, captured.err
    return captured.out


@pytest.mark.parametrize("method", sorted(METHODS))
def test_every_method_simulates(capsys, method):
    _skip_without_package(method)
    summary = json.loads(_run(capsys, "simulate", MODEL, *SHORT, "--method", method, "--json"))
    assert summary["method"] == method


@pytest.mark.parametrize("method", sorted(METHODS))
@pytest.mark.parametrize(("command", "suffix"), [("plot", ".png"), ("animate", ".html")])
def test_every_method_plots_and_animates(capsys, tmp_path, method, command, suffix):
    _skip_without_package(method)
    out = tmp_path / f"figure{suffix}"
    _run(capsys, command, MODEL, *SHORT, "--method", method, "--out", str(out))
    assert out.stat().st_size > 0


@pytest.mark.slow  # compiles our Taylor loop of the pendulum (2-3 s)
def test_method_taylor_runs_ours_where_heyoka_is_not_installed(capsys, tmp_path, monkeypatch):
    _without_heyoka(monkeypatch)
    _skip_without_package("taylor")  # skipped here before ours existed: runs where numba is
    summary = json.loads(_run(capsys, "simulate", MODEL, *SHORT, "--method", "taylor", "--json"))
    assert summary["method"] == "taylor"
    assert summary["choice"].startswith("taylor (numba) on ")
    for command, suffix in (("plot", ".png"), ("animate", ".html")):
        out = tmp_path / f"figure{suffix}"
        _run(capsys, command, MODEL, *SHORT, "--method", "taylor", "--out", str(out))
        assert out.stat().st_size > 0


@pytest.mark.slow
def test_every_run_backend_simulates_the_same_motion(capsys):
    finals = {}
    for backend in sorted(RUN_BACKENDS):
        argv = ("simulate", MODEL, *SHORT, "--backend", backend, "--json")
        finals[backend] = json.loads(_run(capsys, *argv))["final_state"]["theta"]
    assert finals == pytest.approx({backend: finals["numpy"] for backend in finals}, rel=1e-9)


def _ensemble_backend_missing(backend: str) -> str:
    """Why ``backend`` cannot run here ("" when it can)."""
    if backend == "cuda":
        if importlib.util.find_spec("cupy") is None:
            return "CuPy is not installed"
        import cupy

        try:
            if cupy.cuda.runtime.getDeviceCount() < 1:
                return "no NVIDIA GPU"
        except Exception:  # no driver
            return "no NVIDIA GPU"
    return ""


@pytest.mark.slow
@pytest.mark.parametrize("backend", sorted(ensemble_core.BACKENDS))
@pytest.mark.parametrize("method", sorted(ensemble_core.METHODS))
def test_every_ensemble_backend_and_method(capsys, tmp_path, backend, method):
    reason = _ensemble_backend_missing(backend)
    if reason:
        pytest.skip(f"backend {backend}: {reason}")
    out = tmp_path / "runs.nc"
    argv = ("ensemble", MODEL, "--grid", "theta=0.1:0.2:2", *SHORT, "--dt", "0.01")
    argv += ("--backend", backend, "--method", method, "--out", str(out))
    if backend == "dask":
        # as the user runs it, in a process of its own: in a pytest worker that has run many
        # other tests, this case once ended in an AssertionError from the cluster's start that
        # no single test reproduces (not understood yet; see the stop's note)
        done = subprocess.run(
            [sys.executable, "-m", "lagrangian", *argv], capture_output=True, text=True
        )
        assert done.returncode == 0, done.stderr
    else:
        _run(capsys, *argv)
    assert out.stat().st_size > 0


@pytest.mark.parametrize("language", sorted(LANGUAGES))
def test_every_language_exports(capsys, tmp_path, language):
    out = tmp_path / ("model" + LANGUAGES[language].suffix)
    _run(capsys, "export", MODEL, "--to", language, "--out", str(out))
    assert out.read_text().strip()


@pytest.mark.slow
@pytest.mark.parametrize("backend", sorted(RUN_BACKENDS))
def test_every_backend_gives_a_lyapunov_spectrum(capsys, backend):
    summary = json.loads(
        _run(capsys, "lyapunov", MODEL, "--t-end", "2", "--backend", backend, "--json")
    )
    assert summary["sum"] == pytest.approx(0.0, abs=1e-7)  # a conservative flow keeps volume


def test_a_new_target_is_one_class_and_one_registry_line(capsys, monkeypatch):
    """A target written here (one AbstractTarget subclass) and added to the registry
    (one line, here into a copy) is offered by ``export --to`` and runs through it."""
    import lagrangian.export
    from lagrangian.codegen import AbstractTarget

    class ListingTarget(
        AbstractTarget, name="listing", language="a listing", suffix=".txt", base=0
    ):
        def render(self, program, name):
            forcing = program.forcing.outputs[0][1]
            return "".join(f"f[{i}] = {entry}\n" for i, entry in enumerate(forcing))

    assert main(["export", MODEL, "--to", "listing"]) == ExitStatus.BAD_INPUT
    assert "'listing' is not one of" in capsys.readouterr().err
    registry = {**lagrangian.export.LANGUAGES, ListingTarget.name: ListingTarget}
    monkeypatch.setattr(lagrangian.export, "LANGUAGES", registry)
    assert "listing" in _choices("export", "to")
    assert _run(capsys, "export", MODEL, "--to", "listing") == "f[0] = -p_g*p_l*p_m*sin(q_theta)\n"
