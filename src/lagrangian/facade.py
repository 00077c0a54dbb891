"""The facade: the short spellings of the public API, above every layer.

The layers (see :mod:`lagrangian`) hold data and the functions over it, and import only
downward: :class:`lagrangian.model.System` knows nothing of derivation, analysis,
simulation or pictures, and a :class:`~lagrangian.trajectory.Trajectory` knows no
plotting.  This module sees them all and gives the user the convenient forms:

- :class:`System`: the model's ``System`` with the methods ``equations_of_motion``,
  ``simulate``, ``equilibria``, ... that call the layers.  :func:`load`, :func:`loads`
  and ``System.from_lagrangian`` (``from_energies``, ``from_particles``) return one, and
  what is made from one stays one (``change_coordinates``, ``without_inputs`` and a
  Routh reduction build the class they are given).  The studies of its motion (``lyapunov``,
  ``sensitivities``, ``fit``, ``poincare``, ``orbits``, ``continuation``,
  ``bifurcation``) are in :mod:`lagrangian.facade_studies`, mixed into it.
- The pictures and the Jupyter display of results: a trajectory's ``plot``, ``animate``
  and ``_repr_html_``, and the ``_repr_latex_`` of equations of motion, a Hamiltonian, an
  analysis report and a state space.  Those objects are made inside the layers (a
  Trajectory by integrate, ensemble and ``Trajectory.load``), so no constructor here can
  hand out a subclass; their printers are in output/, above them.  This module gives
  those classes the methods when ``lagrangian`` is imported, which Python does before it
  runs any module of the package: it sets them on the classes it imports itself, and
  the others declare them (:class:`lagrangian.provided.Provided`).

The layers are imported inside the methods, as the CLI does, so that ``import
lagrangian`` loads no analysis, ensemble, xarray or matplotlib until they are used.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

from .budget import STAGE_SECONDS
from .derive import EquationsOfMotion, derive
from .facade_studies import StudyMethods
from .model import System as ModelSystem
from .model import load as load_model
from .model import load_file as load_model_file
from .model import loads as loads_model
from .provided import provide
from .trajectory import Trajectory

__all__ = ["System", "load", "load_file", "loads"]

_DERIVED, _HELD = "_equations_of_motion", "_equations_with_inputs_held"


class System(StudyMethods, ModelSystem):
    """A mechanical system with the convenient methods of each stage (see
    :class:`lagrangian.model.System` for the data it holds and its constructors)."""

    # -- stages ----------------------------------------------------------------------
    def equations_of_motion(self) -> EquationsOfMotion:
        """Lagrange's equations (see :class:`~lagrangian.derive.EquationsOfMotion`)."""
        return self._derived(inputs_held=False)

    def _derived(self, *, inputs_held: bool) -> EquationsOfMotion:
        """The equations of motion (of the system with its inputs held at 0), derived once
        per System: it is immutable, and each analysis below asks for them again (a
        notebook's ``conserved_quantities()``, ``hamiltonian()``, ``equilibria()``)."""
        key = _HELD if inputs_held else _DERIVED
        found = self.__dict__.get(key)
        if found is None:
            found = derive(self.without_inputs() if inputs_held else self)
            self.__dict__[key] = found  # the dataclass is frozen: its fields, not this
        return found

    # -- analysis (DESIGN section 6) ------------------------------------------------
    def conserved_quantities(self):
        """Cyclic momenta and the energy function, with reasons for what is not conserved
        (inputs held at 0)."""
        from .analysis import conserved_quantities

        return conserved_quantities(self._derived(inputs_held=True))

    def hamiltonian(self):
        """H(q, p, t) by Legendre transform, with Hamilton's equations."""
        from .analysis import hamiltonian

        return hamiltonian(self._derived(inputs_held=False))

    def equilibria(self):
        """Points at rest that stay at rest, each with its normal modes (inputs held at 0);
        with holonomic constraints, on the constraint surface with the multipliers."""
        from .analysis import rest_points

        return rest_points(self._derived(inputs_held=True))

    def steady_motions(self, momenta: Mapping[str, float] | None = None):
        """Steady motions (cyclic coordinates turning uniformly at the momenta p_c, given
        or symbolic; the others at rest), each with the small oscillations about it."""
        from .analysis import steady_motions

        return steady_motions(self._derived(inputs_held=True), momenta=momenta)

    def linearize(self, at: Mapping[str, object]):
        """M0 x'' + C0 x' + K0 x = 0 about the equilibrium ``at``; ``.normal_modes()``."""
        from .analysis import linearize

        return linearize(self._derived(inputs_held=True), at)

    def state_space(self, at: Mapping[str, object] | None = None, **options: object):
        """x' = A x + B u, y = C x + D u about an equilibrium or steady motion, x = [q, q']
        (options ``outputs``, ``inputs``: see :func:`lagrangian.analysis.state_space`)."""
        from .analysis.state_space import state_space

        return state_space(self._derived(inputs_held=False), at, **options)

    def analyze(
        self,
        *,
        timeout: float | None = STAGE_SECONDS,
        momenta: Mapping[str, float] | None = None,
    ):
        """Every analysis that applies, each stage within ``timeout`` seconds (None: no limit).

        See :func:`lagrangian.analysis.analyze`; stages out of time are in ``undecided``.
        Inputs are held at 0; ``momenta`` gives cyclic momenta values for the steady motions.
        """
        from .analysis import analyze

        return analyze(self._derived(inputs_held=True), timeout=timeout, momenta=momenta)

    def check(
        self,
        *,
        kinetic=None,
        potential=None,
        lagrangian=None,
        equations=(),
        hamiltonian=None,
        conserved=(),
        momenta=None,
    ):
        """A student's answers (text in the model's names, plain or LaTeX, or SymPy) against
        what the toolkit derives: right, equivalent (saying which) or wrong, with the terms
        at fault -> :class:`~lagrangian.analysis.check.CheckResult` (see
        :func:`lagrangian.analysis.check.check`)."""
        from .analysis.check import check

        return check(
            self._derived(inputs_held=False),
            kinetic=kinetic,
            potential=potential,
            lagrangian=lagrangian,
            equations=equations,
            hamiltonian=hamiltonian,
            conserved=conserved,
            momenta=momenta,
        )

    # -- motion -----------------------------------------------------------------------
    def simulate(self, **options: object) -> Trajectory:
        """Integrate the equations of motion -> :class:`~lagrangian.trajectory.Trajectory`.

        Options: t_end, method ("dop853", "radau", "rk4", "variational"), dt,
        rtol, atol, initial ({q: value, q_dot: value}), params, events, n_out,
        backend ("llvm", the default where SymEngine has LLVM, "numpy", or "numba"
        for generated machine code).  The equations are the ones this System keeps
        (derived once, as for ``equations_of_motion``).
        """
        from .simulation import simulate_system

        return simulate_system(self, equations=lambda: self._derived(inputs_held=False), **options)

    def ensemble(self, **options: object):
        """Many runs at once -> EnsembleTrajectory (options: lagrangian.ensemble.run_ensemble)."""
        from .ensemble import ensemble_of_system

        return ensemble_of_system(self, **options)

    def animate(self, path=None, *, trajectory=None, **options: object):
        """The mechanism in motion (default: a run with the model's simulate settings)."""
        from .output.animation import animate

        return animate(
            trajectory if trajectory is not None else self.simulate(), self, path, **options
        )

    def page(
        self,
        *,
        parameters: Mapping[str, float] | None = None,
        initial: Mapping[str, float] | None = None,
        exercise=None,
    ):
        """The model's interactive page (worked solution, live simulation): shown inline
        in Jupyter in a sandboxed frame, ``.html`` its text, ``.save(path)`` a file
        (see :func:`lagrangian.output.page.page_html`; ``exercise``: the steps asked, e.g.
        ``("kinetic", "equations")``, the worked solution hidden)."""
        from .output.display import ModelPage
        from .output.page import page_html

        return ModelPage(page_html(self, parameters=parameters, initial=initial, exercise=exercise))

    def _repr_latex_(self) -> str:
        from .output.latex import latex_expression

        return f"$L = {latex_expression(self.lagrangian)}$"


def load(model: str | Path) -> System:
    """A model file (TOML) or the name of a built-in example -> :class:`System`."""
    return System.adopt(load_model(model))


def load_file(path: str | Path) -> System:
    """The model file at ``path`` -> :class:`System`."""
    return System.adopt(load_model_file(path))


def loads(text: str, *, source: str = "<model>") -> System:
    """The system described by the TOML ``text``; ``source`` names it in errors."""
    return System.adopt(loads_model(text, source=source))


# -- pictures and Jupyter display of the results the layers make -------------------------
def _plot(self: Trajectory, kind: str = "timeseries"):
    """A matplotlib Figure: ``kind`` is timeseries, phase, energy or poincare."""
    from .output.plots import plot

    return plot(self, kind, self.system)


def _animate(self: Trajectory, path: str | os.PathLike | None = None, **options: object):
    """The mechanism in motion; written to ``path`` (.gif, .html, .mp4) when given,
    shown inline in Jupyter otherwise (see :func:`lagrangian.output.animation.animate`)."""
    from .errors import ModelError
    from .output.animation import animate

    if self.system is None:
        raise ModelError("this trajectory has no model to draw (loaded from a file?)")
    return animate(self, self.system, path, **options)


def _trajectory_html(self: Trajectory) -> str:
    from .output.display import trajectory_html

    return trajectory_html(self)


def _plot_lyapunov(self):
    """A matplotlib Figure: the running estimates of the exponents against time."""
    from .output.lyapunov import plot_lyapunov

    return plot_lyapunov(self)


def _plot_section(self, **options: object):
    """A matplotlib Figure: the section's points on its two axes, coloured by orbit."""
    from .output.sections import plot_section

    return plot_section(self, **options)


def _plot_bifurcation(self, **options: object):
    """A matplotlib Figure: the strobed values against the parameter."""
    from .output.bifurcation import plot_bifurcation

    return plot_bifurcation(self, **options)


def _equations_latex(self) -> str:
    from .output.latex import latex_equations

    return latex_equations(self)


def _hamiltonian_latex(self) -> str:
    from .output.latex import latex_expression

    return f"$H = {latex_expression(self.expression)}$"


def _equations_text(self) -> str:
    from .output import format_equations

    return format_equations(self)


def _report_text(self) -> str:
    from .output.analysis import format_analysis

    return format_analysis(self)


def _report_latex(self) -> str:
    from .output.analysis import latex_analysis

    return latex_analysis(self)


def _state_space_latex(self) -> str:
    from .output.state_space import latex_state_space

    return latex_state_space(self)


# Trajectory and EquationsOfMotion come with this module (imported above): their methods
# are set here.  The other results' modules load the integrators, the ensemble or the
# analyses, which ``import lagrangian`` leaves out: their classes declare the methods
# (``plot = Provided()``) and are given the functions here, whenever they are imported.
Trajectory.plot, Trajectory.animate = _plot, _animate
Trajectory._repr_html_ = _trajectory_html
# the REPL shows what the CLI prints, not the dataclass fields (pages of SymPy)
EquationsOfMotion._repr_latex_, EquationsOfMotion.__repr__ = _equations_latex, _equations_text
provide(
    {
        "lagrangian.analysis.report.Analysis.__repr__": _report_text,
        "lagrangian.analysis.report.Analysis._repr_latex_": _report_latex,
        "lagrangian.analysis.hamiltonian.Hamiltonian._repr_latex_": _hamiltonian_latex,
        "lagrangian.analysis.state_space.StateSpace._repr_latex_": _state_space_latex,
        "lagrangian.integrate.lyapunov.LyapunovSpectrum.plot": _plot_lyapunov,
        "lagrangian.integrate.poincare.PoincareSection.plot": _plot_section,
        "lagrangian.ensemble.bifurcation.BifurcationDiagram.plot": _plot_bifurcation,
    }
)
