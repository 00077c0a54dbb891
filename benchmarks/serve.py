"""Seconds of a page through `lagrangian serve`, against page_html in this process.

    python benchmarks/serve.py [--repeat 3] [--models harmonic_oscillator,double_pendulum]

For each built-in model: ``page_html`` of the model read from its text, in this process
(``direct``); the same text POSTed to the application (Starlette's TestClient, the real
worker process) with a comment line that makes it new each time (``served``: the worker
reads, derives and analyses it, sends the page through its pipe, the server sends it as
JSON); and the same text again (``kept``: the page kept by text).  Also the seconds the
worker takes to start (import the toolkit) before the server answers, and the size of
the answer.  Printed are medians over ``--repeat`` runs, the runs interleaved; nothing
is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

from lagrangian.examples import example_path
from lagrangian.output.page import page_html
from lagrangian.serve import served_hosts
from lagrangian.serve.app import create_app
from lagrangian.serve.models import model_from_text
from lagrangian.serve.worker import PageWorker

with warnings.catch_warnings():  # Starlette 1.x announces a move of its TestClient to httpx2
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient

ORIGIN = "http://127.0.0.1:8765"


def seconds(work) -> tuple[float, object]:
    start = time.perf_counter()
    result = work()
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--models", default="harmonic_oscillator,double_pendulum")
    options = parser.parse_args()
    models = options.models.split(",")
    texts = {name: example_path(name).read_text() for name in models}
    times: dict[tuple[str, str], list[float]] = {}
    sizes: dict[str, int] = {}
    worker = PageWorker()
    start_seconds, _ = seconds(worker.start)
    app = create_app(worker, hosts=served_hosts("127.0.0.1", 8765))
    with TestClient(app, base_url=ORIGIN) as client:

        def post(text: str):
            response = client.post("/page", content=text.encode(), headers={"Origin": ORIGIN})
            answer = response.json()
            if "page" not in answer:
                raise SystemExit(f"no page: {answer}")
            return response

        for run in range(options.repeat):
            for name in models:
                text = f"# run {run}\n{texts[name]}"
                direct, _ = seconds(lambda text=text: page_html(model_from_text(text)))
                served, response = seconds(lambda text=text: post(text))
                kept, _ = seconds(lambda text=text: post(text))
                sizes[name] = len(response.content)
                for kind, value in (("direct", direct), ("served", served), ("kept", kept)):
                    times.setdefault((name, kind), []).append(value)
    print(f"worker start (imports, once): {start_seconds:.2f} s")
    print(f"{'model':24s} {'direct':>9s} {'served':>9s} {'kept':>9s} {'answer':>10s}")
    for name in models:
        kinds = ("direct", "served", "kept")
        median = {kind: statistics.median(times[name, kind]) for kind in kinds}
        print(
            f"{name:24s} {median['direct']:8.2f}s {median['served']:8.2f}s "
            f"{median['kept']:8.3f}s {sizes[name] / 1e6:8.2f} MB"
        )


if __name__ == "__main__":
    main()
