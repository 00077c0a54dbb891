"""Every code block of README.md, docs/tutorial.md and docs/architecture.md runs as written.

```python blocks run as scripts (a fresh interpreter each, in a temporary
folder); each ``lagrangian ...`` line of a ```sh / ```console block is a test of
its own (named by file and line, so a failure names the line and the workers
share a long block), run through the CLI in-process in a temporary folder, after
the lines before it in its block that write a file it reads (or with the files they
wrote where the same process ran them already: WRITTEN).  What is not run
is said here, each with its reason (SKIPPED, SYNOPSIS), and so is every change
made to a command before it runs (SMALLER, ANIMATION_FRAMES); a line that is the
same command as one before it (README and tutorial share several) is the same test,
run once under the first place it appears: nothing else is left out or altered.
Where a comment in the docs states what a command prints, the statement is checked
against the output (PRINTS).
"""

from __future__ import annotations

import importlib.util
import itertools
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from lagrangian.cli import ExitStatus, main

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = (ROOT / "README.md", ROOT / "docs" / "tutorial.md", ROOT / "docs" / "architecture.md")

#: Lines not run, with why (matched as substrings of the command line).
SKIPPED = {
    "pip install": "installs packages: needs the network, and changes the environment",
    "&& pytest": "runs this very test suite",
    "--backend cuda": "needs an NVIDIA GPU",
    "--scheduler tcp://": "needs a Dask cluster",
    "lagrangian serve": "serves until stopped (tests/serve/test_editor_browser.py runs it)",
    "pdflatex ": "LaTeX, not this toolkit (tests/output/test_worked_solution_pdf.py compiles "
    "the report of every example)",
}
#: Synopsis lines (placeholders in capitals, alternatives with |, options in [...]).
SYNOPSIS = re.compile(r"\b(MODEL|TRAJECTORY)\b|\[--")
#: Heavy commands run smaller, said explicitly: (what in the docs, what the test runs).
SMALLER = (
    # the million-member flip-time map of the README and the 90,000 of the tutorial:
    # the same command on a 20 x 20 grid
    (":1000 --grid", ":20 --grid"),
    ("-3.14:3.14:1000 ", "-3.14:3.14:20 "),
    (":300 --grid", ":20 --grid"),
    ("-3.14:3.14:300 ", "-3.14:3.14:20 "),
    # the README's Python ensemble of 10,000 members: 100 members
    ("np.linspace(-3, 3, 10_000)", "np.linspace(-3, 3, 100)"),
    # the Python examples' runs of 10 s that are animated (250 frames each): the README's
    # 1 s, 25 frames (shorter saves nothing there: its cost is the first run's setup)
    (
        'simulate(t_end=10, method="variational", dt=1e-3,',
        'simulate(t_end=1, method="variational", dt=1e-3,',
    ),
    # the tutorial's (animated twice, to a GIF and to the notebook's player, whose frames
    # cost 0.09 s each): 0.2 s, 5 frames each
    (
        'simulate(t_end=10, method="variational", dt=0.005)',
        'simulate(t_end=0.2, method="variational", dt=0.005)',
    ),
    # the chaos commands (minutes at full size): a few orbits, values and periods each
    ("--t-end 500 --plot lyapunov.png", "--t-end 5 --plot lyapunov.png"),
    ("--transient 100 --largest", "--transient 5 --t-end 5 --largest"),
    ("--orbits 12 ", "--orbits 2 --t-end 10 "),
    ("--t-end 2000 --plot section.png", "--t-end 10 --plot section.png"),
    ("--orbits 16 ", "--orbits 2 --t-end 10 "),
    ("--t-end 500 --interval 2", "--t-end 6 --interval 2"),
    ("--transient 100 --t-end 1000", "--transient 5 --t-end 5"),
    ("--t-end 10000 --axes", "--t-end 40 --axes"),
    ("9.42477796076938 --transient 100 ", "9.42477796076938 --transient 10 --t-end 40 "),
    ("A=1.35:1.5:400", "A=1.35:1.5:2"),
    # the continuation drawn (branches over a diagram of 200 values): a shorter range, and
    # its text (checked in PRINTS) as written
    ("A=1.05:1.084:35 \\", "A=1.05:1.07:11 \\"),
    # the SALI maps: 3 x 3 starts, a short run (on numpy: no compile)
    (
        "y=-0.4:0.4:100 --grid y_dot=-0.4:0.4:100 --t-end 750 \\\n    --dt 0.05 --observable sali "
        "--backend numba",
        "y=-0.4:0.4:3 --grid y_dot=-0.4:0.4:3 --t-end 2 \\\n    --dt 0.05 --observable sali",
    ),
    (
        "y=-0.4:0.4:20 --grid y_dot=-0.4:0.4:20 --t-end 750",
        "y=-0.4:0.4:3 --grid y_dot=-0.4:0.4:3 --t-end 2",
    ),
    # the basin maps: 6 x 6 starts
    ("3.14159:200 --grid theta_dot=-3:3:200", "3.14159:6 --grid theta_dot=-3:3:6"),
    ("theta=-3.14159:3.14159:100", "theta=-3.14159:3.14159:6"),
    ("theta_dot=-3:3:100 ", "theta_dot=-3:3:6 "),
    ("--transient 300 --axis", "--transient 10 --samples 2 --steps-per-period 50 --axis"),
    ("A=1.35:1.5:300", "A=1.35:1.5:2"),
    ("--transient 300 --samples 60 ", "--transient 10 --samples 2 --steps-per-period 50 "),
    ("--transient 300 --t-end 300 --dt 0.05", "--transient 10 --t-end 20 --dt 0.05 --samples 2"),
    (
        "y=-0.4:0.4:200 --grid y_dot=-0.4:0.4:200 --t-end 200",
        "y=-0.4:0.4:3 --grid y_dot=-0.4:0.4:3 --t-end 2",
    ),
)
#: ``lagrangian animate`` lines draw at most this many frames (``--max-frames``; the docs'
#: runs make up to 500, each drawn by matplotlib): the same command, a shorter film.
ANIMATION_FRAMES = 50
#: The commands whose lines are in the slow tier (``pytest --slow``): films, pages and many
#: motions, seconds each.  Every Python block is too (a fresh interpreter each).
SLOW_COMMANDS = (
    "demo",
    "animate",
    "page",
    "report",
    "ensemble",
    "bifurcation",
    "lyapunov",
    "poincare",
    "sensitivity",
    "orbits",
    "basins",
)
#: Lines in the slow tier by themselves: the four-bar's derivation and its numerical
#: search for its equilibria (2 s of CPU in all).
SLOW_LINES = ("lagrangian analyze four_bar",)
#: ``python docs/make_images.py [FILTER]`` remakes the pictures (every one: about a
#: minute; the double pendulum's: half a minute): the test runs it, into a temporary
#: folder, with this filter instead (the pictures whose name contains it).
MAKE_IMAGES_FILTER = "modes"
#: What the docs say a command prints: (command as in the docs, fragments of its output).
PRINTS = {
    "lagrangian orbits henon_heiles --section x = 0 --energy 0.125 --starts 10 --t-end 40": [
        "6 periodic orbits of period dividing 1 of the section x = 0 at energy 0.125",
        "period 1 (time 6.90059945), unstable saddle, multipliers 3.76069,",
        "period 1 (time 7.54325941), stable elliptic",
    ],
    "lagrangian orbits driven_damped_pendulum --strobe 9.42477796076938 --period 2 --set A=1.07 "
    "--starts 5": [
        "1 periodic orbit of period dividing 2",
        "period 2, stable node, multipliers 0.471104, 0.000171299; (theta, theta_dot) at "
        "(-2.47699, 1.1494), (-2.20769, 1.3461)",
    ],
    "lagrangian orbits driven_damped_pendulum --strobe 9.42477796076938 --vary A=1.05:1.084:35 "
    "--starts 3": [
        "4 branches of periodic orbits of the strobe every 9.42478 followed in A from 1.05",
        "period doubling at A = 1.066372862",
        "period doubling at A = 1.079313906",
        "period doubling at A = 1.082084384",
        "period doubling at A = 1.082678353",
    ],
    "lagrangian derive rotating_wire_bead": ["r̈ = ω² r"],
    "lagrangian fit docs/lab/damped_pendulum.toml docs/lab/pendulum.csv --vary l,gamma,theta "
    "--noise 0.3deg --out lab_fit.png --plot-residuals": [
        "0.619985",  # l in m: 0.62 made the data
        "chi^2 per degree of freedom: 0.908",
    ],
    "lagrangian fit docs/lab/damped_pendulum.toml docs/lab/pendulum.csv --vary l,gamma,theta,m "
    "--noise 0.3deg --json": ['"stderr": null', "the data do not depend on m"],
    "lagrangian simulate double_pendulum": ["method: dop853 in SciPy's loop on"],
    "lagrangian simulate double_pendulum --t-end 1000": ["method: "],
    "lagrangian derive simple_pendulum": ["θ:  l θ̈ + g sin(θ) = 0"],
    "lagrangian analyze four_bar": [
        "θ_crank = -1.8203966572",
        "stable  [numeric, at the default parameter values]",
        "constraint forces at rest: λ₁ = 3.2810040056",
        "mode shapes (θ_crank, θ_coupler, θ_rocker): (1, 0.2657, -0.1097)",
        "periods: 1.18751",
    ],
    "lagrangian analyze simple_pendulum": ["energy = ", "θ = 0: stable", "g/l"],
    "lagrangian derive harmonic_oscillator": ["x:  m ẍ + k x = 0"],
    "lagrangian derive central_force": ["r̈ - r θ̇² + μ/r² = 0", "r² θ̈ + 2 r ṙ θ̇ = 0"],
    "lagrangian analyze central_force": ["Cyclic coordinates: θ", "p_θ = r² θ̇"],
    "lagrangian analyze spherical_pendulum": [
        "Cyclic coordinates: φ",
        "p_φ = l² m φ̇ sin²θ",
        "Routh reduction of φ",
    ],
    "lagrangian derive vertical_spring": ["x:  m ẍ - g m + k x = 0"],
    "lagrangian analyze vertical_spring": ["x = g m/k: stable", "k/m"],
    "lagrangian derive planar_particle_forces": ["m ẍ - Fₓ = 0", "m ÿ - F_y = 0"],
    "lagrangian analyze rotating_wire_bead": [
        "energy = m ṙ²/2 - m ω² r²/2",
        "the Jacobi integral",
    ],
    "lagrangian demo": ["2.397", "5.787"],
    "lagrangian check simple_pendulum --kinetic m*l^2*theta_dot^2": [
        "should be l^2*m*theta_dot^2/2"
    ],
    "lagrangian check simple_pendulum --equation theta_ddot = -g/l*sin(theta)": [
        "equivalent",
        "right up to a factor: the equation of theta times 1/(l^2*m)",
    ],
    "lagrangian check simple_pendulum --kinetic m*l^2*theta_dot^2 --potential -m*g*l*cos(theta)": [
        "the term l^2*m*theta_dot^2 should be l^2*m*theta_dot^2/2",
        "potential -m*g*l*cos(theta): equivalent",
        "right up to a constant",
    ],
    "lagrangian check simple_pendulum --equation m*l^2*theta_ddot = m*g*l*sin(theta)": [
        "the equation of theta with errors",
        "has the wrong sign: it should be g*l*m*sin(theta)",
    ],
    "lagrangian check simple_pendulum --potential m*g*l*cos(theta)": [
        "has the wrong sign: it should be -g*l*m*cos(theta)"
    ],
    "lagrangian report double_pendulum --to tex": [
        "wrote double_pendulum.tex (pictures: double_pendulum-modes.pdf, double_pendulum-phase.pdf)"
    ],
}


def _blocks(path: Path):
    text = path.read_text(encoding="utf-8")
    for match in re.finditer(r"^```(\w+)\n(.*?)^```", text, re.S | re.M):
        line = text[: match.start()].count("\n") + 1
        yield match.group(1), match.group(2), f"{path.name}:{line}"


def _commands(body: str) -> list[str]:
    """The command lines of a shell block, continuation lines joined."""
    return [command for _, command in _numbered_commands(body)]


def _numbered_commands(body: str) -> list[tuple[int, str]]:
    """(offset of its first line in the block, command line) for each command of a block."""
    lines, current, first = [], "", 0
    for offset, raw in enumerate(body.splitlines()):
        line = raw.rstrip()
        if not current:
            first = offset
        if line.endswith("\\"):
            current += line[:-1] + " "
            continue
        current = (current + line).strip()
        if current and not current.startswith("#"):
            lines.append((first, current))
        current = ""
    return lines


def _smaller(text: str) -> str:
    for big, small in SMALLER:
        text = text.replace(big, small)
    return text


def _runs(command: str) -> bool:
    return not (any(key in command for key in SKIPPED) or SYNOPSIS.search(command))


def _written(command: str) -> set[str]:
    """The files a command line writes (its --out)."""
    argv = shlex.split(command, comments=True)
    return {after for before, after in itertools.pairwise(argv) if before == "--out"}


def _shell_lines(blocks) -> list:
    """One test per command line that runs: (the lines it needs first, the line itself).

    A line that reads a file an earlier line of its block writes (``plot run.nc``
    after ``simulate ... --out run.nc``) runs that line first, as the reader would."""
    params, seen = [], set()  # (the lines needed, the command as run) of each test
    for kind, body, where in blocks:
        if kind not in ("sh", "console"):
            continue
        name, start = where.rsplit(":", 1)
        earlier: dict[str, tuple[str, ...]] = {}  # each line that ran -> the lines it needs
        for offset, command in _numbered_commands(body):
            if _runs(command):
                read = set(shlex.split(command, comments=True)) - _written(command)
                needed = tuple(
                    dict.fromkeys(
                        line
                        for writer, before in earlier.items()
                        if _written(writer) & read
                        for line in (*before, writer)
                    )
                )
                earlier[command] = needed
                runs_as = (needed, tuple(shlex.split(_smaller(command), comments=True)))
                if runs_as not in seen:
                    seen.add(runs_as)
                    subcommand = runs_as[1][1]  # lagrangian SUBCOMMAND ...
                    params.append(
                        pytest.param(
                            needed,
                            command,
                            id=f"{name}:{int(start) + 1 + offset}",
                            marks=[pytest.mark.slow]
                            * (subcommand in SLOW_COMMANDS or command in SLOW_LINES),
                        )
                    )
    return params


BLOCKS = [b for path in DOCUMENTS for b in _blocks(path)]
PYTHON = [pytest.param(body, id=where) for kind, body, where in BLOCKS if kind == "python"]
SHELL_LINES = _shell_lines(BLOCKS)


def _normalized(text: str) -> str:
    return text.replace("−", "-")  # the docs may write a typographic minus


def _lab_files(folder: Path) -> None:
    """The lab example's model and data (docs/lab), where the docs' commands, run from the
    repository's root, find them."""
    lab = folder / "docs" / "lab"
    lab.mkdir(parents=True, exist_ok=True)
    for path in (ROOT / "docs" / "lab").glob("*.*"):
        if path.suffix in (".csv", ".toml"):
            (lab / path.name).write_bytes(path.read_bytes())


def _readme_model(folder: Path) -> None:
    """The README's model file, saved where its commands call it my_model.toml."""
    (toml,) = [body for kind, body, where in BLOCKS if kind == "toml" and "README" in where]
    (folder / "my_model.toml").write_text(toml, encoding="utf-8")


@pytest.mark.slow
@pytest.mark.parametrize("body", PYTHON)
def test_python_block_runs(body, tmp_path):
    script = tmp_path / "block.py"
    script.write_text(_smaller(body), encoding="utf-8")
    _lab_files(tmp_path)
    result = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=os.environ | {"MPLBACKEND": "Agg"},
    )
    assert result.returncode == 0, result.stderr[-3000:]


#: The files each line that another line needs wrote when it ran in this process (its own
#: test, or the first that needed it): a later test copies them instead of running it again.
WRITTEN: dict[str, dict[str, bytes]] = {}
NEEDED = {earlier for param in SHELL_LINES for earlier in param.values[0]}


@pytest.mark.parametrize(("needed", "line"), SHELL_LINES)
def test_shell_line_runs(needed, line, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _readme_model(tmp_path)
    _lab_files(tmp_path)
    for earlier in needed:
        if earlier in WRITTEN:
            for name, content in WRITTEN[earlier].items():
                (tmp_path / name).write_bytes(content)
        else:
            _run_line(earlier, tmp_path, capsys)
            _keep(earlier, tmp_path)
    _run_line(line, tmp_path, capsys)
    _keep(line, tmp_path)


def _keep(line: str, folder: Path) -> None:
    if line in NEEDED:
        WRITTEN[line] = {name: (folder / name).read_bytes() for name in _written(line)}


def _run_line(line: str, folder: Path, capsys) -> None:
    """One command line of the docs, through the CLI in-process; what it prints checked."""
    argv = shlex.split(_smaller(line), comments=True)
    if argv[:2] == ["python", "docs/make_images.py"]:
        _make_images(argv[2:], folder)
        return
    assert argv[0] == "lagrangian", f"a command the test does not know how to run: {line}"
    if "run.csv" in argv and "--out" not in argv:  # "a trajectory saved by simulate --out"
        assert main(["simulate", "simple_pendulum", "--out", "run.csv"]) == 0
    if argv[1:2] == ["demo"]:
        argv += ["--out-dir", str(folder / "demo")]
    if argv[1:2] == ["animate"] and "--max-frames" not in argv:
        argv += ["--max-frames", str(ANIMATION_FRAMES)]
    capsys.readouterr()
    status = main(argv[1:])
    out, err = capsys.readouterr()
    assert status == ExitStatus.SUCCESS, f"{line}\n{err}"
    command = " ".join(shlex.split(line, comments=True))
    for fragment in PRINTS.get(command, ()):
        assert _normalized(fragment) in _normalized(out), f"{line}: no {fragment!r} in\n{out}"


def _make_images(arguments: list[str], folder: Path) -> None:
    """docs/make_images.py with its pictures written to ``folder`` (not over docs/images)."""
    spec = importlib.util.spec_from_file_location("make_images", ROOT / "docs" / "make_images.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.IMAGES = folder / "images"
    del arguments  # the docs' filter (none, or "double"): see MAKE_IMAGES_FILTER
    module.main([MAKE_IMAGES_FILTER])


def test_every_statement_checked_is_still_in_the_docs():
    commands = {
        " ".join(shlex.split(c, comments=True))
        for kind, body, _ in BLOCKS
        if kind in ("sh", "console")
        for c in _commands(body)
    }
    assert set(PRINTS) <= commands, set(PRINTS) - commands


def test_every_change_made_before_a_run_still_applies():
    """A SMALLER entry whose text left the docs would silently stop making a run smaller."""
    texts = [body for _, body, _ in BLOCKS]
    stale = [big for big, _ in SMALLER if not any(big in text for text in texts)]
    assert not stale, stale
