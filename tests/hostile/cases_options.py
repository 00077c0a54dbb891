"""Command-line options checked as the library checks them: time budgets (--timeout),
assignment lists (--set, --at, --output, --momentum, --define) and the parameter values
they give (the model file's own sign and inertia checks)."""

import re

from hostile.case import HostileCase

TIMEOUT_REFUSED = r"Invalid value for '--timeout': must be a number of seconds > 0 and at most"

CASES = [
    *(
        HostileCase(
            f"{command[0]}-timeout-{value}-refused",
            (*command, "--timeout", value),
            error=TIMEOUT_REFUSED + rf".*not {re.escape(value)}$",
        )
        for command in (
            ("analyze", "simple_pendulum"),
            ("simulate", "simple_pendulum", "--t-end", "1"),
            ("ensemble", "simple_pendulum", "--grid", "theta=0:1:3", "--t-end", "1"),
            ("plot", "simple_pendulum", "--out", "{dir}/p.png"),
            ("animate", "simple_pendulum", "--out", "{dir}/a.gif"),
        )
        for value in ("nan", "inf", "-inf", "1e+09")
    ),
    HostileCase(
        # the stages' deadlines are due almost at once: each reported undecided, never a
        # traceback (an alarm firing before the guarded block escaped as exit 1)
        "analyze-timeout-1e-5-reports-undecided",
        ("analyze", "double_pendulum", "--timeout", "1e-5"),
        exit_code=0,
        output=r"not decided within 1e-05 s",
    ),
]

# -- assignment lists: one parser, a name given twice is refused (it kept the last) ---------
CASES += [
    HostileCase(
        "state-space-at-given-twice",
        ("analyze", "cart_pole", "--state-space", "--at", "theta=0", "--at", "theta=pi"),
        error=r"Invalid value for --at: 'theta' is given twice$",
    ),
    HostileCase(
        "state-space-output-given-twice",
        (
            "analyze",
            "cart_pole",
            "--state-space",
            "--at",
            "theta=0",
            "--output",
            "y=x",
            "--output",
            "y=theta",
        ),
        error=r"Invalid value for --output: 'y' is given twice$",
    ),
    HostileCase(
        "simulate-set-given-twice",
        ("simulate", "harmonic_oscillator", "--set", "m=1", "--set", "m=2"),
        error=r"Invalid value for --set: 'm' is given twice$",
    ),
    HostileCase(
        "simulate-define-given-twice",
        ("simulate", "velocity_dependent_potential", "--define", "B=x", "--define", "B=0"),
        error=r"Invalid value for --define: 'B' is given twice$",
    ),
    HostileCase(
        "analyze-momentum-given-twice",
        ("analyze", "central_force", "--momentum", "p_theta=1", "--momentum", " p_theta=2"),
        error=r"Invalid value for --momentum: 'p_theta' is given twice$",
    ),
    HostileCase(
        "ensemble-set-and-grid-of-one-name",
        ("ensemble", "simple_pendulum", "--grid", "theta=0:1:3", "--set", "theta=1"),
        error=r"Invalid value for --set: 'theta' is given by --grid too$",
    ),
]

# -- an output's name: an identifier that means nothing else in the model -------------------
CASES += [
    HostileCase(
        f"state-space-output-named-{label}",
        ("analyze", "cart_pole", "--state-space", "--at", "theta=0", "--output", f"{name}=x"),
        error=error,
    )
    for label, name, error in (
        ("with-a-space", "bad name", r"outputs: invalid output name 'bad name'"),
        ("sin", "sin", r"outputs\.sin: 'sin' is a built-in name: give the output another name"),
        ("pi", "pi", r"outputs\.pi: 'pi' is a built-in name"),
        ("t", "t", r"outputs\.t: 't' is a built-in name"),
        ("a-coordinate", "theta", r"outputs\.theta: 'theta' is a coordinate"),
        ("a-velocity", "x_dot", r"outputs\.x_dot: 'x_dot' is a velocity"),
        ("a-parameter", "M", r"outputs\.M: 'M' is a parameter"),
        ("an-input", "F", r"outputs\.F: 'F' is an input"),
    )
]

# -- values given in place of the defaults pass the model file's own checks ------------------
TRIANGLE = r"bodies\[0\]\.inertia: the principal moments 0\.01, 0\.01, {I3} violate the triangle"
POSITIVE_M = r"parameter M = -1 breaks the model's assumption that M is positive"
CASES += [
    HostileCase(
        "simulate-set-breaks-the-triangle-inequality",
        ("simulate", "heavy_top", "--t-end", "0.1", "--set", "I3=1"),
        error=TRIANGLE.format(I3="1") + r".*\(with I3 = 1\)$",
    ),
    HostileCase(
        "plot-set-breaks-the-triangle-inequality",
        ("plot", "heavy_top", "--set", "I3=0.5", "--out", "{dir}/top.png"),
        error=TRIANGLE.format(I3="0.5"),
    ),
    HostileCase(
        "state-space-at-breaks-the-triangle-inequality",
        ("analyze", "heavy_top", "--state-space", "--at", "theta=0", "--at", "I3=1"),
        error=TRIANGLE.format(I3="1"),
    ),
    HostileCase(  # the first member is a valid top, a later one is not
        "ensemble-grid-breaks-the-triangle-inequality",
        ("ensemble", "heavy_top", "--grid", "I3=0.01:0.5:4", "--t-end", "0.1", "--dt", "0.01"),
        error=TRIANGLE.format(I3=r"0\.17\d*") + r".*\(with I3 = 0\.17\d*\)$",
    ),
    HostileCase(
        "state-space-at-breaks-the-sign",
        ("analyze", "cart_pole", "--state-space", "--at", "theta=0", "--at", "M=-1"),
        error=POSITIVE_M,
    ),
    HostileCase(
        "state-space-at-expression-breaks-the-sign",
        ("analyze", "cart_pole", "--state-space", "--at", "theta=0", "--at", "M=-m"),
        error=r"parameter M = -\S+ breaks the model's assumption that M is positive",
    ),
]

# -- a Lagrangian on the command line: read by the safe parser, checked like a model file ----
CASES += [
    HostileCase(
        "derive-lagrangian-evaluates-nothing",
        ("derive", "--lagrangian", "__import__('os').system('true')", "--coordinates", "x"),
        error=r"^lagrangian: error: --lagrangian: lagrangian: ",
    ),
    HostileCase(
        "derive-lagrangian-without-coordinates",
        ("derive", "--lagrangian", "x_dot**2/2"),
        error=r"--lagrangian needs --coordinates, e.g. --coordinates theta$",
    ),
    HostileCase(
        "derive-lagrangian-and-model",
        ("derive", "simple_pendulum", "--lagrangian", "x_dot**2/2", "--coordinates", "x"),
        error=r"give MODEL or --lagrangian, not both$",
    ),
    HostileCase(
        "derive-coordinates-without-lagrangian",
        ("derive", "simple_pendulum", "--coordinates", "x"),
        error=r"--coordinates goes with --lagrangian$",
    ),
    HostileCase("derive-nothing", ("derive",), error=r"give MODEL .* or --lagrangian$"),
    HostileCase(
        "derive-lagrangian-bad-coordinate-name",
        ("derive", "--lagrangian", "x_dot**2/2", "--coordinates", "x,1y"),
        error=r"^lagrangian: error: --lagrangian: coordinates",
    ),
    HostileCase(
        "simulate-lagrangian-needs-its-parameter-values",
        ("simulate", "--lagrangian", "x_dot^2/2 - k*x^2/2", "--coordinates", "x", "--t-end", "1"),
        error=r"no value for parameter\(s\) k \(give them with --set NAME=VALUE\)$",
    ),
]

# -- output sampling of simulate ------------------------------------------------------------
CASES += [
    HostileCase(
        "simulate-samples-one",
        ("simulate", "simple_pendulum", "--samples", "1"),
        error=r"--samples must be a whole number >= 2, not 1$",
    ),
    HostileCase(
        "simulate-dt-out-nan",
        ("simulate", "simple_pendulum", "--dt-out", "nan"),
        error=r"--dt-out must be a time step > 0, not nan$",
    ),
    HostileCase(  # refused by the memory check, before 10^300 times are made
        "simulate-dt-out-tiny",
        ("simulate", "simple_pendulum", "--dt-out", "1e-300"),
        error=r"output times needs about .* ask for fewer output times \(--samples, --dt-out",
    ),
    HostileCase(
        "simulate-samples-and-dt-out",
        ("simulate", "simple_pendulum", "--samples", "3", "--dt-out", "0.1"),
        error=r"give --samples or --dt-out, not both$",
    ),
]
