"""An n-link pendulum from particles against its closed-form equations of motion.

For point masses m_k on massless links l_k, angles from the downward vertical,
with mu_ij = sum_{k >= max(i, j)} m_k:

    sum_j mu_ij l_i l_j cos(theta_i - theta_j) theta_j''
        + sum_j mu_ij l_i l_j sin(theta_i - theta_j) theta_j'^2 + mu_ii g l_i sin(theta_i) = 0.

The mass matrix is the Hessian of L in the velocities, so it must equal the
closed form entry by entry; the accelerations (symbolic where the toolkit
gives them, else M^-1 f solved numerically) must equal the closed form's.
"""

from __future__ import annotations

import math
import random
from functools import cache

import pytest

import lagrangian as lg
from helpers import assert_close, evaluate, random_point, solve_linear


def chain_pendulum(
    n: int, *, length: str = "l{i}", angle: str = "theta{i}", mass: str = "m{i}", **options
):
    """The n-link pendulum from its bobs; ``length``, ``angle`` (of link i from the
    downward vertical) and ``mass`` are texts with ``{i}`` for the link's number."""
    particles = []
    x_text, y_text = "0", "0"
    for i in range(1, n + 1):
        arm, phi = length.format(i=i), angle.format(i=i)
        x_text += f" + {arm}*sin({phi})"
        y_text += f" - {arm}*cos({phi})"
        particles.append(lg.Particle(f"bob{i}", mass=mass.format(i=i), position=[x_text, y_text]))
    return lg.System.from_particles(
        coordinates=[f"theta{i}" for i in range(1, n + 1)],
        particles=particles,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        **options,
    )


@cache
def derived(n: int):
    system = chain_pendulum(n)
    return system, system.equations_of_motion()


def closed_form(n: int, point: dict[str, float]) -> tuple[list[list[float]], list[float]]:
    """M and f of M theta'' = f for the n-link pendulum at ``point``."""
    m = [point[f"m{k}"] for k in range(1, n + 1)]
    l = [point[f"l{k}"] for k in range(1, n + 1)]
    th = [point[f"theta{k}"] for k in range(1, n + 1)]
    w = [point[f"theta{k}_dot"] for k in range(1, n + 1)]
    g = point["g"]

    def mu(i, j):
        return sum(m[max(i, j) :])

    matrix = [
        [mu(i, j) * l[i] * l[j] * math.cos(th[i] - th[j]) for j in range(n)] for i in range(n)
    ]
    forcing = [
        -sum(mu(i, j) * l[i] * l[j] * math.sin(th[i] - th[j]) * w[j] ** 2 for j in range(n))
        - mu(i, i) * g * l[i] * math.sin(th[i])
        for i in range(n)
    ]
    return matrix, forcing


def check_chain(n: int, rng: random.Random, count: int) -> None:
    system, eom = derived(n)
    names = [f"theta{i}" for i in range(1, n + 1)]
    assert list(system.coordinate_names) == names
    assert eom.mass_matrix.shape == (n, n)
    for _ in range(count):
        point = random_point(system, rng)
        matrix, forcing = closed_form(n, point)
        for i in range(n):
            for j in range(n):
                assert_close(
                    evaluate(eom.mass_matrix[i, j], point),
                    matrix[i][j],
                    scale=1.0,
                    what=f"M[{i},{j}]",
                )
        ours = solve_linear(
            [[evaluate(eom.mass_matrix[i, j], point) for j in range(n)] for i in range(n)],
            [evaluate(eom.forcing[i], point) for i in range(n)],
        )
        expected = solve_linear(matrix, forcing)
        for name, value, reference in zip(names, ours, expected, strict=True):
            assert_close(value, reference, rtol=1e-8, scale=1.0, what=f"{name}_ddot from M, f")
        if eom.accelerations is not None:
            for name, reference in zip(names, expected, strict=True):
                value = evaluate(eom.accelerations[name], point)
                assert_close(value, reference, rtol=1e-8, scale=1.0, what=f"{name}_ddot")


@pytest.mark.slow
def test_four_link_pendulum(rng):
    """Four coupled coordinates: the accelerations are solved symbolically (LU)."""
    _, eom = derived(4)
    assert eom.accelerations is not None  # DESIGN 5: always given up to 6 coordinates
    check_chain(4, rng, count=3)


@pytest.mark.slow
def test_ten_link_pendulum_derives_and_is_right(rng):
    check_chain(10, rng, count=2)
