"""Runs given what they cannot use (issue 37): definitions a page did not check, transients
below zero, sections never crossed, states off a holonomic constraint, terms of L in t alone
that are singular at t = 0, names a file cannot hold."""

from hostile.case import HostileCase

# a potential left unspecified: the page then shows the solution only, and used not to read
# the definitions it was given at all
_UNSPECIFIED = """
name = "unspecified"
coordinates = ["x"]
lagrangian = "x_dot^2/2 - V(x) - W(x)"
[functions]
V = ["x"]
W = ["x"]
"""
_NO_CACHE = (("LAGRANGIAN_NO_CACHE", "1"),)

CASES = [
    HostileCase(
        "page-define-of-an-undeclared-function-refused",
        ("page", "{dir}/model.toml", "--define", "U=x", "--out", "{dir}/p.html"),
        error=r"^lagrangian: error: definitions: 'U' is not a declared function "
        r"\(declared: V, W\)$",
        model=_UNSPECIFIED,
        env=_NO_CACHE,
    ),
    HostileCase(
        "page-define-of-a-name-that-is-no-name-refused",
        ("page", "{dir}/model.toml", "--define", "<b>=x", "--out", "{dir}/p.html"),
        error=r"definitions: '<b>' is not a declared function",
        model=_UNSPECIFIED,
        env=_NO_CACHE,
    ),
    HostileCase(
        # V defined with text the parser refuses, W left out: the page used to show the
        # solution only, as if no definition had been given
        "page-define-unreadable-while-another-function-is-unspecified-refused",
        ("page", "{dir}/model.toml", "--define", "V=x**", "--out", "{dir}/p.html"),
        error=r"definitions\.V",
        model=_UNSPECIFIED,
        env=_NO_CACHE,
    ),
]

# --transient: poincare integrated backwards from a negative one and raised ValueError for
# nan; lyapunov and bifurcation refused both, now all three say the same
CASES += [
    HostileCase(
        f"{command.replace(' ', '-')}-transient-{label}-refused",
        (command.split()[0], "harmonic_oscillator", *where, f"--transient={value}"),
        error=rf"^lagrangian: error: the transient must be a time >= 0, not {label}$",
    )
    for command, where in (
        ("poincare section", ("--axes", "x,x_dot", "--section", "x=0")),
        ("poincare strobe", ("--axes", "x,x_dot", "--strobe", "1")),
        ("lyapunov", ()),
        ("bifurcation", ("--vary", "k=1:2:3", "--axis", "x", "--strobe", "1")),
    )
    for label, value in (("-100", "-100"), ("nan", "nan"))
]

# a section never crossed: "0 points", an empty CSV and an empty picture, and nothing said
CASES += [
    HostileCase(
        "poincare-section-never-crossed-said-and-not-drawn",
        ("poincare", "harmonic_oscillator", "--axes", "x,x_dot", "--section", "x=5",
         "--out", "{dir}/s.csv", "--plot", "{dir}/s.png"),
        exit_code=0,
        output=r"0 points",
        warning=r"the orbit does not cross the section x=5 \(direction \+\) up to t = 20: no "
        r"points\nlagrangian: warning: no points to draw: \S+s\.png was not written",
    ),
    HostileCase(
        "bifurcation-section-never-crossed-said-and-not-drawn",
        ("bifurcation", "harmonic_oscillator", "--vary", "k=1:2:2", "--axis", "x", "--section",
         "x=5", "--t-end", "5", "--out", "{dir}/b.csv", "--plot", "{dir}/b.png"),
        exit_code=0,
        warning=r"for none of the 2 values of k between t = 0 and 5: no points\n"
        r"lagrangian: warning: no points to draw: \S+b\.png was not written",
    ),
]  # fmt: skip

# terms of L in t alone that are singular at t = 0: exit 1 (ZeroDivisionError) for 1/t, the
# energy "changed by nan" for log(t); they move nothing, so the run and its energy ignore them
CASES += [
    HostileCase(
        f"simulate-time-only-term-{label}-{method}-ignored",
        ("simulate", "--lagrangian", f"x_dot^2/2 + {term}", "--coordinates", "x",
         "--set", "x_dot=1", "--t-end", "1", "--method", method),
        exit_code=0,
        output=r"drift along the run[^\n]*\n  energy: 0\.000e\+00",
    )
    for label, term in (("1-over-t", "1/t"), ("log-t", "log(t)"))
    for method in ("dop853", "rk4")
] + [
    HostileCase(
        # x/t reaches the equations (x'' = 1/t): a failed run, not ZeroDivisionError (exit 1)
        f"simulate-singular-term-in-the-equations-at-t0-{method}",
        ("simulate", "--lagrangian", "x_dot^2/2 + x/t", "--coordinates", "x", "--t-end", "1",
         "--method", method),
        error=r"the right-hand side is not finite at t = 0 \(x = 0, x_dot = 0\)",
    )
    for method in ("dop853", "rk4")
]  # fmt: skip

# initial states off a holonomic constraint: x = y = 0 raised LinAlgError (exit 1) with every
# method and backend; x = 0.5, y = 0 was moved to x = 1 with nothing said
_SINGULAR_START = (
    r"the initial state{} \(x = 0, y = 0, x_dot = 0, y_dot = 0\) cannot be moved onto the "
    r"constraints: it is a singular point of theirs"
)
CASES += [
    *(
        HostileCase(
            f"simulate-start-at-a-singular-point-of-the-constraint-{'-'.join(how)}",
            ("simulate", "cartesian_pendulum", "--set", "x=0", "--set", "y=0", "--t-end", "0.1",
             *how),
            error=_SINGULAR_START.format(""),
        )
        for how in (("--method", "dop853"), ("--method", "rk4"), ("--backend", "numba"))
    ),
    HostileCase(
        "ensemble-start-at-a-singular-point-of-the-constraint",
        ("ensemble", "cartesian_pendulum", "--grid", "x=1:0:2", "--set", "y=0", "--t-end",
         "0.01"),
        error=_SINGULAR_START.format(" of motion 1"),
    ),
    HostileCase(
        "poincare-start-at-a-singular-point-of-the-constraint",
        ("poincare", "cartesian_pendulum", "--axes", "x,x_dot", "--section", "x=0", "--set",
         "x=0", "--set", "y=0", "--t-end", "1"),
        error=_SINGULAR_START.format(""),
    ),
    HostileCase(
        "simulate-start-off-the-constraint-moved-and-said",
        ("simulate", "cartesian_pendulum", "--set", "x=0.5", "--set", "y=0", "--t-end", "0.1"),
        exit_code=0,
        warning=r"the initial state was moved onto the constraints \(values changed by up to "
        r"0\.5\): x 0\.5 -> 1; give a state on the constraints to start from it",
    ),
]  # fmt: skip

# the sibling in plot: a trajectory's Poincaré section with no crossing was written with
# nothing said (its title says so, a script does not read it)
CASES += [
    HostileCase(
        "plot-poincare-of-a-run-at-rest-said",
        ("plot", "henon_heiles", "--kind", "poincare", "--set", "x=0", "--set", "y=0",
         "--set", "x_dot=0", "--set", "y_dot=0", "--t-end", "5", "--out", "{dir}/p.png"),
        exit_code=0,
        warning=r"the run does not cross the section x = 0 upwards: the Poincaré section has "
        r"no points",
    ),
]  # fmt: skip
