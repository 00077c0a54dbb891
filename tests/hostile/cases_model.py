"""Cases of model files (issue 10, part B): constants that are not real in every kind of field,
model paths that are not regular files, TOML made to be slow or too large, and names that
look like slips for a velocity (a warning where they are parameters, a suggestion where
they are unknown)."""

from __future__ import annotations

import os
import socket
from pathlib import Path

from hostile.case import HostileCase

MODEL = ("derive", "{dir}/model.toml")
HEAD = 'coordinates = ["x"]\n'
PARAMETERS = "\n[parameters]\nm = 1.0\nk = 2.0\n"


def _lagrangian(expression: str) -> str:
    return f'{HEAD}lagrangian = "m*x_dot**2/2 - {expression}"{PARAMETERS}'


def _particle(mass: str = "m", x: str = "x", y: str = "0") -> str:
    return f'[[particles]]\nmass = "{mass}"\nposition = ["{x}", "{y}"]\n'


# -- constants that are not real, or not finite, in each kind of field ------------------------
NOT_REAL = [
    ("lagrangian", _lagrangian("sqrt(-1)*x**2"), r"lagrangian: sqrt\(-1\) is not a real number"),
    (
        "potential",
        f'{HEAD}kinetic = "m*x_dot**2/2"\npotential = "acos(2)*x**2"{PARAMETERS}',
        r"potential: acos\(2\) is not a real number at position 1 in 'acos\(2\)\*x\*\*2'",
    ),
    (
        "position",
        HEAD + PARAMETERS + _particle(y="atan2(acos(2), acos(2))"),
        r"particles\[0\]\.position\[1\]: acos\(2\) is not a real number",
    ),
    (
        "mass",
        HEAD + PARAMETERS + _particle(mass="m*log(-1)"),
        r"particles\[0\]\.mass: log\(-1\) is not a real number",
    ),
    (
        "force",
        _lagrangian("k*x**2/2") + '[forces]\nx = "-(-1)^(1/2)*x_dot"\n',
        r"forces\.x: \(-1\)\*\*\(1/2\) is not a real number",
    ),
    (
        "dissipation",
        f'{HEAD}dissipation = "asin(3)*x_dot**2"\n' + _lagrangian("k*x**2/2").removeprefix(HEAD),
        r"dissipation: asin\(3\) is not a real number",
    ),
    (
        "constraint",
        'coordinates = ["x", "y"]\nlagrangian = "m*(x_dot**2 + y_dot**2)/2"\n'
        'constraints = ["x_dot - (-8)^(1/3)*y_dot"]' + PARAMETERS,
        r"constraints\[0\]: \(-8\)\*\*\(1/3\) is not a real number",
    ),
    (
        "gravity",
        HEAD + PARAMETERS + _particle() + '[gravity]\ng = "sqrt(-k)"\n',
        r"gravity\.g: sqrt\(-k\) is not a real number",  # k is positive: SymPy's I*sqrt(k)
    ),
    (
        "spring",
        HEAD + PARAMETERS + _particle() + '[[springs]]\nstiffness = "k"\nends = ["particle1", '
        '[0, 0]]\nrest_length = "log(0)"\n',
        r"springs\[0\]\.rest_length: log\(0\) is infinite or undefined",
    ),
    ("division", _lagrangian("k*x**2/(1 - 1)"), r"lagrangian: division by zero"),
]

CASES = [
    HostileCase(f"model-not-real-{field}", MODEL, error=error, model=text)
    for field, text, error in NOT_REAL
]
CASES += [
    HostileCase(
        f"model-not-real-{command}",
        (command, "{dir}/model.toml", *extra),
        error=r"lagrangian: acos\(2\) is not a real number",
        model=_lagrangian("acos(2)*x**2"),
    )
    for command, extra in (("analyze", ()), ("simulate", ("--t-end", "1")))
]


# -- model paths that are not regular files ---------------------------------------------------
def _fifo(folder: Path) -> None:
    os.mkfifo(folder / "model.toml")  # opening it for reading would wait for a writer


def _socket(folder: Path) -> None:
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(folder / "model.toml"))  # the socket file stays after the close


def _folder(folder: Path) -> None:
    (folder / "model.toml").mkdir()


def _link_to_zero(folder: Path) -> None:
    (folder / "model.toml").symlink_to("/dev/zero")


def _sparse(folder: Path) -> None:
    from lagrangian.model.limits import MAX_FILE_BYTES

    with open(folder / "model.toml", "wb") as stream:
        stream.truncate(MAX_FILE_BYTES + 1)  # no disk used; refused by its size, unread


CASES += [
    HostileCase("model-fifo", MODEL, error=r"model\.toml: is a named pipe \(FIFO\)", setup=_fifo),
    HostileCase("model-dev-zero", ("derive", "/dev/zero"), error=r"/dev/zero: is a character"),
    HostileCase("model-link-to-dev-zero", MODEL, error=r"is a character", setup=_link_to_zero),
    HostileCase("model-folder", MODEL, error=r"model\.toml: is a folder", setup=_folder),
    HostileCase("model-socket", MODEL, error=r"model\.toml: is a socket", setup=_socket),
    HostileCase(
        "model-file-over-1-mib",
        MODEL,
        error=r"file too large \(1048577 bytes, limit 1048576 = 1 MiB\)",
        setup=_sparse,
    ),
    HostileCase("model-not-utf8", MODEL, error=r"not UTF-8", model=b'coordinates = ["\xff"]\n'),
]

# -- TOML made to be slow: under the size limit, refused in about a second ------------------
CASES += [
    HostileCase(
        "model-toml-arrays-10000-deep",
        MODEL,
        error=r"invalid TOML: arrays or tables nested too deeply",
        model=HEAD + "a = " + "[" * 10_000 + "]" * 10_000 + "\n",
    ),
    HostileCase(
        "model-toml-inline-tables-5000-deep",
        MODEL,
        error=r"invalid TOML: arrays or tables nested too deeply",
        model=HEAD + "a = " + "{b=" * 5_000 + "1" + "}" * 5_000 + "\n",
    ),
    HostileCase(
        "model-toml-dotted-key-100000-parts",
        MODEL,
        error=r"a dotted key of more than 32 parts \(line 2\)",
        model=HEAD + ".".join(["a"] * 100_000) + " = 1\n",
    ),
    HostileCase(
        "model-toml-100000-keys",
        MODEL,
        error=r"parameters: too many \(100001, limit 1000\)",
        model=_lagrangian("k*x**2/2").replace(
            "m = 1.0", "".join(f"a{i}=1\n" for i in range(100_000))
        ),
    ),
    HostileCase(
        "model-toml-50000-coordinates",
        MODEL,
        error=r"coordinates: too many \(50000, limit 200\)",
        model="coordinates = ["
        + ",".join(f'"q{i}"' for i in range(50_000))
        + ']\nlagrangian = "1"\n',
    ),
    HostileCase(
        "model-toml-5000-particles",
        MODEL,
        error=r"particles: too many \(5000, limit 500\)",
        model=HEAD + PARAMETERS + _particle() * 5_000,
    ),
    HostileCase(
        "model-expressions-too-long-in-all",
        MODEL,
        error=r"expressions too long in all \(\d+ characters in 13 fields, limit 200000",
        model=_lagrangian("k*x**2/2").replace(
            "\n[parameters]",
            "\nconstraints = ["
            + ",".join(['"' + "+".join(["x_dot"] * 3_000) + '"'] * 12)
            + "]\n[parameters]",
        ),
    ),
]

# -- names that look like slips for a velocity -----------------------------------------------
CASES += [
    HostileCase(
        "model-typo-declared-parameter-warns",
        MODEL,
        exit_code=0,
        model=_lagrangian("k*x**2/2") + 'xdot = 1.0\n[forces]\nx = "-k*xdot"\n',  # x_dot meant
        warning=r"lagrangian: warning: .*parameters\.xdot: 'xdot' is declared as a parameter "
        r"\(a constant\); did you mean 'x_dot'\?",
        output=r"k x",
    ),
    HostileCase(
        "model-typo-unknown-velocity-suggested",
        MODEL,
        error=r"lagrangian: unknown symbol 'x_dott' \(did you mean 'x_dot'\?\) at position 3",
        model=_lagrangian("k*x**2/2").replace("m*x_dot", "m*x_dott"),
    ),
    HostileCase(
        "model-typo-unknown-thetadot-suggested",
        MODEL,
        error=r"unknown symbol 'thetadot' \(did you mean 'theta_dot'\?\)",
        model='coordinates = ["theta"]\nlagrangian = "m*thetadot**2/2 + k*cos(theta)"' + PARAMETERS,
    ),
]

# -- masses: > 0 in the file's defaults and in every value given later, whatever the sign ----
PENDULUM = (
    'coordinates = ["x"]\n[parameters]\nm = {m}\n'
    '[[particles]]\nname = "bob"\nmass = "{mass}"\nposition = ["x", "0"]\n'
    '[[bodies]]\nname = "disc"\nmass = "1"\ninertia = "{inertia}"\ncenter = ["x", "0"]\n'
    'angle = "x"\n'
)
CASES += [
    HostileCase(
        f"model-mass-{name}-refused",
        MODEL,
        error=error,
        model=PENDULUM.format(m=m, mass=mass, inertia=inertia),
    )
    for name, m, mass, inertia, error in (
        (
            "negative-default",
            "-1.0",
            "m",
            "1",
            r"model.toml: parameters.m: the mass of 'bob' \(particles\[0\].mass = m\) is -1 "
            r"with m = -1: it must be > 0$",
        ),
        ("zero-default", "0.0", "m", "1", r"parameters.m: the mass of 'bob' .* is 0 with m = 0"),
        (
            "declared-real",
            '{value = -2.0, sign = "real"}',
            "m",
            "1",
            r"parameters.m: the mass of 'bob' .* is -2 with m = -2: it must be > 0$",
        ),
        ("literal", "1.0", "-m", "1", r"parameters.m: the mass of 'bob' \(.* = -m\) is -1 with"),
        ("zero-literal", "1.0", "0", "1", r"model.toml: the mass of 'bob' is 0: it must be > 0$"),
        (
            "planar-inertia",
            "1.0",
            "m",
            "-m/2",
            r"parameters.m: the moment of inertia of .disc. .* is -0.5 with m = 1: it must be >= 0",
        ),
    )
]
CASES += [
    HostileCase(
        f"{argv[0]}-{name}-mass-refused",
        argv,
        error=r"the mass of 'bob' \(particles\[0\].mass = m\) is -1 with m = -1: it must be > 0$",
        model=PENDULUM.format(m='{value = 1.0, sign = "real"}', mass="m", inertia="1"),
    )
    for name, argv in (
        ("set", ("simulate", "{dir}/model.toml", "--t-end", "0.1", "--set", "m=-1")),
        ("grid", ("ensemble", "{dir}/model.toml", "--t-end", "0.1", "--grid", "m=-1:1:3")),
    )
]
