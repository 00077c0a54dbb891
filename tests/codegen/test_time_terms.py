"""Time-only terms read from a table (lagrangian.codegen.time_terms) against the plain
generated rk4 step, on driven systems that are not the basin map's pendulum."""

from __future__ import annotations

import numpy as np
import pytest
import sympy

from lagrangian.codegen.time_terms import shared_parameters, split_time_terms, tabulated_loop
from lagrangian.derive import derive
from lagrangian.facade import load
from lagrangian.integrate import tableaus
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

#: m x'' = -d x' - a x - b x^3 + F cos(w t): M = m is free of the state (M^-1 tabulated).
DUFFING = """
name = "Driven Duffing oscillator"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "a*x^2/2 + b*x^4/4"

[parameters]
m = 1.3
d = 0.2
a = -1.0
b = 1.0
F = 0.3
w = 1.2

[forces]
x = "F*cos(w*t) - d*x_dot"

[initial]
x = 0.1
"""

_SHAKEN_KINETIC = (
    "m1/2*((l1*cos(u)*u_dot)^2 + (-c*w*sin(w*t) + l1*sin(u)*u_dot)^2)"
    " + m2/2*((l1*cos(u)*u_dot + l2*cos(v)*v_dot)^2"
    " + (-c*w*sin(w*t) + l1*sin(u)*u_dot + l2*sin(v)*v_dot)^2)"
)
#: A double pendulum whose pivot moves up and down as c cos(w t): M depends on the state
#: (it is solved at each stage), f on the drive through c w^2 cos(w t) and c w sin(w t).
SHAKEN_DOUBLE_PENDULUM = f"""
name = "Double pendulum on a shaken pivot"
coordinates = ["u", "v"]
kinetic = "{_SHAKEN_KINETIC}"
potential = "m1*g*(c*cos(w*t) - l1*cos(u)) + m2*g*(c*cos(w*t) - l1*cos(u) - l2*cos(v))"

[parameters]
m1 = 1.0
m2 = 0.7
l1 = 1.0
l2 = 0.8
g = 9.81
c = 0.05
w = 25.0

[forces]
u = "-0.1*u_dot"
v = "-0.1*v_dot"

[initial]
u = 0.1
"""


def _compiled(tmp_path, text: str, name: str):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return compile_equations(derive(load(str(path))))


def _plain(compiled, y0, p, grid, every):
    """The states of the plain rk4 loop of the numba ensemble (numba_stepping.run)."""
    from lagrangian.ensemble.numba_backend import kernel

    count = y0.shape[0]
    final = np.empty_like(y0)
    paths = np.empty((count, y0.shape[1], (grid.size - 1) // every + 1))
    kernel(compiled, "rk4").run(
        y0, np.repeat(p[None, :], count, axis=0), grid, False, False, every, 0.0, 0.0, 0,
        final, np.empty(count), np.empty(count, dtype=np.int64), paths, np.empty(count),
    )  # fmt: skip
    return paths


def _tabulated(compiled, y0, p, grid, every):
    loop = tabulated_loop(compiled.forms, range(p.size), tableau=tableaus.RK4)
    final = np.empty_like(y0)
    paths = np.empty((y0.shape[0], y0.shape[1], (grid.size - 1) // every + 1))
    per_member = np.repeat(p[None, :], y0.shape[0], axis=0)
    loop.run(y0, per_member, grid, loop.table(grid, p), every, final, paths)
    assert np.array_equal(final, paths[:, :, -1])
    return paths


@pytest.mark.slow  # numba compiles both loops
@pytest.mark.parametrize(
    ("text", "width", "inverse"), [(DUFFING, 1.5, True), (SHAKEN_DOUBLE_PENDULUM, 0.5, False)]
)
def test_tabulated_steps_follow_the_plain_rk4_step(tmp_path, text, width, inverse):
    compiled = _compiled(tmp_path, text, "driven")
    p = np.asarray(compiled.parameter_vector({}), dtype=float)
    assert split_time_terms(compiled.forms, range(p.size)).inverse is inverse
    y0 = np.random.default_rng(7).uniform(-width, width, (40, 2 * compiled.n))
    grid = 0.3 + 0.01 * np.arange(1201)  # not starting at 0: the drive's phase matters
    ours, plain = _tabulated(compiled, y0, p, grid, 100), _plain(compiled, y0, p, grid, 100)
    assert np.all(np.isfinite(plain))
    scale = 1.0 + np.abs(plain)
    assert np.max(np.abs(ours - plain) / scale) < 1e-12
    # the drive matters over this run: without it the states are far from these
    still = p.copy()
    still[compiled.parameter_names.index("F" if inverse else "c")] = 0.0
    undriven = _plain(compiled, y0, still, grid, 100)
    assert np.max(np.abs(undriven[:, :, -1] - plain[:, :, -1])) > 1e-2


def _time_terms(split) -> list[sympy.Expr]:
    t = sympy.Symbol("_t")
    return [term for term in split.terms if term.has(t)]


def test_the_drive_is_tabulated_only_over_shared_parameters(tmp_path):
    compiled = _compiled(tmp_path, DUFFING, "duffing")
    names = compiled.parameter_names
    F, w = (sympy.Symbol(f"_p{names.index(name)}") for name in ("F", "w"))
    t = sympy.Symbol("_t")
    every = range(len(names))
    assert _time_terms(split_time_terms(compiled.forms, every)) == [F * sympy.cos(w * t)]
    # F differs between members, w does not: the cosine alone is read from the table
    some = [j for j in every if names[j] != "F"]
    assert _time_terms(split_time_terms(compiled.forms, some)) == [sympy.cos(w * t)]
    # w differs: nothing that depends on t can be tabulated
    others = [j for j in every if names[j] != "w"]
    split = split_time_terms(compiled.forms, others)
    assert _time_terms(split) == []
    assert any(e.has(t) for e in split.forcing)
    # m differs: M^-1 is not tabulated
    assert not split_time_terms(compiled.forms, [j for j in every if names[j] != "m"]).inverse


def test_shared_parameters_are_the_columns_every_member_has():
    params = np.array([[1.0, 2.0, 3.0], [1.0, 2.5, 3.0], [1.0, 2.0, 3.0]])
    assert shared_parameters(params) == (0, 2)
    assert shared_parameters(np.array([1.0, 2.0])) == (0, 1)


def test_a_system_without_time_terms_has_an_empty_table_row(tmp_path):
    # no parameters, no drive, M depends on the state: nothing to tabulate or invert
    bare = """
name = "Bare double pendulum"
coordinates = ["a", "b"]
kinetic = "a_dot^2 + a_dot*b_dot*cos(a - b) + b_dot^2/2"
potential = "-2*cos(a) - cos(b)"

[initial]
a = 0.1
"""
    split = split_time_terms(_compiled(tmp_path, bare, "bare").forms, ())
    assert (split.terms, split.inverse, split.width) == ((), False, 0)
    assert all(not e.has(sympy.Symbol("_t")) for e in (*split.forcing, *split.mass))


@pytest.mark.slow  # numba compiles the loop
def test_numba_ensemble_with_a_varied_drive_equals_numpy(tmp_path):
    # the numba backend's rk4 runs the tabulated loop; F differs between members, so the
    # table carries cos(w t) and each member multiplies by its own F (a table made with
    # one member's F would give every member that drive)
    from lagrangian.ensemble import run_ensemble

    compiled = _compiled(tmp_path, DUFFING, "duffing")
    options = dict(
        initial={"x": 0.5, "x_dot": 0.0}, params={"F": np.linspace(0.1, 0.5, 5)},
        t_end=20.0, dt=0.01, save_every=100,
    )  # fmt: skip
    expected = run_ensemble(compiled, **options)
    got = run_ensemble(compiled, backend="numba", **options)
    assert got.attrs["backend"] == "numba"
    for name in expected.dataset.data_vars:
        np.testing.assert_allclose(got[name], expected[name], rtol=1e-12, atol=1e-12)
    finals = np.asarray(got["final_x"])
    assert np.ptp(finals) > 1e-2  # the members' drives do differ
