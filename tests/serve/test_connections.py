"""The server's bounds on connections (issue 37 item 4): requests that never arrive
whole are closed, connections beyond the cap are refused, each kind of refusal is
logged once per interval.

A real uvicorn server on 127.0.0.1 (a port of the system's choosing) with a stand-in
renderer, in a thread; the bounds are made small so that the test is quick, and every
wait is bounded by a socket time-out, never a sleep.
"""

from __future__ import annotations

import logging
import socket
import threading

import pytest

pytest.importorskip("uvicorn", reason="the serve extra (uvicorn) is not installed")

from lagrangian.serve import connections, served_hosts
from lagrangian.serve.app import create_app
from lagrangian.serve.connections import OncePerInterval, bounded_config
from lagrangian.serve.worker import Rendered

#: Seconds any one wait of the test may take (a bound for a hang, not a measurement).
WAIT_SECONDS = 60


class Held:
    """A renderer that answers once the test lets it."""

    def __init__(self):
        self.rendering, self.release = threading.Event(), threading.Event()

    def start(self) -> None:
        pass

    def render(self, text: str) -> Rendered:
        self.rendering.set()
        self.release.wait(WAIT_SECONDS)
        return Rendered(page="<p>page</p>")

    def close(self) -> None:
        self.release.set()


class Lines(logging.Handler):
    def __init__(self):
        super().__init__()
        self.lines: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.lines.append(record.getMessage())


@pytest.fixture
def server(monkeypatch):
    """(port, renderer, logged lines) of a running server with small bounds."""
    import uvicorn

    monkeypatch.setattr(connections, "MAX_CONNECTIONS", 4)
    # a request deadline far longer than opening the test's connections takes on a busy
    # machine, and one log line of a kind per test however long it runs
    monkeypatch.setattr(connections, "REQUEST_SECONDS", 2.0)
    monkeypatch.setattr(connections, "LOG_INTERVAL_SECONDS", 3600.0)
    listening = socket.create_server(("127.0.0.1", 0))
    port = listening.getsockname()[1]
    renderer = Held()
    instance = uvicorn.Server(
        bounded_config(create_app(renderer, hosts=served_hosts("127.0.0.1", port)))
    )
    lines = Lines()
    logger = logging.getLogger("uvicorn.error")
    logger.addHandler(lines)
    thread = threading.Thread(target=instance.run, kwargs={"sockets": [listening]})
    thread.start()
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=WAIT_SECONDS) as probe:
            probe.sendall(get(port))  # answered once the server has started
            assert answer(probe).startswith(b"HTTP/1.1 200 ")  # and closed: not counted
        yield port, renderer, lines.lines
    finally:
        renderer.release.set()
        instance.should_exit = True
        thread.join(WAIT_SECONDS)
        logger.removeHandler(lines)
        listening.close()


def get(port: int) -> bytes:
    return f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n".encode()


def half_sent(port: int) -> socket.socket:
    """A connection whose request never ends its headers."""
    connection = socket.create_connection(("127.0.0.1", port), timeout=WAIT_SECONDS)
    connection.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n".encode())
    return connection


def answer(connection: socket.socket) -> bytes:
    """Everything the server sends until it closes the connection."""
    received = b""
    while chunk := connection.recv(65536):
        received += chunk
    return received


def refusal(connection: socket.socket) -> str:
    """How the server ended a connection it refused: "503" (its answer came first),
    "reset" (the unread request reset it before), "closed" (nothing said)."""
    try:
        received = answer(connection)
    except ConnectionResetError:
        return "reset"
    return "503" if received.startswith(b"HTTP/1.1 503 ") else "closed"


def test_half_sent_requests_are_closed_and_the_rest_refused_once_logged(server):
    port, _, lines = server
    held = [half_sent(port) for _ in range(4)]  # the cap
    refused = [half_sent(port) for _ in range(6)]
    try:
        for connection in refused:  # a 503, unless the request's unread bytes reset it first
            assert refusal(connection) in ("503", "reset")
        for connection in held:  # closed by the server once their time ran out
            assert answer(connection) == b""
        with socket.create_connection(("127.0.0.1", port), timeout=WAIT_SECONDS) as editor:
            editor.sendall(get(port))
            assert answer(editor).startswith(b"HTTP/1.1 200 ")
    finally:
        for connection in held + refused:
            connection.close()
    # one line of each kind in the interval, not one per event
    assert lines == [
        "refused a connection: 4 are open, the most at once",
        "closed a connection whose request had not arrived whole within 2 s",
    ]


def test_a_request_that_arrived_whole_is_answered_however_long_it_takes(server):
    port, renderer, _ = server
    origin = f"http://127.0.0.1:{port}"
    body = b"m*x_dot**2/2"
    with socket.create_connection(("127.0.0.1", port), timeout=WAIT_SECONDS) as posting:
        posting.sendall(
            f"POST /page HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: {origin}\r\n"
            f"Content-Length: {len(body)}\r\nConnection: close\r\n\r\n".encode()
            + body
        )
        assert renderer.rendering.wait(WAIT_SECONDS)
        with half_sent(port) as later:  # its deadline is due after the POST's
            assert answer(later) == b""
        renderer.release.set()
        assert answer(posting).startswith(b"HTTP/1.1 200 ")


def test_each_kind_of_message_is_logged_once_per_interval():
    now = [0.0]
    once = OncePerInterval(10.0, clock=lambda: now[0])

    def passes(message: str, name: str = "uvicorn.error") -> str | None:
        record = logging.LogRecord(name, logging.WARNING, "", 0, message, None, None)
        return record.getMessage() if once.filter(record) else None

    assert passes("refused") == "refused"
    assert passes("refused") is None
    assert passes("closed") == "closed"  # another kind
    assert passes("refused", "asyncio") == "refused"  # another logger
    now[0] = 9.9
    assert passes("refused") is None
    now[0] = 10.0
    assert passes("refused") == "refused (2 more like it in the last 10 s)"
    now[0] = 25.0
    assert passes("refused") == "refused"
    # asyncio's messages run over lines (the socket, the traceback): the first one is the kind
    now[0] = 40.0
    assert passes("socket.accept() out of system resource\nsocket: <fd=3>") is not None
    assert passes("socket.accept() out of system resource\nsocket: <fd=4>") is None


def test_a_body_that_never_arrives_whole_is_closed_without_an_error_logged(server):
    port, renderer, lines = server
    origin = f"http://127.0.0.1:{port}"
    with socket.create_connection(("127.0.0.1", port), timeout=WAIT_SECONDS) as posting:
        posting.sendall(
            f"POST /page HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: {origin}\r\n"
            "Content-Length: 100\r\n\r\nm*x_dot**2".encode()  # 10 of the 100 bytes
        )
        assert answer(posting) == b""
    with socket.create_connection(("127.0.0.1", port), timeout=WAIT_SECONDS) as editor:
        editor.sendall(get(port))  # answered after the request given up has been handled
        assert answer(editor).startswith(b"HTTP/1.1 200 ")
    # the application saw the client go (no "Exception in ASGI application"), and
    # derived nothing
    assert lines == ["closed a connection whose request had not arrived whole within 2 s"]
    assert not renderer.rendering.is_set()
