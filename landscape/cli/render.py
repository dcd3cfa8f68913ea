"""The ``landscape render`` command: 3-D and 2-D figures of one landscape and the robot at its minimum and saddle.

Parses, validates, calls :func:`landscape.computation.compute`, lays the result out as plain arrays
(:mod:`landscape.viz.scene`) and hands them to the renderers in :mod:`landscape.viz.render`.
"""

from __future__ import annotations

import click

from landscape.barriers import EXITS
from landscape.cli.options import (
    finite,
    grid_step,
    memory_budget_bytes,
    method_option,
    robot_from,
    robot_options,
    writable_dir,
)


@click.command()
@click.option("--theta-w", type=float, default=0.0, show_default=True, help="Wing angle, degrees.")
@click.option("--theta-l", type=float, default=0.0, show_default=True, help="Leg angle, degrees.")
@click.option("--step", type=float, default=1.0, show_default=True, help="Grid step, degrees; divides 360.")
@method_option
@click.option("--exit", "exit_kind", type=click.Choice(list(EXITS)), default="righting", show_default=True,
              help="Which barrier's saddle and path to mark.")
@robot_options
@click.option("--out", type=click.Path(file_okay=False), required=True,
              help="Directory for landscape.png/.vts/.html, contour.png/.svg, robot_start.png, robot_saddle.png.")
def render(theta_w, theta_l, step, method, exit_kind, out, **kw):
    """3-D landscape (PNG, VTK, HTML), 2-D contour map (PNG, SVG) and the robot at its minimum and saddle."""
    from landscape.computation import compute as run
    from landscape.viz.scene import render_computation

    for name, v in (("theta-w", theta_w), ("theta-l", theta_l), ("step", step)):
        finite(v, name)
    grid_step(step)
    writable_dir(out, "--out")
    robot = robot_from(kw)
    c = run(robot, theta_w_deg=theta_w, theta_l_deg=theta_l, step_deg=step, method=method,
            memory_budget_bytes=memory_budget_bytes())
    written, notes = render_computation(c, out, robot_name=robot.name, exit_kind=exit_kind)
    for note in notes:
        click.echo(f"landscape: note: {note}", err=True)
    click.echo(f"wrote {', '.join(p.name for p in written)} in {out}")
