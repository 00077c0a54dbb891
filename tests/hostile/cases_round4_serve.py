"""Issue 37 items 11 and 13: messages that name the option the user typed (and only
options the command has), ranges whose width overflows, the hosts ``serve`` answers."""

from hostile.case import HostileCase

#: A range of finite ends whose width is not finite (1e308 - -1e308 overflows).
HUGE = "-1e308:1e308"

CASES = [
    HostileCase(
        # said "Invalid value for --grid": bifurcation has no --grid
        "bifurcation-vary-nan-names-vary",
        (
            "bifurcation",
            "driven_damped_pendulum",
            "--vary",
            "A=nan:1:3",
            "--strobe",
            "1",
            "--axis",
            "theta",
        ),
        error=r"Invalid value for --vary: expected NAME=LO:HI:N \(N a whole number >= 1\), "
        r"got 'A=nan:1:3'$",
    ),
    HostileCase(
        "bifurcation-vary-width-overflows",
        (
            "bifurcation",
            "driven_damped_pendulum",
            "--vary",
            f"A={HUGE}:3",
            "--strobe",
            "1",
            "--axis",
            "theta",
        ),
        error=r"Invalid value for --vary: 'A' from -1e\+308 to 1e\+308: the range's width "
        r"overflows$",
    ),
    HostileCase(
        # the members' values were nan: "initial x = nan is not a finite number"
        "ensemble-grid-width-overflows",
        ("ensemble", "harmonic_oscillator", "--grid", f"x={HUGE}:3", "--t-end", "1"),
        error=r"Invalid value for --grid: 'x' from -1e\+308 to 1e\+308: the range's width "
        r"overflows$",
    ),
    HostileCase(
        # blamed the equations: "the right-hand side is not finite at t = 0 (... y = nan ...)"
        "poincare-spread-width-overflows",
        (
            "poincare",
            "henon_heiles",
            "--section",
            "x=0",
            "--axes",
            "y,y_dot",
            "--spread",
            f"y={HUGE}",
            "--orbits",
            "3",
            "--t-end",
            "10",
        ),
        error=r"Invalid value for --spread: 'y' from -1e\+308 to 1e\+308: the range's width "
        r"overflows$",
    ),
    *(
        HostileCase(
            f"poincare-spread-{label}-refused",
            (
                "poincare",
                "henon_heiles",
                "--section",
                "x=0",
                "--axes",
                "y,y_dot",
                "--spread",
                f"y={value}",
                "--orbits",
                "3",
                "--t-end",
                "10",
            ),
            error=r"Invalid value for --spread: expected NAME=LO:HI \(LO and HI finite "
            r"numbers\)",
        )
        for label, value in (("nan", "nan:1"), ("inf", "0:inf"))
    ),
    HostileCase(
        # said "or a larger save_every", which no command has, and --grid, which
        # bifurcation has not; with --strobe neither --dt nor save_every can be set
        "bifurcation-strobe-out-of-memory-names-its-options",
        (
            "bifurcation",
            "driven_damped_pendulum",
            "--vary",
            "A=0:1:100000000",
            "--strobe",
            "1",
            "--axis",
            "theta",
            "--samples",
            "1000",
        ),
        error=r"an ensemble of 100,000,000 members, keeping 1,001 states each .* needs about "
        r"[0-9,]+ GB of memory, more than the [0-9.]+ GB available[^:]*: use fewer values of "
        r"--vary, fewer --samples or a shorter --transient$",
    ),
    HostileCase(
        "bifurcation-section-out-of-memory-names-its-options",
        (
            "bifurcation",
            "driven_damped_pendulum",
            "--vary",
            "A=0:1:100000000",
            "--section",
            "theta=0",
            "--axis",
            "theta_dot",
            "--t-end",
            "1000",
        ),
        error=r"an ensemble of 100,000,000 members, .* needs about [0-9,]+ GB of memory, more "
        r"than the [0-9.]+ GB available[^:]*: use fewer values of --vary, a shorter "
        r"--transient or --t-end, or a larger --dt$",
    ),
    HostileCase(
        "ensemble-out-of-memory-names-no-save-every",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0:1:1000000000", "--t-end", "1"),
        error=r"use fewer members \(fewer points per --grid\), or fewer steps \(a larger "
        r"--dt\)$",
    ),
    *(
        HostileCase(
            f"serve-allow-host-{label}-refused",
            ("serve", "--host", "0.0.0.0", "--allow-remote", "--allow-host", name),
            error=rf"--allow-host: '{name}' is not a host name or an IP address$",
        )
        for label, name in (("space", "bad name"), ("port", "host:80"), ("slash", "a/b"))
    ),
    HostileCase(
        # the setting was named as Python spells it ("count: ..."): lyapunov has --count
        "lyapunov-count-names-its-option",
        ("lyapunov", "simple_pendulum", "--count", "99", "--t-end", "1"),
        error=r"--count: the number of exponents must be from 1 to 2 \(twice the coordinates\), "
        r"not 99$",
    ),
    HostileCase(
        # said "or a larger --dt": lyapunov has no --dt (its runs are adaptive)
        "lyapunov-pace-names-only-its-options",
        ("lyapunov", "henon_heiles", "--interval", "1e-9", "--t-end", "1000"),
        error=r"more than the 300 s allowed; give a shorter --t-end or a looser --rtol, or "
        r"allow more time with --timeout SECONDS$",
        slow=True,
    ),
]
