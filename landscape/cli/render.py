"""The ``landscape render`` command: 3-D and 2-D figures of one landscape and the robot at its minimum and saddle.

Parses, validates, calls :func:`landscape.computation.compute`, lays the result out as plain arrays
(:mod:`landscape.viz.scene`) and hands them to the renderers in :mod:`landscape.viz.render`.
"""

from __future__ import annotations

import click

from landscape.barriers import EXITS
from landscape.cli.options import (
    UsageError,
    check_theta_w,
    grid_step,
    memory_budget_bytes,
    method_option,
    pose_options,
    robot_from,
    robot_options,
    warn_radians,
    writable_dir,
)


@click.command()
@pose_options
@method_option
@click.option(
    "--exit",
    "exit_kind",
    type=click.Choice(list(EXITS)),
    default="righting",
    show_default=True,
    help="Which barrier's saddle and path to mark.",
)
@robot_options
@click.option(
    "--trace",
    "traces",
    multiple=True,
    type=click.Path(dir_okay=False),
    help="A trial trace (`landscape simulate --trace FILE`) to draw as a pitch-roll path on the landscape "
    "(trajectories.png, trajectories_contour.png/.svg); repeat for several. Without --theta-w/--theta-l "
    "the landscape is the traces' pose [default: no traces].",
)
@click.option(
    "--physical",
    "physical_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="The lab's data-robot folder (e.g. ../shared/ref/physical_robot): draw the physical robot's recorded "
    "attempts (one per wing opening, righted or not) over the landscape at their measured wing plateau and "
    "theta_l 0 (trajectories.png, trajectories_contour.png/.svg). --theta-w W then picks the commanded wing angle "
    "W (60, 75 or 90 degrees; without it, each one into OUT/wing_W/) and --theta-l L the trials' leg amplitude "
    "(degrees; 0, the leg still, by default) [default: no physical attempts].",
)
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    required=True,
    help="Directory for landscape.png/.vts/.html, contour.png/.svg, robot_start.png, robot_saddle.png.",
)
@click.pass_context
def render(ctx, theta_w, theta_l, step, method, exit_kind, traces, physical_dir, out, **kw):
    """3-D landscape (PNG, VTK, HTML), 2-D contour map (PNG, SVG) and the robot at its minimum and saddle; with
    --trace (simulated trials) or --physical (the physical robot's recorded attempts), their paths over the
    landscape, righted and not righted apart."""
    from landscape.computation import compute as run
    from landscape.viz.scene import render_computation

    grid_step(step)
    writable_dir(out, "--out")
    robot = robot_from(kw)
    warn_radians(robot, theta_w=theta_w, theta_l=theta_l)
    if physical_dir is not None:
        if traces:
            raise UsageError(
                "give either --trace FILE (simulated trials) or --physical DIR (recorded attempts), "
                "not both; they are drawn on different landscapes"
            )
        _render_physical(ctx, robot, physical_dir, theta_w, theta_l, step, method, exit_kind, out)
        return
    read = []
    if traces:
        from landscape.viz.trajectory import read_trace_csv

        read = [read_trace_csv(t) for t in traces]
        theta_w, theta_l = _traces_pose(ctx, read, theta_w, theta_l)
    if robot.drives("theta_w"):
        check_theta_w(theta_w, robot.theta_limits_deg(), robot.name, opening=False)
    c = run(
        robot,
        theta_w_deg=theta_w,
        theta_l_deg=theta_l,
        step_deg=step,
        method=method,
        memory_budget_bytes=memory_budget_bytes(),
    )
    written, notes = render_computation(c, out, robot_name=robot.name, exit_kind=exit_kind)
    if read:
        import numpy as np

        from landscape.viz.trajectory import check_trace_robot, render_trajectories

        for t in read:
            check_trace_robot(t, robot_hash=robot.robot_hash, mass_kg=c.mass_kg, robot_name=robot.name)
        written += render_trajectories(
            c,
            [np.column_stack([t.pitch_deg, t.roll_deg]) for t in read],
            [t.righted for t in read],
            out,
            robot_name=robot.name,
            exit_kind=exit_kind,
        )
    for note in notes:
        click.echo(f"landscape: note: {note}", err=True)
    click.echo(f"wrote {', '.join(p.name for p in written)} in {out}")


POSE_TOL_DEG = 1e-6


def _traces_pose(ctx, read, theta_w, theta_l):
    """The (theta_w, theta_l) of the traces, which must agree with each other and with the options if given."""
    from click.core import ParameterSource

    first = read[0]
    for t in read[1:]:
        if (
            abs(t.theta_w_deg - first.theta_w_deg) > POSE_TOL_DEG
            or abs(t.theta_l_deg - first.theta_l_deg) > POSE_TOL_DEG
        ):
            raise UsageError(
                f"{t.path} ran at theta_w {t.theta_w_deg:g}°, theta_l {t.theta_l_deg:g}° but {first.path} "
                f"at {first.theta_w_deg:g}°, {first.theta_l_deg:g}°; one landscape is one pose, so render "
                "each pose's traces separately"
            )
    for name, given, got in (
        ("theta-w", theta_w, first.theta_w_deg),
        ("theta-l", theta_l, first.theta_l_deg),
    ):
        explicit = ctx.get_parameter_source(name.replace("-", "_")) is not ParameterSource.DEFAULT
        if explicit and abs(given - got) > POSE_TOL_DEG:
            raise UsageError(
                f"--{name} {given:g} but {first.path} ran at {got:g}°; drop --{name} to use the "
                "traces' pose, or give traces of this pose"
            )
    return first.theta_w_deg, first.theta_l_deg


def _render_physical(ctx, robot, data_dir, theta_w, theta_l, step, method, exit_kind, out) -> None:
    """``render --physical``: per commanded wing angle, the landscape at the measured wing plateau and theta_l 0,
    with the recorded attempts of the trials at that wing angle and leg amplitude ``theta_l`` drawn on it."""
    from click.core import ParameterSource

    from landscape.analysis.physical.recording import WING_COMMANDS_DEG
    from landscape.viz.trajectory import physical_poses, physical_robot_note, render_physical

    one = ctx.get_parameter_source("theta_w") is not ParameterSource.DEFAULT
    if one and theta_w not in WING_COMMANDS_DEG:
        raise UsageError(
            f"--theta-w {theta_w:g} with --physical picks the trials' commanded wing angle; the physical robot ran "
            f"at {', '.join(f'{w:g}' for w in WING_COMMANDS_DEG)} degrees"
        )
    # read every attempt first: a data problem is refused before any note or computation
    poses = physical_poses(
        data_dir, commands_deg=[theta_w] if one else list(WING_COMMANDS_DEG), theta_l_deg=theta_l
    )
    for note in physical_robot_note(robot, theta_l):
        click.echo(f"landscape: note: {note}", err=True)
    for pose in poses:
        if robot.drives("theta_w"):
            check_theta_w(pose.theta_w_deg, robot.theta_limits_deg(), robot.name, opening=False)
    done = render_physical(
        robot,
        poses,
        out,
        step_deg=step,
        method=method,
        exit_kind=exit_kind,
        one_dir=one,
        memory_budget_bytes=memory_budget_bytes(),
    )
    for r in done:
        click.echo(r.summary)
    for note in dict.fromkeys(n for r in done for n in r.notes):
        click.echo(f"landscape: note: {note}", err=True)
