"""Time derivatives along the motion, symbolic and at sample points.

d/dt C(q, q', t) = sum_j (dC/dq_j q_j' + dC/dq_j' q_j'') + dC/dt with q'' from
M q'' = f.  The symbolic form keeps q'' as symbols (linear in them); the
numeric check evaluates it at random states with q'' solved numerically, which
is how every conservation claim is double-checked before it is reported.
"""

from __future__ import annotations

import random

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..derive import EquationsOfMotion
from ..pointwise import evaluate

#: Relative size below which a sampled time derivative counts as zero.
ZERO_TOLERANCE = 1e-9


def total_derivative(expr: sympy.Expr, eom: EquationsOfMotion) -> sympy.Expr:
    """dC/dt by the chain rule, with the accelerations left as q'' symbols."""
    system = eom.system
    rate = sympy.diff(expr, system.time)
    for c in system.coordinates:
        rate += sympy.diff(expr, c.q) * c.q_dot + sympy.diff(expr, c.q_dot) * c.q_ddot
    return rate


def vanishes_along_motion(
    expr: sympy.Expr, eom: EquationsOfMotion, *, samples: int = 6, seed: int = 1
) -> bool:
    """True when dC/dt = 0 at ``samples`` random states (q'' from M q'' = f).

    Unspecified functions are replaced by random smooth functions of their
    arguments and parameters by random positive values, so the check covers
    the whole family the symbolic answer claims.  False when a sample shows
    dC/dt != 0, and also when no sample point could be evaluated.
    """
    verdicts = list(_zero_rate_at_samples(expr, eom, samples, seed))
    return bool(verdicts) and all(verdicts)


def contradicted_along_motion(
    expr: sympy.Expr, eom: EquationsOfMotion, *, samples: int = 6, seed: int = 1
) -> bool:
    """True only when a sample state shows dC/dt != 0.

    Where no sample can be evaluated in float64 (V = exp(exp(exp(exp(exp(x)))))
    overflows everywhere) there is no evidence either way, and a symbolic
    conservation claim stands.
    """
    return not all(_zero_rate_at_samples(expr, eom, samples, seed))


def _zero_rate_at_samples(expr, eom: EquationsOfMotion, samples: int, seed: int):
    """Whether dC/dt is zero, for each of up to ``samples`` random states that evaluate;
    stops at the first state where it is not."""
    rng = random.Random(seed)
    system = eom.system
    # one random stand-in for each declared function, put in once: putting one in M, f
    # and dC/dt (replace, then doit) costs far more than evaluating them at a point
    concrete = _concrete_functions(system, rng)
    rate = _substitute(total_derivative(expr, eom), concrete)
    mass_matrix = _substitute(eom.mass_matrix, concrete)
    forcing_vector = _substitute(eom.forcing, concrete)
    checked = 0
    for _ in range(samples * 4):
        point = _random_point(system, rng)
        mass = evaluate(mass_matrix, point)
        forcing = evaluate(forcing_vector, point)
        if mass is None or forcing is None:
            continue  # an undefined or overflowing sample point: draw another
        try:
            accelerations = np.linalg.solve(mass, forcing).ravel()
        except np.linalg.LinAlgError:
            continue  # a singular sample point
        for c, a in zip(system.coordinates, accelerations, strict=True):
            point[c.q_ddot] = float(a)
        scale = max(1.0, float(np.abs(forcing).max()), float(np.abs(mass).max()))
        value = evaluate(rate, point)
        if value is None:
            continue
        zero = abs(float(value)) <= ZERO_TOLERANCE * scale * 10
        yield zero
        checked += 1
        if not zero or checked == samples:
            return


def _random_point(system, rng: random.Random) -> dict:
    point = {system.time: rng.uniform(0.1, 2.0)}
    for c in system.coordinates:
        point[c.q] = rng.uniform(0.3, 1.3)
        point[c.q_dot] = rng.uniform(-1.5, 1.5)
    for p in system.parameters:
        value = rng.uniform(0.5, 2.0)
        point[p.symbol] = -value if p.sign == "negative" else value
    return point


def _concrete_functions(system, rng: random.Random) -> dict:
    """A random smooth stand-in for each declared function: c0 + sum c_k sin(a_k x_k + b_k)."""
    stand_ins = {}
    for declaration in system.functions:
        arguments = sympy.symbols(f"_a0:{len(declaration.arguments)}", real=True)
        body = sympy.Float(rng.uniform(-1, 1))
        for a in arguments:
            body += sympy.Float(rng.uniform(0.5, 1.5)) * sympy.sin(
                sympy.Float(rng.uniform(0.5, 2)) * a + sympy.Float(rng.uniform(0, 3))
            )
        stand_ins[declaration.function] = sympy.Lambda(arguments, body)
    return stand_ins


def _substitute(expr, concrete: dict):
    if concrete and expr.has(AppliedUndef):
        for function, stand_in in concrete.items():
            expr = expr.replace(function, stand_in)
        expr = expr.doit()
    return expr
