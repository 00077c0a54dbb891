"""The page (``lagrangian page``): write time, size, and the live animation in Chromium.

    python benchmarks/page.py [--repeat 3] [--links 10] [--seconds 10] [--skip write|browser]

1. Write time of the double pendulum's page: ``lagrangian page double_pendulum`` as a
   child process (interpreter start-up and imports included), median of ``--repeat`` of
   the wall time and of the CPU time (user + sys, the child's children included: SymPy's
   solve of the equilibria runs in one); the same for two systems not among the examples
   (a 3-link chain, a spring pendulum), so that a gain is not one model's.  "cold" is a page
   made anew (``--no-cache``: the target), "warm" one written from the cache of pages (a
   folder of this run, filled by one run first).  Then, in this process, the parts of one
   ``page_html`` (derive, analyse, the generated code, the rest) timed by wrapping them.
2. Page size (bytes) of the double pendulum and of the ``--links`` chain.
3. The ``--links`` chain (benchmarks/cli.py's n-link pendulum, theta1 = 0.5) animating in
   headless Chromium (Debian's, driven by Playwright) for ``--seconds`` of wall time at
   speed 1: frames per second, the ms of page work per frame (integration, drawing,
   plots), DOP853 steps per simulated second, simulated seconds per wall second (1.0 =
   real time), and a synchronous ``run(10)`` from the start; beside it, the frames per
   second of an empty page that only draws a square (the browser on this machine now).

The machine may be shared: the load average is printed beside the figures.  Nothing is
asserted.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import lagrangian as lg
from cli import chain_model
from lagrangian.output import page, page_content

#: A spring pendulum: a bob on a spring hung from the origin (not an example model).
SPRING_PENDULUM = """
name = "Spring pendulum"
coordinates = ["r", "theta"]

[parameters]
m = 1.0
k = 20.0
r0 = 1.0
g = 9.81

[[particles]]
name = "bob"
mass = "m"
position = ["r*sin(theta)", "-r*cos(theta)"]

[[springs]]
ends = [[0, 0], "bob"]
stiffness = "k"
rest_length = "r0"

[gravity]
g = "g"
direction = [0, -1]

[initial]
r = 1.2
theta = 0.8
"""


def write_seconds(
    model: str, repeat: int, folder: Path, *, warm: bool = False
) -> tuple[list[float], list[float]]:
    """Wall and CPU seconds (user + sys of the process and its children) of ``repeat``
    runs of ``lagrangian page MODEL``: made anew, or (``warm``) from the cache of pages in
    ``folder``, filled by a run before the timed ones."""
    environment = dict(os.environ, LAGRANGIAN_CACHE=str(folder / "cache"))
    flags = [] if warm else ["--no-cache"]
    if warm:
        out = folder / f"{Path(model).stem}_fill.html"
        command = [sys.executable, "-m", "lagrangian", "page", model, "--out", str(out)]
        subprocess.run(command, check=True, capture_output=True, env=environment)
    wall, cpu = [], []
    for k in range(repeat):
        out = folder / f"{Path(model).stem}_{k}.html"
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "lagrangian", "page", model, "--out", str(out), *flags],
            check=True,
            capture_output=True,
            env=environment,
        )
        wall.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    return wall, cpu


def print_write_times(repeat: int, folder: Path) -> None:
    (folder / "chain3.toml").write_text(chain_model(3), encoding="utf-8")
    (folder / "spring_pendulum.toml").write_text(SPRING_PENDULUM, encoding="utf-8")
    models = ["double_pendulum", str(folder / "chain3.toml"), str(folder / "spring_pendulum.toml")]
    for model in models:
        for warm in (False, True):
            wall, cpu = write_seconds(model, repeat, folder, warm=warm)
            size = (folder / f"{Path(model).stem}_0.html").stat().st_size
            print(
                f"lagrangian page {Path(model).stem} (a process, {'warm' if warm else 'cold'}):"
                f" median {statistics.median(wall):.2f} s wall of"
                f" {', '.join(f'{s:.2f}' for s in wall)}; CPU (user + sys) median"
                f" {statistics.median(cpu):.2f} s of {', '.join(f'{s:.2f}' for s in cpu)};"
                f" {size:,} bytes; load average {os.getloadavg()[0]:.1f}"
            )


def parts_of_one_write(system) -> dict[str, float]:
    """Seconds in derive, analyze and the code of one page_html (in this process)."""
    spent = {"derive": 0.0, "analyze": 0.0, "code": 0.0}
    originals = {
        "derive": page_content.derive,
        "analyze": page_content.analyze,
        "code": page_content._script,
    }

    def timed(name):
        def wrapper(*args, **kwargs):
            start = time.perf_counter()
            try:
                return originals[name](*args, **kwargs)
            finally:
                spent[name] += time.perf_counter() - start

        return wrapper

    page_content.derive, page_content.analyze = timed("derive"), timed("analyze")
    page_content._script = timed("code")
    try:
        start = time.perf_counter()
        page.page_html(system)
        total = time.perf_counter() - start
    finally:
        page_content.derive = originals["derive"]
        page_content.analyze = originals["analyze"]
        page_content._script = originals["code"]
    spent["rest"] = total - sum(spent.values())
    spent["total"] = total
    return spent


def animation(path: Path, seconds: float) -> dict:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        return {"skipped": "no chromium on the PATH"}
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        tab = browser.new_page(viewport={"width": 1300, "height": 900})
        baseline = _empty_page_fps(tab)
        baseline_cpu = frame_cpu(tab)
        tab.goto(path.resolve().as_uri())
        tab.wait_for_function("() => window.lagrangian !== undefined")
        tab.evaluate("() => { lagrangian.reset(); lagrangian.play(); }")
        samples = []
        start = time.perf_counter()
        t0 = tab.evaluate("() => lagrangian.state().t")
        while time.perf_counter() - start < seconds:
            tab.wait_for_timeout(1000)
            samples.append(tab.evaluate("() => lagrangian.stats()"))
        wall = time.perf_counter() - start
        simulated = tab.evaluate("() => lagrangian.state().t") - t0
        cpu = frame_cpu(tab)
        begin = time.perf_counter()
        tab.evaluate("() => { lagrangian.pause(); lagrangian.reset(); lagrangian.run(10); }")
        run_wall = time.perf_counter() - begin
        steps = tab.evaluate("() => lagrangian.stats().steps")
        browser.close()
    steady = samples[1:] or samples  # the first second includes the start
    return {
        "baseline_fps": baseline,
        "baseline_cpu": baseline_cpu,
        "cpu": cpu,
        "fps": statistics.median(s["fps"] for s in steady),
        "frame_ms": statistics.median(s["frame_ms"] for s in steady),
        "steps_per_second": samples[-1]["steps_per_second"],
        "pace": simulated / wall,
        "run10_wall": run_wall,
        "run10_steps": steps,
    }


#: A page that only counts its animation frames: what this browser on this machine gives.
_EMPTY = """<canvas width="600" height="600"></canvas><script>
window.frames_counted = 0;
const c = document.querySelector("canvas").getContext("2d");
function frame() {
  window.frames_counted += 1;
  c.clearRect(0, 0, 600, 600);
  c.fillRect(window.frames_counted % 600, 10, 20, 20);
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
</script>"""


def frame_cpu(tab, seconds: float = 3.0) -> dict[str, float]:
    """Thread CPU time per animation frame (ms), from a Chromium trace (CDP ``Tracing``) of
    ``seconds`` of the page running: the renderer's main thread (the page's scripts, style,
    layout, paint) and every thread of the browser together (the compositor, raster,
    GPU process included).  CPU time, not wall time: the load of the machine does not
    enter, only how much work a frame is."""
    client = tab.context.new_cdp_session(tab)
    events: list[dict] = []
    finished: list[bool] = []
    client.on("Tracing.dataCollected", lambda message: events.extend(message["value"]))
    client.on("Tracing.tracingComplete", lambda message: finished.append(True))
    categories = "toplevel,devtools.timeline,disabled-by-default-devtools.timeline.frame"
    client.send("Tracing.start", {"categories": categories, "transferMode": "ReportEvents"})
    tab.wait_for_timeout(seconds * 1000)
    client.send("Tracing.end")
    while not finished:
        tab.wait_for_timeout(100)
    client.detach()
    names = {
        (e["pid"], e["tid"]): e["args"]["name"]
        for e in events
        if e.get("ph") == "M" and e.get("name") == "thread_name"
    }
    main = {key for key, name in names.items() if name == "CrRendererMain"}
    frames = [e for e in events if e.get("name") == "FireAnimationFrame"]
    busiest = max(main, key=lambda key: sum((e["pid"], e["tid"]) == key for e in frames))
    count = sum((e["pid"], e["tid"]) == busiest for e in frames)
    tasks = [e for e in events if e.get("ph") == "X" and "toplevel" in e.get("cat", "")]
    on_main = sum(e.get("tdur", 0) for e in tasks if (e["pid"], e["tid"]) == busiest)
    everywhere = sum(e.get("tdur", 0) for e in tasks)
    return {
        "frames": count,
        "main_ms": on_main / 1000 / max(count, 1),
        "all_ms": everywhere / 1000 / max(count, 1),
    }


def _empty_page_fps(tab, seconds: float = 3.0) -> float:
    tab.set_content(_EMPTY)
    first = tab.evaluate("() => window.frames_counted")
    start = time.perf_counter()
    tab.wait_for_timeout(seconds * 1000)
    counted = tab.evaluate("() => window.frames_counted") - first
    return counted / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--links", type=int, default=10)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument(
        "--skip", choices=("write", "browser"), help="leave out the write times or the browser"
    )
    options = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        if options.skip != "write":
            print_write_times(options.repeat, folder)
            parts = parts_of_one_write(lg.load("double_pendulum"))
            print("  in this process: " + ", ".join(f"{k} {v:.2f} s" for k, v in parts.items()))
        if options.skip == "browser":
            return
        chain = lg.loads(chain_model(options.links))
        start = time.perf_counter()
        text = page.page_html(chain)
        written = time.perf_counter() - start
        path = folder / "chain.html"
        path.write_text(text, encoding="utf-8")
        print(f"{options.links}-link chain: page written in {written:.2f} s, {len(text):,} bytes")
        result = animation(path, options.seconds)
        if "skipped" in result:
            print(f"  animation: skipped, {result['skipped']}")
            return
        empty, busy = result["baseline_cpu"], result["cpu"]
        print(
            f"  an empty page that only draws a square per frame: {result['baseline_fps']:.1f}"
            f" frames/s (the browser on this machine now); CPU per frame (trace of"
            f" {empty['frames']} frames): {empty['main_ms']:.2f} ms on the renderer's main"
            f" thread, {empty['all_ms']:.2f} ms on all threads"
        )
        print(
            f"  the chain's page, CPU per frame (trace of {busy['frames']} frames):"
            f" {busy['main_ms']:.2f} ms on the renderer's main thread, {busy['all_ms']:.2f} ms"
            " on all threads (16.7 ms is one frame at 60 frames/s)"
        )
        print(
            f"  animation in headless Chromium over {options.seconds:g} s: {result['fps']:.1f}"
            f" frames/s, {result['frame_ms']:.2f} ms of page work per frame,"
            f" {result['steps_per_second']:.0f} DOP853 steps per simulated second,"
            f" {result['pace']:.2f} simulated s per wall s;"
            f" run(10): {result['run10_wall']:.2f} s wall, {result['run10_steps']} steps"
        )
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
