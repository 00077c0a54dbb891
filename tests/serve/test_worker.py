"""Pages made in a worker process within a time budget; a stuck or dead worker is replaced."""

from __future__ import annotations

import os
import signal

import pytest

from lagrangian.serve.worker import PageWorker, render

OSCILLATOR = "m*x_dot**2/2 - k*x**2/2"


def test_render_gives_the_page_or_the_error_line():
    assert render(OSCILLATOR).page.lower().startswith("<!doctype html")
    assert render(OSCILLATOR).error is None
    bad = render("x_dot**2 + )")
    assert bad.page is None
    assert bad.error == "editor: lagrangian: unexpected ')' at position 12 in 'x_dot**2 + )'"


def test_render_stops_a_model_out_of_time():
    rendered = render(OSCILLATOR, seconds=1e-6)
    assert rendered.page is None
    assert rendered.error.startswith("page: not decided within 1e-06 s")


@pytest.mark.slow
def test_a_dead_or_stuck_worker_is_replaced_and_pages_are_kept():
    worker = PageWorker(seconds=60.0, grace=0.5)  # a busy machine may take seconds a page
    other = "m*x_dot**2/2 - k*x**4/4"
    try:
        worker.start()
        os.kill(worker._process.pid, signal.SIGKILL)  # died between two pages
        worker._process.join(timeout=60)
        page = worker.render(OSCILLATOR).page
        assert page is not None
        os.kill(worker._process.pid, signal.SIGSTOP)  # stuck where no deadline reaches
        assert worker.render(OSCILLATOR).page == page  # kept: the worker is not asked
        worker.seconds = 0.25  # waited for: 4 x 0.25 + 0.5 s (CPU seconds stretched by load)
        stuck = worker.render(other)
        assert stuck.error == "page: not made within 1.5 s; stopped"
        assert worker._process is None  # killed
        worker.seconds = 60.0
        assert worker.render(other).page is not None
    finally:
        worker.close()
    assert worker._process is None
