"""``lagrangian serve``: what it refuses before it serves (the served editor: tests/serve)."""

from __future__ import annotations

import re
import socket
import sys

import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.errors import ModelError
from lagrangian.serve import check_host, served_hosts
from lagrangian.serve.hosts import machine_names


@pytest.mark.parametrize("host", ["0.0.0.0", "::", "192.168.1.20", "example.org", "10.0.0.1"])
def test_a_non_loopback_host_is_refused_without_allow_remote(capsys, host):
    assert main(["serve", "--host", host]) == ExitStatus.BAD_INPUT
    err = capsys.readouterr().err
    assert err == (
        f"lagrangian: error: {host} is not a loopback address: other machines could reach "
        "the editor and make this machine derive their models (allow it with --allow-remote)\n"
    )


@pytest.mark.parametrize("host", ["127.0.0.1", "127.0.0.2", "::1", "[::1]", "localhost"])
def test_loopback_hosts_need_no_permission(host):
    assert check_host(host) == host


def test_allow_remote_permits_any_host_and_the_library_names_it_as_python_does():
    assert check_host("0.0.0.0", allow_remote=True) == "0.0.0.0"
    with pytest.raises(ModelError, match=r"allow it with allow_remote=True\)$"):
        check_host("0.0.0.0")


def test_a_port_in_use_is_one_line(capsys):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["serve", "--port", str(port)]) == ExitStatus.BAD_INPUT
    err = capsys.readouterr().err
    assert err.startswith(f"lagrangian: error: cannot listen on 127.0.0.1:{port}: ")
    assert err.count("\n") == 1


def test_without_the_serve_extra_the_error_names_it(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "uvicorn", None)  # import uvicorn fails
    assert main(["serve", "--port", "0"]) == ExitStatus.BAD_INPUT
    assert capsys.readouterr().err == (
        "lagrangian: error: lagrangian serve needs uvicorn: "
        'pip install ".[serve]" in a clone of lagrangian\n'
    )


def test_the_served_host_names_carry_the_port():
    loopback = {"127.0.0.1:8765", "localhost:8765", "[::1]:8765"}
    assert served_hosts("127.0.0.1", 8765).names == loopback
    assert served_hosts("[::1]", 8765).names == loopback  # written as in a URL: same names
    assert "localhost" in served_hosts("::1", 80)
    assert served_hosts("192.168.1.20", 8000).names == {
        "192.168.1.20:8000",
        *(f"{name}:8000" for name in machine_names()),
    }


# -- issue 37 item 11: listening beyond loopback keeps the Host check and warns -------------
def an_address_of_this_machine_beyond_loopback() -> str | None:
    """An address of this machine other than loopback (the one its default route uses)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("192.0.2.1", 9))  # a documentation address: nothing is sent
        except OSError:
            return None
        address = probe.getsockname()[0]
    return None if address.startswith("127.") or address == "0.0.0.0" else address


@pytest.mark.parametrize("host", ["0.0.0.0", "::"])
def test_every_address_answers_this_machine_only_and_the_names_allowed(host):
    served = served_hosts(host, 8765, allowed=["Editor.Example.org"])
    for own in ("127.0.0.1:8765", "localhost:8765", "[::1]:8765", "editor.example.org:8765"):
        assert own in served
    for name in machine_names():
        assert f"{name}:8765" in served
    # DNS rebinding: a page of another site names its own host; and no other machine's
    # address, nor this machine's on another port, nor a mangled header
    for other in (
        "attacker.example:8765",
        "8.8.8.8:8765",
        "[2001:db8::1]:8765",
        "127.0.0.1:9999",
        "127.0.0.1",
        "::1:8765",
        "127.0.0.1:80x",
    ):
        assert other not in served
    own = an_address_of_this_machine_beyond_loopback()
    if own is not None and host == "0.0.0.0":
        assert f"{own}:8765" in served
        assert own not in served  # the port is part of it (not 80)


@pytest.mark.parametrize("name", ["bad name", "a/b", "host:80", "", "-x.org", "x" * 254])
def test_a_bad_allowed_host_is_one_line(capsys, name):
    argv = ["serve", "--host", "0.0.0.0", "--allow-remote", "--allow-host", name]
    assert main(argv) == ExitStatus.BAD_INPUT
    assert capsys.readouterr().err == (
        f"lagrangian: error: --allow-host: {name!r} is not a host name or an IP address\n"
    )


def ran_server(monkeypatch) -> list:
    """The servers ``serve`` would have run (uvicorn's run replaced: nothing is served)."""
    import uvicorn

    ran = []
    monkeypatch.setattr(uvicorn.Server, "run", lambda server, sockets: ran.append(server))
    return ran


def test_listening_beyond_loopback_warns_and_loopback_does_not(capsys, monkeypatch):
    ran = ran_server(monkeypatch)
    assert main(["serve", "--host", "0.0.0.0", "--allow-remote", "--port", "0"]) == 0
    captured = capsys.readouterr()
    assert captured.err == (
        "lagrangian: warning: the editor listens on every address of this machine: any "
        "machine that reaches it can make this machine derive models (it answers only "
        "requests that name this machine: its names and addresses, and the names allowed)\n"
    )
    assert captured.out.startswith("the model editor is at http://0.0.0.0:")
    assert main(["serve", "--port", "0"]) == 0
    assert capsys.readouterr().err == ""
    assert len(ran) == 2


def test_an_ipv6_address_in_brackets_is_announced_with_one_pair(capsys, monkeypatch):
    ran_server(monkeypatch)
    assert main(["serve", "--host", "[::1]", "--port", "0"]) == 0
    out = capsys.readouterr().out
    assert re.fullmatch(r"the model editor is at http://\[::1\]:\d+/ \(Ctrl-C stops it\)\n", out)
