"""Ensembles: grids too large to make, steps too large for the motion, members that fail,
dask clusters that cannot be reached; the numba code cache; the pace message (issue 21)."""

from hostile.case import HostileCase

CASES = [
    HostileCase(
        # the 74.5 GiB linspace of the grid was made before the memory check: MemoryError
        "ensemble-grid-of-10^10-points-refused-before-it-is-made",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0:1:10000000000"),
        error=r"an ensemble of 10,000,000,000 members \([0-9,]+ steps\) needs about [0-9,]+ GB "
        r"of memory, more than the [0-9.]+ GB available[^:]*: use fewer members",
    ),
    HostileCase(
        "ensemble-two-grids-of-10^5-points-refused-at-once",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0:1:100000", "--grid", "x_dot=0:1:100000"),
        error=r"an ensemble of 10,000,000,000 members \([0-9,]+ steps\) needs about [0-9,]+ GB "
        r"of memory, more than the [0-9.]+ GB available[^:]*: use fewer members",
    ),
]

# dask: addresses checked before anything runs, a refused connection reported at once
CASES += [
    *(
        HostileCase(
            f"ensemble-dask-scheduler-malformed-{label}",
            (
                "ensemble",
                "harmonic_oscillator",
                "--grid",
                "x=0:1:2",
                "--backend",
                "dask",
                "--scheduler",
                address,
            ),
            error=r"the dask scheduler address must be tcp://HOST:PORT \(PORT 1-65535\), not ",
        )
        for label, address in (
            ("no-port", "foo"),
            ("port-out-of-range", "tcp://127.0.0.1:99999"),
            ("ipv6-unclosed", "tcp://[::1"),
            ("inproc", "inproc://x"),
        )
    ),
    HostileCase(
        # distributed retried for its 10 s timeout
        "ensemble-dask-scheduler-refused-loopback-port",
        (
            "ensemble",
            "harmonic_oscillator",
            "--grid",
            "x=0:1:2",
            "--backend",
            "dask",
            "--scheduler",
            "tcp://127.0.0.1:1",
        ),
        error=r"cannot reach the dask scheduler tcp://127\.0\.0\.1:1 within 5 s: .*refused",
    ),
    HostileCase(
        # was silently ignored
        "ensemble-scheduler-without-backend-dask",
        (
            "ensemble",
            "harmonic_oscillator",
            "--grid",
            "x=0:1:2",
            "--scheduler",
            "tcp://127.0.0.1:1",
        ),
        error=r"--scheduler needs --backend dask",
    ),
]


def _open_cache(folder):
    cache = folder / "cache" / "numba"
    cache.mkdir(parents=True)
    cache.chmod(0o777)  # anyone could plant a module or numba's pickled machine code here


# the numba code cache (codegen.cache): a folder others may write is not used
CASES += [
    HostileCase(
        "numba-cache-folder-writable-by-others-not-used",
        ("simulate", "harmonic_oscillator", "--backend", "numba", "--t-end", "0.1"),
        setup=_open_cache,
        env=(("LAGRANGIAN_CACHE", "{dir}/cache"),),
        exit_code=0,
        warning=r"lagrangian: warning: the code cache .*cache/numba cannot be used \(others may "
        r"write to it \(mode 0777\)\)",
    ),
]

# a pace message of 629 characters (the projected days written out in full)
CASES += [
    HostileCase(
        "simulate-t-end-1e300-pace-message-short",
        ("simulate", "harmonic_oscillator", "--t-end", "1e300"),
        error=r"^.{0,250}$",
    ),
]

# V = k sqrt(x): from x <= 1 at rest the motion reaches x < 0, where V is undefined, by t = 1.9
SQRT = """coordinates = ["x"]
kinetic = "x_dot^2/2"
potential = "k*sqrt(x)"
[parameters]
k = 1.0
[simulate]
t_end = 3.0
"""

# fixed steps against the motion's time scale (integrate.step_size); failed members counted
CASES += [
    HostileCase(
        # dt = t_end/1000 = 10: every member NaN, exit 0
        "ensemble-step-past-the-stability-limit",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0.5:1:3", "--t-end", "1e4", "--dt", "10"),
        error=r"rk4 with dt = 10 is unstable for this motion: ω·dt = 10 reaches the stability "
        r"limit 2\.8 of rk4 \(ω = 1, .*\); give a --dt below 2\.8",
    ),
    HostileCase(
        "simulate-variational-step-at-the-stability-limit",
        ("simulate", "harmonic_oscillator", "--method", "variational", "--dt", "2"),
        error=r"variational with dt = 2 is unstable for this motion: .* stability limit 2 ",
    ),
    HostileCase(
        # a default dt = 1: the oscillator damped to nothing, silently
        "ensemble-coarse-step-warned-about",
        ("ensemble", "harmonic_oscillator", "--grid", "x=0.5:1:2", "--dt", "0.5"),
        exit_code=0,
        warning=r"lagrangian: warning: dt = 0\.5 is coarse for this motion: ω·dt = 0\.5 > 0\.1",
    ),
    HostileCase(
        "ensemble-every-member-failed",
        ("ensemble", "{dir}/model.toml", "--grid", "x=0.5:1:3"),
        model=SQRT,
        error=r"the ensemble integration failed for all 3 members: the state is not finite",
    ),
    HostileCase(
        "ensemble-some-members-failed",
        ("ensemble", "{dir}/model.toml", "--grid", "x=1:20:3"),
        model=SQRT,
        exit_code=0,
        output=r"failed: 1 of 3 members \(state not finite\)",
        warning=r"lagrangian: warning: 1 of 3 members failed \(the state is not finite",
    ),
]
