"""Linkages in motion: the built-in four-bar and slider-crank against closed-form
kinematics, an independent one-coordinate derivation and Newton-Euler on each link."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy

import lagrangian as lg

G = 9.81

pytestmark = pytest.mark.slow  # each derives a linkage (1-2 s of CPU) and runs it


@pytest.fixture(scope="module")
def driven():
    system = lg.load("four_bar_driven")
    return system, system.simulate(t_end=1.5, n_out=61)


@pytest.fixture(scope="module")
def free():
    system = lg.load("four_bar")
    return system, system.simulate(t_end=2.0, n_out=81)


@pytest.fixture(scope="module")
def slider():
    system = lg.load("slider_crank")
    return system, system.simulate(t_end=1.0, n_out=81)


def values(system) -> dict[str, float]:
    return {p.name: p.default for p in system.parameters}


def four_bar_closed_form(p, crank, above):
    """Coupler and rocker angles at a crank angle: C where the circles about B (radius b)
    and D (radius c) meet, on the side of BD that ``above`` says (Freudenstein's loop)."""
    bx, by = p["a"] * np.cos(crank), p["a"] * np.sin(crank)
    ex, ey = p["d"] - bx, -by
    e = np.hypot(ex, ey)
    ux, uy = ex / e, ey / e
    along = (p["b"] ** 2 - p["c"] ** 2 + e**2) / (2 * e)
    h = np.sqrt(p["b"] ** 2 - along**2) * (1 if above else -1)
    cx, cy = bx + along * ux - h * uy, by + along * uy + h * ux
    return np.arctan2(cy - by, cx - bx), np.arctan2(cy, cx - p["d"])


def same_angle(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


def test_driven_four_bar_follows_its_closed_form_kinematics(driven):
    system, run = driven
    p = values(system)
    crank = run["theta_crank"]
    assert np.max(np.abs(crank - (p["theta0"] + p["omega"] * run.t))) < 1e-9
    coupler, rocker = four_bar_closed_form(p, crank, above=True)
    assert np.max(same_angle(run["theta_coupler"], coupler)) < 1e-9
    assert np.max(same_angle(run["theta_rocker"], rocker)) < 1e-9


def four_bar_residual(p, run):
    a, b, c, d = p["a"], p["b"], p["c"], p["d"]
    t1, t2, t3 = run["theta_crank"], run["theta_coupler"], run["theta_rocker"]
    return np.hypot(
        a * np.cos(t1) + b * np.cos(t2) - d - c * np.cos(t3),
        a * np.sin(t1) + b * np.sin(t2) - c * np.sin(t3),
    )


def test_loops_stay_closed_along_the_runs(driven, free, slider):
    for system, run in (driven, free):
        assert np.max(four_bar_residual(values(system), run)) < 1e-10
    system, run = slider
    p = values(system)
    theta, phi = run["theta"], run["phi"]
    gap = np.hypot(
        p["r"] * np.cos(theta) + p["l"] * np.cos(phi) - run["x"],
        p["r"] * np.sin(theta) + p["l"] * np.sin(phi),
    )
    assert np.max(gap) < 1e-10


def test_slider_crank_piston_follows_the_crank(slider):
    system, run = slider
    p = values(system)
    theta = run["theta"]
    expected = p["r"] * np.cos(theta) + np.sqrt(p["l"] ** 2 - p["r"] ** 2 * np.sin(theta) ** 2)
    assert np.max(np.abs(run["x"] - expected)) < 1e-9
    assert np.ptp(theta) > 2 * math.pi  # the flywheel turns


def influence(p, crank):
    """d(coupler)/d(crank), d(rocker)/d(crank) from the differentiated loop (Cramer)."""
    coupler, rocker = four_bar_closed_form(p, crank, above=True)
    a, b, c = p["a"], p["b"], p["c"]
    # a s1 + b s2 k2 = c s3 k3 ; a c1 + b c2 k2 = c c3 k3 (s = sin, c = cos, k = rates)
    m = np.array(
        [[-b * np.sin(coupler), c * np.sin(rocker)], [b * np.cos(coupler), -c * np.cos(rocker)]]
    )
    rhs = np.array([a * np.sin(crank), -a * np.cos(crank)])
    return coupler, rocker, np.linalg.solve(m, rhs)


def reduced_energy(p, crank, rate):
    """E = J(crank) rate^2 / 2 + V(crank) of the free four-bar in one coordinate."""
    a, b, c = p["a"], p["b"], p["c"]
    m1, m2, m3 = p["m_crank"], p["m_coupler"], p["m_rocker"]
    coupler, rocker, (k2, k3) = influence(p, crank)
    # centre velocities per unit crank rate
    v1 = a / 2 * np.array([-np.sin(crank), np.cos(crank)])
    v2 = a * np.array([-np.sin(crank), np.cos(crank)]) + k2 * b / 2 * np.array(
        [-np.sin(coupler), np.cos(coupler)]
    )
    v3 = k3 * c / 2 * np.array([-np.sin(rocker), np.cos(rocker)])
    inertia = m1 * v1 @ v1 + m2 * v2 @ v2 + m3 * v3 @ v3
    inertia += m1 * a**2 / 12 + m2 * b**2 / 12 * k2**2 + m3 * c**2 / 12 * k3**2
    heights = (
        m1 * a / 2 * np.sin(crank)
        + m2 * (a * np.sin(crank) + b / 2 * np.sin(coupler))
        + m3 * c / 2 * np.sin(rocker)
    )
    return inertia * rate**2 / 2 + G * heights, (k2, k3)


def test_free_four_bar_matches_a_one_coordinate_derivation(free):
    """A 1-DOF conservative motion is fixed by E(theta, theta') = const, with E from the
    loop solved in closed form: the run keeps that E and the dependent rates it implies."""
    system, run = free
    p = values(system)
    energies = []
    for k in range(run.t.shape[0]):
        crank, rate = run["theta_crank"][k], run["theta_crank_dot"][k]
        energy, (k2, k3) = reduced_energy(p, crank, rate)
        energies.append(energy)
        assert run["theta_coupler_dot"][k] == pytest.approx(k2 * rate, abs=1e-9)
        assert run["theta_rocker_dot"][k] == pytest.approx(k3 * rate, abs=1e-9)
    assert np.ptp(energies) < 1e-9 * max(abs(energies[0]), 1.0)
    assert np.ptp(run["theta_crank_dot"]) > 1.0  # gravity speeds and slows the crank


def test_free_four_bar_accelerations_match_the_reduced_equation(free):
    """J theta'' + J'(theta) theta'^2 / 2 + V'(theta) = 0 at states of the run."""
    system, run = free
    p = values(system)
    eom = system.equations_of_motion()
    names = ["theta_crank", "theta_coupler", "theta_rocker"]
    symbols = [sympy.Symbol(n, real=True) for n in names]
    rates = [sympy.Symbol(f"{n}_dot", real=True) for n in names]
    by_name = {s.name: s for s in eom.accelerations["theta_crank"].free_symbols}
    arguments = [by_name.get(s.name, s) for s in [*symbols, *rates]]
    values_ = {by_name[n]: v for n, v in p.items() if n in by_name}
    acceleration = sympy.lambdify(arguments, eom.accelerations["theta_crank"].subs(values_))
    h = 1e-5
    for k in (5, 30, 60):
        state = [run[n][k] for n in names] + [run[f"{n}_dot"][k] for n in names]
        crank, rate = state[0], state[3]

        def inertia_and_height(x):
            energy_one, _ = reduced_energy(p, x, 1.0)
            height, _ = reduced_energy(p, x, 0.0)
            return 2 * (energy_one - height), height

        j, _ = inertia_and_height(crank)
        dj = (inertia_and_height(crank + h)[0] - inertia_and_height(crank - h)[0]) / (2 * h)
        dv = (inertia_and_height(crank + h)[1] - inertia_and_height(crank - h)[1]) / (2 * h)
        expected = -(dj * rate**2 / 2 + dv) / j
        assert acceleration(*state) == pytest.approx(expected, rel=1e-6, abs=1e-6)


def newton_euler(p, q, rates, accelerations, driven):
    """Joint forces (on the second side from the first) and the drive torque by
    Newton-Euler on the three links: 9 equations, solved by least squares."""
    a, b, c, d = p["a"], p["b"], p["c"], p["d"]
    masses = [p["m_crank"], p["m_coupler"], p["m_rocker"]]
    lengths = [a, b, c]
    angles, w, alpha = q, rates, accelerations
    u = [np.array([np.cos(x), np.sin(x)]) for x in angles]
    n = [np.array([-np.sin(x), np.cos(x)]) for x in angles]
    A, B = np.zeros(2), a * u[0]
    C, D = B + b * u[1], np.array([d, 0.0])
    centres = [A + a / 2 * u[0], B + b / 2 * u[1], D + c / 2 * u[2]]
    acc = [
        a / 2 * (alpha[0] * n[0] - w[0] ** 2 * u[0]),
        a * (alpha[0] * n[0] - w[0] ** 2 * u[0]) + b / 2 * (alpha[1] * n[1] - w[1] ** 2 * u[1]),
        c / 2 * (alpha[2] * n[2] - w[2] ** 2 * u[2]),
    ]

    def cross(r, column):  # moment of a unit force along a column
        return r[0] * column[1] - r[1] * column[0]

    # unknowns: R_A (2), R_B (2), R_C (2), R_D (2), tau
    rows, rhs = [], []
    # link, [(unknown index, sign, point)]
    acting = [
        (0, [(0, 1, A), (2, -1, B)]),
        (1, [(2, 1, B), (4, -1, C)]),
        (2, [(4, 1, C), (6, 1, D)]),
    ]
    for link, forces in acting:
        m, centre = masses[link], centres[link]
        inertia = m * lengths[link] ** 2 / 12
        for axis in range(2):
            row = np.zeros(9)
            for index, sign, _ in forces:
                row[index + axis] = sign
            rows.append(row)
            rhs.append(m * acc[link][axis] + (m * G if axis == 1 else 0.0))
        row = np.zeros(9)
        for index, sign, point in forces:
            for axis in range(2):
                unit = np.eye(2)[axis]
                row[index + axis] += sign * cross(point - centre, unit)
        if link == 0:
            row[8] = 1.0
        rows.append(row)
        rhs.append(inertia * alpha[link])
    matrix = np.array(rows)
    if not driven:
        matrix = matrix[:, :8]
    solution, *_ = np.linalg.lstsq(matrix, np.array(rhs), rcond=None)
    assert np.max(np.abs(matrix @ solution - np.array(rhs))) < 1e-8  # consistent
    return solution


@pytest.mark.parametrize("which", ["driven", "free"])
def test_joint_reactions_match_newton_euler_on_each_link(which, driven, free):
    system, run = driven if which == "driven" else free
    p = values(system)
    eom = system.equations_of_motion()
    names = ["theta_crank", "theta_coupler", "theta_rocker"]
    accelerations = [eom.accelerations[n] for n in names]
    found = {s.name: s for e in accelerations for s in e.free_symbols}
    arguments = [found.get(n, sympy.Symbol(n)) for n in ["t", *names, *(f"{n}_dot" for n in names)]]
    numbers = {found[n]: v for n, v in p.items() if n in found}
    function = sympy.lambdify(arguments, [e.subs(numbers) for e in accelerations])
    assert set(run.reactions) >= {"R_A_x", "R_A_y", "R_B_x", "R_B_y", "R_C_x", "R_D_y"}
    for k in (3, 20, 45):
        q = [run[n][k] for n in names]
        w = [run[f"{n}_dot"][k] for n in names]
        alpha = function(run.t[k], *q, *w)
        expected = newton_euler(p, q, w, alpha, driven=which == "driven")
        for j, joint in enumerate("ABCD"):
            got = [run[f"R_{joint}_x"][k], run[f"R_{joint}_y"][k]]
            assert got == pytest.approx(expected[2 * j : 2 * j + 2], rel=1e-7, abs=1e-7)
        if which == "driven":
            assert run["tau_A"][k] == pytest.approx(expected[8], rel=1e-7, abs=1e-7)


def test_slider_crank_reactions_match_newton_euler(slider):
    """The prismatic joint P (a tree joint, cut along its normal and in angle) and the
    revolute ones against Newton-Euler on the crank, the rod and the piston."""
    system, run = slider
    p = values(system)
    eom = system.equations_of_motion()
    names = ["theta", "x", "phi"]
    accelerations = [eom.accelerations[n] for n in names]
    found = {s.name: s for e in accelerations for s in e.free_symbols}
    arguments = [found.get(n, sympy.Symbol(n)) for n in ["t", *names, *(f"{n}_dot" for n in names)]]
    numbers = {found[n]: v for n, v in p.items() if n in found}
    function = sympy.lambdify(arguments, [e.subs(numbers) for e in accelerations])
    r, rod, g = p["r"], p["l"], G
    for k in (5, 40, 70):
        theta, x, phi = (run[n][k] for n in names)
        w_theta, w_x, w_phi = (run[f"{n}_dot"][k] for n in names)
        a_theta, a_x, a_phi = function(run.t[k], theta, x, phi, w_theta, w_x, w_phi)
        u, n = np.array([np.cos(phi), np.sin(phi)]), np.array([-np.sin(phi), np.cos(phi)])
        A = r * np.array([np.cos(theta), np.sin(theta)])
        B = np.array([x, 0.0])
        centre = A + rod / 2 * u
        a_rod = r * (a_theta * np.array([-np.sin(theta), np.cos(theta)])
                     - w_theta**2 * np.array([np.cos(theta), np.sin(theta)]))  # fmt: skip
        a_rod = a_rod + rod / 2 * (a_phi * n - w_phi**2 * u)

        def cross(v, w):
            return v[0] * w[1] - v[1] * w[0]

        # unknowns: R_O (0, 1), R_A (2, 3), R_B (4, 5), N (6), M (7)
        rows, rhs = [], []
        m_c, m_r, m_p = p["m_crank"], p["m_rod"], p["m_piston"]
        for axis in range(2):  # the crank: centre of mass at the pivot O, at rest
            row = np.zeros(8)
            row[0 + axis], row[2 + axis] = 1, -1
            rows.append(row), rhs.append(m_c * g * (axis == 1))
        row = np.zeros(8)
        row[2], row[3] = -cross(A, [1, 0]), -cross(A, [0, 1])
        rows.append(row), rhs.append(p["I_flywheel"] * a_theta)
        for axis in range(2):  # the rod
            row = np.zeros(8)
            row[2 + axis], row[4 + axis] = 1, -1
            rows.append(row), rhs.append(m_r * a_rod[axis] + m_r * g * (axis == 1))
        row = np.zeros(8)
        row[2], row[3] = cross(A - centre, [1, 0]), cross(A - centre, [0, 1])
        row[4], row[5] = -cross(B - centre, [1, 0]), -cross(B - centre, [0, 1])
        rows.append(row), rhs.append(m_r * rod**2 / 12 * a_phi)
        for axis in range(2):  # the piston: at B, sliding along x, not turning
            row = np.zeros(8)
            row[4 + axis] = 1
            row[6] = 1.0 * (axis == 1)
            rows.append(row), rhs.append(m_p * a_x * (axis == 0) + m_p * g * (axis == 1))
        row = np.zeros(8)
        row[7] = 1.0
        rows.append(row), rhs.append(0.0)
        matrix, rhs = np.array(rows), np.array(rhs)
        solution, *_ = np.linalg.lstsq(matrix, rhs, rcond=None)
        assert np.max(np.abs(matrix @ solution - rhs)) < 1e-8
        got = [run[c][k] for c in ("R_O_x", "R_O_y", "R_A_x", "R_A_y", "R_B_x", "R_B_y")]
        assert got == pytest.approx(solution[:6], rel=1e-7, abs=1e-7)
        assert run["R_P_x"][k] == pytest.approx(0.0, abs=1e-7)
        assert run["R_P_y"][k] == pytest.approx(solution[6], rel=1e-7, abs=1e-7)
        assert run["M_P"][k] == pytest.approx(solution[7], abs=1e-7)


def test_reactions_reach_the_files_and_the_summary(driven, tmp_path):
    _, run = driven
    summary = run.summary()["reactions"]
    assert summary["tau_A"]["final"] == run["tau_A"][-1]
    assert summary["R_C_y"]["max_abs"] == np.max(np.abs(run["R_C_y"]))
    header = run.to_csv(tmp_path / "run.csv").read_text().splitlines()[0].split(",")
    assert header[-9:] == [
        "R_A_x", "R_A_y", "tau_A", "R_B_x", "R_B_y", "R_D_x", "R_D_y", "R_C_x", "R_C_y"
    ]  # fmt: skip
    back = lg.Trajectory.load(run.to_netcdf(tmp_path / "run.nc"))
    assert back.reactions == run.reactions
    assert np.array_equal(back["R_B_x"], run["R_B_x"])


def test_derive_says_the_count_the_loops_and_the_reactions(free, driven):
    from lagrangian.output.json_out import derive_document
    from lagrangian.output.text import format_equations

    system, _ = driven
    text = format_equations(system.equations_of_motion())
    assert text.splitlines()[-5:] == [
        "Linkage:",
        "  3 links, 4 joints: 1 degree of freedom (Grübler: 3 x 3 - 2 x 4)",
        "  held at assembly: none (driven)",
        "  joint A is driven: omega*t + theta0 (lambda1)",
        "  joint C closes a loop (lambda2, lambda3)",
    ]
    system, _ = free
    document = derive_document(system.equations_of_motion())["linkage"]
    assert document["degrees_of_freedom"] == 1 and document["held"] == ["theta_crank"]
    assert document["joints"]["C"] == {
        "kind": "revolute",
        "connects": ["coupler.end", "rocker.end"],
        "closes_loop": True,
        "multipliers": ["lambda1", "lambda2"],
    }
    assert document["reactions"]["R_C_x"] == "lambda1"
    names = {s.name: s for s in system.linkage.reactions["R_B_y"].free_symbols}
    back = sympy.parse_expr(document["reactions"]["R_B_y"], local_dict=names | {
        "lambda2": sympy.Symbol("lambda2")})  # fmt: skip
    placeholder = system.linkage.multipliers[1]
    expected = system.linkage.reactions["R_B_y"].xreplace({placeholder: sympy.Symbol("lambda2")})
    assert sympy.simplify(back - expected) == 0


def test_a_slot_on_a_turning_link_transmits_what_newton_euler_says():
    """Whitworth's quick return under gravity (tests/model/test_linkages.py): the block's
    slot is a prismatic tree joint on the turning rocker, its reaction the normal force
    N n and the moment M on the block; checked with the pin's and pivots' against
    Newton-Euler on crank, rocker and block."""
    from model.test_linkages import QUICK_RETURN

    system = lg.loads(QUICK_RETURN + '[gravity]\ng = 9.81\n[initial]\ntheta = 0.4\nphi = 1.2\n'
                      's = 0.7\ntheta_dot = 3.0\n')  # fmt: skip
    run = system.simulate(t_end=1.0, n_out=21)
    eom = system.equations_of_motion()
    names = ["theta", "phi", "s"]
    found = {s.name: s for n in names for s in eom.accelerations[n].free_symbols}
    arguments = [found.get(n, sympy.Symbol(n)) for n in [*names, *(f"{n}_dot" for n in names)]]
    numbers = {
        found[k]: v for k, v in {"r": 0.3, "h": 0.5, "L": 1.2, "m": 1.0}.items() if k in found
    }
    numbers |= {found["g"]: G} if "g" in found else {}
    function = sympy.lambdify(arguments, [eom.accelerations[n].subs(numbers) for n in names])
    r, h, L, m, w = 0.3, 0.5, 1.2, 1.0, 0.1

    def cross(v, f):
        return v[0] * f[1] - v[1] * f[0]

    for k in (2, 10, 18):
        theta, phi, s = (run[n][k] for n in names)
        wt, wp, ws = (run[f"{n}_dot"][k] for n in names)
        at, ap, as_ = function(theta, phi, s, wt, wp, ws)
        e = np.array([np.cos(theta), np.sin(theta)])
        et = np.array([-np.sin(theta), np.cos(theta)])
        u, n = np.array([np.cos(phi), np.sin(phi)]), np.array([-np.sin(phi), np.cos(phi)])
        O, Q = np.zeros(2), np.array([0.0, -h])
        P = Q + s * u
        c1, c2, c3 = r / 2 * e, Q + L / 2 * u, P + w / 2 * u
        a1 = r / 2 * (at * et - wt**2 * e)
        a2 = L / 2 * (ap * n - wp**2 * u)
        a3 = as_ * u + 2 * ws * wp * n + (s + w / 2) * (ap * n - wp**2 * u)
        # unknowns: R_O (0, 1), R_Q (2, 3), R_pin (4, 5) on the block, N (6), M (7)
        rows, rhs = [], []

        def force_rows(terms, mass_acc, rows=rows, rhs=rhs):
            for axis in range(2):
                row = np.zeros(8)
                for index, sign, direction in terms:
                    row[index] += sign * (direction[axis] if direction is not None else 0)
                    if direction is None:
                        row[index + axis] += sign
                rows.append(row)
                rhs.append(mass_acc[axis] + (m * G if axis == 1 else 0.0))

        force_rows([(0, 1, None), (4, -1, None)], m * a1)
        force_rows([(2, 1, None), (6, -1, n)], m * a2)
        force_rows([(4, 1, None), (6, 1, n)], m * a3)
        moments = [
            ({0: cross(O - c1, [1, 0]), 1: cross(O - c1, [0, 1]),
              4: -cross(P - c1, [1, 0]), 5: -cross(P - c1, [0, 1])}, m * r**2 / 12 * at),
            ({2: cross(Q - c2, [1, 0]), 3: cross(Q - c2, [0, 1]),
              6: -cross(P - c2, n), 7: -1.0}, m * L**2 / 12 * ap),
            ({4: cross(P - c3, [1, 0]), 5: cross(P - c3, [0, 1]),
              6: cross(P - c3, n), 7: 1.0}, m * w**2 / 12 * ap),
        ]  # fmt: skip
        for entries, value in moments:
            row = np.zeros(8)
            for index, coefficient in entries.items():
                row[index] += coefficient
            rows.append(row)
            rhs.append(value)
        matrix, rhs = np.array(rows), np.array(rhs)
        solution, *_ = np.linalg.lstsq(matrix, rhs, rcond=None)
        assert np.max(np.abs(matrix @ solution - rhs)) < 1e-8
        got = [run[c][k] for c in ("R_joint1_x", "R_joint1_y", "R_joint2_x", "R_joint2_y",
                                   "R_pin_x", "R_pin_y")]  # fmt: skip
        assert got == pytest.approx(solution[:6], rel=1e-7, abs=1e-7)
        slot = [run["R_slot_x"][k], run["R_slot_y"][k]]
        assert slot == pytest.approx(solution[6] * n, rel=1e-7, abs=1e-7)
        assert run["M_slot"][k] == pytest.approx(solution[7], rel=1e-7, abs=1e-7)
