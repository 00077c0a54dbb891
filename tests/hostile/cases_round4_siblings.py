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
