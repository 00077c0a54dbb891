"""Where the editor may listen, and which Host headers it answers.

A page of another site can re-point its own name at this machine (DNS rebinding) and
then drive the editor from the user's browser; its requests name that site in their
Host header.  So the server answers only requests that name it: its own address,
the names of this machine, and the names the user allows (``--allow-host``); one
that listens on every address (``0.0.0.0``, ``::``) answers for any address of this
machine too (an address is this machine's when a socket can be bound to it).

Stdlib only: the command line imports this module to name its defaults.
"""

from __future__ import annotations

import contextlib
import ipaddress
import re
import socket
from collections.abc import Iterable
from dataclasses import dataclass

from ..errors import ModelError, setting

#: The names of this machine that every loopback server answers.
LOOPBACK_NAMES = ("localhost", "127.0.0.1", "[::1]")
#: A host name as a Host header carries it (letters, digits, hyphens, dots).
_HOST_NAME = re.compile(r"[a-z0-9]([a-z0-9-]*[a-z0-9])?(\.[a-z0-9]([a-z0-9-]*[a-z0-9])?)*\.?")


def check_host(host: str, *, allow_remote: bool = False) -> str:
    """``host`` if the server may listen there: a loopback address (``127.0.0.1``,
    ``::1``, ``localhost``), or any address when ``allow_remote`` says so."""
    if allow_remote or is_loopback(host):
        return host
    raise ModelError(
        f"{host} is not a loopback address: other machines could reach the editor and make "
        f"this machine derive their models (allow it with {setting('allow_remote')})"
    )


def bare(host: str) -> str:
    """``host`` without the brackets of an IPv6 address written for a URL (``[::1]``)."""
    return host[1:-1] if host.startswith("[") and host.endswith("]") else host


def in_url(host: str) -> str:
    """``host`` as a URL writes it: an IPv6 address in brackets, once."""
    address = bare(host)
    return f"[{address}]" if ":" in address else address


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine only (a name other than localhost may not)."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(bare(host)).is_loopback
    except ValueError:
        return False


def is_wildcard(host: str) -> bool:
    """Whether ``host`` is every address of this machine (``0.0.0.0``, ``::``)."""
    try:
        return ipaddress.ip_address(bare(host)).is_unspecified
    except ValueError:
        return False


def checked_host_name(name: str) -> str:
    """``name`` (of ``--allow-host``) lowercased: a host name or an IP address, no port."""
    lowered = name.strip().lower()
    try:
        return in_url(str(ipaddress.ip_address(bare(lowered))))
    except ValueError:
        pass
    if len(lowered) > 253 or not _HOST_NAME.fullmatch(lowered):
        raise ModelError(
            f"{name!r} is not a host name or an IP address", field=setting("allow_host")
        )
    return lowered


@dataclass(frozen=True)
class ServedHosts:
    """The Host header values a server at ``port`` answers: ``names`` (each with the port,
    and without it too for port 80), and with ``any_own_address`` any address of this
    machine.  ``in`` asks whether a (lowercased) Host header is one of them."""

    names: frozenset[str]
    port: int
    any_own_address: bool = False

    def __contains__(self, host: object) -> bool:
        if not isinstance(host, str):
            return False
        if host in self.names:
            return True
        if not self.any_own_address:
            return False
        address, port = _split_port(host)
        return port == self.port and address is not None and is_own_address(address)


def served_hosts(host: str, port: int, *, allowed: Iterable[str] = ()) -> ServedHosts:
    """The Host headers of a server listening on ``host``:``port``: the address itself;
    for a loopback one the other names of this machine's loopback; for any other, the
    names of this machine (and, listening on every address, any of its addresses); and
    the ``allowed`` names in every case."""
    names = {in_url(host).lower(), *(checked_host_name(name) for name in allowed)}
    if is_loopback(host) or is_wildcard(host):
        names.update(LOOPBACK_NAMES)
    if not is_loopback(host):
        names.update(machine_names())
    with_port = {f"{name}:{port}" for name in names}
    return ServedHosts(
        frozenset(with_port | names if port == 80 else with_port), port, is_wildcard(host)
    )


def machine_names() -> set[str]:
    """This machine's host name and fully qualified name, lowercased (none it cannot tell)."""
    names = set()
    for name in (socket.gethostname(), socket.getfqdn()):
        with contextlib.suppress(ModelError):  # a name no Host header could carry
            names.add(checked_host_name(name))
    return names


def is_own_address(address: ipaddress.IPv4Address | ipaddress.IPv6Address) -> bool:
    """Whether ``address`` is one of this machine's: a socket can be bound to it (the
    kernel refuses any other with EADDRNOTAVAIL), asked afresh each time, as a machine's
    addresses change (a new network, DHCP)."""
    if address.is_loopback:
        return True
    if address.is_unspecified or address.is_multicast:
        return False
    family = socket.AF_INET6 if address.version == 6 else socket.AF_INET
    try:
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.bind((str(address), 0))
    except OSError:
        return False
    return True


def _split_port(host: str) -> tuple[ipaddress.IPv4Address | ipaddress.IPv6Address | None, int]:
    """The IP address of a Host header (``10.0.0.5:8765``, ``[fe80::1]:80``) and its port
    (80 when none is given); no address for a name."""
    text, port = host, 80
    if host.startswith("["):
        text, _, rest = host[1:].partition("]")
        if rest:
            if not rest.startswith(":") or not rest[1:].isdigit():
                return None, port
            port = int(rest[1:])
    elif host.count(":") > 1:  # an IPv6 address comes in brackets
        return None, port
    elif host.count(":") == 1:
        text, _, digits = host.partition(":")
        if not digits.isdigit():
            return None, port
        port = int(digits)
    try:
        return ipaddress.ip_address(text), port
    except ValueError:
        return None, port
