"""``landscape serve``: the HTTP service and its page (:mod:`landscape.service`). Only click loads at import time;
FastAPI and uvicorn load when the command runs."""

from __future__ import annotations

import ipaddress
import os

import click

from geometry.bounds import Bounds
from geometry.errors import UsageError
from landscape.cli.options import WORKERS_BOUNDS, ranged_option

TOKEN_ENV = "LANDSCAPE_TOKEN"
PORT_BOUNDS = Bounds(0, 65535, integer=True, meaning="a TCP port (0: any free one)")


def is_local(host: str) -> bool:
    """Whether binding to ``host`` keeps the service on this machine (a loopback address or ``localhost``).

    Examples
    --------
    >>> is_local("127.0.0.1"), is_local("localhost"), is_local("::1"), is_local("0.0.0.0")
    (True, True, True, False)
    """
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


@click.command("serve")
@click.option(
    "--host",
    default="127.0.0.1",
    show_default=True,
    help="Address to bind; anything but loopback needs --token.",
)
@ranged_option("--port", bounds=PORT_BOUNDS, default=8000, show_default=True, help="TCP port, {range}.")
@click.option(
    "--data",
    "data_dir",
    type=click.Path(file_okay=False),
    default="landscape-data",
    show_default=True,
    help="Directory for uploads, the cache and sweep jobs (kept across restarts).",
)
@ranged_option(
    "--workers",
    bounds=WORKERS_BOUNDS,
    default=None,
    help="Local worker processes of sweeps, {range} [default: all cores].",
)
@click.option(
    "--scheduler",
    type=str,
    default=None,
    help="Run sweeps on this Dask scheduler tcp://HOST:PORT [default: none, local worker processes].",
)
@click.option(
    "--token",
    type=str,
    default=None,
    envvar=TOKEN_ENV,
    show_envvar=True,
    help="Require 'Authorization: Bearer TOKEN' on every /api request [default: none, only allowed on "
    "a loopback --host].",
)
@click.option(
    "--log-level",
    type=click.Choice(["debug", "info", "warning", "error"]),
    default="info",
    show_default=True,
    help="uvicorn's log level.",
)
def serve(host, port, data_dir, workers, scheduler, token, log_level):
    """Serve landscapes, barrier maps and sweeps over HTTP, with a page at / (API docs at /docs)."""
    if workers is not None and scheduler is not None:
        raise UsageError("give either --workers N (local processes) or --scheduler ADDRESS (Dask), not both")
    local = is_local(host)
    if not local and not token:
        raise UsageError(
            f"binding to {host} exposes the service to the network: give --token T (or {TOKEN_ENV}) "
            "and send 'Authorization: Bearer T'"
        )
    import uvicorn

    from landscape.service.app import create_app
    from landscape.service.config import LOCAL_HOSTS, ServiceConfig

    config = ServiceConfig(
        data_dir=os.path.abspath(data_dir),
        workers=workers,
        scheduler=scheduler,
        token=token or None,
        allowed_hosts=LOCAL_HOSTS if local else None,
    )
    click.echo(
        f"landscape serve: http://{host if ':' not in host else f'[{host}]'}:{port}/  (API docs at /docs)",
        err=True,
    )
    uvicorn.run(create_app(config), host=host, port=port, log_level=log_level)
