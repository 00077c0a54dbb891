"""Siblings of issue 37's items, found while fixing it: the same defect in the next command
or the next kind of input (plot and animate beside simulate's memory check, a mass matrix
beside the ones the float rank judged, a particle's field beside the Lagrangian's)."""

from hostile.case import HostileCase
from hostile.cases_round4_budget import COORDINATE_LIST, POSITION_POWER

SUM = " + ".join(f"q{i}" for i in range(20))
TOO_LARGE = r"expanded, it makes more than 2,000,000 terms .*too large to derive"

# The refusal of a model built from parts named "lagrangian:", a field the user never wrote.
BODY_ANGLE_POWER = f"""coordinates = [{COORDINATE_LIST}]

[[bodies]]
name = "plate"
mass = "1"
inertia = "1"
center = ["q0", "q1"]
angle = "({SUM})^20"
"""
SECOND_PARTICLE_POWER = f"""coordinates = [{COORDINATE_LIST}]

[[particles]]
name = "a"
mass = "1"
position = ["q0", "0"]

[[particles]]
name = "b"
mass = "1"
position = ["q1", "({SUM})^6"]
"""

# M = I + 3540 s^58 J is positive definite; floats read its rank as 1 (condition ~1e41).
HUGE_RANK_ONE = 'coordinates = ["x", "y", "z"]\n' + (
    'lagrangian = "(x_dot^2 + y_dot^2 + z_dot^2)/2 + (x_dot + y_dot + z_dot)^60"\n'
)
TRULY_SINGULAR = 'coordinates = ["x", "y"]\nlagrangian = "(x_dot + y_dot)^2/2"\n'

CASES = [
    *(
        HostileCase(
            f"{command}-particle-position-too-large-names-the-particle",
            (command, "{dir}/model.toml", *extra),
            error=r"particles\[0\]\.position\[0\]: " + TOO_LARGE,
            model=POSITION_POWER,
        )
        for command, extra in [
            ("analyze", ()),
            ("simulate", ("--t-end", "1")),
            ("page", ("--out", "{dir}/page.html", "--no-cache")),
        ]
    ),
    HostileCase(
        "derive-second-particle-too-large-names-it",
        ("derive", "{dir}/model.toml"),
        error=r"particles\[1\]\.position\[1\]: " + TOO_LARGE,
        model=SECOND_PARTICLE_POWER,
    ),
    HostileCase(
        "derive-body-angle-too-large-names-the-body",
        ("derive", "{dir}/model.toml"),
        error=r"bodies\[0\]\.angle: " + TOO_LARGE,
        model=BODY_ANGLE_POWER,
    ),
    HostileCase(
        "derive-identity-plus-huge-rank-one-is-regular",
        ("derive", "{dir}/model.toml"),
        exit_code=0,
        output=r"Accelerations:",
        model=HUGE_RANK_ONE,
        slow=True,
    ),
    HostileCase(
        "derive-truly-singular-keeps-its-message",
        ("derive", "{dir}/model.toml"),
        error=r"model\.toml: singular mass matrix \(rank 1 of 2\): the velocities of x, y "
        r"enter the Lagrangian only in a combination; use fewer coordinates$",
        model=TRULY_SINGULAR,
    ),
]

# An adaptive run keeps every step unless told output times; how many it takes is known
# only as it goes (plot henon_heiles --t-end 1e7 grew to 7.8 GB in 2 minutes).  The loop
# projects them from its pace after 8,192 steps and refuses what cannot fit; --samples
# (new on plot and animate) keeps only the outputs, and the run then keeps its --timeout.
# t_end = 1e9: about 5e9 steps, 1,700 GB, more than any machine has.  The method is the
# default's choice: taylor where heyoka is installed (its steps are kept from heyoka's
# continuous output at 0.3 us a step since issue 36), dop853 elsewhere.
KEPT = (
    r"(dop853|taylor) to t_end = 1e\+09 keeping every step \(about [\d,]+ at the pace so far\) "
    r"needs about [\d,.e+]+ GB of memory, more than the [\d,.]+ GB available[^:]*: "
)
PLOT_ADVICE = r"give --samples N \(N output times\) or a shorter --t-end$"
CASES += [
    *(
        HostileCase(
            f"plot-{kind}-t-end-1e9-refused-before-it-fills-memory",
            ("plot", "henon_heiles", "--kind", kind, "--t-end", "1e9", "--out", "{dir}/a.png"),
            error=KEPT + PLOT_ADVICE,
        )
        for kind in ("timeseries", "phase", "energy", "poincare")
    ),
    HostileCase(
        "animate-t-end-1e9-refused-before-it-fills-memory",
        ("animate", "henon_heiles", "--t-end", "1e9", "--out", "{dir}/a.gif"),
        error=KEPT + PLOT_ADVICE,
    ),
    HostileCase(
        "simulate-t-end-1e9-every-step-refused-before-it-fills-memory",
        ("simulate", "henon_heiles", "--t-end", "1e9"),
        error=KEPT + r"give --samples N \(N output times\), a shorter --t-end "
        r"or a looser --rtol$",
    ),
    HostileCase(
        "plot-samples-t-end-1e9-keeps-its-timeout",
        (
            "plot",
            "henon_heiles",
            "--t-end",
            "1e9",
            "--samples",
            "1000",
            "--timeout",
            "1",
            "--out",
            "{dir}/a.png",
        ),
        # ended by its pace (projected) or at its 1 s, whichever a loaded machine reaches first
        error=r"(at its pace so far the run would take about [\d,]+ (minutes|hours|days)"
        r"|the run did not finish within 1 s)",
    ),
    HostileCase(
        "plot-samples-of-a-trajectory-file-is-a-usage-error",
        ("plot", "{dir}/run.csv", "--samples", "100", "--out", "{dir}/a.png"),
        error=r"--t-end, --samples, --method, --set and --define apply to a MODEL, not a file",
        setup=lambda folder: (folder / "run.csv").write_text("t,x,x_dot\n0,1,0\n1,0.5,0.1\n"),
    ),
    HostileCase(
        "plot-samples-draws-the-run-at-those-times",
        ("plot", "harmonic_oscillator", "--samples", "50", "--out", "{dir}/a.png"),
        exit_code=0,
        output=r"wrote .*a\.png",
        slow=True,
    ),
]
