"""Cases of inputs ([inputs]), ``analyze --state-space`` and ``export`` (issue 13): bad and
hostile inputs, operating points and outputs, and output paths and languages of export."""

from __future__ import annotations

from pathlib import Path

from hostile.case import HostileCase

SLIDER = 'coordinates = ["x"]\nkinetic = "m*x_dot**2/2"\npotential = "k*x**2/2"\n'
PARAMETERS = "[parameters]\nm = 1.0\nk = 2.0\n"
DERIVE = ("derive", "{dir}/model.toml")
STATE_SPACE = ("analyze", "{dir}/model.toml", "--state-space")


def _inputs(table: str) -> str:
    return f"{SLIDER}{PARAMETERS}[inputs]\n{table}\n"


def _many_inputs(folder: Path) -> None:
    lines = "\n".join(f'u{i} = "x"' for i in range(50_000))
    (folder / "model.toml").write_text(f"{SLIDER}{PARAMETERS}[inputs]\n{lines}\n")


def _folder_target(folder: Path) -> None:
    (folder / "out.c").mkdir()


VALID = _inputs('F = "x"')

CASES = [
    # -- [inputs] -------------------------------------------------------------------------
    HostileCase(
        "inputs-not-a-coordinate",
        DERIVE,
        r"inputs\.F: 'y' is not a coordinate",
        model=_inputs('F = "y"'),
    ),
    HostileCase(
        "inputs-code-injection",
        DERIVE,
        r"inputs\.F\.x: ",
        model=_inputs("F = {x = \"__import__('os').system('true')\"}"),
    ),
    HostileCase(
        "inputs-force-without-input",
        DERIVE,
        r"does not depend on the input 'F'",
        model=_inputs('F = {x = "k*x"}'),
    ),
    HostileCase(
        "inputs-in-the-potential",
        DERIVE,
        r"potential: the input 'F' may appear only",
        model=_inputs('F = "x"').replace('"k*x**2/2"', '"F*x"'),
    ),
    HostileCase(
        "inputs-wrong-type",
        DERIVE,
        r"inputs\.F: expected the name of a coordinate",
        model=_inputs("F = [1, 2]"),
    ),
    HostileCase(
        "inputs-50000", DERIVE, r"inputs: too many \(50000, limit 200\)", setup=_many_inputs
    ),
    HostileCase(
        "inputs-huge-exponent", DERIVE, r"inputs\.F\.x: ", model=_inputs('F = {x = "F*10**10**10"}')
    ),
    HostileCase(
        "inputs-not-real-constant",
        DERIVE,
        r"inputs\.F\.x: sqrt\(-1\) is not a real",
        model=_inputs('F = {x = "F*sqrt(-1)"}'),
    ),
    # -- analyze --state-space ------------------------------------------------------------
    HostileCase(
        "state-space-at-injection",
        (*STATE_SPACE, "--at", "x=__import__('os')"),
        r"at\.x: ",
        model=VALID,
    ),
    HostileCase(
        "state-space-at-not-real",
        (*STATE_SPACE, "--at", "x=acos(2)"),
        r"at\.x: acos\(2\) is not a real number",
        model=VALID,
    ),
    HostileCase(
        "state-space-not-equilibrium",
        (*STATE_SPACE, "--at", "x=1"),
        r"not an equilibrium or steady motion",
        model=VALID,
    ),
    HostileCase(
        "state-space-at-unknown",
        (*STATE_SPACE, "--at", "y=1"),
        r"'y' is not a coordinate, velocity, input or parameter",
        model=VALID,
    ),
    HostileCase(
        "state-space-at-malformed", (*STATE_SPACE, "--at", "x"), r"expected NAME=EXPR", model=VALID
    ),
    HostileCase(
        "state-space-output-huge",
        (*STATE_SPACE, "--at", "x=0", "--output", "y=" + "x+" * 30_000 + "x"),
        r"outputs\.y: ",
        model=VALID,
    ),
    HostileCase(
        "state-space-constraints",
        ("analyze", "rolling_disc", "--state-space"),
        r"constraints: state-space linearization with constraints is not supported",
    ),
    HostileCase(
        "state-space-time-dependent",
        (*STATE_SPACE, "--at", "x=0"),
        r"depend explicitly on t",
        model=_inputs('F = "x"').replace('"k*x**2/2"', '"k*x**2/2 + x*cos(t)"'),
    ),
    HostileCase(
        "at-without-state-space",
        ("analyze", "cart_pole", "--at", "theta=0"),
        r"--at and --output go with --state-space",
    ),
    # -- export ---------------------------------------------------------------------------
    HostileCase(
        "export-missing-folder",
        ("export", "cart_pole", "--to", "c", "--out", "{dir}/missing/out.c"),
        r"the folder .*missing does not exist",
    ),
    HostileCase(
        "export-folder-target",
        ("export", "cart_pole", "--to", "c", "--out", "{dir}/out.c"),
        r"out\.c",
        setup=_folder_target,
    ),
    HostileCase(
        "export-unknown-language",
        ("export", "cart_pole", "--to", "fortran"),
        r"Invalid value for '--to'",
    ),
    HostileCase(
        "export-matlab-file-name",
        ("export", "cart_pole", "--to", "matlab", "--out", "{dir}/cart-pole.m"),
        r"needs a name that is an identifier",
    ),
    HostileCase(
        "export-undefined-function",
        ("export", "{dir}/model.toml", "--to", "c"),
        r"V",
        model=SLIDER.replace('"k*x**2/2"', '"V"') + PARAMETERS + '[functions]\nV = ["x"]\n',
    ),
    HostileCase(
        "export-define-injection",
        ("export", "{dir}/model.toml", "--to", "c", "--define", "V=__import__('os')"),
        r"V",
        model=SLIDER.replace('"k*x**2/2"', '"V"') + PARAMETERS + '[functions]\nV = ["x"]\n',
    ),
    HostileCase(
        "export-to-stdout",
        ("export", "{dir}/model.toml", "--to", "numpy"),
        exit_code=0,
        output=r"def rhs\(t, y, params=DEFAULT_PARAMS, u=None\)",
        model=VALID,
    ),
]
