"""The command ``serve``: the web editor of models (registered on ``app``).

A thin shell over :mod:`lagrangian.serve`, imported only when the command runs, so
that the other commands never load Starlette or uvicorn.
"""

from __future__ import annotations

import click

from .app import app


@app.command()
@click.option(
    "--host",
    default="127.0.0.1",
    show_default=True,
    help="Address to listen on: a loopback one, unless --allow-remote.",
)
@click.option(
    "--port", type=click.IntRange(0, 65535), default=8765, show_default=True, help="0: any free."
)
@click.option(
    "--allow-remote",
    is_flag=True,
    help="Listen on an address other machines can reach (anyone who reaches it can make "
    "this machine derive models).",
)
def serve(host: str, port: int, allow_remote: bool) -> None:
    """Open the model editor in a browser: edit a model (TOML or a Lagrangian) and see its
    page, derived on this machine, beside the editor."""
    from ..serve import check_host

    check_host(host, allow_remote=allow_remote)  # before the imports: a bad host fails at once
    from ..serve import serve as run_server

    run_server(host, port, allow_remote=allow_remote, announce=click.echo)
