"""``lagrangian serve``: what it refuses before it serves (the served editor: tests/serve)."""

from __future__ import annotations

import socket
import sys

import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.errors import ModelError
from lagrangian.serve import check_host, served_hosts


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
    assert served_hosts("127.0.0.1", 8765) == {"127.0.0.1:8765", "localhost:8765", "[::1]:8765"}
    assert "localhost" in served_hosts("::1", 80)
    assert served_hosts("192.168.1.20", 8000) == {"192.168.1.20:8000"}
