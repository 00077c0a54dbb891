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

    serve(host="127.0.0.1", port=8765, *, allow_remote=False, announce=print)
    create_app(renderer, hosts=...)            the ASGI application (:mod:`.app`)
    check_host(host, allow_remote=False)       loopback only, unless told otherwise
"""

from __future__ import annotations

import contextlib
import ipaddress
import socket
from collections.abc import Callable

from ..errors import LagrangianError, MissingDependencyError, ModelError, setting

#: The address the server listens on unless told otherwise: this machine only.
DEFAULT_HOST = "127.0.0.1"
#: The port the server listens on unless told otherwise (0: any free port).
DEFAULT_PORT = 8765

_LOOPBACK_NAMES = ("localhost", "127.0.0.1", "[::1]")


def check_host(host: str, *, allow_remote: bool = False) -> str:
    """``host`` if the server may listen there: a loopback address (``127.0.0.1``,
    ``::1``, ``localhost``), or any address when ``allow_remote`` says so."""
    if allow_remote or is_loopback(host):
        return host
    raise ModelError(
        f"{host} is not a loopback address: other machines could reach the editor and make "
        f"this machine derive their models (allow it with {setting('allow_remote')})"
    )


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine only (a name other than localhost may not)."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def serve(
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    *,
    allow_remote: bool = False,
    announce: Callable[[str], object] = print,
) -> None:
    """Serve the editor at http://host:port until interrupted (Ctrl-C).

    ``announce`` receives the line that gives the address (with the port chosen, for
    port 0) once the server listens.
    """
    check_host(host, allow_remote=allow_remote)
    try:
        import uvicorn

        from .app import create_app
    except ImportError as error:
        raise MissingDependencyError(
            "lagrangian serve", error.name or "starlette", "serve"
        ) from None
    from .worker import PageWorker

    listening = _listen(host, port)
    port = listening.getsockname()[1]
    hosts = None if _is_wildcard(host) else served_hosts(host, port)
    app = create_app(PageWorker(), hosts=hosts)
    config = uvicorn.Config(app, log_level="warning", access_log=False, lifespan="on")
    shown = f"[{host}]" if ":" in host else host
    announce(f"the model editor is at http://{shown}:{port}/ (Ctrl-C stops it)")
    with contextlib.suppress(KeyboardInterrupt), listening:
        uvicorn.Server(config).run(sockets=[listening])


def served_hosts(host: str, port: int) -> frozenset[str]:
    """The Host header values a browser sends to this server: its own address and, for a
    loopback one, the other names of this machine (with the port; without it for 80)."""
    names = {f"[{host}]" if ":" in host else host}
    if is_loopback(host):
        names.update(_LOOPBACK_NAMES)
    with_port = {f"{name}:{port}" for name in names}
    return frozenset(with_port | names if port == 80 else with_port)


def _is_wildcard(host: str) -> bool:
    try:
        return ipaddress.ip_address(host.strip("[]")).is_unspecified
    except ValueError:
        return False


def _listen(host: str, port: int) -> socket.socket:
    """A socket listening on host:port, or one line saying why there is none."""
    try:
        family, kind, protocol, _, address = socket.getaddrinfo(
            host.strip("[]"), port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE
        )[0]
        listening = socket.socket(family, kind, protocol)
    except (OSError, UnicodeError) as error:
        raise LagrangianError(f"cannot listen on {host}:{port}: {_reason(error)}") from None
    try:
        listening.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listening.bind(address)
        listening.listen(128)
    except OSError as error:
        listening.close()
        raise LagrangianError(f"cannot listen on {host}:{port}: {_reason(error)}") from None
    return listening


def _reason(error: Exception) -> str:
    return getattr(error, "strerror", None) or str(error)


__all__ = ["DEFAULT_HOST", "DEFAULT_PORT", "check_host", "is_loopback", "serve", "served_hosts"]
