"""The jax backend: the single-run fixed-step methods as one ``jax.jit``-compiled loop.

The physics is the JAX array backend's :class:`~lagrangian.numeric.compiled.CompiledSystem`
of the same equations (``compile_equations(..., backend="jax")``), whose
functions take a batch of states (2n, B) exactly like the NumPy ones; only the
loop around them is written here, with ``jax.lax`` control flow so that XLA
compiles the whole chunk at once:

- explicit Runge-Kutta (``rk4``): the tableau and stage sums of
  :class:`~lagrangian.integrate.explicit_rk.AbstractExplicitRungeKutta`;
  constrained states are projected after every step (``compiled.project``)
  as the fixed-step driver does;
- ``variational``: the schemes of :mod:`lagrangian.integrate.variational`
  (Stormer-Verlet when separable, else the midpoint scheme: the NumPy batch's code,
  :mod:`lagrangian.integrate.midpoint_batch`, traced), with each Newton
  iteration a ``lax.while_loop`` that runs until every member has converged
  by the same per-member test, at most ``max_newton`` times.  A member that
  does not converge is an error after the loop (traced code cannot raise).

For the ``lyapunov`` observable the rk4 loop steps the state with one displacement,
[F(t, y), J(t, y) w] with J the traced symbolic Jacobian (``rhs_jacobian``), renormalised
after every step, as the numpy backend's :class:`~lagrangian.integrate.lyapunov.TangentFlow`.

Linear solves (M q'' = f of the compiled ``mass_matrix`` and ``forcing``, the
Newton steps) are the Gaussian elimination every target prints, unrolled over the
batch (:func:`_solve`), several times faster than XLA's batched LU for small n.
Both use the step grid of :func:`~lagrangian.integrate.fixed_step.step_grid`,
so in float64 a member agrees with the numpy backend to rounding.

Precision is scoped: the run is traced and executed inside
``jax.enable_x64(precision == "float64")``, so it neither depends on nor
changes the process-wide ``jax_enable_x64`` setting (the compiled functions
take their float type from it when traced: ``jnp.result_type(float)``).
In float32 the Newton tolerances are raised to float32 rounding (see
:func:`_tolerances`).  One jitted loop is kept per compiled system and
integrator settings (and precision, saving, flip tracking); JAX retraces it
only for a new chunk shape (the last chunk is padded to the others' size).
JAX is imported here only (``pip install ".[jax]"``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

import numpy as np

from ..codegen import arrays
from ..codegen.cache import built
from ..errors import MissingDependencyError, ModelError
from ..integrate.explicit_rk import AbstractExplicitRungeKutta
from ..integrate.midpoint_batch import ArrayNewton, legendre_velocity, midpoint_velocity
from ..integrate.variational import ROUNDING_FLOOR, Variational
from .choices import PRECISIONS
from .chunk import GPU_CHUNK_SIZE, AbstractEnsembleBackend, Chunk, Chunks, Outputs, Progress

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Linear solves up to this size are unrolled Gaussian elimination (see _solve).
UNROLLED_SOLVE = 8


def _jax():
    try:
        import jax
    except ImportError:
        raise MissingDependencyError("backend 'jax'", "JAX", "jax") from None
    return jax


@dataclass(frozen=True)
class JaxBackend(AbstractEnsembleBackend):
    """The jitted loop on JAX's default device; ``pad_to``: run that many members, the
    last one repeated, so that a smaller last chunk reuses the loop JAX compiled for the
    others (one per batch size).  Its chunks are not sized by time: each new size would
    cost a compile, seconds that make the early pace of a run look hopeless."""

    name: ClassVar[str] = "jax"
    precisions: ClassVar[tuple[str, ...]] = PRECISIONS
    chunk_size: ClassVar[int] = GPU_CHUNK_SIZE
    compiles_per_shape: ClassVar[bool] = True
    pad_to: int | None = None

    def run(self, chunks: Chunks, progress: Progress | None = None) -> list[Outputs]:
        # one compiled loop for every chunk: the last, smaller one padded to the others' size
        made = list(chunks)
        padded = replace(self, pad_to=made[0].count) if len(made) > 1 else self
        return AbstractEnsembleBackend.run(padded, Chunks.given(made), progress)

    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        jax = _jax()
        compiled, integrator, count = chunk.compiled, chunk.integrator, chunk.count
        integrator.check(compiled)
        y_start = np.asarray(chunk.y0, dtype=float)
        with jax.enable_x64(chunk.precision == "float64"):
            tangent = "lyapunov" in chunk.names
            run = _loop(compiled, integrator, chunk.precision, chunk.every, chunk.track, tangent)
            size = max(count, self.pad_to or 0)
            arrays = (*_padded(y_start, np.asarray(chunk.params), size), chunk.grid)
            results = run(*(array.astype(chunk.dtype) for array in arrays))
            final, flips, failed, paths, exponents = (
                np.asarray(x)[..., :count] for x in jax.device_get(results)
            )
        chunk.check_newton(failed)
        paths = np.transpose(paths, (1, 2, 0)) if chunk.every else None
        values = chunk.result(final, chunk.flip_times(flips), paths)
        if tangent:
            values["lyapunov"] = np.asarray(exponents, dtype=float)
        return values


def _padded(y0: np.ndarray, params: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray]:
    """The members, the last one repeated up to ``size``."""
    count = y0.shape[1]
    if size == count:
        return y0, params
    y0 = np.pad(y0, ((0, 0), (0, size - count)), mode="edge")
    if params.ndim == 2:
        params = np.pad(params, ((0, 0), (0, size - count)), mode="edge")
    return y0, params


def traced_system(compiled: CompiledSystem) -> CompiledSystem:
    """The JAX twin of ``compiled``: the same equations, definitions and Baumgarte rate."""
    from ..codegen.forms import DEFAULT_BAUMGARTE
    from ..numeric import compile_equations

    if compiled.backend == "jax":
        return compiled
    return compile_equations(
        compiled.equations,
        backend="jax",
        definitions=dict(compiled.definitions),
        baumgarte=compiled.baumgarte if compiled.has_constraints else DEFAULT_BAUMGARTE,
    )


def _loop(compiled, integrator, precision: str, every: int, track: bool, tangent: bool):
    """The jitted ``run(y0, params, grid)`` for these settings (built once, then cached);
    ``tangent``: carrying one displacement per member (the ``lyapunov`` observable)."""
    key = (*_settings(integrator, precision, every, track), tangent)
    if compiled.forms is None:  # functions given by hand: nothing to key them on
        return _loop_of(traced_system(compiled), integrator, precision, every, track, tangent)
    fingerprint, baumgarte = compiled.forms.fingerprint, compiled.baumgarte
    system = built(fingerprint, "jax", lambda: traced_system(compiled), baumgarte)
    build = lambda: _loop_of(system, integrator, precision, every, track, tangent)  # noqa: E731
    return built(fingerprint, "jax", build, baumgarte, key)


def _settings(integrator, precision: str, every: int, track: bool) -> tuple:
    settings = tuple(
        (field.name, getattr(integrator, field.name))
        for field in dataclasses.fields(integrator)
        if field.name != "dt"  # the grid is an argument: a new dt needs no new trace
    )
    return (type(integrator), settings, precision, every, track)


def _loop_of(system, integrator, precision: str, every: int, track: bool, tangent: bool):
    eps = float(np.finfo(np.float64 if precision == "float64" else np.float32).eps)
    if tangent:
        return _build(system, _tangent_stepper(system, integrator), every, track, tangent)
    return _build(system, _stepper(system, integrator, eps), every, track)


# -- the loop ----------------------------------------------------------------------------
def _build(system: CompiledSystem, stepper: Stepper, every: int, track: bool, tangent=False):
    """``run(y0, params, grid) -> (y_end, flip, failure, saved, exponent)``, jitted.

    ``flip`` and ``failure`` are per member the index in ``grid`` of the first
    flip (the step's end) and of the first failed step (its start), -1 if none,
    so that times are read from the float64 grid whatever the precision.  The
    steps run in blocks of ``every`` (a ``lax.scan`` stacking the state after
    each block: the saved path), then the remainder; without saving, one block.
    With ``tangent`` the stepper moves [y, w], a displacement w per member that starts
    along (1, ..., 1) and is renormalised after every step; ``exponent`` is the mean of
    log |w| per unit time (0 without).
    """
    jax = _jax()
    jnp, lax = jax.numpy, jax.lax
    project = system.project if system.has_constraints else None
    n = system.n
    m = 2 * n

    def flipped(y):
        return jnp.any(jnp.abs(y[:n]) > math.pi, axis=0)

    def run(y0, params, grid):
        steps = grid.shape[0] - 1
        size = every or steps
        blocks, never = steps // size, jnp.full(y0.shape[1:], -1, dtype=jnp.int32)

        def one(s, carry):
            y, state, flip, failed, stretch = carry
            s = jnp.asarray(s, jnp.int32)  # the index type of flip and failed
            ta, tb = grid[s], grid[s + 1]
            y, state, bad = stepper.step(ta, tb - ta, y, state, params)
            if project is not None:
                y = project(tb, y, params)
            if track:
                flip = jnp.where((flip < 0) & flipped(y), s + 1, flip)
            if bad is not None:
                failed = jnp.where((failed < 0) & bad, s, failed)
            if tangent:
                w = y[m:]
                norm = jnp.sqrt(jnp.sum(w * w, axis=0))
                stretch = stretch + jnp.log(norm)
                y = jnp.concatenate([y[:m], w / norm])
            return y, state, flip, failed, stretch

        def block(carry, start):
            carry = lax.fori_loop(0, size, lambda i, c: one(start + i, c), carry)
            return carry, (carry[0][:m] if every else None)

        flip = jnp.where(flipped(y0), 0, never) if track else never
        z0 = jnp.concatenate([y0, jnp.full_like(y0, 1.0 / math.sqrt(m))]) if tangent else y0
        stretch = jnp.zeros(y0.shape[1:], dtype=y0.dtype)
        carry = (z0, stepper.init(grid[0], z0, params), flip, never, stretch)
        carry, saved = lax.scan(block, carry, jnp.arange(blocks, dtype=jnp.int32) * size)
        carry = lax.fori_loop(blocks * size, steps, one, carry)
        paths = jnp.concatenate([y0[None], saved]) if every else y0[None]
        return carry[0][:m], carry[2], carry[3], paths, carry[4] / (grid[-1] - grid[0])

    return jax.jit(run)


class Stepper(NamedTuple):
    """A method as traceable functions: ``init(t, y, p) -> state`` and
    ``step(t, h, y, state, p) -> (y, state, failed per member or None)``."""

    init: Any
    step: Any


def _stepper(system: CompiledSystem, integrator, eps: float) -> Stepper:
    if isinstance(integrator, AbstractExplicitRungeKutta):
        return _explicit_rk(system, integrator.tableau)
    if isinstance(integrator, Variational):
        if integrator.scheme(system) == "stormer-verlet":
            return _stormer_verlet(system)
        return _midpoint(system, integrator, eps)
    raise ModelError(f"backend 'jax' does not integrate with method {integrator.name}")


def _tangent_stepper(system: CompiledSystem, integrator) -> Stepper:
    """The explicit method stepping the state with one displacement, z = [y, w]:
    z' = [F(t, y), J(t, y) w], the numpy backend's
    :class:`~lagrangian.integrate.lyapunov.TangentFlow` (J the compiled symbolic Jacobian)."""
    if not isinstance(integrator, AbstractExplicitRungeKutta):
        raise ModelError(
            f"the lyapunov observable needs an explicit method (rk4), not {integrator.name}"
        )
    if system.has_constraints:
        raise ModelError("backend 'jax' does not compute lyapunov with constraints (use numpy)")
    jnp = _jax().numpy
    rhs, m = _rhs(system), 2 * system.n

    def tangent(t, z, params):
        y, w = z[:m], z[m:]
        stretched = jnp.einsum("ij...,j...->i...", system.rhs_jacobian(t, y, params), w)
        return jnp.concatenate([rhs(t, y, params), stretched])

    return _explicit_rk(system, integrator.tableau, tangent)


# -- explicit Runge-Kutta --------------------------------------------------------------
def _explicit_rk(system: CompiledSystem, tableau, rhs=None) -> Stepper:
    """The stage sums of AbstractExplicitRungeKutta.step, term for term (same rounding);
    ``rhs``: the slope stepped (default: the system's, :func:`_rhs`)."""
    a = [[float(x) for x in row] for row in tableau.a]
    b, c = [float(x) for x in tableau.b], [float(x) for x in tableau.c]
    rhs = _rhs(system) if rhs is None else rhs

    def step(t, h, y, state, params):
        stages = []
        for i in range(tableau.stages):
            y_stage = y
            for j in range(i):
                if a[i][j] != 0.0:
                    y_stage = y_stage + (h * a[i][j]) * stages[j]
            stages.append(rhs(t + c[i] * h, y_stage, params))
        increment = sum(b_i * k for b_i, k in zip(b, stages, strict=True) if b_i != 0.0)
        return y + h * increment, state, None

    return Stepper(lambda t, y, params: (), step)


def _rhs(system: CompiledSystem):
    """``system.rhs``, with M q'' = f solved by :func:`_solve` when unconstrained."""
    if system.has_constraints:
        return system.rhs  # the augmented solve of numeric.dynamics
    jnp = _jax().numpy
    n = system.n

    def rhs(t, y, params):
        q, v = y[:n], y[n:]
        mass, force = system.mass_matrix(t, q, v, params), system.forcing(t, q, v, params)
        return jnp.concatenate([v, _solve(mass, force)])

    return rhs


# -- the variational schemes ------------------------------------------------------------
def _stormer_verlet(system: CompiledSystem) -> Stepper:
    """Variational._verlet: state (p_k, L_q(q_k), M^-1), M constant."""
    jnp = _jax().numpy
    n = system.n

    def apply(inverse, x):
        return jnp.einsum("bij,jb->ib", inverse, x)

    def init(t, y, params):
        q, w = y[:n], y[n:]
        mass = jnp.broadcast_to(system.mass_matrix(t, q, w, params), (n, n, y.shape[1]))
        inverse = jnp.linalg.inv(jnp.moveaxis(mass, -1, 0))
        force = system.lagrangian_gradient(t, q, w, params)
        return jnp.einsum("ijb,jb->ib", mass, w), force, inverse

    def step(t, h, y, state, params):
        momenta, force, inverse = state
        p_half = momenta + (h / 2) * force
        v_half = apply(inverse, p_half)
        q_new = y[:n] + h * v_half
        force = system.lagrangian_gradient(t + h, q_new, v_half, params)
        p_new = p_half + (h / 2) * force
        y_new = jnp.concatenate([q_new, apply(inverse, p_new)])
        return y_new, (p_new, force, inverse), None

    return Stepper(init, step)


def _tolerances(integrator: Variational, eps: float) -> tuple[float, float]:
    """(newton_tol, rounding floor), raised to a few ulps where the precision is coarser.

    In float64 they are the single run's (1e-14, ROUNDING_FLOOR); in float32
    (eps 1.2e-7) the residual cannot get below ~eps, so 8 eps and 1024 eps.
    """
    return max(integrator.newton_tol, 8 * eps), max(ROUNDING_FLOOR, 1024 * eps)


def _midpoint(system: CompiledSystem, integrator: Variational, eps: float) -> Stepper:
    """Variational's midpoint step (:mod:`lagrangian.integrate.midpoint_batch`, the NumPy
    batch's code traced): state (p_k, the last midpoint velocity)."""
    jax = _jax()
    jnp = jax.numpy
    n = system.n
    tolerance, floor = _tolerances(integrator, eps)
    settings = ArrayNewton(jnp, jax.lax.while_loop, _solve, tolerance, floor,
                           integrator.max_newton)  # fmt: skip

    def init(t, y, params):
        q, w = y[:n], y[n:]
        return system.momenta(t, q, w, params), w  # 2w - w = w: the first guess is w

    def step(t, h, y, state, params):
        q, w = y[:n], y[n:]
        p, v_previous = state
        found = midpoint_velocity(system, settings, t, h, q, w, p, v_previous, params)
        p_new = p + h * found.extra
        q_new = q + h * found.x
        velocity = legendre_velocity(system, settings, t + h, q_new, p_new, found.x, params)
        failed = found.failed | velocity.failed
        return jnp.concatenate([q_new, velocity.x]), (p_new, found.x), failed

    return Stepper(init, step)


def _solve(matrix, rhs):
    """x (n, B) with matrix[:, :, b] x[:, b] = rhs[:, b], for every member b.

    The one Gaussian elimination with partial pivoting
    (:func:`lagrangian.codegen.steps.elimination`) walked over the entries, each an array
    over the batch, when traced (:func:`lagrangian.codegen.arrays.solve`): for the small
    n of mechanics this is several times faster on CPU than the batched LU of
    ``jnp.linalg.solve``, which a larger n falls back to.
    """
    jnp = _jax().numpy
    n = rhs.shape[0]
    stacked = jnp.moveaxis(jnp.broadcast_to(matrix, (n, n, rhs.shape[1])), -1, 0)
    if n > UNROLLED_SOLVE:
        return jnp.linalg.solve(stacked, rhs.T[..., None])[..., 0].T
    return arrays.solve(jnp, stacked, rhs.T)[0].T
