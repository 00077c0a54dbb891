"""Make the reference pictures of docs/tutorial.md (into docs/images/).

    python docs/make_images.py            # every picture: minutes, most for henon, driven
    python docs/make_images.py double     # only those whose name contains "double"

Every picture comes from the toolkit's own functions (the same ones the CLI
uses), at the models' default parameters; each file is kept under 200 KB.
"""

from __future__ import annotations

import contextlib
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

import lagrangian as lg
from lagrangian.integrate import simulate
from lagrangian.numeric import compile_equations
from lagrangian.output.animation import animate, mechanism_view
from lagrangian.output.continuation import plot_continuation
from lagrangian.output.fit import plot_fit
from lagrangian.output.mode_shapes import plot_normal_modes
from lagrangian.output.phase import phase_family, plot_phase_portrait
from lagrangian.output.plots import new_figure, plot_energy_error, plot_timeseries, save_figure
from lagrangian.output.poincare import plot_poincare, section_event
from lagrangian.output.sensitivity import plot_sensitivities

IMAGES = Path(__file__).resolve().parent / "images"
LIMIT = 200_000  # bytes per picture
DPI = 80
#: The energy of the double pendulum's Poincaré section (the lowest is -29.43).
POINCARE_H = -22.0


def kept(path: Path, note: str = "") -> None:
    """The picture at ``path`` listed with its size; over LIMIT, the script stops."""
    size = path.stat().st_size
    print(f"  {path.name:34s} {size / 1000:6.1f} kB{note}")
    if size > LIMIT:
        raise SystemExit(f"{path.name} is larger than {LIMIT // 1000} kB")


def save(figure, name: str) -> None:
    kept(save_figure(figure, IMAGES / name, dpi=DPI))


def still(system, run, name: str, frame: int, **options) -> None:
    """One frame of the animation, as a PNG."""
    from PIL import Image

    view, _ = mechanism_view(run, system, **options)
    Image.fromarray(view.render(frame)).convert("RGB").save(IMAGES / name, optimize=True)
    kept(IMAGES / name)


def orbit(run, x, y, title: str, name: str, *, origin: bool = True) -> None:
    """The path of a particle in its plane, 1:1."""
    figure, axes = new_figure(1, 1, width=5.2, height=5.0)
    ax = axes[0, 0]
    ax.plot(x, y, color="C0", lw=1.2)
    ax.plot([x[0]], [y[0]], "o", color="C0", label="start")
    if origin:
        ax.plot([0], [0], "+", color="black", ms=10, label="origin")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("$x$")
    ax.set_ylabel("$y$")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    figure.suptitle(title)
    save(figure, name)


def simple_pendulum() -> None:
    system = lg.load("simple_pendulum")
    save(plot_phase_portrait(phase_family(system, t_end=6.0), system), "simple_pendulum_phase.png")
    save(
        plot_timeseries(system.simulate(t_end=10.0, n_out=1001), system),
        "simple_pendulum_timeseries.png",
    )


def velocity_dependent_potential() -> None:
    """A charge in a uniform magnetic field B along z and an electric field E along y."""
    system = lg.load("velocity_dependent_potential")
    fields = {"A": "-y/2", "B": "x/2", "C": "0", "V": "-y/5"}  # B_z = 1, E_y = 1/5
    compiled = compile_equations(system.equations_of_motion(), definitions=fields)
    run = simulate(compiled, t_end=40.0, initial={"x_dot": 1.0}, n_out=4001)
    orbit(
        run,
        run["x"],
        run["y"],
        "Charge in crossed fields: the E x B drift",
        "charge_drift.png",
        origin=False,
    )


def harmonic_oscillator() -> None:
    system = lg.load("harmonic_oscillator")
    save(
        plot_phase_portrait(phase_family(system, t_end=7.0), system),
        "harmonic_oscillator_phase.png",
    )


def central_force() -> None:
    system = lg.load("central_force")
    run = system.simulate(t_end=20.0, n_out=4001)
    r, theta = run["r"], run["theta"]
    orbit(run, r * np.cos(theta), r * np.sin(theta), "Inverse-square force: a Kepler ellipse",
          "central_force_orbit.png")  # fmt: skip
    save(plot_energy_error(run, system), "central_force_drift.png")
    crossings = system.simulate(t_end=100.0, events=[section_event(system)], n_out=2)
    save(plot_poincare(crossings, system), "central_force_poincare.png")


def spherical_pendulum() -> None:
    system = lg.load("spherical_pendulum")
    run = system.simulate(t_end=10.0, n_out=2001)
    still(system, run, "spherical_pendulum_frame.png", 60, trail=2.0)
    save(plot_energy_error(run, system), "spherical_pendulum_drift.png")


def double_pendulum() -> None:
    system = lg.load("double_pendulum")
    run = system.simulate(t_end=10.0, method="variational", dt=0.005)
    reference = system.simulate(t_end=10.0)
    still(system, run, "double_pendulum_frame.png", 140)
    first = system.simulate(t_end=4.0, method="variational", dt=0.005)  # 100 frames, real time
    result = animate(first, system, IMAGES / "double_pendulum.gif", size=3.0, dpi=60)
    kept(result.path, f"  ({result.plan.description})")
    save(plot_phase_portrait(run, system), "double_pendulum_phase.png")
    save(plot_energy_error([run, reference], system), "double_pendulum_energy.png")
    save(plot_normal_modes(system, {"theta1": 0, "theta2": 0}), "double_pendulum_modes.png")
    # one energy, several motions through the section: invariant curves and islands
    compiled = compile_equations(system.equations_of_motion())
    params = compiled.parameter_vector()
    runs, labels = [], []
    for a in (0.0, 0.3, 0.6, 0.9, 1.1, 1.3):  # theta2 on the section theta1 = 0, theta2' = 0

        def excess(v, a=a):
            return float(compiled.energy(0.0, np.array([0.0, a, v, 0.0]), params)) - POINCARE_H

        speed = brentq(excess, 0.0, 50.0)  # theta1' > 0 that gives the energy h
        initial = {"theta1": 0.0, "theta2": a, "theta1_dot": speed, "theta2_dot": 0.0}
        runs.append(simulate(compiled, t_end=100.0, initial=initial,
                             events=[section_event(system)], n_out=2))  # fmt: skip
        labels.append(f"$\\theta_2$ = {a:g}")
    figure = plot_poincare(runs, system, labels=labels)
    figure.suptitle(figure.get_suptitle() + f", all with $h$ = {POINCARE_H:g}")
    save(figure, "double_pendulum_poincare.png")


def double_pendulum_flip_map() -> None:
    """The flip-time map, 300 x 300 starts at rest, through the CLI (numba when installed)."""
    from lagrangian.cli import ExitStatus
    from lagrangian.cli import main as cli

    try:
        import numba  # noqa: F401

        backend = "numba"
    except ImportError:
        backend = "numpy"
    name = "double_pendulum_flip_map.png"
    grids = ["--grid", "theta1=-3.14:3.14:300", "--grid", "theta2=-3.14:3.14:300"]
    arguments = ["ensemble", "double_pendulum", *grids, "--observable", "flip_time",
                 "--t-end", "10", "--dt", "0.01", "--backend", backend,
                 "--out", str(IMAGES / name)]  # fmt: skip
    if cli(arguments) != ExitStatus.SUCCESS:
        raise SystemExit("the ensemble run failed")
    kept(IMAGES / name)


def vertical_spring() -> None:
    system = lg.load("vertical_spring")
    save(
        plot_timeseries(system.simulate(t_end=5.0, n_out=1001), system),
        "vertical_spring_timeseries.png",
    )


def free_particle_spherical() -> None:
    system = lg.load("free_particle_spherical")
    run = system.simulate(t_end=10.0, n_out=1001)
    still(system, run, "free_particle_frame.png", 200, trail=5.0)
    save(plot_energy_error(run, system), "free_particle_drift.png")


def planar_particle_forces() -> None:
    system = lg.load("planar_particle_forces")
    save(
        plot_timeseries(system.simulate(t_end=5.0, n_out=501), system),
        "planar_forces_timeseries.png",
    )


def rotating_wire_bead() -> None:
    system = lg.load("rotating_wire_bead")
    run = system.simulate(t_end=3.0, n_out=601)
    still(system, run, "rotating_wire_frame.png", 74, trail=3.0)
    save(plot_energy_error(run, system), "rotating_wire_drift.png")


def cart_pole() -> None:
    """The nonlinear cart-pole against its state space x' = A x + B u: the hanging pole
    pushed by F = 0.2 from rest, and the upright pole released at 0.01 rad."""
    from scipy.linalg import expm

    system = lg.load("cart_pole")
    push, tilt = 0.2, 0.01
    hanging = system.state_space(at={"theta": "pi"}).numeric()
    upright = system.state_space(at={"theta": 0}).numeric()
    pushed = system.simulate(t_end=4.0, n_out=401, initial={"theta": np.pi}, params={"F": push},
                             rtol=1e-10, atol=1e-10)  # fmt: skip
    falling = system.simulate(t_end=1.3, n_out=401, initial={"theta": tilt}, rtol=1e-10,
                              atol=1e-10)  # fmt: skip
    # linear responses: x(t) = integral of exp(A s) B u ds (the exponential of [[A, B u], [0, 0]])
    # and x(t) = exp(A t) x0
    block = np.zeros((5, 5))
    block[:4, :4], block[:4, 4] = hanging.A, hanging.B[:, 0] * push
    forced = np.array([expm(block * s)[:4, 4] for s in pushed.t])
    free = np.array([expm(upright.A * s) @ [0.0, tilt, 0.0, 0.0] for s in falling.t])
    figure, axes = new_figure(3, 1, width=6.4, height=7.0)
    rows = [
        (pushed.t, pushed["x"], forced[:, 0], "$x$ (hanging, pushed)"),
        (pushed.t, pushed["theta"] - np.pi, forced[:, 1], r"$\theta - \pi$ (hanging, pushed)"),
        (falling.t, falling["theta"], free[:, 1], r"$\theta$ (upright, released)"),
    ]
    for ax, (t, nonlinear, linear, label) in zip(axes[:, 0], rows, strict=True):
        ax.plot(t, nonlinear, color="C0", lw=1.6, label="nonlinear (simulate)")
        ax.plot(t, linear, "--", color="C3", lw=1.2, label="linear: $x' = A x + B u$")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[2, 0].set_ylim(-0.05, 1.2)
    axes[2, 0].set_xlabel("$t$")
    axes[0, 0].legend(loc="upper left", fontsize=8)
    figure.suptitle("Cart-pole: the simulation and the state-space model")
    save(figure, "cart_pole_state_space.png")
    still(system, pushed, "cart_pole_frame.png", 80, trail=2.0)


def heavy_top() -> None:
    """The disc top: released tilted by 0.4 rad with spin 80 rad/s; nutation and precession."""
    system = lg.load("heavy_top")
    run = system.simulate(t_end=4.0, n_out=4001)
    still(system, run, "heavy_top_frame.png", 60, trail=2.5)
    first = system.simulate(t_end=3.0, n_out=601)  # 75 frames, real time
    result = animate(first, system, IMAGES / "heavy_top.gif", size=2.6, dpi=50, trail=0.5)
    kept(result.path, f"  ({result.plan.description})")
    save(plot_timeseries(run, system), "heavy_top_timeseries.png")


def film(system, run, name: str, size: float = 2.6, **options) -> None:
    """An animation of ``run`` as a small GIF (under the size limit)."""
    result = animate(run, system, IMAGES / name, size=size, dpi=50, **options)
    kept(result.path, f"  ({result.plan.description})")


def linkages() -> None:
    """The four-bar (free; driven, with its joint reactions) and the slider-crank."""
    free = lg.load("four_bar")
    film(free, free.simulate(t_end=3.0, n_out=301), "four_bar.gif", trail=0.5)
    driven = lg.load("four_bar_driven")
    run = driven.simulate(t_end=1.0, n_out=401)
    film(driven, run, "four_bar_driven.gif", trail=0.3, reactions=True)
    still(driven, run, "four_bar_driven_frame.png", 10, reactions=True, trail=0.3)
    figure, axes = new_figure(2, 1, width=6.0, height=5.0)
    for joint in "ABCD":
        magnitude = np.hypot(run[f"R_{joint}_x"], run[f"R_{joint}_y"])
        axes[0, 0].plot(run.t, magnitude, label=f"|R_{joint}|")
    axes[0, 0].set_ylabel("joint force (N)")
    axes[0, 0].legend(loc="upper right", fontsize=8, ncols=4)
    axes[1, 0].plot(run.t, run["tau_A"], color="C3")
    axes[1, 0].set_ylabel("driving torque τ_A (N m)")
    axes[1, 0].set_xlabel("t (s): one turn of the crank")
    figure.suptitle("Four-bar linkage, driven crank: joint reactions over one turn")
    save(figure, "four_bar_reactions.png")
    slider = lg.load("slider_crank")
    run = slider.simulate(t_end=1.0, n_out=401)
    film(slider, run, "slider_crank.gif", size=4.0, trail=0.2)


def impacts() -> None:
    """The bouncing ball to rest and the impact oscillator: films and time series."""
    ball = lg.load("bouncing_ball")
    film(ball, ball.simulate(t_end=10.0, n_out=1001), "bouncing_ball.gif", size=3.0, trail=0.6)
    save(
        plot_timeseries(ball.simulate(t_end=10.0, n_out=2001), ball), "bouncing_ball_timeseries.png"
    )
    oscillator = lg.load("impact_oscillator")
    run = oscillator.simulate(t_end=60.0, n_out=3001)
    film(oscillator, oscillator.simulate(t_end=12.0, n_out=601), "impact_oscillator.gif", trail=0.4)
    save(plot_timeseries(run, oscillator), "impact_oscillator_timeseries.png")
    block = lg.load("rocking_block")
    film(block, block.simulate(t_end=1.0, n_out=501), "rocking_block.gif", size=3.0, trail=0.3)


@contextlib.contextmanager
def chromium(what: str = "the page's screenshot"):
    """Debian's headless Chromium, driven by Playwright (pip install playwright): the
    browser, closed afterwards."""
    from playwright.sync_api import sync_playwright

    executable = shutil.which("chromium") or shutil.which("chromium-browser")
    if executable is None:
        raise SystemExit(f"{what} needs chromium on the PATH")
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=executable, args=["--no-sandbox"])
        try:
            yield browser
        finally:
            browser.close()


@contextlib.contextmanager
def page_tab(model: str, ready: str = "window.lagrangian", **page_options):
    """A 1280 x 900 tab of Chromium showing the page of ``model`` (``page_html`` with
    ``page_options``, from a temporary file), once ``ready`` is defined."""
    from lagrangian.output.page import page_html

    with chromium() as browser, tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"{model}.html"
        path.write_text(page_html(lg.load(model), **page_options), encoding="utf-8")
        tab = browser.new_page(viewport={"width": 1280, "height": 900})
        tab.goto(path.as_uri())
        tab.wait_for_function(f"() => {ready} !== undefined")
        yield tab


def double_pendulum_page() -> None:
    """A screenshot of ``lagrangian page double_pendulum`` in headless Chromium after a few
    seconds of play."""
    name = "double_pendulum_page.png"
    with page_tab("double_pendulum") as tab:
        tab.wait_for_function("() => lagrangian.state().t > 3", timeout=60_000)
        tab.evaluate("() => lagrangian.pause()")
        tab.wait_for_timeout(300)
        tab.screenshot(path=str(IMAGES / name))
    kept(IMAGES / name)


def henon_heiles_section_panel() -> None:
    """The Poincaré section panel of ``lagrangian page henon_heiles``, built by hand as a
    student builds it: twelve clicks in the plane (y, p_y) of the section x = 0 at
    E = 1/8, each an orbit of t = 1000 in its own colour."""
    name = "henon_heiles_section_panel.png"
    clicks = [
        (-0.35, 0.0), (-0.25, 0.0), (-0.1, 0.0), (0.05, 0.0), (0.2, 0.0), (0.32, 0.0),
        (0.45, 0.0), (0.55, 0.0), (0.0, 0.3), (0.0, 0.4), (-0.15, 0.2), (0.35, 0.2),
    ]  # fmt: skip
    with page_tab("henon_heiles") as tab:
        tab.evaluate("() => lagrangian.pause()")
        tab.evaluate(
            "(clicks) => { lagrangian.section.configure({axis: 'y', kind: 'momentum',"
            " energy: 0.125, t_end: 1000}); for (const [u, w] of clicks)"
            " lagrangian.section.launch(u, w); }",
            clicks,
        )
        tab.locator("fieldset.poincare").screenshot(path=str(IMAGES / name))
    kept(IMAGES / name)


def exercise_page() -> None:
    """The exercise page of the simple pendulum (``lagrangian page simple_pendulum
    --exercise``) in headless Chromium, a student's answers typed and checked: a T with a
    wrong factor, V up to a constant, the equation divided through."""
    from lagrangian.output.exercise import STEPS

    name = "exercise_page.png"
    answers = {
        "kinetic": "m*l^2*theta_dot^2",
        "potential": "-m*g*l*cos(theta)",
        "lagrangian": "m*l^2*theta_dot^2/2 - m*g*l*cos(theta)",
        "equations-0": "theta_ddot = -g/l*sin(theta)",
    }
    with page_tab("simple_pendulum", ready="window.lagrangianCheck", exercise=STEPS) as tab:
        tab.evaluate("() => lagrangian.pause()")
        for field, text in answers.items():
            tab.fill(f"#exercise-{field}", text)
            tab.locator(f"#exercise-{field}").press("Enter")
        tab.locator("#exercise").screenshot(path=str(IMAGES / name))
    kept(IMAGES / name)


def page_share_and_embed() -> None:
    """The double pendulum's page as a course page embeds it (``#embed`` in an
    ``<iframe sandbox="allow-scripts">``, with g = 3.7 from a share link), and its
    equilibria at a phone's width (412 px): verdicts and numbers in view."""
    from lagrangian.output.page import page_html

    with chromium("the page's screenshots") as browser, tempfile.TemporaryDirectory() as folder:
        page = Path(folder) / "double_pendulum.html"
        page.write_text(page_html(lg.load("double_pendulum")), encoding="utf-8")
        course = Path(folder) / "week3.html"
        course.write_text(
            "<!DOCTYPE html><html><body style='font: 16px sans-serif; margin: 24px'>"
            "<h2>Week 3: the double pendulum</h2><p>Try g = 3.7 (the Moon is 1.6): which "
            "mode is slower now?</p>"
            f'<iframe sandbox="allow-scripts" src="{page.as_uri()}#embed&p.g=3.7"'
            ' width="640" height="470" style="border: 1px solid #ccc"></iframe></body></html>',
            encoding="utf-8",
        )
        tab = browser.new_page(viewport={"width": 700, "height": 620})
        tab.goto(course.as_uri())
        frame = tab.frames[1]
        frame.wait_for_function("() => window.lagrangian !== undefined")
        frame.wait_for_function("() => lagrangian.state().t > 2", timeout=60_000)
        frame.evaluate("() => lagrangian.pause()")
        tab.wait_for_timeout(300)
        tab.screenshot(path=str(IMAGES / "page_embed.png"))
        phone = browser.new_page(viewport={"width": 412, "height": 900})
        phone.goto(page.as_uri())
        phone.wait_for_function("() => window.lagrangian !== undefined")
        phone.evaluate("() => lagrangian.pause()")
        phone.wait_for_timeout(500)
        phone.locator(".equilibrium").first.screenshot(
            path=str(IMAGES / "page_equilibrium_phone.png")
        )
    for name in ("page_embed.png", "page_equilibrium_phone.png"):
        kept(IMAGES / name)


def double_pendulum_report() -> None:
    """Two pages of ``lagrangian report double_pendulum --to tex`` as pdflatex sets them
    (the derivation, and the normal modes with their numbers), rendered by pdftoppm or
    mutool, whichever is installed."""
    import subprocess

    from lagrangian.output.worked_solution import worked_solution, write_report

    pdflatex = shutil.which("pdflatex")
    renderer = shutil.which("pdftoppm") or shutil.which("mutool")
    if pdflatex is None or renderer is None:
        raise SystemExit("the report's pictures need pdflatex and pdftoppm (or mutool)")
    with tempfile.TemporaryDirectory() as folder:
        write_report(worked_solution(lg.load("double_pendulum")), Path(folder) / "report.tex")
        for _ in range(2):  # the second run settles the floats
            subprocess.run(
                [pdflatex, "-interaction=nonstopmode", "-halt-on-error", "report.tex"],
                cwd=folder,
                check=True,
                capture_output=True,
            )
        for page, name in (
            (2, "report_double_pendulum_steps.png"),
            (3, "report_double_pendulum_modes.png"),
        ):
            target = IMAGES / name
            if Path(renderer).name == "pdftoppm":
                command = [renderer, "-png", "-r", str(DPI), "-f", str(page), "-l", str(page),
                           "-singlefile", "report.pdf", str(target.with_suffix(""))]  # fmt: skip
            else:
                command = [
                    renderer,
                    "draw",
                    "-r",
                    str(DPI),
                    "-o",
                    str(target),
                    "report.pdf",
                    str(page),
                ]
            subprocess.run(command, cwd=folder, check=True, capture_output=True)
            kept(target)


def serve_editor() -> None:
    """A screenshot of `lagrangian serve`: the editor beside the double pendulum's page,
    taken by Debian's Chromium through Playwright."""
    import os
    import re
    import signal
    import subprocess

    sources = Path(__file__).resolve().parents[1] / "src"
    server = subprocess.Popen(
        [sys.executable, "-m", "lagrangian", "serve", "--port", "0"],
        stdout=subprocess.PIPE,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(sources)),
    )
    try:
        url = re.search(r"http://\S+", server.stdout.readline())[0]
        with chromium() as browser:
            page = browser.new_page(viewport={"width": 1280, "height": 760})
            page.set_default_timeout(120_000)
            page.goto(url)
            page.locator("#status", has_text="derived in").wait_for()
            page.wait_for_timeout(3000)  # the page's typesetting and a few frames of motion
            picture = IMAGES / "serve_editor.png"
            page.screenshot(path=picture)
    finally:
        server.send_signal(signal.SIGINT)
        server.wait(timeout=30)
    kept(picture)


#: The Baker-Gollub pendulum's drive period 2 pi / (2/3).
DRIVE_PERIOD = 3 * np.pi


def henon_heiles() -> None:
    """Sections x = 0 at E = 1/12, 1/8 and just below the escape energy 1/6 (at 1/6 the
    shell opens along y = 1): islands breaking into a chaotic sea."""
    system = lg.load("henon_heiles")
    figure, axes = new_figure(1, 3, width=12.0, height=4.4)
    energies = (("1/12", 1 / 12), ("1/8", 1 / 8), ("0.1666 ≈ 1/6", 0.1666))
    for ax, (label, energy) in zip(axes[0], energies, strict=True):
        points = system.poincare(
            section="x = 0",
            axes=("y", "p_y"),
            energy=energy,
            orbits=16,
            t_end=400,
            rtol=1e-9,
            timeout=None,
        )
        colours = [f"C{k % 10}" for k in points.orbits]
        ax.scatter(points["y"], points["p_y"], s=0.6, c=colours, linewidths=0, rasterized=True)
        ax.set_title(f"E = {label} ({points.count} points)", fontsize=10)
        ax.set_xlabel("$y$")
        ax.grid(True, alpha=0.3)
    axes[0, 0].set_ylabel("$p_y$")
    figure.suptitle("Hénon–Heiles: section x = 0, ẋ > 0, 16 orbits per energy")
    save(figure, "henon_heiles_sections.png")
    save(system.lyapunov(t_end=500, interval=2.0).plot(), "henon_heiles_lyapunov.png")


def henon_heiles_sali() -> None:
    """Regular and chaotic starts of Hénon–Heiles on the section x = 0 at E = 1/8 by SALI
    up to t = 750 (the ``sali`` observable of an ensemble, numba; x' > 0 from the energy):
    each chaotic start coloured by the time its SALI fell below 1e-4, the regular ones
    (never) white."""
    from lagrangian.derive import derive
    from lagrangian.ensemble import run_ensemble

    compiled = compile_equations(derive(lg.load("henon_heiles")))
    y, py = np.meshgrid(np.linspace(-0.45, 0.7, 60), np.linspace(-0.5, 0.5, 60))
    kinetic = 2 * (0.125 - (y**2 / 2 - y**3 / 3)) - py**2
    inside = kinetic > 1e-6
    initial = {"x": 0 * y[inside], "y": y[inside], "x_dot": np.sqrt(kinetic[inside])}
    initial["y_dot"] = py[inside]
    result = run_ensemble(
        compiled, initial=initial, t_end=750.0, dt=0.05, observables=("sali",), backend="numba"
    )
    values = np.full(y.shape, np.nan)
    values[inside] = result.dataset["sali_time"].values
    figure, axes = new_figure(width=6.5, height=5.0)
    axes[0, 0].contour(y, py, np.where(inside, 0.0, 1.0), levels=[0.5], colors="grey")
    image = axes[0, 0].pcolormesh(y, py, np.ma.masked_invalid(values), cmap="viridis")
    figure.colorbar(image, ax=axes[0, 0], label="time SALI fell below 1e-4 (white: never)")
    axes[0, 0].set_xlabel("$y$")
    axes[0, 0].set_ylabel("$p_y$")
    share = float(np.mean(result.dataset["sali_chaotic"].values))
    axes[0, 0].set_title(f"Hénon–Heiles, E = 1/8, x = 0: {share:.0%} of the starts chaotic")
    save(figure, "henon_heiles_sali.png")


def driven_pendulum() -> None:
    """The strange attractor (stroboscopic section) and the period-doubling diagram."""
    system = lg.load("driven_damped_pendulum")
    points = system.poincare(
        strobe=DRIVE_PERIOD, transient=100, axes=("theta", "theta_dot"), t_end=10_000,
        rtol=1e-8, atol=1e-10, timeout=None,
    )  # fmt: skip
    save(points.plot(size=1.0), "driven_pendulum_attractor.png")
    diagram = system.bifurcation(
        vary={"A": np.linspace(1.35, 1.5, 300)}, variable="theta_dot", period=DRIVE_PERIOD,
        transient=300, samples=60, backend="numba", timeout=None,
    )  # fmt: skip
    save(diagram.plot(size=0.5), "driven_pendulum_bifurcation.png")


def driven_pendulum_continuation() -> None:
    """The period-doubling cascade followed by continuation, over the brute-force diagram
    (what ``lagrangian orbits --vary A=1.05:1.084:35 --out F.png`` draws, with a
    background of 300 values)."""
    system = lg.load("driven_damped_pendulum")
    result = system.continuation(
        vary={"A": (1.05, 1.084, 35)}, strobe=DRIVE_PERIOD, attractor=3, timeout=None
    )
    diagram = system.bifurcation(
        vary={"A": np.linspace(1.05, 1.084, 300)}, variable="theta_dot", period=DRIVE_PERIOD,
        transient=300 * DRIVE_PERIOD, samples=40, backend="numba", timeout=None,
    )  # fmt: skip
    save(plot_continuation(result, "theta_dot", diagram), "driven_pendulum_continuation.png")


def driven_pendulum_basins() -> None:
    """The basins of the two period-2 attractors of the driven pendulum at A = 1.073."""
    from lagrangian.ensemble.system import basins_of_system
    from lagrangian.output.basins import plot_basins

    system = lg.load("driven_damped_pendulum")
    grid = {"theta": (-np.pi, np.pi, 400), "theta_dot": (-3.0, 3.0, 400)}
    basins = basins_of_system(
        system, grid=grid, period=DRIVE_PERIOD, params={"A": 1.073}, timeout=None
    )
    save(plot_basins(basins), "driven_pendulum_basins.png")


def driven_pendulum_sensitivity() -> None:
    """d theta(t) / d(b, l, theta(0)) of the driven pendulum in its regular regime."""
    system = lg.load("driven_damped_pendulum")
    result = system.sensitivities(["b", "l", "theta"], t_end=20.0, params={"A": 0.5})
    save(plot_sensitivities(result), "driven_pendulum_sensitivity.png")


def lab_pendulum_fit() -> None:
    """The lab example: the filmed pendulum's data, the fit of l, gamma and theta(0), and
    the residuals (README: ``lagrangian fit docs/lab/...``)."""
    lab = Path(__file__).resolve().parent / "lab"
    system = lg.load(lab / "damped_pendulum.toml")
    result = system.fit(lab / "pendulum.csv", ["l", "gamma", "theta"], noise="0.3 deg")
    save(plot_fit(result, system, residuals=True), "lab_pendulum_fit.png")


PICTURES = (
    simple_pendulum,
    velocity_dependent_potential,
    harmonic_oscillator,
    central_force,
    spherical_pendulum,
    double_pendulum,
    double_pendulum_flip_map,
    double_pendulum_page,
    page_share_and_embed,
    double_pendulum_report,
    exercise_page,
    vertical_spring,
    free_particle_spherical,
    planar_particle_forces,
    rotating_wire_bead,
    heavy_top,
    linkages,
    impacts,
    cart_pole,
    serve_editor,
    henon_heiles,
    henon_heiles_section_panel,
    henon_heiles_sali,
    driven_pendulum,
    driven_pendulum_continuation,
    driven_pendulum_basins,
    driven_pendulum_sensitivity,
    lab_pendulum_fit,
)


def main(argv: list[str]) -> None:
    IMAGES.mkdir(exist_ok=True)
    for make in PICTURES:
        if argv and not any(word in make.__name__ for word in argv):
            continue
        start = time.perf_counter()
        print(make.__name__)
        make()
        print(f"  ({time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main(sys.argv[1:])
