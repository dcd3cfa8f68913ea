"""``landscape bench``: speed and memory of the landscape numerics, as ratios against the brute force."""

from __future__ import annotations

import click

from landscape.cli.options import THETA_W_LANDSCAPE_HELP, finite, robot_from, robot_options


@click.command()
@click.option(
    "--theta-w", type=float, default=74.0, show_default=True, help=f"{THETA_W_LANDSCAPE_HELP} The timed pose."
)
@click.option(
    "--repeat",
    type=click.IntRange(min=1, max=10_000),
    default=20,
    show_default=True,
    help="Timed repetitions of the fast methods (the best is reported).",
)
@robot_options
def bench(theta_w, repeat, **kw):
    """Speed and memory against the lab's brute-force method, measured in this run, as ratios."""
    from landscape.analysis.bench import landscape_bench

    finite(theta_w, "theta-w")
    robot = robot_from(kw, theta_w_deg=theta_w)
    theta_w = theta_w if robot.drives("theta_w") else 0.0  # the default pose of a body without wing joints
    click.echo(landscape_bench(robot, theta_w_deg=theta_w, repeat=repeat))
