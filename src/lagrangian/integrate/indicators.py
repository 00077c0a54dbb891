"""Fast chaos indicators: SALI and GALI_k from deviation vectors carried with the motion.

k deviation vectors w_1 ... w_k follow the variational equations w' = J(t, y) w along
the motion (J the Jacobian of the flow compiled from the symbolic equations, as for the
Lyapunov exponents), each renormalised to length 1 after every step so that only their
directions are kept.  On a chaotic orbit every direction is turned towards the most
unstable one, so the vectors align: the volume they span shrinks exponentially.  On a
regular orbit (a torus) they stay apart:

- SALI = min(|w_1 + w_2|, |w_1 - w_2|) (Skokos 2001): from sqrt(2) (orthogonal) to 0
  (parallel or antiparallel); it decays like exp(-(λ1 - λ2) t) on a chaotic orbit and
  keeps fluctuating about a positive value on a regular one;
- GALI_k = the volume of the parallelepiped of the k unit vectors, the product of the
  singular values of the 2n x k matrix [w_1 ... w_k] (Skokos, Bountis & Antonopoulos
  2007; GALI_2 = |sin| of the angle between w_1 and w_2): exponentially small on a
  chaotic orbit, constant for k up to the torus' dimension on a regular one and falling
  only as a power of t above it.

Classification.  A start is labelled chaotic by SALI when SALI falls below
:data:`SALI_BELOW` (1e-4) at some step of the run: the first crossing, at which a run
asking for nothing that needs the state at t_end stops the member (the ensemble's ``sali``
observable).  On a chaotic orbit of 2 degrees of freedom SALI falls like
exp(-λ1 t) (λ2 = 0) down to rounding (1e-16) and stays there; a regular orbit's keeps
fluctuating about a positive value.  Chosen on 164 starts of Hénon–Heiles at E = 1/8
(benchmarks/README.md, "Chaos indicators"): by t = 750 (a fifth of the cost of the
Lyapunov map at t = 4000) it agrees with that map on 96 % of the starts, where SALI at
t_end below 1e-8 (the literature's rule for a value at t_end: regular above 1e-4,
"sticky" in between) agrees on 90 %: a chaotic orbit with λ1 = 0.01 crosses 1e-4 by
t ≈ 920, 1e-8 only by t ≈ 1850.  The margin: the regular orbits' lowest SALI by t = 1500
is 5.7e-4 (1.8e-4 by t = 4000); 1e-5 keeps more of it but needs t = 900 for 96 %.
GALI_k keeps that rule: chaotic when below :data:`CHAOTIC_BELOW` (1e-8) at t_end (GALI_3
falls like exp(-2 λ1 t) on a chaotic orbit, only like t^-2 on a regular one).

The starting vectors are the same for every member: w_1 = (1, ..., 1) / sqrt(2n) (the
displacement of the ``lyapunov`` observable, whose stretch therefore gives the largest
exponent along the way), the others orthonormal to it and to each other (a fixed QR).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: GALI_k below this at t_end labels the start chaotic.
CHAOTIC_BELOW = 1e-8
#: SALI below this at any step labels the start chaotic (its first crossing; see above).
SALI_BELOW = 1e-4


def starting_vectors(size: int, count: int) -> np.ndarray:
    """``count`` orthonormal vectors of length ``size`` (columns), the first along
    (1, ..., 1): the same for every run."""
    basis = np.eye(size)[:, :count].copy()
    basis[:, 0] = 1.0
    q, r = np.linalg.qr(basis)
    return q * np.sign(np.diag(r))  # the first along +(1, ..., 1)


class TangentFlows:
    """The state with ``count`` deviation vectors, z = [y, w_1, ..., w_k] (2n (k + 1)[, B]),
    as a system an explicit Runge-Kutta method steps unchanged:
    ``rhs(t, z, params)`` = [F(t, y), J(t, y) w_1, ..., J(t, y) w_k]."""

    def __init__(self, compiled: CompiledSystem, count: int):
        self.compiled = compiled
        self.size = 2 * compiled.n
        self.count = count

    def start(self, y: np.ndarray) -> np.ndarray:
        vectors = starting_vectors(self.size, self.count)
        w = [np.broadcast_to(vectors[:, [i]], y.shape) for i in range(self.count)]
        return np.concatenate([y, *w], axis=0)

    def rhs(self, t, z, params):
        y = z[: self.size]
        jacobian = self.compiled.rhs_jacobian(t, y, params)
        parts = [self.compiled.rhs(t, y, params)]
        for i in range(1, self.count + 1):
            w = z[i * self.size : (i + 1) * self.size]
            parts.append(np.einsum("ij...,j...->i...", jacobian, w))
        return np.concatenate(parts, axis=0)

    def vectors(self, z: np.ndarray) -> np.ndarray:
        """The deviation vectors (k, 2n[, B])."""
        return z[self.size :].reshape(self.count, self.size, *z.shape[1:])

    def renormalised(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z with every |w_i| = 1, log |w_1| before): w_1's stretch, as the ``lyapunov``
        observable's displacement."""
        w = self.vectors(z)
        norms = np.sqrt(np.sum(w * w, axis=1, keepdims=True))
        with np.errstate(divide="ignore", invalid="ignore"):
            scaled = (w / norms).reshape(self.count * self.size, *z.shape[1:])
            return np.concatenate((z[: self.size], scaled), axis=0), np.log(norms[0, 0])


def sali(vectors: np.ndarray) -> np.ndarray:
    """min(|w_1 + w_2|, |w_1 - w_2|) of unit vectors (k >= 2, 2n[, B])."""
    first, second = vectors[0], vectors[1]
    plus = np.sqrt(np.sum((first + second) ** 2, axis=0))
    minus = np.sqrt(np.sum((first - second) ** 2, axis=0))
    return np.minimum(plus, minus)


def gali(vectors: np.ndarray, k: int) -> np.ndarray:
    """The product of the singular values of [w_1 ... w_k] (unit vectors), per member."""
    w = np.asarray(vectors[:k], dtype=float)
    if w.ndim == 2:
        w = w[..., None]
    matrices = np.moveaxis(w, -1, 0).transpose(0, 2, 1)  # (B, 2n, k)
    values = np.linalg.svd(matrices, compute_uv=False)
    return np.prod(values, axis=-1) if vectors.ndim == 3 else np.prod(values, axis=-1)[0]
