"""``landscape bench``: speed and memory of the landscape numerics, as ratios against the brute force."""

from __future__ import annotations

import click

from geometry.bounds import Bounds
from landscape.cli.options import (
    THETA_W_LANDSCAPE_HELP,
    angle_option,
    ranged_option,
    robot_from,
    robot_options,
)

REPEAT_BOUNDS = Bounds(1, 10_000, integer=True, meaning="timed repetitions")


@click.command()
@angle_option("--theta-w", default=74.0, show_default=True, help=f"{THETA_W_LANDSCAPE_HELP} The timed pose.")
@ranged_option(
    "--repeat",
    bounds=REPEAT_BOUNDS,
    default=20,
    show_default=True,
    help="Timed repetitions of the fast methods, {range} (the best is reported).",
)
@robot_options
def bench(theta_w, repeat, **kw):
    """Speed and memory against the lab's brute-force method, measured in this run, as ratios."""
    from landscape.analysis.bench import landscape_bench

    robot = robot_from(kw, theta_w_deg=theta_w)
    theta_w = theta_w if robot.drives("theta_w") else 0.0  # the default pose of a body without wing joints
    click.echo(landscape_bench(robot, theta_w_deg=theta_w, repeat=repeat))
