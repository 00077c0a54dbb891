"""The facade's studies of one system's motion: chaos (Lyapunov exponents, Poincaré
sections, periodic orbits, their continuation, bifurcation diagrams), sensitivities and
fits, the methods of :class:`lagrangian.System` that :class:`StudyMethods` gives it.

Kept beside :mod:`lagrangian.facade` (one layer below it) so that module stays the
stages and the display of results; like it, each method imports its layer when it runs,
so that ``import lagrangian`` loads none of them.
"""

from __future__ import annotations


class StudyMethods:
    """The methods of :class:`lagrangian.System` that study its motion; mixed into it by
    :mod:`lagrangian.facade` (``fit`` uses that class's ``_derived``, the equations of
    motion derived once per System)."""

    def lyapunov(self, **options: object):
        """Lyapunov exponents along one motion -> :class:`~lagrangian.integrate.lyapunov.
        LyapunovSpectrum` (``.exponents``, ``.history``, ``.plot()``).

        Options: t_end, count (default: all 2n), transient, interval (of the QR
        re-orthonormalisation), rtol, atol, initial, params, backend, timeout (see
        :func:`lagrangian.simulation.lyapunov_of_system`).
        """
        from .simulation import lyapunov_of_system

        return lyapunov_of_system(self, **options)

    def sensitivities(self, wrt, **options: object):
        """dy(t)/dw along one motion for each name w in ``wrt`` (parameters, or coordinates
        and velocities for their initial values) -> :class:`~lagrangian.integrate.
        sensitivity.Sensitivities` (``.values``, ``.of(state, w)``, ``.to_dataset()``).

        From the forward sensitivity equations, integrated with the motion (in the compiled
        loop with backend="numba").  Options: t_end, points (output times), rtol, atol,
        initial, params, backend, timeout (see
        :func:`lagrangian.simulation.sensitivities_of_system`).

        >>> import lagrangian as lg
        >>> spring = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
        >>> result = spring.sensitivities(["x"], t_end=1.0, params={"m": 1, "k": 4},
        ...                               initial={"x": 1.0})
        >>> round(float(result.of("x", "x")[-1]), 6)  # d x(1) / d x(0) = cos(2)
        -0.416147
        """
        from .simulation import sensitivities_of_system

        return sensitivities_of_system(self, wrt=wrt, **options)

    def fit(self, data, vary, **options: object):
        """The parameters (and initial values) that make the motion fit measured ``data`` ->
        :class:`~lagrangian.integrate.fit_result.FitResult` (``.parameters`` {name: (value,
        stderr)}, ``.correlation``, ``.rms``, ``.chi2_per_dof``, ``.warnings``,
        ``.residuals``).

        ``data``: a CSV or NetCDF path, an xarray Dataset, a pandas DataFrame or a mapping
        with a column ``t`` and columns named for coordinates, velocities or the names of
        ``observe``; ``vary``: names (``"k"``, ``"theta"`` for theta's initial value), with
        start guesses as ``"k=2.5"`` or a mapping.  Weighted least squares with the exact
        Jacobian of the sensitivity equations (see :mod:`lagrangian.integrate.fit`).
        Options: observe, starts, noise, seed, rtol, atol, initial, params, assignments,
        definitions, backend (see :func:`lagrangian.fitting.fit_of_system`).

        >>> import numpy as np, lagrangian as lg
        >>> spring = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
        >>> t = np.linspace(0, 3, 61)
        >>> result = spring.fit({"t": t, "x": np.cos(2 * t)}, ["k=3"], params={"m": 1},
        ...                     initial={"x": 1.0}, backend="llvm")
        >>> round(result.parameters["k"][0], 6)  # omega = sqrt(k/m) = 2
        4.0
        """
        from .fitting import fit_of_system

        equations = self._derived(inputs_held=False)
        return fit_of_system(self, data, vary=vary, equations=equations, **options)

    def poincare(self, **options: object):
        """A Poincaré section -> :class:`~lagrangian.integrate.poincare.PoincareSection`
        (``.values``, ``["y"]``, ``.save("points.csv")``, ``.plot()``).

        Options: axes (two names: coordinates, velocities, momenta p_q), section
        ("x = 0") and direction ("+", "-", "both") or strobe (a period; the points at
        t = phase + k strobe, phase default 0, whatever the transient) and transient,
        energy and orbits (starts on an energy shell) or spread ({name: (low, high)}),
        t_end, rtol, atol, initial, params, backend, timeout (see
        :func:`lagrangian.simulation.poincare_of_system`).
        """
        from .simulation import poincare_of_system

        return poincare_of_system(self, **options)

    def orbits(self, **options: object):
        """Periodic orbits of the strobe map -> :class:`~lagrangian.integrate.orbits.
        OrbitSearch` (``.orbits``: each with ``.points``, ``.multipliers``, ``.stable``,
        ``.kind``).

        Options: strobe (the drive's period), period (K: orbits of period dividing K),
        phase, grid ({name: values}: starts), attractor (strobe points of the motion used
        as starts, default 20), transient, rtol, atol, initial, params, backend, timeout
        (see :func:`lagrangian.simulation.orbits_of_system`).
        """
        from .simulation import orbits_of_system

        return orbits_of_system(self, **options)

    def continuation(self, **options: object):
        """Periodic orbits followed in a parameter -> :class:`~lagrangian.integrate.
        continuation.Continuation` (``.branches``: each with ``.points`` and
        ``.bifurcations``).

        Options: vary ({parameter: (low, high, count)}), strobe, period, phase,
        max_doublings (default 3), grid, attractor, transient, rtol, atol, initial, params,
        backend, timeout (see :func:`lagrangian.simulation.continuation_of_system`).
        """
        from .simulation import continuation_of_system

        return continuation_of_system(self, **options)

    def bifurcation(self, **options: object):
        """A bifurcation diagram -> :class:`~lagrangian.ensemble.bifurcation.
        BifurcationDiagram` (``.points``, ``.to_csv(path)``, ``.plot()``).

        Options: vary ({parameter: values}), variable, period, transient, samples,
        steps_per_period, initial, params, method, backend (numpy, numba, jax, cuda,
        dask), timeout (see :func:`lagrangian.ensemble.bifurcation.bifurcation_diagram`).
        """
        from .ensemble import bifurcation_of_system

        return bifurcation_of_system(self, **options)
