"""Derivation within budgets: the readable route bounded in time, with correct fallbacks.

The leaning rolling disc (5 coordinates, 2 rolling constraints) must finish, and
its q'' and lambda must satisfy M q'' = f + A^T lambda, A q'' = beta at random
points with M and f equal to the large route's (SymEngine, derived independently
of the readable route's tidying).  Tiny budgets force each fallback: the large
route for M and f, the untidied solve for q'', and none (numerical solve).
"""

from __future__ import annotations

import importlib
import random

import pytest
import sympy

import lagrangian as lg
from helpers import assert_close, evaluate, random_point
from lagrangian.derive.fast import derive_large

euler_lagrange = importlib.import_module("lagrangian.derive.euler_lagrange")

DISC_KINETIC = (
    "m*((x_dot + R*(cos(theta)*sin(phi)*theta_dot + sin(theta)*cos(phi)*phi_dot))**2"
    " + (y_dot - R*(cos(theta)*cos(phi)*theta_dot - sin(theta)*sin(phi)*phi_dot))**2"
    " + R**2*sin(theta)**2*theta_dot**2)/2"
    " + m*R**2*(theta_dot**2 + phi_dot**2*cos(theta)**2)/8"
    " + m*R**2*(psi_dot + phi_dot*sin(theta))**2/4"
)


def leaning_disc() -> lg.System:
    """A thin disc rolling without slipping: contact (x, y), lean theta, heading phi, spin psi."""
    return lg.System.from_energies(
        DISC_KINETIC,
        "m*g*R*cos(theta)",
        coordinates=["x", "y", "theta", "phi", "psi"],
        parameters={"m": 1.0, "R": 1.0, "g": 9.81},
        constraints=["x_dot - R*psi_dot*cos(phi)", "y_dot - R*psi_dot*sin(phi)"],
    )


def _check(system, eom, rng, *, solved=True):
    """M, f equal the large route's; q'', lambda (when given) solve the constrained system."""
    reference = derive_large(system, eom.constraints)
    forms = eom.constraints
    n = len(system.coordinates)
    for _ in range(3):
        point = random_point(system, rng)
        m = [[evaluate(eom.mass_matrix[i, j], point) for j in range(n)] for i in range(n)]
        for i in range(n):
            for j in range(n):
                assert_close(m[i][j], evaluate(reference.mass_matrix[i, j], point), what="M")
            assert_close(
                evaluate(eom.forcing[i], point), evaluate(reference.forcing[i], point), what="f"
            )
        if not solved:
            continue
        a = {c.name: evaluate(eom.accelerations[c.name], point) for c in system.coordinates}
        lam = [evaluate(eom.multipliers[s.name], point) for s in forms.multipliers]
        for i in range(n):
            inertia = sum(m[i][j] * a[c.name] for j, c in enumerate(system.coordinates))
            force = evaluate(eom.forcing[i], point) + sum(
                lam[k] * evaluate(forms.matrix[k, i], point) for k in range(len(lam))
            )
            assert_close(inertia, force, scale=1.0, what=f"(M q'' - f - A^T lambda)[{i}]")
        for k in range(len(lam)):
            rate = sum(
                evaluate(forms.matrix[k, j], point) * a[c.name]
                for j, c in enumerate(system.coordinates)
            )
            assert_close(rate, evaluate(forms.bias[k], point), scale=1.0, what="A q'' = beta")


@pytest.mark.slow
def test_leaning_rolling_disc_is_derived_with_its_accelerations():
    system = leaning_disc()
    eom = system.equations_of_motion()
    assert eom.accelerations is not None and eom.multipliers is not None
    _check(system, eom, random.Random(3))


@pytest.mark.slow
def test_past_the_readable_budget_the_large_route_gives_the_same_equations(monkeypatch):
    monkeypatch.setattr(euler_lagrange, "READABLE_SECONDS", 1e-4)
    system = leaning_disc()
    eom = system.equations_of_motion()
    assert eom.accelerations is not None  # up to 6 coordinates: still solved (untidied)
    _check(system, eom, random.Random(4))


@pytest.mark.slow
def test_past_the_tidying_budget_the_solution_is_untidied_and_right(monkeypatch):
    solve = importlib.import_module("lagrangian.derive.solve")
    calls = []

    def slow_tidy_solve(*args, **kwargs):
        calls.append(1)
        raise_out_of_time()

    monkeypatch.setattr(euler_lagrange, "solve_constrained", slow_tidy_solve)
    system = leaning_disc()
    eom = system.equations_of_motion()
    assert calls and eom.accelerations is not None
    _check(system, eom, random.Random(5))
    assert solve.plain_solution  # the fallback that answered


def raise_out_of_time():
    from lagrangian.budget import OutOfTime

    # what the deadline raises in the tidied solve: as if its 5 s had run out
    raise OutOfTime("accelerations", euler_lagrange.SOLVE_SECONDS)


def test_with_no_time_for_any_solve_q_ddot_is_left_to_the_numerical_solve(monkeypatch):
    monkeypatch.setattr(euler_lagrange, "SOLVE_SECONDS", 1e-4)
    system = lg.load("double_pendulum")
    eom = system.equations_of_motion()
    if eom.accelerations is None:  # both solves ran out: nothing half-made is reported
        assert eom.multipliers is None
    else:  # a fast machine solved within 0.1 ms: then it is right
        point = random_point(system, random.Random(6))
        m = eom.mass_matrix.xreplace({s: point[s.name] for s in eom.mass_matrix.free_symbols})
        f = [evaluate(e, point) for e in eom.forcing]
        a = [evaluate(eom.accelerations[c.name], point) for c in system.coordinates]
        for i in range(2):
            assert_close(float(sum(m[i, j] * a[j] for j in range(2))), f[i], scale=1.0)


@pytest.mark.parametrize("name", ["double_pendulum", "rolling_disc", "spherical_pendulum"])
def test_the_worked_examples_keep_their_readable_accelerations(name):
    eom = lg.load(name).equations_of_motion()
    assert eom.accelerations is not None
    assert all(len(str(a)) < 2_000 for a in eom.accelerations.values())
    assert sympy.count_ops(eom.mass_matrix) < 200


def test_the_driven_four_bars_schur_complement_is_not_given_to_trigsimp(monkeypatch):
    # its entries (12-30 operations) cost 0.15-0.3 s each in trigsimp and none came out
    # shorter; the solution must still solve M q'' = f + A^T lambda, A q'' = beta
    calls = []
    trigsimp = sympy.trigsimp

    def spy(expr, *args, **kwargs):
        calls.append(sympy.count_ops(expr))
        return trigsimp(expr, *args, **kwargs)

    monkeypatch.setattr(sympy, "trigsimp", spy)
    system = lg.load("four_bar_driven")
    eom = system.equations_of_motion()
    assert calls == []
    assert eom.accelerations is not None and eom.multipliers is not None
    _check(system, eom, random.Random(7))
