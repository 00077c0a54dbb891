r"""The variational integrator of the midpoint discrete Lagrangian (and Stormer-Verlet).

Discrete mechanics replaces the action integral over one step by the
discrete Lagrangian (Marsden & West, "Discrete mechanics and variational
integrators", Acta Numerica 10 (2001) 357-514, section 2.2)

    L_d(q0, q1) = h L(q_m, v, t + h/2),   q_m = (q0 + q1)/2,   v = (q1 - q0)/h,

and forces by the discrete Lagrange-d'Alembert principle with the midpoint
forces f_d^- = f_d^+ = (h/2) Q(q_m, v, t + h/2), Q = the non-conservative
forces minus dF/dq' (``compiled.nonconservative_forces``; Marsden & West
section 3.2).  In position-momentum form one step (q_k, p_k) -> (q_{k+1}, p_{k+1}) is

    p_k     = -D1 L_d - f_d^- = L_q'(q_m, v) - (h/2) [L_q(q_m, v) + Q(q_m, v)],
    p_{k+1} =  D2 L_d + f_d^+ = L_q'(q_m, v) + (h/2) [L_q(q_m, v) + Q(q_m, v)],
    q_{k+1} = q_k + h v.

The first line is solved for the midpoint velocity v by Newton's method with
the Jacobian

    J = M + (h/2)(P_q - P_q^T) - (h^2/4) L_qq - (h/2)[(h/2) Q_q + Q_q'],

M = d^2L/dq'^2 (``mass_matrix``), P_q = d^2L/dq'dq (``momenta_jacobian_q``),
L_qq (``lagrangian_hessian_q``), Q_q, Q_q' (``nonconservative_forces_jacobian_*``),
until the residual is ``newton_tol`` (1e-14) relative to the momenta (or, once
an update no longer halves it, ``ROUNDING_FLOOR`` relative to the momenta times
max(1, |q|): the coordinates' own rounding, which the momenta inherit); then
p_{k+1} = p_k + h [L_q + Q](q_m, v), which keeps the momentum of a cyclic
coordinate (L_q = 0, Q = 0) constant to the last bit.  The velocity q'_{k+1}
of the state comes from p_{k+1} by the Legendre transform, L_q'(q_{k+1}, q') = p_{k+1}
(Newton with M).

When ``compiled.separable`` (L = q'^T M q'/2 - V(q), M constant, no forces)
the trapezoidal discrete Lagrangian (h/2)[L(q0, v) + L(q1, v)] gives the
explicit Stormer-Verlet scheme instead, one gradient evaluation per step:

    p_{k+1/2} = p_k + (h/2) L_q(q_k),   q_{k+1} = q_k + h M^{-1} p_{k+1/2},
    p_{k+1}   = p_{k+1/2} + (h/2) L_q(q_{k+1}).

Both are symplectic, symmetric and of order 2 (Hairer, Lubich & Wanner,
*Geometric Numerical Integration*, 2nd ed. 2006, VI.6): the energy error
stays bounded, O(h^2), over exponentially long times, and by the discrete
Noether theorem momenta of symmetries (cyclic coordinates, rotations) are
conserved.  Constraints are not handled (use rk4, dop853 or radau).  Both
work on a batch of states y (2n, B): Newton per batch element with a stacked
linear solve, an element stops iterating when it has converged.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..errors import ModelError, SingularMassMatrixError
from ..numeric.backends import numpy_backend
from .compiled_loop import Newton, Unavailable
from .fixed_step import AbstractFixedStepIntegrator, StepFailure
from .midpoint_batch import (
    STALL_RATIO,
    ArrayNewton,
    legendre_velocity,
    midpoint_velocity,
    python_while,
)
from .midpoint_step import midpoint_functions, step_one

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: A residual that stopped decreasing is accepted below this size relative to the
#: momenta times max(1, max |q|): the rounding floor of badly conditioned mass matrices,
#: and of coordinates that have grown (a spinning angle of 600 rad carries 600 times the
#: absolute rounding of one of 1 rad, and the momenta depend on it).
ROUNDING_FLOOR = 1e-10

_NUMPY = numpy_backend()


@dataclass(frozen=True)
class Variational(AbstractFixedStepIntegrator):
    """Midpoint variational integrator (Stormer-Verlet when separable); see the module.

    >>> Variational(dt=0.01).settings()
    {'method': 'variational', 'dt': 0.01, 'newton_tol': 1e-14}
    """

    newton_tol: float = 1e-14
    max_newton: int = 30
    explicit_when_separable: bool = True
    name: ClassVar[str] = "variational"
    order: ClassVar[int] = 2
    default_omega_dt: ClassVar[float] = 0.02  # phase error (ω dt)^2/24 = 2e-5 per radian
    stability_limit: ClassVar[float] = 2.0  # Stormer-Verlet's; the midpoint's Newton too
    symplectic: ClassVar[bool] = True
    needs: ClassVar[str] = "lagrangian"

    def __post_init__(self) -> None:
        super().__post_init__()
        if not 0 < self.newton_tol < 1e-6:
            raise ModelError(f"newton_tol must lie in (0, 1e-6), not {self.newton_tol!r}")
        if int(self.max_newton) != self.max_newton or self.max_newton < 1:
            raise ModelError(f"max_newton must be a whole number >= 1, not {self.max_newton!r}")

    def check(self, compiled: CompiledSystem) -> None:
        if compiled.has_constraints:
            names = ", ".join(compiled.constraint_names) or "constraints"
            raise ModelError(
                f"the variational integrator does not handle constraints ({names}): "
                "use rk4, dop853 or radau"
            )

    def settings(self) -> dict[str, object]:
        return {"method": self.name, "dt": self.dt, "newton_tol": self.newton_tol}

    def settings_for(self, compiled: CompiledSystem) -> dict[str, object]:
        return {**self.settings(), "scheme": self.scheme(compiled)}

    def scheme(self, compiled: CompiledSystem) -> str:
        """``"stormer-verlet"`` for separable systems (unless disabled), else ``"midpoint"``."""
        return (
            "stormer-verlet" if compiled.separable and self.explicit_when_separable else "midpoint"
        )

    def printed_scheme(self, compiled: CompiledSystem) -> str:
        return self.scheme(compiled)

    def newton_settings(self) -> Newton:
        return Newton(self.newton_tol, ROUNDING_FLOOR, STALL_RATIO, int(self.max_newton))

    def failure_text(self, code: int) -> str:
        if code == 1:
            return (
                "Newton's method for the midpoint velocity did not converge in "
                f"{self.max_newton} iterations"
            )
        return f"the velocity for the momenta did not converge in {self.max_newton} iterations"

    # -- the protocol of fixed-step methods ---------------------------------------
    def init(self, compiled, t, y, params, work):
        q, w = _split(_batch(y))
        work.rhs_evaluations += 1
        n, batch = q.shape
        mass = np.broadcast_to(compiled.mass_matrix(t, q, w, params), (n, n, batch))
        _check_regular(compiled, t, q, np.moveaxis(mass, -1, 0))
        if self.scheme(compiled) == "midpoint":
            return _MidpointState(compiled.momenta(t, q, w, params), None)
        inverse = np.linalg.inv(np.moveaxis(mass, -1, 0))  # (B, n, n), M is constant
        force = compiled.lagrangian_gradient(t, q, w, params)
        return _VerletState(_mul(mass, w), force, inverse)

    def step(self, compiled, t, h, y, state, params, work):
        single = y.ndim == 1
        if single and isinstance(state, _MidpointState) and np.ndim(params) == 1:
            functions = midpoint_functions(compiled)
            if functions is not None:
                newton = self.newton_settings()
                momenta, last = state.momenta[:, 0], state.velocity
                try:
                    y_new, p_new, v_new = step_one(
                        functions, t, h, y, momenta, None if last is None else last[:, 0],
                        params, work, newton,
                    )  # fmt: skip
                except Unavailable:
                    pass  # the NumPy functions take this step (and give its inf or NaN)
                else:
                    return y_new, _MidpointState(p_new[:, None], v_new[:, None])
        q, w = _split(_batch(y))
        if isinstance(state, _VerletState):
            q_new, w_new, state = self._verlet(compiled, t, h, q, state, params, work)
        else:
            q_new, w_new, state = self._midpoint(compiled, t, h, q, w, state, params, work)
        y_new = np.concatenate([q_new, w_new])
        return (y_new[:, 0] if single else y_new), state

    # -- the two schemes ----------------------------------------------------------
    def _verlet(self, compiled, t, h, q, state, params, work):
        p_half = state.momenta + (h / 2) * state.force
        v_half = _apply(state.inverse, p_half)
        q_new = q + h * v_half
        force = compiled.lagrangian_gradient(t + h, q_new, v_half, params)
        work.rhs_evaluations += 1
        p_new = p_half + (h / 2) * force
        return q_new, _apply(state.inverse, p_new), _VerletState(p_new, force, state.inverse)

    def _midpoint(self, compiled, t, h, q, w, state, params, work):
        settings = ArrayNewton(np, python_while, _solve, self.newton_tol, ROUNDING_FLOOR,
                               self.max_newton)  # fmt: skip
        last = w if state.velocity is None else state.velocity  # 2 w - w = w: the guess is w
        found = midpoint_velocity(compiled, settings, t, h, q, w, state.momenta, last, params)
        work.rhs_evaluations += found.updates + 1
        work.jacobian_evaluations += found.updates
        work.newton_iterations += found.updates
        if found.failed.any():
            raise StepFailure(
                "Newton's method for the midpoint velocity did not converge in "
                f"{self.max_newton} iterations (residual {np.max(found.size):.2e})"
            )
        p_new = state.momenta + h * found.extra
        q_new = q + h * found.x
        velocity = legendre_velocity(compiled, settings, t + h, q_new, p_new, found.x, params)
        work.rhs_evaluations += velocity.updates + 1
        work.jacobian_evaluations += velocity.updates
        if velocity.failed.any():
            raise StepFailure(
                f"the velocity for the momenta did not converge in {self.max_newton} iterations"
            )
        return q_new, velocity.x, _MidpointState(p_new, found.x)


def _check_regular(compiled, t, q: np.ndarray, mass: np.ndarray) -> None:
    """Refuse a start where M (B, n, n) is singular: the momenta would not fix the velocity.

    The explicit methods find this in their first solve; here the momenta of such
    a state are computed without one, and the run would silently lose the velocity.
    """
    with np.errstate(all="ignore"):
        condition = np.linalg.cond(mass)
    bad = ~(condition < 1 / np.finfo(float).eps)
    if not bad.any():
        return
    k = int(np.argmax(bad))
    raise SingularMassMatrixError.at_state(
        float(np.max(t)), compiled.coordinate_names, q[:, k].tolist()
    )


@dataclass(frozen=True)
class _MidpointState:
    momenta: np.ndarray  # p_k, (n, B)
    velocity: np.ndarray | None  # the last midpoint velocity, for the first guess


@dataclass(frozen=True)
class _VerletState:
    momenta: np.ndarray  # p_k, (n, B)
    force: np.ndarray  # L_q(q_k), (n, B)
    inverse: np.ndarray  # M^{-1}, (B, n, n)


def _batch(y: np.ndarray) -> np.ndarray:
    return y[:, None] if y.ndim == 1 else y


def _split(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = y.shape[0] // 2
    return y[:n], y[n:]


def _solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x (n, B) with matrix[:, :, b] x[:, b] = rhs[:, b] for every batch element (the
    NumPy backend's solve)."""
    n, batch = rhs.shape
    if matrix.shape != (n, n, batch):
        matrix = np.broadcast_to(matrix, (n, n, batch))
    try:
        return _NUMPY.solve(matrix.transpose(2, 0, 1), rhs.T).T
    except np.linalg.LinAlgError:
        raise StepFailure("the Newton matrix (the mass matrix) is singular") from None


def _apply(inverse: np.ndarray, x: np.ndarray) -> np.ndarray:
    """inverse (B, n, n) applied to x (n, B)."""
    return np.einsum("bij,jb->ib", inverse, x)


def _mul(matrix: np.ndarray, x: np.ndarray) -> np.ndarray:
    """matrix (n, n, B) applied to x (n, B)."""
    return np.einsum("ijb,jb->ib", matrix, x)
