"""`System` + measured data -> the fitted parameters: the facade's ``System.fit``.

Reads the data (:mod:`lagrangian.measurements`: checked, converted to the model's SI
units), the observed expressions and the start guesses, compiles the model once (on numba
where it is installed: the sensitivity equations' compiled loop) and hands the problem to
:func:`lagrangian.integrate.fit.fit_parameters`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from .derive import EquationsOfMotion, derive
from .errors import ModelError, setting
from .integrate.fit_result import FitResult
from .model import System
from .numeric import compile_equations, default_backend
from .simulation import RunSettings


def fit_of_system(
    system: System,
    data: object,
    *,
    vary: Sequence[str] | Mapping[str, float | None],
    observe: Mapping[str, str] | Sequence[str] = (),
    starts: int = 1,
    noise: float | Mapping[str, float] | None = None,
    seed: int = 0,
    equations: EquationsOfMotion | None = None,
    **settings: Any,
) -> FitResult:
    """The best fit of ``vary`` (parameters, or coordinates and velocities for their initial
    values; names, ``"k=2.5"`` with a start guess, or a mapping name -> guess or None) to
    ``data`` (see :func:`lagrangian.measurements.read_measurements`): its columns are
    coordinates, velocities or the names of ``observe`` (``{"x_tip": "l*sin(theta)"}`` or
    ``["x_tip = l*sin(theta)"]``).  ``noise``: the measurements' standard deviation (one
    for all columns, or column -> sigma), which weights the columns and gives chi^2 per
    degree of freedom.  The backend is numba where it is installed (the compiled loop of
    the sensitivity equations, built once and cached), unless ``backend`` says otherwise.
    See :mod:`lagrangian.integrate.fit`; ``settings``: the keywords of :class:`RunSettings`
    (``timeout``: CPU seconds for the whole search); ``equations``: those of ``system`` when derived
    already (the facade keeps them: a second fit does not derive them again)."""
    from .integrate.compiled_dop853 import numba_installed
    from .integrate.fit import FitProblem, fit_parameters, whole_number
    from .integrate.observation import observation, observed_expressions
    from .measurements import noise_levels, read_measurements

    guesses = _guesses(system, vary)
    if system.units is not None:  # a bare guess is in the unit the model declares for it
        guesses = {n: None if v is None else system.units.bare(n, v) for n, v in guesses.items()}
    starts = whole_number("starts", starts)
    noise_levels(noise, (), system)  # its values checked before the data are read
    expressions = observed_expressions(system, observe)
    measured = read_measurements(data, system, expressions)
    if settings.get("backend") is None:
        settings["backend"] = "numba" if numba_installed() else None
    run = RunSettings(**settings)
    initial, params = run.values(system)
    initial |= {
        n: v for n, v in guesses.items() if n not in system.parameter_names and v is not None
    }
    params |= {n: v for n, v in guesses.items() if n in system.parameter_names and v is not None}
    compiled = compile_equations(
        equations if equations is not None else derive(system),
        backend=run.backend or default_backend(), definitions=run.definitions,
    )  # fmt: skip
    for name, value in guesses.items():
        unknown = name not in params and name not in compiled.default_parameters
        if value is None and name in system.parameter_names and unknown:
            raise ModelError(
                f"{name} has no value to start the fit from: give a guess, "
                f"{setting('vary')} {name}=VALUE"
            )
    p = compiled.parameter_vector(params)  # every parameter has a value, the guesses checked
    y0 = compiled.state_vector(initial)
    start = dict(zip(compiled.parameter_names, p, strict=True))
    start |= dict(
        zip(
            (*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)),
            y0,
            strict=True,
        )
    )
    columns = tuple(measured.columns)
    sigma = noise_levels(noise, columns, system, expressions)
    problem = FitProblem(
        times=measured.times,
        data=np.array([measured.columns[c] for c in columns]),
        observation=observation(system, columns, expressions),
        sigma=np.ones(len(columns)) if sigma is None else sigma,
        noise_given=sigma is not None,
        y0=y0,
        p=p,
    )
    result = fit_parameters(
        compiled, problem, {n: float(start[n]) for n in guesses}, starts=starts, seed=seed,
        rtol=run.rtol, atol=run.atol, timeout=run.timeout,
    )  # fmt: skip
    if measured.dropped:
        rows = ", ".join(map(str, measured.dropped[:10])) + (
            ", ..." if len(measured.dropped) > 10 else ""
        )
        note = (
            f"{measured.source}: {len(measured.dropped)} rows with a missing value (empty or "
            f"NaN) dropped ({'rows' if measured.place == 'row' else 'indices'} {rows})"
        )
        result = replace(result, warnings=(note, *result.warnings), dropped=measured.dropped)
    return replace(result, source=measured.source)


def _guesses(system: System, vary) -> dict[str, float | None]:
    """name -> start guess (None: the model's value) of ``vary``."""
    if isinstance(vary, str):
        vary = [vary]
    if isinstance(vary, Mapping):
        pairs = [(str(n), v) for n, v in vary.items()]
    else:
        pairs = []
        for entry in vary:
            name, _, value = str(entry).partition("=")
            pairs.append((name.strip(), value.strip() or None))
    if not pairs:
        raise ModelError("give at least one name to fit", field=setting("vary"))
    states = {n for q in system.coordinate_names for n in (q, f"{q}_dot")}
    guesses: dict[str, float | None] = {}
    for name, value in pairs:
        if name in guesses:
            raise ModelError(f"'{name}' is given twice", field=setting("vary"))
        if name not in system.parameter_names and name not in states:
            raise ModelError(
                f"'{name}' is neither a parameter nor a coordinate or velocity (parameters: "
                f"{', '.join(system.parameter_names) or 'none'}; initial values: "
                f"{', '.join(sorted(states))})",
                field=setting("vary"),
            )
        guesses[name] = None if value is None else _number(name, value)
    return guesses


def _number(name: str, value: object) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError(
            f"the start guess of {name} is not a number: {value!r}", field=setting("vary")
        ) from None
    if not np.isfinite(number):
        raise ModelError(
            f"the start guess of {name} is not finite: {value!r}", field=setting("vary")
        )
    return number
