"""``lagrangian fit`` given hostile data and options (issue 33 item 3): each is one line
naming the file and the row or column, or the option, and exit 2."""

from pathlib import Path

from hostile.case import HostileCase

SPRING = """coordinates = ["x"]
lagrangian = "m*x_dot^2/2 - k*x^2/2"
[parameters]
m = 1.0
k = 2.0
[initial]
x = 1.0
"""
DIMENSIONED = SPRING.replace("m = 1.0\nk = 2.0", 'm = "1 kg"\nk = "2 N/m"') + '[units]\nx = "m"\n'


def data(text: str | bytes):
    def write(folder: Path) -> None:
        payload = text if isinstance(text, bytes) else text.encode()
        (folder / "data.csv").write_bytes(payload)

    return write


def case(name, text, error, *options, model=SPRING, exit_code=2, output=""):
    return HostileCase(
        f"fit-{name}",
        ("fit", "{dir}/model.toml", "{dir}/data.csv", "--vary", "k", "--backend", "llvm", *options),
        error=error,
        model=model,
        setup=data(text),
        exit_code=exit_code,
        output=output,
    )


GOOD = "t,x\n0,1\n0.5,0.4\n1,-0.2\n1.5,-0.6\n2,-1\n"

CASES = [
    case("empty-file", "", r"data\.csv: the file is empty"),
    case("header-only", "t,x\n", r"data\.csv: no data rows after the header"),
    case("binary-garbage", b"\xff\xfe\x00\x01t,x", r"data\.csv: cannot be read as CSV"),
    case(
        "no-time-column",
        "time,x\n0,1\n",
        r"data\.csv: no column 't' \(the columns there: time, x\)",
    ),
    case("unknown-column", "t,x,y\n0,1,2\n", r"data\.csv: column 'y' is neither a coordinate"),
    case(
        "observed-column-missing",
        GOOD,
        r"data\.csv: no column 'tip' to compare with",
        "--observe",
        "tip = 2*x",
    ),
    case(
        "text-cell", "t,x\n0,1\n0.5,abc\n", r"data\.csv: row 3, column 'x': 'abc' is not a number"
    ),
    case("infinite-cell", "t,x\n0,1\n0.5,1e999\n", r"row 3, column 'x': 1e999 is not finite"),
    case("short-row", "t,x\n0,1\n0.5\n", r"data\.csv: row 3 has 1 cells, the header 2"),
    case(
        "times-backwards", "t,x\n0,1\n1,0\n0.5,0\n", r"row 4: t = 0\.5 is not after t = 1 of row 3"
    ),
    case("negative-time", "t,x\n-1,1\n0,1\n", r"row 2: t = -1 is before 0"),
    case("all-rows-nan", "t,x\n0,nan\n1,\n", r"every row has a missing value"),
    case("unit-without-model-units", "t,x [cm]\n0,1\n1,2\n", r"column 'x \[cm\]' has a unit but"),
    case(
        "unit-of-another-dimension",
        "t,x [s]\n0,1\n1,2\n",
        r"column 'x \[s\]': x is a length \(m\), but s is a time \(s\)",
        model=DIMENSIONED,
    ),
    case(
        "unknown-unit", "t,x [furlongz]\n0,1\n1,2\n", r"unknown unit 'furlongz'", model=DIMENSIONED
    ),
    case("too-few-values", "t,x\n0,1\n", r"1 measured values cannot fit 1 unknowns"),
    case("bad-observe", GOOD, r"--observe tip: unknown symbol 'y'", "--observe", "tip = y"),
    case(
        "observe-no-equals",
        GOOD,
        r"--observe: an observed expression is 'NAME = EXPR'",
        "--observe",
        "tip",
    ),
    case(
        "observe-shadows-name", GOOD, r"--observe k: 'k' is already a name", "--observe", "k = 2*x"
    ),
    case("noise-zero", GOOD, r"--noise: the noise level must be a positive number", "--noise", "0"),
    case(
        "noise-nan", GOOD, r"--noise: the noise level must be a positive number", "--noise", "nan"
    ),
    case(
        "starts-huge-negative",
        GOOD,
        r"--starts: starts must be a whole number >= 1",
        "--starts",
        "-5",
    ),
    case(
        "starts-a-billion",
        GOOD,
        r"--starts: at most 1000 starts, not 1000000000: a fit that needs more wants better "
        r"guesses \(--vary NAME=GUESS\)",
        "--starts",
        "1000000000",
    ),
    case(
        "timeout-tiny",
        GOOD,
        r"the fit did not finish within 1e-06 s of CPU \(1 start\(s\)\): give a larger "
        r"--timeout SECONDS",
        "--timeout",
        "0.000001",
    ),
    case(
        "guess-not-number", GOOD, r"--vary: the start guess of m is not a number", "--vary", "m=abc"
    ),
    case("guess-infinite", GOOD, r"--vary: the start guess of m is not finite", "--vary", "m=inf"),
    case("guess-breaks-sign", GOOD, r"m = -1", "--vary", "m=-1"),
    HostileCase(
        "fit-data-is-a-folder",
        ("fit", "{dir}/model.toml", "{dir}", "--vary", "k"),
        error=r": no such file",
        model=SPRING,
    ),
    case(
        "clean-fit",
        GOOD,
        "",
        exit_code=0,
        output=r"rms of the residuals",
    ),
]
