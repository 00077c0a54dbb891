"""What importing the package loads: a command loads the layers it uses and no more (issue
18: ``lagrangian page`` is written in seconds), and the public API is whole whichever
module is imported first."""

from __future__ import annotations

import subprocess
import sys

import pytest

import lagrangian

#: Layers and libraries that deriving, analysing or writing a page never uses.
UNUSED_BY_THE_PAGE = (
    "lagrangian.integrate",
    "lagrangian.numeric",
    "lagrangian.ensemble",
    "lagrangian.export",
    "lagrangian.serve.app",
    "scipy",
    "matplotlib",
    "xarray",
    "jax",
    "numba",
)


def _loaded_after(code: str) -> set[str]:
    """The modules a fresh interpreter holds after running ``code``."""
    script = f"{code}\nimport sys\nprint('\\n'.join(sys.modules))"
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    )
    return set(done.stdout.split())


def test_the_command_line_and_the_package_load_no_integrator_ensemble_or_plotting():
    loaded = _loaded_after("import lagrangian.cli")
    unused = sorted(
        m for m in loaded if any(m == u or m.startswith(u + ".") for u in UNUSED_BY_THE_PAGE)
    )
    assert unused == []


def test_every_public_name_of_the_package_resolves():
    for name in lagrangian.__all__:
        assert getattr(lagrangian, name) is not None, name
    assert set(lagrangian.__all__) <= set(dir(lagrangian))
    assert lagrangian.simulate.__module__ == "lagrangian.integrate.simulate"
    assert lagrangian.CompiledSystem.__name__ == "CompiledSystem"


def test_display_methods_are_added_to_classes_imported_after_the_package():
    code = """
import lagrangian
from lagrangian.ensemble.bifurcation import BifurcationDiagram
from lagrangian.integrate.lyapunov import LyapunovSpectrum
from lagrangian.integrate.poincare import PoincareSection
from lagrangian.analysis.report import Analysis
from lagrangian.analysis.hamiltonian import Hamiltonian
from lagrangian.analysis.state_space import StateSpace
from lagrangian.trajectory import Trajectory
assert BifurcationDiagram.plot.__name__ == "_plot_bifurcation"
assert LyapunovSpectrum.plot.__name__ == "_plot_lyapunov"
assert PoincareSection.plot.__name__ == "_plot_section"
assert Analysis.__repr__.__name__ == "_report_text"
assert Hamiltonian._repr_latex_.__name__ == "_hamiltonian_latex"
assert StateSpace._repr_latex_.__name__ == "_state_space_latex"
assert Trajectory.plot.__name__ == "_plot"
"""
    _loaded_after(code)  # check=True: an assertion that fails fails the run


def test_the_package_leaves_the_import_system_as_it_found_it():
    """The display methods of results whose modules ``import lagrangian`` leaves out are
    declared on their classes (lagrangian.provided), not added by an import hook."""
    code = """
import sys
finders = list(sys.meta_path)
import lagrangian
assert sys.meta_path == finders, sys.meta_path
assert "lagrangian.integrate.lyapunov" not in sys.modules
"""
    _loaded_after(code)


def test_a_provided_method_is_missing_until_given_then_bound():
    from lagrangian.provided import Provided, provide

    class Result:
        plot = Provided()

    result = Result()
    assert not hasattr(result, "plot")  # as an undeclared method: Jupyter skips it
    key = f"{__name__}.{Result.__qualname__}.plot"
    with pytest.raises(AttributeError, match=f"{key} is given by lagrangian.facade"):
        Result.plot  # noqa: B018

    def draw(self, size=1.0):
        return self, size

    provide({key: draw})
    assert Result.plot is draw
    assert result.plot(size=2.0) == (result, 2.0)


def test_the_command_line_does_not_load_the_unit_library():
    """pint is read only for a model with units (issue 31): the start-up stays as it was."""
    assert "pint" not in _loaded_after("import lagrangian.cli")


def test_simulate_json_makes_no_dataset():
    """``simulate --json`` prints a summary of a few arrays: the trajectory keeps them in a
    table, and xarray (with the pandas, dask and pint its first Dataset imports, about 1 s
    of CPU) is never loaded (issue 36 item 3)."""
    code = """
import contextlib, io
from lagrangian.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    try:
        main(["simulate", "harmonic_oscillator", "--json"])
    except SystemExit as stop:
        assert not stop.code, stop.code
assert '"status": "success"' in out.getvalue(), out.getvalue()
"""
    loaded = _loaded_after(code)
    assert "lagrangian.integrate" in loaded  # it did run
    assert {"xarray", "pandas", "dask"} & loaded == set()


@pytest.mark.slow  # a fresh interpreter derives, analyses and writes a page: 2.7 s of CPU
def test_writing_a_page_does_not_load_scipys_integrators(tmp_path):
    """The page's DOP853 steps and dense output read their coefficients from the page's
    assets (lagrangian.output.page_dop853), not from scipy.integrate: a first page (none
    kept, LAGRANGIAN_NO_CACHE from the suite's fixture) is written without it."""
    page = tmp_path / "page.html"
    code = f"""
import contextlib, io
from lagrangian.cli import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        main(["page", "henon_heiles", "--out", {str(page)!r}])
    except SystemExit as stop:
        assert not stop.code, stop.code
"""
    loaded = _loaded_after(code)
    assert '"available": true' in page.read_text("utf-8")  # the section panel's numbers too
    assert "lagrangian.output.page_dop853" in loaded
    assert sorted(m for m in loaded if m.startswith("scipy.integrate")) == []


@pytest.mark.parametrize(
    ("option", "writers", "unused"),
    [
        ("--json", ("json_out", "large"), ("text", "latex", "notation", "large_walks")),
        ("--latex", ("latex", "large", "large_walks", "notation"), ("text", "json_out")),
        ("--steps", ("text", "large", "large_walks", "notation"), ("latex", "json_out")),
    ],
)
def test_derive_of_a_large_system_loads_its_format_s_writer_only(option, writers, unused):
    """``derive`` imports its format's writer and not the others, nor the units and linkage
    summaries of a model without them (issue 36: milliseconds of a 20-link chain's
    command, where the writers were imported together)."""
    terms = " + ".join(f"x{i}_dot**2/2 - x{i}**2/2" for i in range(1, 8))
    names = ",".join(f"x{i}" for i in range(1, 8))
    code = f"""
import contextlib, io
from lagrangian.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    assert main(["derive", "--lagrangian", "{terms}", "--coordinates", "{names}", "{option}"]) == 0
assert len(out.getvalue().splitlines()) > 7, out.getvalue()
"""
    loaded = _loaded_after(code)
    assert {f"lagrangian.output.{m}" for m in writers} <= loaded
    never = {*unused, "units", "linkage_summary"}
    assert {f"lagrangian.output.{m}" for m in never} & loaded == set()
