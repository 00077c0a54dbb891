"""A large model's T, V and L as assembled in SymEngine: each distinct piece made once.

Above ``FAST_MIN_COORDINATES`` coordinates T is assembled from the Jacobian columns of
the positions: each distinct sum of masses is grouped once (a chain has n of them, under
n(n+1)/2 pairs of columns), each distinct term of the positions looked at once, and
L = T - V is made in SymEngine (SymPy would sort its thousands of terms anew).  The
values must still be the n-link pendulum's closed form.
"""

from __future__ import annotations

import importlib
import math

import sympy

from derive.test_chain_pendulum import chain_pendulum
from helpers import assert_close, evaluate, random_point
from lagrangian.algebra import to_symengine


def _counting(monkeypatch, module: str, name: str) -> list:
    """Patch ``module.name`` to record its calls (and still do its work)."""
    target = importlib.import_module(module)
    original = getattr(target, name)
    calls: list = []

    def counted(*args, **kwargs):
        calls.append(args)
        return original(*args, **kwargs)

    monkeypatch.setattr(target, name, counted)
    return calls


def _closed_form_energies(n: int, point: dict) -> tuple[float, float]:
    """T and V of the n-link pendulum at ``point`` (angles from the downward vertical)."""
    m = [point[f"m{k}"] for k in range(1, n + 1)]
    l = [point[f"l{k}"] for k in range(1, n + 1)]
    th = [point[f"theta{k}"] for k in range(1, n + 1)]
    w = [point[f"theta{k}_dot"] for k in range(1, n + 1)]
    kinetic = sum(
        sum(m[max(i, j) :]) * l[i] * l[j] * math.cos(th[i] - th[j]) * w[i] * w[j] / 2
        for i in range(n)
        for j in range(n)
    )
    potential = -point["g"] * sum(
        m[k] * sum(l[i] * math.cos(th[i]) for i in range(k + 1)) for k in range(n)
    )
    return kinetic, potential


def test_each_distinct_sum_of_masses_is_grouped_once(monkeypatch, rng):
    grouped = _counting(monkeypatch, "lagrangian.model.energy", "factor_common")
    n = 12
    system = chain_pendulum(n)
    # n sums m_j + ... + m_n, each once, and once more as the coefficient of its products
    # (before: twice for each of the n(n+1)/2 pairs of links, 156 times)
    assert len(grouped) <= 2 * n
    point = random_point(system, rng)
    kinetic, potential = _closed_form_energies(n, point)
    assert_close(evaluate(system.kinetic, point), kinetic, scale=1.0)
    assert_close(evaluate(system.potential, point), potential, scale=1.0)
    assert_close(evaluate(system.lagrangian, point), kinetic - potential, scale=1.0)


def test_the_lagrangian_is_not_sorted_anew_by_sympy(monkeypatch, rng):
    flatten = sympy.Add.flatten.__func__
    sizes: list[int] = []

    def counted(cls, seq):
        made = flatten(cls, seq)
        sizes.append(len(made[0]))  # the terms of the sum made (nested sums flattened)
        return made

    sympy.core.cache.clear_cache()  # sums made by tests before are not made again
    monkeypatch.setattr(sympy.Add, "flatten", classmethod(counted))
    n = 20
    system = chain_pendulum(n)
    monkeypatch.undo()
    terms = len(system.lagrangian.args)
    assert terms == n * (n + 1) // 2 + n  # q_i' q_j' for i <= j, and gravity's n terms
    assert 0 < max(sizes) < terms  # before: T - V, 230 terms, sorted by SymPy's Add
    # L is T - V, and the SymEngine form the large route of derive starts from is L's
    built, converted = system.symengine_lagrangian
    assert built is system.lagrangian
    assert converted == to_symengine(system.lagrangian)
    difference = converted - (to_symengine(system.kinetic) - to_symengine(system.potential))
    assert difference.expand() == 0
    point = random_point(system, rng)
    assert_close(
        evaluate(system.lagrangian, point),
        evaluate(system.kinetic, point) - evaluate(system.potential, point),
        scale=1.0,
    )
