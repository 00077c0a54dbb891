"""Pages made in a worker process within a time budget; a stuck or dead worker is replaced."""

from __future__ import annotations

import os
import signal

import pytest

from lagrangian.serve.worker import PageWorker, render

OSCILLATOR = "m*x_dot**2/2 - k*x**2/2"


def chain_text(links: int) -> str:
    """A model file of a planar chain of ``links`` pendulums (5 links: a minute of CPU
    for a page, the derivation's and analysis' symbolic work growing fast with links)."""
    names = ", ".join(f'"theta{i}"' for i in range(1, links + 1))
    lines = [f'name = "Chain of {links}"', f"coordinates = [{names}]", "", "[parameters]"]
    lines += [f"m{i} = 1.0\nl{i} = 1.0" for i in range(1, links + 1)] + ["g = 9.81"]
    x, y = "0", "0"
    for i in range(1, links + 1):
        x, y = f"{x} + l{i}*sin(theta{i})", f"{y} - l{i}*cos(theta{i})"
        lines += ["", "[[particles]]", f'name = "bob{i}"', f'mass = "m{i}"']
        lines.append(f'position = ["{x}", "{y}"]')
    lines += ["", "[gravity]", 'g = "g"', "direction = [0, -1]"]
    return "\n".join(lines) + "\n"


def test_render_gives_the_page_or_the_error_line():
    assert render(OSCILLATOR).page.lower().startswith("<!doctype html")
    assert render(OSCILLATOR).error is None
    bad = render("x_dot**2 + )")
    assert bad.page is None
    assert bad.error == "editor: lagrangian: unexpected ')' at position 12 in 'x_dot**2 + )'"


def test_render_makes_the_exercise_page_on_request():
    def asked(page: str) -> bool:
        return '"exercise": {' in page

    assert not asked(render(OSCILLATOR).page)
    assert asked(render(OSCILLATOR, exercise=True).page)


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


def test_a_stage_out_of_time_is_said_and_its_page_marked(monkeypatch):
    # the page is made with the stage said undecided; the worker must learn that a
    # deadline ran out (its process is then replaced), and the page is not kept
    from lagrangian.output import page_content

    own_budget = page_content.ANALYSIS_SECONDS
    monkeypatch.setattr(page_content, "ANALYSIS_SECONDS", 1e-6)
    rendered = render(OSCILLATOR)
    assert rendered.error is None
    assert "not decided within 1e-06 s" in rendered.page
    assert rendered.timed_out
    # the deadlines restored: the next page, with the stages' own budgets, is decided (with
    # 1e-6 s a stage is not: that it was came from the enclosing deadlines' ends drifting)
    monkeypatch.setattr(page_content, "ANALYSIS_SECONDS", own_budget)
    assert not render("m*x_dot**2/2", seconds=60.0).timed_out
    out_of_time = render(OSCILLATOR, seconds=1e-6)
    assert out_of_time.page is None and out_of_time.timed_out


@pytest.mark.slow
def test_a_worker_that_ran_out_of_time_is_replaced_before_the_next_edit():
    # issue 37 item 1: a worker in which a deadline ran out served every later edit
    # "not decided within 5 s"; now it never serves another: the next edit (the
    # harmonic oscillator, 0.6 s of CPU) gets a page from a fresh process
    worker = PageWorker(seconds=2.0)
    try:
        worker.start()
        first = worker._process.pid
        costly = worker.render(chain_text(5))
        assert costly.error == (
            "page: not decided within 2 s: the model is too costly to derive here"
        )
        assert worker._process.pid != first  # replaced at once, importing meanwhile
        page = worker.render(OSCILLATOR)
        assert page.error is None and "Lagrange" in page.page
    finally:
        worker.close()


@pytest.mark.slow
def test_a_worker_killed_during_a_page_is_reported_by_its_signal():
    # issue 37 item 13: the pipe closes an instant before the process is reaped, and
    # the message said "exit code None"
    worker = PageWorker()
    try:
        worker.start()
        connection, process = worker._connection, worker._process

        class KilledOnSend:
            def __getattr__(self, name):
                return getattr(connection, name)

            def send(self, text):
                connection.send(text)
                os.kill(process.pid, signal.SIGKILL)

        worker._connection = KilledOnSend()
        killed = worker.render(OSCILLATOR)
        assert killed.error == "the process making the page was killed (SIGKILL); try again"
        assert worker._process is None
    finally:
        worker.close()
