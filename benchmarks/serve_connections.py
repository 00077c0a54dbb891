"""`lagrangian serve` under connections that never finish their requests (issue 37 item 4).

    python benchmarks/serve_connections.py [--connections 1020] [--hold 15] [--nofile 1024]

Starts ``lagrangian serve --port 0`` with its descriptor limit at ``--nofile`` (1024, a
common default), opens ``--connections`` connections to it on 127.0.0.1 that send
half a request's headers and nothing more, and then, while they are held and after
``--hold`` seconds, asks for the editor (GET /) as a browser would.  Printed: how many
connections the server accepted, refused or closed, each GET's status and seconds, and
the bytes the server wrote on stderr (before the bounds: the editor unreachable, and
1.46 GB of stderr in 140 s).  Only 127.0.0.1; bounded in count and time; nothing is
asserted.
"""

from __future__ import annotations

import argparse
import http.client
import os
import re
import resource
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

SOURCES = Path(__file__).resolve().parents[1] / "src"
#: Seconds any one step may take (a bound for a hang).
STEP_SECONDS = 180


def editor(port: int) -> str:
    """The status of GET / and its seconds, or why there was none."""
    start = time.perf_counter()
    try:
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        connection.request("GET", "/", headers={"Host": f"127.0.0.1:{port}"})
        status = connection.getresponse().status
        connection.close()
    except OSError as error:
        return f"no answer ({type(error).__name__}) after {time.perf_counter() - start:.2f} s"
    return f"{status} in {time.perf_counter() - start:.3f} s"


def ended(connection: socket.socket) -> str:
    """How the server ended a held connection by now: its answer's first line, or none."""
    connection.setblocking(False)
    try:
        data = connection.recv(64)
    except BlockingIOError:
        return "open"
    except ConnectionResetError:
        return "reset"
    return data.split(b"\r\n", 1)[0].decode() if data else "closed"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--connections", type=int, default=1020)
    parser.add_argument("--hold", type=float, default=15.0)
    parser.add_argument("--nofile", type=int, default=1024)
    options = parser.parse_args()
    if not 0 < options.connections <= 4000 or not 0 < options.hold <= 120:
        raise SystemExit("at most 4000 connections, held at most 120 s")
    _, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, options.connections + 256), hard))

    def limited() -> None:
        resource.setrlimit(resource.RLIMIT_NOFILE, (options.nofile, hard))

    with tempfile.TemporaryFile() as stderr:
        server = subprocess.Popen(
            [sys.executable, "-m", "lagrangian", "serve", "--port", "0"],
            stdout=subprocess.PIPE,
            stderr=stderr,
            text=True,
            env=dict(os.environ, PYTHONPATH=str(SOURCES)),
            preexec_fn=limited,
            start_new_session=True,
        )
        try:
            lines: list[str] = []
            reader = threading.Thread(target=lambda: lines.append(server.stdout.readline()))
            reader.start()
            reader.join(STEP_SECONDS)
            found = re.search(r":(\d+)/", lines[0]) if lines else None
            if found is None:
                raise SystemExit("the server did not start")
            port = int(found[1])
            print(f"server: {lines[0].strip()} (descriptors: {options.nofile})")
            print(f"before: GET / {editor(port)}")
            held = []
            for _ in range(options.connections):
                connection = socket.create_connection(("127.0.0.1", port), timeout=5)
                connection.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n".encode())
                held.append(connection)
            print(f"opened {len(held)} connections with half-sent headers")
            print(f"while held: GET / {editor(port)}")
            time.sleep(options.hold)
            print(f"after {options.hold:g} s: GET / {editor(port)}")
            outcomes: dict[str, int] = {}
            for connection in held:
                outcome = ended(connection)
                outcomes[outcome] = outcomes.get(outcome, 0) + 1
                connection.close()
            print("the held connections:", ", ".join(f"{k}: {v}" for k, v in outcomes.items()))
            stderr.seek(0, os.SEEK_END)
            print(f"stderr: {stderr.tell()} bytes")
            stderr.seek(0)
            for line in stderr.read().decode(errors="replace").splitlines()[:6]:
                print(f"  {line}")
        finally:
            server.send_signal(signal.SIGINT)
            try:
                server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(server.pid, signal.SIGKILL)
                server.wait(timeout=30)


if __name__ == "__main__":
    main()
