"""``lagrangian serve``: a local web editor of models, each edit shown as the model's page.

The browser shows an editor (a model file in TOML, or a Lagrangian alone; the
built-in examples in a menu) beside the page of the model
(:func:`lagrangian.output.page.page_html`) in a sandboxed frame.  Each edit is sent
to the server, which reads, derives and analyses the model in a worker process
within the time budgets (:mod:`.worker`), and answers with the new page or with the
model's one-line error, shown beside the editor while the last good page stays.

The layers: a thin shell like the CLI, above the facade and below the CLI, with no
physics of its own.  Starlette and uvicorn (the optional extra ``serve``) are
imported only here, when a server is made.

    serve(host="127.0.0.1", port=8765, *, allow_remote=False, allowed_hosts=(),
          announce=print, warn=...)
    create_app(renderer, hosts=...)            the ASGI application (:mod:`.app`)
    check_host(host, allow_remote=False)       loopback only, unless told otherwise
    served_hosts(host, port, allowed=())       the Host headers answered (:mod:`.hosts`)
"""

from __future__ import annotations

import contextlib
import socket
import sys
from collections.abc import Callable, Iterable

from ..errors import LagrangianError, MissingDependencyError
from .hosts import bare, check_host, in_url, is_loopback, is_wildcard, served_hosts

#: The address the server listens on unless told otherwise: this machine only.
DEFAULT_HOST = "127.0.0.1"
#: The port the server listens on unless told otherwise (0: any free port).
DEFAULT_PORT = 8765


def _warn_on_stderr(line: str) -> None:
    print(f"lagrangian: warning: {line}", file=sys.stderr, flush=True)


def serve(
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    *,
    allow_remote: bool = False,
    allowed_hosts: Iterable[str] = (),
    announce: Callable[[str], object] = print,
    warn: Callable[[str], object] = _warn_on_stderr,
) -> None:
    """Serve the editor at http://host:port until interrupted (Ctrl-C).

    ``announce`` receives the line that gives the address (with the port chosen, for
    port 0) once the server listens; ``warn`` a line first when other machines can
    reach it.  ``allowed_hosts``: more names the server answers for (a proxy's, a DNS
    name of this machine); see :mod:`.hosts`.
    """
    check_host(host, allow_remote=allow_remote)
    allowed = tuple(allowed_hosts)
    served_hosts(host, 0, allowed=allowed)  # a bad name fails before anything listens
    try:
        import uvicorn

        from .app import create_app
        from .connections import BACKLOG, bounded_config
    except ImportError as error:
        raise MissingDependencyError(
            "lagrangian serve", error.name or "starlette", "serve"
        ) from None
    from .worker import PageWorker

    listening = _listen(host, port, BACKLOG)
    port = listening.getsockname()[1]
    hosts = served_hosts(host, port, allowed=allowed)
    app = create_app(PageWorker(), hosts=hosts)
    if not is_loopback(host):
        warn(remote_warning(host, hosts.any_own_address))
    announce(f"the model editor is at http://{in_url(host)}:{port}/ (Ctrl-C stops it)")
    with contextlib.suppress(KeyboardInterrupt), listening:
        uvicorn.Server(bounded_config(app)).run(sockets=[listening])


def remote_warning(host: str, every_address: bool) -> str:
    """The line that says who can reach a server listening on ``host`` (not loopback)."""
    where = "every address of this machine" if every_address else in_url(host)
    return (
        f"the editor listens on {where}: any machine that reaches it can make this machine "
        "derive models (it answers only requests that name this machine: its names and "
        "addresses, and the names allowed)"
    )


def _listen(host: str, port: int, backlog: int) -> socket.socket:
    """A socket listening on host:port, or one line saying why there is none."""
    try:
        family, kind, protocol, _, address = socket.getaddrinfo(
            bare(host), port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE
        )[0]
        listening = socket.socket(family, kind, protocol)
    except (OSError, UnicodeError) as error:
        raise LagrangianError(f"cannot listen on {host}:{port}: {_reason(error)}") from None
    try:
        listening.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listening.bind(address)
        listening.listen(backlog)
    except OSError as error:
        listening.close()
        raise LagrangianError(f"cannot listen on {host}:{port}: {_reason(error)}") from None
    return listening


def _reason(error: Exception) -> str:
    return getattr(error, "strerror", None) or str(error)


__all__ = [
    "DEFAULT_HOST",
    "DEFAULT_PORT",
    "check_host",
    "is_loopback",
    "is_wildcard",
    "remote_warning",
    "serve",
    "served_hosts",
]
