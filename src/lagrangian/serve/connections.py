"""The server's connections, bounded: how many, how long a request may take to arrive,
and how often a refusal is logged.

A client that opens connections and never finishes their requests (a thousand of them
took every file descriptor of a process limited to 1024: the editor unreachable, and
asyncio's "socket.accept() out of system resource" with its traceback on stderr at
10 MB/s) is met by three bounds:

* at most :data:`MAX_CONNECTIONS` are open at once; one more is answered 503 and
  closed at once (a browser opens six to a server);
* a request must arrive whole (headers and body) within :data:`REQUEST_SECONDS` of its
  connection opening, or of the previous response on it; else the connection is
  closed (an idle one between requests is closed by uvicorn's keep-alive timeout,
  :data:`KEEP_ALIVE_SECONDS`);
* each kind of message of the server's loggers is printed at most once per
  :data:`LOG_INTERVAL_SECONDS`, with the count of those left out since.

The server listens with a backlog of :data:`BACKLOG`, so that one burst of accepted
connections (asyncio accepts up to the backlog before any is served) stays far below
the descriptor limit too.
"""

from __future__ import annotations

import asyncio
import logging
import time

import h11
import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol

#: Connections open at once; more are refused (503).
MAX_CONNECTIONS = 64
#: Seconds a request has to arrive whole, from its connection's start or the last response.
REQUEST_SECONDS = 10.0
#: Seconds an idle connection is kept between requests (uvicorn's keep-alive timeout).
KEEP_ALIVE_SECONDS = 5
#: Connections waiting to be accepted (the listening socket's backlog, and so the most
#: that asyncio accepts in one go).
BACKLOG = 128
#: Seconds between two messages of one kind in the server's log.
LOG_INTERVAL_SECONDS = 10.0
#: The loggers whose messages come once per interval: uvicorn's and asyncio's.
RATE_LIMITED_LOGGERS = ("uvicorn.error", "asyncio")

_BUSY = (
    b"HTTP/1.1 503 Service Unavailable\r\nconnection: close\r\ncontent-type: text/plain\r\n"
    b"content-length: 42\r\n\r\nthe editor has too many connections open\r\n"
)
# The client's states in which its request has not arrived whole.
_ARRIVING = (h11.IDLE, h11.SEND_BODY)


class BoundedH11Protocol(H11Protocol):
    """uvicorn's HTTP/1.1 protocol with the bounds of this module."""

    def connection_made(self, transport: asyncio.BaseTransport) -> None:  # type: ignore[override]
        self._deadline: asyncio.TimerHandle | None = None
        self._refused = len(self.connections) >= MAX_CONNECTIONS
        if self._refused:
            self.logger.warning(
                "refused a connection: %d are open, the most at once", MAX_CONNECTIONS
            )
            transport.write(_BUSY)  # type: ignore[attr-defined]
            transport.close()
            return
        super().connection_made(transport)  # type: ignore[arg-type]
        self._arm()

    def connection_lost(self, exc: Exception | None) -> None:
        if self._refused:
            return
        self._disarm()
        super().connection_lost(exc)

    def on_response_complete(self) -> None:
        super().on_response_complete()
        if not self.transport.is_closing():
            self._arm()  # the next request on this connection has its own time

    def _arm(self) -> None:
        self._disarm()
        self._deadline = self.loop.call_later(REQUEST_SECONDS, self._request_too_slow)

    def _disarm(self) -> None:
        if self._deadline is not None:
            self._deadline.cancel()
            self._deadline = None

    def _request_too_slow(self) -> None:
        self._deadline = None
        if self.conn.their_state in _ARRIVING and not self.transport.is_closing():
            self.logger.warning(
                "closed a connection whose request had not arrived whole within %g s",
                REQUEST_SECONDS,
            )
            self.transport.close()


class OncePerInterval(logging.Filter):
    """Lets each kind of message (its logger and first line, before arguments) through
    once per ``interval`` seconds, saying how many of its kind were left out since."""

    def __init__(self, interval: float = LOG_INTERVAL_SECONDS, clock=time.monotonic):
        super().__init__()
        self.interval, self.clock = interval, clock
        self._last: dict[tuple[str, str], float] = {}
        self._left_out: dict[tuple[str, str], int] = {}

    def filter(self, record: logging.LogRecord) -> bool:
        kind = (record.name, str(record.msg).split("\n", 1)[0])
        now = self.clock()
        last = self._last.get(kind)
        if last is not None and now - last < self.interval:
            self._left_out[kind] = self._left_out.get(kind, 0) + 1
            return False
        self._last[kind] = now
        left_out = self._left_out.pop(kind, 0)
        if left_out:
            record.msg = f"{record.msg} ({left_out} more like it in the last {now - last:.0f} s)"
        return True


def bounded_config(app) -> uvicorn.Config:
    """uvicorn's configuration of the editor's server, with the bounds of this module."""
    config = uvicorn.Config(
        app,
        http=BoundedH11Protocol,
        log_level="warning",
        access_log=False,
        lifespan="on",
        backlog=BACKLOG,
        timeout_keep_alive=KEEP_ALIVE_SECONDS,
    )
    # after the Config, which sets up uvicorn's loggers; one filter of a server's own
    # (an earlier server's in this process, a test's, is replaced with its counts)
    once = OncePerInterval(LOG_INTERVAL_SECONDS)
    for name in RATE_LIMITED_LOGGERS:
        logger = logging.getLogger(name)
        for earlier in [each for each in logger.filters if isinstance(each, OncePerInterval)]:
            logger.removeFilter(earlier)
        logger.addFilter(once)
    return config
