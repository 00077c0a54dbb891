"""Compiled right-hand sides against SymPy evaluated at seeded random points.

Oracles: the symbolic accelerations of ``EquationsOfMotion`` (or, where not
solved, M q'' = f evaluated and solved in extended precision), evaluated with
30 digits; with constraints, the Baumgarte-stabilised augmented system built
here from the symbolic A, beta and c.  A batch must equal a loop of single
evaluations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy

import lagrangian as lg
from helpers import evaluate, solve_linear
from lagrangian.numeric import compile_equations

from .cases import (
    CONSTRAINED,
    EXAMPLES,
    ORACLE_FUNCTIONS,
    arguments,
    assert_arrays_close,
    compiled,
    equations,
    point,
)

RTOL = 1e-10
N_POINTS = 4
BATCH = 7


def oracle_accelerations(name: str, values: dict[str, float]) -> list[float]:
    """q'' from the symbolic equations (exact constraints: A q'' = beta)."""
    eom = equations(name)
    functions = ORACLE_FUNCTIONS.get(name)
    if eom.accelerations is not None:
        return [
            evaluate(eom.accelerations[c], values, functions) for c in eom.system.coordinate_names
        ]
    n = len(eom.coordinates)
    matrix = [
        [evaluate(eom.mass_matrix[i, j], values, functions) for j in range(n)] for i in range(n)
    ]
    forcing = [evaluate(eom.forcing[i], values, functions) for i in range(n)]
    return solve_linear(matrix, forcing)


@pytest.mark.parametrize("name", EXAMPLES)
def test_rhs_equals_the_symbolic_accelerations(name, rng):
    system = compiled(name, baumgarte=0.0)
    for _ in range(N_POINTS):
        values = point(name, rng)
        t, y, params = arguments(system, values)
        expected = oracle_accelerations(name, values)
        n = system.n
        assert_arrays_close(system.rhs(t, y, params), [*y[n:], *expected], RTOL, name)
        assert_arrays_close(system.accelerations(t, y[:n], y[n:], params), expected, RTOL, name)


@pytest.mark.parametrize("name", EXAMPLES)
def test_mass_matrix_and_forcing_equal_the_symbolic_ones(name, rng):
    eom, system = equations(name), compiled(name)
    functions = ORACLE_FUNCTIONS.get(name)
    values = point(name, rng)
    t, y, params = arguments(system, values)
    n = system.n
    matrix = [
        [evaluate(eom.mass_matrix[i, j], values, functions) for j in range(n)] for i in range(n)
    ]
    forcing = [evaluate(eom.forcing[i], values, functions) for i in range(n)]
    assert_arrays_close(system.mass_matrix(t, y[:n], y[n:], params), matrix, RTOL, name)
    assert_arrays_close(system.forcing(t, y[:n], y[n:], params), forcing, RTOL, name)


@pytest.mark.parametrize("name", CONSTRAINED)
def test_stabilised_rhs_solves_the_augmented_system(name, rng):
    """[[M, -A^T], [A, 0]] [q''; lambda] = [f; beta - 2 alpha c' - alpha^2 c] off the manifold."""
    eom, system = equations(name), compiled(name)
    alpha = system.baumgarte
    assert alpha > 0
    forms = eom.constraints
    coordinates = eom.system.coordinates
    n, m = len(coordinates), len(forms.multipliers)
    rows = []
    for j, constraint in enumerate(eom.system.constraints):
        rate = sum(
            (sympy.diff(constraint, c.q) * c.q_dot for c in coordinates), sympy.Integer(0)
        ) + sympy.diff(constraint, eom.system.time)
        if forms.holonomic[j]:
            rows.append(forms.bias[j] - 2 * alpha * rate - alpha**2 * constraint)
        else:
            rows.append(forms.bias[j] - 2 * alpha * constraint)
    for _ in range(N_POINTS):
        values = point(name, rng)
        t, y, params = arguments(system, values)
        matrix = [[0.0] * (n + m) for _ in range(n + m)]
        for i in range(n):
            for k in range(n):
                matrix[i][k] = evaluate(eom.mass_matrix[i, k], values)
            for j in range(m):
                a = evaluate(forms.matrix[j, i], values)
                matrix[i][n + j] = -a
                matrix[n + j][i] = a
        rhs = [evaluate(eom.forcing[i], values) for i in range(n)]
        rhs += [evaluate(row, values) for row in rows]
        solution = solve_linear(matrix, rhs)
        assert_arrays_close(system.rhs(t, y, params), [*y[n:], *solution[:n]], RTOL, name)
        assert_arrays_close(system.multipliers(t, y, params), solution[n:], RTOL, name)


@pytest.mark.parametrize("name", CONSTRAINED)
def test_multipliers_equal_the_symbolic_ones(name, rng):
    eom, system = equations(name), compiled(name, baumgarte=0.0)
    for _ in range(N_POINTS):
        values = point(name, rng)
        t, y, params = arguments(system, values)
        expected = [evaluate(eom.multipliers[s], values) for s in system.constraint_names]
        assert_arrays_close(system.multipliers(t, y, params), expected, RTOL, name)


@pytest.mark.parametrize("name", EXAMPLES)
def test_batch_equals_a_loop_of_single_evaluations(name, rng):
    system = compiled(name)
    columns = [arguments(system, point(name, rng)) for _ in range(BATCH)]
    t = columns[0][0]
    ys = np.stack([y for _, y, _ in columns], axis=-1)
    params = np.stack([p for _, _, p in columns], axis=-1)
    n = system.n

    def loop(function, *, per_state_params=True):
        return np.stack(
            [
                function(t, ys[:, b], params[:, b] if per_state_params else params[:, 0])
                for b in range(BATCH)
            ],
            axis=-1,
        )

    state_functions = {
        "rhs": system.rhs,
        "rhs_jacobian": system.rhs_jacobian,
        "energy": system.energy,
        **system.invariants,
    }
    if system.has_constraints:
        state_functions.update(
            multipliers=system.multipliers,
            constraint_residual=system.constraint_residual,
            project=system.project,
        )
    for what, function in state_functions.items():
        assert_arrays_close(function(t, ys, params), loop(function), 1e-13, what)
        shared = function(t, ys, params[:, 0])  # one parameter vector for every state
        assert_arrays_close(shared, loop(function, per_state_params=False), 1e-13, what)
    split = {"mass_matrix": system.mass_matrix, "accelerations": system.accelerations}
    for what, function in split.items():
        batched = function(t, ys[:n], ys[n:], params)
        single = np.stack(
            [function(t, ys[:n, b], ys[n:, b], params[:, b]) for b in range(BATCH)], axis=-1
        )
        assert_arrays_close(batched, single, 1e-13, what)


def test_one_state_with_a_batch_of_parameters(rng):
    system = compiled("double_pendulum")
    t, y, params = arguments(system, point("double_pendulum", rng))
    grid = params[:, None] * np.linspace(0.5, 1.5, BATCH)[None, :]
    result = system.rhs(t, y, grid)
    assert result.shape == (4, BATCH)
    for b in range(BATCH):
        assert_arrays_close(result[:, b], system.rhs(t, y, grid[:, b]), 1e-13, "rhs")


def test_constant_entries_broadcast_to_the_batch():
    system = compiled("harmonic_oscillator")  # M = [[m]], dM/dq = 0
    params = system.parameter_vector()
    states = np.linspace(-1, 1, 2 * BATCH).reshape(2, BATCH)
    assert system.mass_matrix(0.0, states[:1], states[1:], params).shape == (1, 1, BATCH)
    assert system.rhs_jacobian(0.0, states, params).shape == (2, 2, BATCH)
    grid = np.zeros((2, 3, 4))  # any batch shape
    assert system.rhs(0.0, grid, params).shape == (2, 3, 4)
    assert system.energy(0.0, grid, params).shape == (3, 4)


def test_time_as_a_batch_axis():
    system = compiled("rotating_wire_bead")
    params = system.parameter_vector({"omega": 2.0})
    times = np.linspace(0, 1, BATCH)
    y = np.array([1.5, 0.3])
    result = system.rhs(times, y, params)
    assert result.shape == (2, BATCH)
    assert_arrays_close(result[1], np.full(BATCH, 2.0**2 * 1.5), RTOL, "r''")


def test_explicit_time_dependence_of_a_moving_pivot(rng):
    """Pivot at x = a cos(w t): l theta'' = -g sin(theta) + a w^2 cos(w t) cos(theta)."""
    system = lg.System.from_particles(
        coordinates=["theta"],
        particles=[lg.Particle("bob", "m", ["a*cos(w*t) + l*sin(theta)", "-l*cos(theta)"])],
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        parameters={"m": 1.0, "a": 0.3, "w": 2.0, "l": 1.2, "g": 9.81},
    )
    compiled_system = compile_equations(system.equations_of_motion())
    params = compiled_system.parameter_vector()
    values = dict(zip(compiled_system.parameter_names, params, strict=True))
    a, w, l, g = values["a"], values["w"], values["l"], values["g"]
    for _ in range(N_POINTS):
        t, theta, omega = rng.uniform(-3, 3), rng.uniform(-2, 2), rng.uniform(-2, 2)
        expected = (-g * math.sin(theta) + a * w**2 * math.cos(w * t) * math.cos(theta)) / l
        result = compiled_system.rhs(t, [theta, omega], params)
        assert_arrays_close(result, [omega, expected], RTOL, "moving pivot")
    assert "energy" not in compiled_system.invariants  # L depends on t


def test_rotating_wire_bead_is_r_ddot_omega_squared_r(rng):
    system = compiled("rotating_wire_bead")
    for _ in range(N_POINTS):
        values = point("rotating_wire_bead", rng)
        t, y, params = arguments(system, values)
        assert_arrays_close(
            system.rhs(t, y, params), [y[1], values["omega"] ** 2 * y[0]], RTOL, "bead"
        )
