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
    "this machine derive models; a warning says so).",
)
@click.option(
    "--allow-host",
    "allowed_hosts",
    multiple=True,
    metavar="NAME",
    help="Also answer requests addressed to NAME (a DNS name of this machine, a proxy's); "
    "repeatable.  Others are refused, as a page that re-points its own name here sends.",
)
def serve(host: str, port: int, allow_remote: bool, allowed_hosts: tuple[str, ...]) -> None:
    """Serve the model editor until Ctrl-C: in a browser, edit a model (TOML or a
    Lagrangian) and see its page, derived on this machine, beside the editor."""
    run_server(
        host,
        port,
        allow_remote=allow_remote,
        allowed_hosts=allowed_hosts,
        announce=click.echo,
        warn=lambda line: click.echo(f"lagrangian: warning: {line}", err=True),
    )
