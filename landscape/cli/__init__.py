"""The ``landscape`` command: one click group, one module per command group (rasterio's ``rio/`` layout).

Every command parses, validates, calls one library function and writes. The command modules import only
click and :mod:`landscape.cli.options` at import time, so ``landscape --help`` loads neither the numerics nor
pybullet; each command imports what it needs when it runs.

Exit status: 0 ok; 2 bad input (:class:`geometry.errors.UsageError` or a click usage error: one line on
stderr, no traceback); 1 a failure that is not the input's fault (an unexpected exception is a bug: one line
saying so, the traceback with ``--debug`` or ``LANDSCAPE_DEBUG=1``); 130 interrupted.
"""

from __future__ import annotations

import os
import sys

import click

from geometry.errors import UsageError
from landscape.cli import analyze, bench, compute, models, physical, render, robot, serve, sim

DEBUG_ENV = "LANDSCAPE_DEBUG"
BUG_REPORT = (
    "this is a bug in selfrighting-landscape, not in your input; please report it with the command "
    f"line (rerun with --debug or {DEBUG_ENV}=1 for the traceback)"
)


@click.group(context_settings={"help_option_names": ["-h", "--help"]}, invoke_without_command=True)
@click.version_option(package_name="selfrighting-landscape")
@click.option(
    "--debug", is_flag=True, help=f"Show the traceback of an unexpected error (also {DEBUG_ENV}=1)."
)
@click.pass_context
def cli(ctx, debug):
    """Potential-energy landscapes, self-righting barriers and self-righting trials of legged/winged robots.

    Angles are degrees, energies are reported in mJ (files: J), lengths in mm (files: m).
    """
    if ctx.invoked_subcommand is None:
        click.echo(ctx.get_help())


for _cmd in (
    compute.compute,
    compute.barrier_map,
    render.render,
    robot.robot,
    bench.bench,
    sim.simulate,
    sim.sweep,
    sim.export,
    analyze.analyze,
    analyze.report_cmd,
    serve.serve,
    physical.physical,
    models.models,
):
    cli.add_command(_cmd)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status (0 ok, 1 failure or bug, 2 bad input, 130 interrupted)."""
    args = sys.argv[1:] if argv is None else list(argv)
    debug = bool(os.environ.get(DEBUG_ENV)) or "--debug" in args
    try:
        rv = cli.main(args=args, prog_name="landscape", standalone_mode=False)
    except click.exceptions.Exit as exc:
        return int(exc.exit_code)
    except (click.exceptions.Abort, KeyboardInterrupt):
        click.echo("landscape: interrupted", err=True)
        return 130
    except click.exceptions.ClickException as exc:
        click.echo(f"landscape: error: {exc.format_message()}", err=True)
        return exc.exit_code
    except UsageError as exc:
        click.echo(f"landscape: error: {_first_line(exc)}", err=True)
        return 2
    except Exception as exc:
        if isinstance(exc, OSError) and exc.filename is not None and not debug:
            # the environment, not the code: a file that cannot be read or written
            click.echo(f"landscape: error: {exc.strerror or type(exc).__name__}: {exc.filename}", err=True)
            return 2
        if debug:
            raise
        click.echo(f"landscape: internal error: {type(exc).__name__}: {_first_line(exc)}", err=True)
        click.echo(f"landscape: {BUG_REPORT}", err=True)
        return 1
    return int(rv or 0)


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


if __name__ == "__main__":
    sys.exit(main())
