"""The command ``serve``: the web editor of models (registered on ``app``).

A thin shell over :mod:`lagrangian.serve`, whose package imports Starlette and uvicorn
only when a server is made, so that the other commands never load them.
"""

from __future__ import annotations

import click

from ..serve import DEFAULT_HOST, DEFAULT_PORT
from ..serve import serve as run_server
from .app import app


@app.command()
@click.option(
    "--host",
    default=DEFAULT_HOST,
    show_default=True,
    help="Address to listen on: a loopback one, unless --allow-remote.",
)
@click.option(
    "--port",
    type=click.IntRange(0, 65535),
    default=DEFAULT_PORT,
    show_default=True,
    help="Port to listen on (0: any free one; the address is printed).",
)
@click.option(
    "--allow-remote",
    is_flag=True,
    help="Listen on an address other machines can reach (anyone who reaches it can make "
    "this machine derive models).",
)
def serve(host: str, port: int, allow_remote: bool) -> None:
    """Serve the model editor until Ctrl-C: in a browser, edit a model (TOML or a
    Lagrangian) and see its page, derived on this machine, beside the editor."""
    run_server(host, port, allow_remote=allow_remote, announce=click.echo)
