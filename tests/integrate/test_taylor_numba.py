"""Taylor's method by our own code generation (backend "numba"): the coefficients of every
elementary operation against SymPy, runs against exact solutions and SciPy's DOP853."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.codegen.taylor_numba import SCALED, module_text, table_rows
from lagrangian.codegen.taylor_tape import tape_of
from lagrangian.errors import ModelError
from lagrangian.integrate import choice as choice_module
from lagrangian.integrate import taylor_compiled
from lagrangian.integrate.choice import choose_run, heyoka_installed
from lagrangian.integrate.events import Event
from lagrangian.integrate.taylor import Taylor
from lagrangian.integrate.taylor_compiled import MAX_ORDER, order_for
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

#: Lagrangians whose equations, together, use every operation of the tape: products,
#: squares, quotients (a mass that depends on x), sqrt, a real power, exp, log, sin/cos and
#: tan, sinh/cosh and tanh, negation, time, and parameters alone (hoisted into constants);
#: each small, so that SymPy differentiates it along the flow in a fraction of a second.
EVERY_OPERATION = (
    ("(1 + x**2/4)*x_dot**2/2 - k*x**2/2 - exp(-x**2) + x*log(3 + x**2)", {"k": 1.3}),
    ("x_dot**2/2 - sqrt(3 + x**2) - x*(2 + x**2)**(5/3)/9 + x*cos(w*t)", {"w": 2.1}),
    (
        "x_dot**2/2 + a*cos(x)*sinh(x/2) + tan(x/4) - x*tanh(x/5) + cosh(x/7)*exp(b)",
        {"a": 0.7, "b": 0.4},
    ),
)


def _compiled(lagrangian: str, coordinates: list[str], **parameters: float):
    system = lg.System.from_lagrangian(lagrangian, coordinates=coordinates, parameters=parameters)
    return compile_equations(system.equations_of_motion())


def _as_python(text: str) -> dict:
    """The names of a generated module's ``text`` run as plain Python (numba's decorator
    made a no-op): the same text, without compiling it."""
    namespace: dict = {}
    text = text.replace(
        "from numba import njit, uint64",
        "njit = lambda *f, **options: f[0] if f else lambda f: f\nuint64 = int",
    )
    text = text.replace("from lagrangian.codegen.numba_cache import tolerate_full_disk", "")
    text = text.replace("tolerate_full_disk()", "")
    exec(compile(text, "<generated>", "exec"), namespace)  # our own text
    return namespace


def _python_coefficients(compiled, t: float, y: np.ndarray, params: np.ndarray, order: int):
    """The generated module's coefficients run as plain Python."""
    tape = tape_of(compiled.forms)
    namespace = _as_python(module_text(tape)[1])
    c = np.zeros(max(len(tape.constants), 1))
    namespace["constants"](params, c)
    tc = np.zeros((namespace["ROWS"], namespace["STRIDE"]))
    tc[: y.shape[0], 0] = y
    namespace["coefficients"](t, c, order, tc, tc.reshape(-1), None, None)
    return tape, tc[: y.shape[0], : order + 1]


def _lie_coefficients(compiled, t: float, y: np.ndarray, params: np.ndarray, order: int):
    """y^(k)(t) / k! by differentiating F along the flow in SymPy: y^(k+1) = dy^(k)/dt + J F,
    independent of the tape."""
    forms = compiled.forms
    n = forms.n
    state = [*forms.coordinates, *forms.velocities]
    rates = [*forms.velocities, *forms.mass_matrix.LUsolve(forms.forcing)]
    values = dict(zip(forms.parameters, params, strict=True))
    rates = [sympy.sympify(rate).subs(values) for rate in rates]
    point = {forms.time: t, **dict(zip(state, y, strict=True))}
    columns = [np.array(y, dtype=float)]
    derivatives = list(state)
    for k in range(1, order + 1):
        derivatives = [
            sympy.diff(d, forms.time)
            + sum(sympy.diff(d, s) * r for s, r in zip(state, rates, strict=True))
            for d in derivatives
        ]
        columns.append(
            np.array([float(d.evalf(30, subs=point)) for d in derivatives]) / math.factorial(k)
        )
    assert len(columns[0]) == 2 * n
    return np.array(columns).T


@pytest.mark.slow  # derives the three systems (9 s)
def test_the_tapes_use_every_operation():
    kinds = set()
    for lagrangian, parameters in EVERY_OPERATION:
        compiled = _compiled(lagrangian, ["x"], **parameters)
        kinds |= {op.kind for op in tape_of(compiled.forms).ops}
    assert kinds == {"add", "sub", "mul", "square", "div", "neg", "sqrt", "pow", "exp", "log",
                     "sincos", "sinhcosh"}  # fmt: skip


@pytest.mark.parametrize(
    ("lagrangian", "parameters"),
    [
        pytest.param(*case, marks=pytest.mark.slow) if "cosh" in case[0] else case
        for case in EVERY_OPERATION
    ],
)  # the hyperbolic one derives and differentiates in 10 s
def test_coefficients_are_those_of_differentiating_along_the_flow(lagrangian, parameters):
    compiled = _compiled(lagrangian, ["x"], **parameters)
    params = compiled.parameter_vector({})
    y, t = np.array([0.4, -0.3]), 0.6
    _, ours = _python_coefficients(compiled, t, y, params, 4)
    reference = _lie_coefficients(compiled, t, y, params, 4)
    np.testing.assert_allclose(ours, reference, rtol=1e-12, atol=1e-13)


@pytest.mark.slow  # SymPy's series to order 12 (2 s)
def test_charged_particle_coefficients_are_the_exact_circle():
    # L = m v^2/2 + (qB/2)(x y' - y x'): a circle of angular frequency w = qB/m, whose
    # Taylor coefficients at t are those of x = cx + R cos(w t + phi), y = cy + R sin(...)
    compiled = _compiled(
        "m*(x_dot**2 + y_dot**2)/2 + qB*(x*y_dot - y*x_dot)/2", ["x", "y"], m=2.0, qB=3.0
    )
    params = compiled.parameter_vector({})
    w = -1.5  # the sign: the force q v x B turns the velocity clockwise for qB > 0
    state = np.array([0.3, -0.2, 0.5, 0.8])
    _, ours = _python_coefficients(compiled, 0.0, state, params, 12)
    s = sympy.Symbol("s")
    center = (state[0] - state[3] / w, state[1] + state[2] / w)
    x = (
        center[0]
        + (state[0] - center[0]) * sympy.cos(w * s)
        - (state[1] - center[1]) * sympy.sin(w * s)
    )
    yy = (
        center[1]
        + (state[0] - center[0]) * sympy.sin(w * s)
        + (state[1] - center[1]) * sympy.cos(w * s)
    )
    for row, path in enumerate((x, yy, sympy.diff(x, s), sympy.diff(yy, s))):
        series = sympy.series(path, s, 0, 13).removeO()
        exact = [float(series.coeff(s, k)) for k in range(13)]
        np.testing.assert_allclose(ours[row], exact, rtol=1e-12, atol=1e-14)


@pytest.mark.slow  # derives two systems (6 s)
def test_exp_sin_cos_sinh_cosh_keep_j_u_j_in_spare_rows():
    # the recurrences of exp and of the sin/cos and sinh/cosh pairs sum j u_j times their
    # own coefficients: each such operation writes k u_k once per order into a row of its own
    for lagrangian, parameters in (EVERY_OPERATION[0], EVERY_OPERATION[2]):
        compiled = _compiled(lagrangian, ["x"], **parameters)
        tape = tape_of(compiled.forms)
        scaled = [op for op in tape.ops if op.kind in SCALED]
        assert {"exp", "sincos", "sinhcosh"} & {op.kind for op in scaled}
        namespace = _as_python(module_text(tape)[1])
        assert namespace["ROWS"] == tape.rows + len(scaled) == table_rows(tape)
        c = np.zeros(max(len(tape.constants), 1))
        namespace["constants"](compiled.parameter_vector({}), c)
        tc = np.zeros((namespace["ROWS"], namespace["STRIDE"]))
        tc[:2, 0] = [0.4, -0.3]
        namespace["coefficients"](0.6, c, 8, tc, tc.reshape(-1), None, None)
        k = np.arange(1, 8)
        for spare, op in enumerate(scaled, start=tape.rows):
            np.testing.assert_array_equal(tc[spare, 1:8], k * tc[op.args[0][1], 1:8])


def test_the_step_size_is_heyokas_rule_and_the_ten_ulp_test_exact():
    # the loop takes rho as one exp of the smaller log, and asks nextafter only for a step
    # under 10 eps |t|: both against their plain forms
    loop = _as_python(Path(taylor_compiled.__file__).with_name("numba_taylor.py").read_text())
    rng = np.random.default_rng(7)
    for order in (5, 13, 20):
        for scale in (1e-3, 1.0, 40.0):
            tc = scale * rng.standard_normal((4, order + 1)) * 0.3 ** np.arange(order + 1)
            safety = math.exp(-2.0 - 0.7 / (order - 1))
            x = max(np.max(np.abs(tc[:, 0])), 1.0)
            rho = min(
                (x / np.max(np.abs(tc[:, order]))) ** (1.0 / order),
                (x / np.max(np.abs(tc[:, order - 1]))) ** (1.0 / (order - 1)),
            )
            h = loop["step_size"](tc, 4, order, safety)
            assert h == pytest.approx(rho * safety, rel=1e-14)
    tc = np.zeros((2, 6))
    assert loop["step_size"](tc, 2, 5, 1.0) == math.inf  # the last two orders vanish
    tc[1, 4] = math.nan
    assert math.isnan(loop["step_size"](tc, 2, 5, 1.0))
    times = [0.0, 5e-324, -3e-310, 2.2250738585072014e-308, 1.0, -1.0, 0.75, 1e6, -1e6]
    times += list(rng.uniform(-1.0, 1.0, 20) * 10.0 ** rng.integers(-300, 300, 20))
    for t in times:
        ten = 10.0 * abs(math.nextafter(t, math.inf) - t)
        for h in (ten, math.nextafter(ten, 0.0), math.nextafter(ten, math.inf), 3 * ten):
            for sign in (1.0, -1.0):
                assert loop["below_ten_ulp"](sign * h, t) == (h <= ten), (t, h)


def test_the_order_follows_the_tolerance_as_heyokas():
    assert [order_for(tol) for tol in (1e-10, 1e-12, 1e-15, 2**-52)] == [13, 15, 19, 20]


def test_an_unsupported_function_is_refused_naming_it():
    compiled = _compiled("x_dot**2/2 - x*atan(x)", ["x"])
    with pytest.raises(ModelError) as error:
        tape_of(compiled.forms)
    assert str(error.value) == (
        "method 'taylor' (numba) cannot differentiate atan (in atan(x)): its Taylor "
        "recurrences cover sin, cos, tan, exp, log, sqrt, sinh, cosh, tanh, powers; use "
        "backend 'heyoka' or dop853"
    )


def test_an_unknown_backend_is_refused():
    with pytest.raises(
        ModelError, match=r"unknown backend 'c' of method 'taylor' \(backends: heyoka, numba\)"
    ):
        Taylor(backend="c")


KEPLER = "m*(r_dot**2 + r**2*theta_dot**2)/2 + k*m/r"


@pytest.mark.slow  # compiles the loop (2-3 s)
def test_kepler_orbit_matches_dop853_and_keeps_energy_and_angular_momentum():
    compiled = _compiled(KEPLER, ["r", "theta"], m=1.0, k=1.0)
    params = compiled.parameter_vector({})
    y0 = np.array([1.0, 0.0, 0.0, 1.2])  # eccentricity 0.44, period about 9.2
    grid = np.linspace(0.0, 50.0, 11)
    result = Taylor(tol=1e-15, backend="numba").solve(
        compiled, (0.0, 50.0), y0, params, t_eval=grid
    )
    assert result.success and result.settings["backend"] == "numba"
    reference = solve_ivp(
        lambda t, y: compiled.rhs(t, y, params), (0.0, 50.0), y0, method="DOP853",
        rtol=1e-13, atol=1e-13, t_eval=grid,
    )  # fmt: skip
    np.testing.assert_allclose(result.y, reference.y, rtol=0, atol=1e-8)
    r, theta_dot, r_dot = result.y[0], result.y[3], result.y[2]
    energy = (r_dot**2 + r**2 * theta_dot**2) / 2 - 1 / r
    momentum = r**2 * theta_dot
    assert np.max(np.abs(energy - energy[0])) < 1e-10
    assert np.max(np.abs(momentum - momentum[0])) < 1e-10
    every = Taylor(tol=1e-12, backend="numba").solve(compiled, (0.0, 50.0), y0, params)
    assert every.t[0] == 0.0 and every.t[-1] == 50.0 and np.all(np.diff(every.t) > 0)
    assert every.steps == every.t.shape[0] - 1


@pytest.mark.slow  # compiles the loop (2-3 s)
def test_driven_duffing_matches_dop853_and_heyokas_steps():
    compiled = _compiled(
        "x_dot**2/2 - a*x**2/2 - b*x**4/4 + F*x*cos(w*t)", ["x"], a=-1.0, b=1.0, F=0.3, w=1.2
    )
    params = compiled.parameter_vector({})
    y0 = np.array([0.5, 0.1])
    ours = Taylor(tol=1e-13, backend="numba").solve(compiled, (0.0, 20.0), y0, params)
    reference = solve_ivp(
        lambda t, y: compiled.rhs(t, y, params), (0.0, 20.0), y0, method="DOP853",
        rtol=1e-13, atol=1e-13,
    )  # fmt: skip
    np.testing.assert_allclose(ours.y[:, -1], reference.y[:, -1], rtol=0, atol=1e-9)
    if heyoka_installed():
        theirs = Taylor(tol=1e-13, backend="heyoka").solve(compiled, (0.0, 20.0), y0, params)
        assert ours.steps == theirs.steps  # the same order and step rule


@pytest.mark.slow  # compiles the loop (2-3 s)
def test_a_singularity_fails_naming_the_state():
    compiled = _compiled("x_dot**2/2 + 1/x", ["x"])  # falls into x = 0 in finite time
    params = compiled.parameter_vector({})
    result = Taylor(tol=1e-12, backend="numba").solve(compiled, (0.0, 10.0), [1.0, 0.0], params)
    assert not result.success
    assert "t = " in result.message and "x = " in result.message


@pytest.mark.slow  # compiles the loop (3 s)
def test_events_are_located_as_dop853_locates_them():
    compiled = _compiled(KEPLER, ["r", "theta"], m=1.0, k=1.0)
    params = compiled.parameter_vector({})
    y0 = np.array([1.0, 0.0, 0.1, 1.2])  # off an apsis: none at the start
    apsis = Event(lambda t, y, p: y[2], name="apsis")  # r' = 0: twice an orbit
    stop = Event(lambda t, y, p: y[1] - 20.0, terminal=True, name="turns")  # theta = 20
    grid = np.linspace(0.0, 60.0, 61)
    ours = Taylor(tol=1e-14, backend="numba").solve(
        compiled, (0.0, 60.0), y0, params, t_eval=grid, events=[apsis, stop]
    )
    reference = solve_ivp(
        lambda t, y: compiled.rhs(t, y, params), (0.0, 60.0), y0, method="DOP853",
        rtol=1e-13, atol=1e-13, events=[lambda t, y: y[2], _terminal(lambda t, y: y[1] - 20.0)],
    )  # fmt: skip
    assert ours.status.name == "EVENT"
    found = {record.name: record.times for record in ours.events}
    np.testing.assert_allclose(found["apsis"], reference.t_events[0], rtol=0, atol=1e-9)
    np.testing.assert_allclose(found["turns"], reference.t_events[1], rtol=0, atol=1e-9)
    assert ours.t[-1] == found["turns"][0] and np.all(ours.t[:-1] < ours.t[-1])
    assert abs(ours.y[1, -1] - 20.0) < 1e-9
    every = Taylor(tol=1e-14, backend="numba").solve(
        compiled, (0.0, 60.0), y0, params, events=[apsis, stop]
    )
    assert every.t[-1] == found["turns"][0] and every.t.shape[0] == every.steps + 1


def _terminal(function):
    function.terminal = True
    return function


def _choose(t_end: float, **given):
    settings = {"method": None, "backend": None, "rtol": None, "atol": None, "params": {}}
    settings.update(given)
    eom = lg.load("double_pendulum").equations_of_motion()
    return choose_run(eom, t_end=t_end, initial={"theta1": 2.0, "theta2": 0.5}, **settings)


def test_without_heyoka_method_taylor_is_ours_and_says_so(monkeypatch):
    monkeypatch.setattr(choice_module, "heyoka_installed", lambda: False)
    run = _choose(20.0, method="taylor")
    assert run.method == "taylor"
    assert run.reason == f"taylor (numba) on {run.compiled.backend}: the method asked for"
    taylor = run.integrator(20.0)
    assert taylor.chosen_backend == "numba" and taylor.settings()["backend"] == "numba"


@pytest.mark.slow  # the probe and the numba backend's text for three runs (10 s)
def test_without_heyoka_a_long_smooth_run_takes_ours(monkeypatch):
    monkeypatch.setattr(choice_module, "heyoka_installed", lambda: False)
    monkeypatch.setattr(choice_module, "taylor_compiled_ready", lambda compiled: False)
    run = _choose(1e5)
    assert run.method == "taylor"
    assert run.reason.startswith("taylor (numba, tol 1e-12): about ")
    assert "taylor (numba) ~" in run.reason and "compiled loop ~" in run.reason
    with_events = _choose(1e5, events=(Event(lambda t, y, p: y[0]),))
    assert with_events.method == "taylor"  # located on each step's polynomial
    assert _choose(20.0).method == "dop853"  # too short to pay for a compile


@pytest.mark.slow  # compiles the compact mode's walk (4 s)
def test_the_compact_mode_gives_the_printed_coefficients_and_run(monkeypatch):
    from lagrangian.codegen.cache import load_text, package_text

    walk = load_text(
        *package_text(Path(taylor_compiled.__file__).with_name("numba_taylor_tape.py"))
    )
    y, t = np.array([0.4, -0.3]), 0.6
    for lagrangian, parameters in EVERY_OPERATION:
        compiled = _compiled(lagrangian, ["x"], **parameters)
        params = compiled.parameter_vector({})
        # to the highest order: the printed rows of fixed length (STRIDE) do not overlap
        tape, printed = _python_coefficients(compiled, t, y, params, MAX_ORDER)
        program, exponents = taylor_compiled._program(tape)
        tc = np.zeros((tape.rows, MAX_ORDER + 1))
        tc[:2, 0] = y
        c = taylor_compiled.constant_values(tape, params)
        walk.coefficients(t, c, MAX_ORDER, tc, tc.reshape(-1), program, exponents)
        np.testing.assert_allclose(tc[:2], printed, rtol=1e-12, atol=1e-15)
    compiled = _compiled(KEPLER, ["r", "theta"], m=1.0, k=1.0)
    params, y0 = compiled.parameter_vector({}), np.array([1.0, 0.0, 0.0, 1.2])
    runs = []
    for operations in (10**6, 0):
        monkeypatch.setattr(taylor_compiled, "COMPACT_OPERATIONS", operations)
        runs.append(Taylor(tol=1e-13, backend="numba").solve(compiled, (0.0, 30.0), y0, params))
    assert runs[0].steps == runs[1].steps
    np.testing.assert_allclose(runs[1].y[:, -1], runs[0].y[:, -1], rtol=0, atol=1e-12)


def test_the_tape_keeps_no_dead_operation_nor_a_reciprocal_or_square_as_a_product():
    # the elimination divides by its pivot as a product with 1/pivot, and M[1][0]/M[0][0]
    # times M[0][1] is c x * x: a quotient and a square are cheaper (each a sum of k terms,
    # the square half of one), and the reciprocal, no longer read, is dropped
    compiled = compile_equations(lg.load("double_pendulum").equations_of_motion())
    tape = tape_of(compiled.forms)
    read = {row for op in tape.ops for kind, row in op.args if kind == "s"}
    read |= {row for kind, row in tape.rates if kind == "s"}
    assert all(set(op.rows) & read for op in tape.ops)
    one = next(j for j, entry in enumerate(tape.constants) if entry.number == 1.0)
    assert not [op for op in tape.ops if op.kind == "div" and op.args[0] == ("c", one)]
    made = {op.rows[0]: op for op in tape.ops}
    for op in tape.ops:
        if op.kind == "mul" and all(kind == "s" for kind, _ in op.args):
            for (_, a), b in (op.args, op.args[::-1]):
                inner = made.get(a)
                assert not (inner and inner.kind == "mul" and b in inner.args), op
    assert [op.kind for op in tape.ops].count("square") == 3  # v1^2, v2^2, cos^2


@pytest.mark.slow  # compiles the double pendulum's loop (3 s)
def test_the_command_line_runs_ours_without_heyoka_and_says_so(monkeypatch, capsys):
    import json

    from lagrangian.cli import ExitStatus, main

    monkeypatch.setattr(choice_module, "heyoka_installed", lambda: False)
    monkeypatch.setitem(sys.modules, "heyoka", None)  # an import of it fails, as uninstalled
    arguments = ["simulate", "double_pendulum", "--method", "taylor", "--t-end", "5"]
    assert main([*arguments, "--rtol", "1e-13", "--json"]) == ExitStatus.SUCCESS
    summary = json.loads(capsys.readouterr().out)
    assert summary["method"] == "taylor"
    assert summary["choice"].startswith("taylor (numba) on ")
    assert summary["compiled"] in (
        "the loop of 25 operations, Taylor's method by numba",
        "nothing: 25 operations, Taylor's method by numba from the code cache",
    )
    assert main([*arguments, "--json"]) == ExitStatus.SUCCESS  # again: made in this process
    again = json.loads(capsys.readouterr().out)["compiled"]
    assert again == "nothing: the Taylor loop was made earlier in this process"
    reference = lg.load("double_pendulum").simulate(t_end=5.0, rtol=1e-13, atol=1e-13)
    for name, value in reference.final_state.items():
        assert abs(summary["final_state"][name] - value) < 1e-9


def test_the_help_of_method_says_taylor_runs_without_heyoka(capsys):
    from lagrangian.cli import main

    main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "or taylor: heyoka's where installed, else ours" in text


def test_without_heyoka_the_choice_leaves_ours_out_where_a_function_has_no_recurrence(monkeypatch):
    monkeypatch.setattr(choice_module, "heyoka_installed", lambda: False)
    eom = lg.System.from_lagrangian(
        "x_dot**2/2 - x*atan(x)", coordinates=["x"]
    ).equations_of_motion()
    run = choose_run(
        eom, t_end=1e5, method=None, backend=None, rtol=None, atol=None, initial={"x": 1.0},
        params={},
    )  # fmt: skip
    assert run.method == "dop853"
    assert "; taylor (numba) cannot differentiate atan" in run.reason


def test_the_cost_of_ours_follows_the_measured_paces():
    # benchmarks/taylor_numba.py: 0.3 of the compiled DOP853's time for the double pendulum
    # (0.0132 s for DOP853's 19,446 steps), 3.5 for a 3-link chain and 12 for a 10-link chain
    # in the compact mode
    steps = 1e6
    for n, measured in ((2, 0.3), (3, 3.5), (10, 12.0)):
        pace = choice_module.taylor_numba_seconds(n, steps, True) - 0.7
        relative = pace / (steps * choice_module.compiled_step_seconds(n))
        assert measured / 1.1 < relative < measured * 1.1
