"""A fit's result and the statistics of its optimum: standard errors, correlation,
identifiability.

At the optimum x* of the weighted sum of squares sum r_i^2, with J = dr/dx, the
covariance of the estimates is

    C = s^2 (J^T J)^-1,

with s^2 the residuals' variance sum r_i^2 / (N - k) when no noise level is given, or 1
when the residuals are already divided by the given noise sigma (then chi^2 per degree
of freedom, sum r_i^2 / (N - k), says whether sigma and the model fit the data: about 1).
(J^T J)^-1 is taken from the SVD of J with its columns scaled to unit length, so that
the parameters' units do not decide what is "small": a relative singular value below
:data:`RANK_TOLERANCE` means the data cannot tell some combination of parameters apart
(a rank-deficient Jacobian), and a correlation above :data:`CORRELATION_LIMIT` that they
are nearly so; both are named in a warning with what to do.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

#: |correlation| above which two fitted names are reported as not separable.
CORRELATION_LIMIT = 0.99
#: Relative singular value of the scaled Jacobian below which it is rank-deficient.
RANK_TOLERANCE = 1e-8
#: A name whose relative change moves the residuals by less than this fraction of the
#: largest such move of another is one the data do not depend on.
INSENSITIVE = 1e-8


@dataclass(frozen=True)
class FitResult:
    """The best fit of ``names`` (parameters, or coordinates and velocities for their
    initial values) to measured columns.

    ``values`` and ``stderr`` (k,): estimates and standard errors (inf where the data do
    not determine one); ``correlation`` (k, k); ``rms``: root mean square of the residuals
    data - fit over every column, in the data's units; ``chi2_per_dof``: with a
    ``noise`` level only (None otherwise); ``warnings``: identifiability, dropped rows,
    starts that failed; ``starts`` tried, ``converged``: how many reached the best
    optimum; ``iterations`` (Jacobians of the best start) and ``evaluations`` (of the
    model, all starts); ``state_names``: the model's coordinates and velocities (a fitted
    one is an initial value); ``dropped``: the data's rows left out for a missing value.
    ``times``, ``observed`` and ``fitted`` (column -> (m,)): the data
    and the fitted motion's values there.
    """

    names: tuple[str, ...]
    values: np.ndarray
    stderr: np.ndarray
    correlation: np.ndarray
    rms: float
    chi2_per_dof: float | None
    dof: int
    warnings: tuple[str, ...]
    starts: int
    converged: int
    iterations: int
    evaluations: int
    times: np.ndarray
    observed: Mapping[str, np.ndarray]
    fitted: Mapping[str, np.ndarray]
    noise: Mapping[str, float] | None = None
    source: str = ""
    name: str = ""
    state_names: tuple[str, ...] = ()
    dropped: tuple[int, ...] = ()

    @property
    def parameters(self) -> dict[str, tuple[float, float]]:
        """name -> (value, standard error)."""
        return {
            n: (float(v), float(e))
            for n, v, e in zip(self.names, self.values, self.stderr, strict=True)
        }

    @property
    def residuals(self) -> dict[str, np.ndarray]:
        """column -> data - fit at :attr:`times`."""
        return {name: self.observed[name] - self.fitted[name] for name in self.observed}

    def correlation_of(self, a: str, b: str) -> float:
        return float(self.correlation[self.names.index(a), self.names.index(b)])


@dataclass(frozen=True)
class Spread:
    """Standard errors, correlation and the warnings of the identifiability checks."""

    stderr: np.ndarray
    correlation: np.ndarray
    chi2_per_dof: float | None
    dof: int
    warnings: tuple[str, ...]


def spread(
    names: tuple[str, ...],
    jacobian: np.ndarray,
    residuals: np.ndarray,
    noise_given: bool,
    values: np.ndarray | None = None,
) -> Spread:
    """The :class:`Spread` at an optimum ``values`` with weighted ``residuals`` (N,) and
    their ``jacobian`` (N, k); ``noise_given``: the residuals were divided by the noise
    sigma."""
    count, k = jacobian.shape
    dof = count - k
    chi2 = float(residuals @ residuals)
    variance = 1.0 if noise_given else chi2 / dof
    lengths = np.linalg.norm(jacobian, axis=0)
    scale = np.where(lengths > 0, lengths, 1.0)
    # a name whose relative change moves the residuals by 1e-8 of what the others' do is
    # not seen (the integration's own error is that size): its column is noise
    effect = lengths * (np.abs(values) if values is not None else 1.0)
    blind = effect <= INSENSITIVE * effect.max() if effect.max() > 0 else np.ones(k, bool)
    seen = np.flatnonzero(~blind)  # the statistics of the others, without the noise columns
    stderr, correlation = np.full(k, np.inf), np.full((k, k), np.nan)
    warnings = [_blind_warning(names[i]) for i in np.flatnonzero(blind)]
    if seen.size:
        part = jacobian[:, seen] / scale[seen]
        _, singular, rows = np.linalg.svd(part, full_matrices=False)
        relative = singular / singular[0]
        # a direction the data do not see has a zero singular value: its variance is
        # bounded here (so that the correlations of the names it mixes come out +-1), and
        # their standard errors are reported as undetermined (inf) below
        inverse = 1.0 / np.maximum(singular, singular[0] * 1e-15) ** 2
        covariance = (rows.T * inverse) @ rows / np.outer(scale[seen], scale[seen])
        deviation = np.sqrt(np.abs(np.diag(covariance)))
        errors = deviation * np.sqrt(variance)
        named = [names[i] for i in seen]
        for value, row in zip(relative, rows, strict=True):
            if value < RANK_TOLERANCE:
                involved = np.abs(row) > 0.1 * np.abs(row).max()
                errors[involved] = np.inf
                warnings.append(_rank_warning(named, involved, value))
        stderr[seen] = errors
        correlation[np.ix_(seen, seen)] = covariance / np.outer(deviation, deviation)
    np.fill_diagonal(correlation, 1.0)
    warnings += _pair_warnings(names, correlation)
    return Spread(
        stderr=stderr,
        correlation=correlation,
        chi2_per_dof=chi2 / dof if noise_given else None,
        dof=dof,
        warnings=tuple(warnings),
    )


def _blind_warning(name: str) -> str:
    return (
        f"the data do not depend on {name}: it cannot be fitted from them; fix it at a "
        "known value (leave it out of vary) or measure something it changes"
    )


def _rank_warning(names: list[str], involved: np.ndarray, value: float) -> str:
    chosen = [n for n, inside in zip(names, involved, strict=True) if inside]
    if len(chosen) == 1:
        return _blind_warning(chosen[0])
    return (
        f"the data cannot tell {_listed(chosen)} apart (the Jacobian is rank-deficient: "
        f"relative singular value {value:.1e}): only a combination of them is fitted; "
        "fix all but one at known values, or measure something that depends on them "
        "differently"
    )


def _pair_warnings(names, correlation) -> list[str]:
    warnings = []
    for i, a in enumerate(names):
        for j in range(i + 1, len(names)):
            value = correlation[i, j]
            if np.isfinite(value) and abs(value) > CORRELATION_LIMIT:
                b = names[j]
                warnings.append(
                    f"{a} and {b} are correlated ({value:+.4f}): the data fix a combination "
                    f"of them, not each one; fix one at a known value (leave it out of vary), "
                    f"or measure something that depends on one without the other"
                )
    return warnings


def _listed(names: list[str]) -> str:
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"
