"""The ``landscape render`` command: 3-D and 2-D figures of one landscape and the robot at its minimum and saddle.

Parses, validates, calls :func:`landscape.computation.compute`, lays the result out as plain arrays
(:mod:`landscape.viz.scene`) and hands them to the renderers in :mod:`landscape.viz.render`.
"""

from __future__ import annotations

from pathlib import Path

import click

from landscape.cli.options import MJ, UsageError, finite, method_option, robot_from, robot_options

EXITS = {"righting": "righting", "pitch-wise": "pitch_wise", "roll-wise": "roll_wise", "escape": "escape"}


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
    import numpy as np

    from landscape.computation import compute as run
    from landscape.energy import height_at
    from landscape.viz import render as rd
    from landscape.viz.scene import nearest_twin_deg, posed_meshes_world, wrapped_path_deg

    for name, v in (("theta-w", theta_w), ("theta-l", theta_l), ("step", step)):
        finite(v, name)
    robot = robot_from(kw)
    c = run(robot, theta_w_deg=theta_w, theta_l_deg=theta_l, step_deg=step, method=method)
    angles_deg, energy_j = c.landscape.inclusive()
    ex = getattr(c.barrier, EXITS[exit_kind])
    mg = c.mass_kg * c.landscape.g_m_s2
    marks = {"minimum_deg": None, "minimum_j": c.minimum.energy_j, "saddle_deg": None, "saddle_j": None,
             "path_deg": None, "path_j": None}
    if ex is not None:
        path_deg = wrapped_path_deg(ex.path_deg)
        ok = np.isfinite(path_deg[:, 0])
        path_j = np.full(len(path_deg), np.nan)
        path_j[ok] = mg * height_at(c.pose, path_deg[ok, 0], path_deg[ok, 1])
        marks.update(path_deg=path_deg, path_j=path_j, saddle_j=c.minimum.energy_j + ex.barrier_j,
                     saddle_deg=nearest_twin_deg(ex.saddle_pitch_deg, ex.saddle_roll_deg, path_deg))
        marks["minimum_deg"] = nearest_twin_deg(c.minimum.pitch_deg, c.minimum.roll_deg, path_deg[:1])
    else:
        marks["minimum_deg"] = (c.minimum.pitch_deg, c.minimum.roll_deg)
    pose_text = "" if c.theta_w_deg is None else f"  wing {c.theta_w_deg:g}°, leg {c.theta_l_deg:g}°"
    barrier_text = f"{exit_kind} barrier none" if ex is None else f"{exit_kind} barrier {ex.barrier_j * MJ:.2f} mJ"
    title = f"{robot.name}{pose_text}  {barrier_text}"

    outd = Path(out)
    written = []
    contour = {k: marks[k] for k in ("minimum_deg", "saddle_deg", "saddle_j", "path_deg")}
    for suffix in ("png", "svg"):
        written.append(rd.render_contour(energy_j, angles_deg, angles_deg, outd / f"contour.{suffix}",
                                         title=title, **contour))
    try:
        written.append(rd.write_vtk(energy_j, angles_deg, angles_deg, outd / "landscape.vts"))
        problem = rd.off_screen_problem()
    except rd.MissingDependencyError as exc:
        problem = str(exc)
    if problem is not None:
        raise UsageError(f"{problem} (wrote only {', '.join(p.name for p in written)} in {outd})")
    written.append(rd.render_landscape(energy_j, angles_deg, angles_deg, outd / "landscape.png", title=title,
                                       **marks))
    robots = [("start", "start minimum", c.minimum.pitch_deg, c.minimum.roll_deg)]
    if ex is not None:
        robots.append(("saddle", f"{exit_kind} saddle", ex.saddle_pitch_deg, ex.saddle_roll_deg))
    for name, what, p, r in robots:
        meshes, com = posed_meshes_world(c.pose, p, r)
        written.append(rd.render_robot(meshes, outd / f"robot_{name}.png", com_m=com,
                                       title=f"{robot.name}{pose_text}\n{what}: pitch {p:.1f}°, roll {r:.1f}°\n"
                                             f"CoM {com[2] * 1e3:.1f} mm above the ground"))
    try:
        written.append(rd.export_landscape_html(energy_j, angles_deg, angles_deg, outd / "landscape.html",
                                                title=title, **marks))
    except rd.MissingDependencyError as exc:
        click.echo(f"landscape: note: skipped landscape.html: {exc}", err=True)
    click.echo(f"wrote {', '.join(p.name for p in written)} in {outd}")

