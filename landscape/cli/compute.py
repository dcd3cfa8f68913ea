"""``landscape compute`` and ``landscape barrier-map``: one landscape with its barriers, and barriers over a
theta_w x theta_l grid (the source paper's Fig. 5). Each parses, calls one library function and writes."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import click

from geometry.bounds import ORIENTATION_DEG_BOUNDS
from landscape.cli.options import (
    MJ,
    MM,
    UsageError,
    angle_option,
    grid_step,
    grid_step_option,
    memory_budget_bytes,
    method_option,
    pose_model_option,
    pose_model_set,
    pose_options,
    ranged_option,
    robot_from,
    robot_options,
    writable_dir,
)


def _fmt_exit(name: str, x, mg: float) -> str:
    if x is None:
        return f"  {name:<12} none"
    return (
        f"  {name:<12} {x.barrier_j * MJ:9.3f} mJ  = CoM lift {x.barrier_j / mg * MM:7.3f} mm   "
        f"saddle ({x.saddle_pitch_deg:7.2f}, {x.saddle_roll_deg:7.2f})  {x.direction}"
    )


def human_summary(c, robot, *, mass_note: str = "", units: str | None = None) -> str:
    """The table ``landscape compute`` prints. ``mass_note`` follows the mass (e.g. that it is a default);
    ``units`` names the unit a ``--mesh`` file was read in."""
    import math

    mg = c.mass_kg * c.landscape.g_m_s2
    p, r = math.radians(c.minimum.pitch_deg), math.radians(c.minimum.roll_deg)
    upright = math.cos(p) * math.cos(r) < 0  # world-up u_z < 0 in the body frame
    tw = "-" if c.theta_w_deg is None else f"{c.theta_w_deg:g}°"
    tl = "-" if c.theta_l_deg is None else f"{c.theta_l_deg:g}°"
    lines = [
        f"robot        {robot.name}  ({robot.source or 'in memory'})"
        + (f"  read in {units} (--units)" if units else ""),
        f"pose         theta_w {tw}  theta_l {tl}   grid step {c.step_deg:g}°   method {c.method}",
        f"mass         {c.mass_kg * 1e3:.1f} g{mass_note}",
        "CoM          ({:.2f}, {:.2f}, {:.2f}) mm  ({})".format(*(c.com_m * MM), robot.com_source),
        f"minimum      pitch {c.minimum.pitch_deg:.2f}°  roll {c.minimum.roll_deg:.2f}°  "
        f"E {c.minimum.energy_j * MJ:.3f} mJ  h {c.minimum.height_m * MM:.3f} mm"
        + ("  (already upright: no righting needed)" if upright else ""),
        "barriers     (pitch, roll) of the saddle in degrees",
        _fmt_exit("righting", c.barrier.righting, mg),
        _fmt_exit("pitch-wise", c.barrier.pitch_wise, mg),
        _fmt_exit("roll-wise", c.barrier.roll_wise, mg),
        _fmt_exit("escape", c.barrier.escape, mg),
        "timing       " + "  ".join(f"{k} {v * 1e3:.1f} ms" for k, v in c.timing_s.items()),
    ]
    return "\n".join(lines)


@click.command()
@pose_options
@ranged_option(
    "--start-pitch",
    bounds=ORIENTATION_DEG_BOUNDS,
    default=None,
    help="Start by descent from this pitch, degrees, {range} [default: the metastable minimum].",
)
@ranged_option(
    "--start-roll",
    bounds=ORIENTATION_DEG_BOUNDS,
    default=None,
    help="Start by descent from this roll, degrees, {range} [default: the metastable minimum].",
)
@click.option(
    "--connectivity",
    type=click.Choice(["8", "4"]),
    default="8",
    show_default=True,
    help="Grid neighbours of the grid search (8: with diagonals).",
)
@method_option
@robot_options
@pose_model_option
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default=None,
    help="Write landscape.npz, landscape.csv and summary.json into this directory [default: write nothing].",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of the table.")
def compute(
    theta_w, theta_l, step, start_pitch, start_roll, connectivity, method, pose_model, out, as_json, **kw
):
    """Landscape, start minimum and minimal barriers at one (theta_w, theta_l)."""
    from landscape.computation import compute as run
    from landscape.viz import files

    grid_step(step)
    if out:
        writable_dir(out, "--out")
    robot = robot_from(kw, theta_w_deg=theta_w, theta_l_deg=theta_l)
    ms = pose_model_set(pose_model, robot)
    robot = ms.robot_for(robot) if ms else robot
    wing_joints = ms.wing_joints_deg(robot.joint_map.wing, theta_w) if ms else None
    c = run(
        robot,
        wing_joints_deg=wing_joints,
        theta_w_deg=theta_w,
        theta_l_deg=theta_l,
        step_deg=step,
        start_pitch_deg=start_pitch,
        start_roll_deg=start_roll,
        connectivity=int(connectivity),
        method=method,
        memory_budget_bytes=memory_budget_bytes(),
    )
    s = files.summary(
        c,
        robot_name=robot.name,
        robot_source=str(robot.source) if robot.source else None,
        robot_hash=robot.robot_hash,
        com_source=robot.com_source,
        description_hash=robot.description_hash,
    )
    if pose_model is not None:
        s = dict(s) | {"model_set": pose_model, "wing_joints_deg": wing_joints}
    if out:
        files.write_computation(c, s, Path(out))
    if as_json:
        s = dict(s)
        s.pop("paths")
        click.echo(files.json_text(s))
    else:
        mesh = kw["mesh"] is not None
        click.echo(
            human_summary(
                c,
                robot,
                units=(kw["units"] or "m") if mesh else None,
                mass_note="  (default; give --mass KG)" if mesh and kw["mass"] is None else "",
            )
        )
        if wing_joints:
            joints = ", ".join(f"{k} {v:.2f}°" for k, v in wing_joints.items())
            click.echo(f"model set    {pose_model}: each wing servo at its measured plateau ({joints})")
        if ms is not None and ms.joint_shift_mm is not None:
            joint, mm = ms.joint_shift_mm
            shift = ", ".join(f"{v:g}" for v in mm)
            click.echo(f"model set    {pose_model}: joint {joint} moved by ({shift}) mm with what it carries")
        if ms is not None and ms.com_offset_y_mm:
            click.echo(
                f"model set    {pose_model}: CoM moved {ms.com_offset_y_mm:+g} mm along the body's y axis"
            )
        if out:
            click.echo(f"wrote        {out}/landscape.npz, landscape.csv, summary.json")


@click.command("barrier-map")
@angle_option(
    "--theta-w",
    many=True,
    default="70:76:2",
    show_default=True,
    help="Wing angles: list 70,72 or range START:STOP:STEP (inclusive), degrees, each {range} and anywhere "
    "within the wing joints' limits (below 0 too, where the joints allow it).",
)
@angle_option(
    "--theta-l",
    many=True,
    default="20:50:10",
    show_default=True,
    help="Leg angles: list or range, degrees, each {range} and within the leg joint's limits (a body without "
    "a leg joint: leave it out).",
)
@grid_step_option
@method_option
@robot_options
@pose_model_option
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default="barrier-map",
    show_default=True,
    help="Directory for barrier_map.csv and barrier_map.png.",
)
def barrier_map(theta_w, theta_l, step, method, pose_model, out, **kw):
    """Minimal barrier over theta_w x theta_l: CSV and heat map (the source paper's Fig. 5)."""
    import numpy as np
    from tqdm import tqdm

    from landscape.computation import barrier_map as run
    from landscape.viz import files, plots

    ws, ls_ = theta_w, theta_l
    grid_step(step)
    writable_dir(out, "--out")
    robot = robot_from(kw, theta_w_deg=ws, theta_l_deg=ls_)
    if not robot.has_joints:
        if robot.movable_joints:
            raise robot.undriven("theta_w", option="--theta-w", drop=False)
        raise UsageError(
            f"barrier-map sweeps joint angles, and {robot.name} is a single rigid body without joints; "
            "`landscape compute` gives its landscape and barriers"
        )
    # an angle no joint takes (a legless or wingless body) stays 0; given explicitly, robot_from refused it
    ws = ws if robot.drives("theta_w") else [0.0]
    ls_ = ls_ if robot.drives("theta_l") else [0.0]
    ms = pose_model_set(pose_model, robot)
    robot = ms.robot_for(robot) if ms else robot
    joints = ms.wing_joints_by_theta_w(robot.joint_map.wing, ws) if ms else None
    t0 = time.perf_counter()
    with tqdm(
        total=len(ws) * len(ls_), desc="barrier-map", unit="pose", file=sys.stderr, disable=None
    ) as bar:
        bm = run(
            robot,
            ws,
            ls_,
            step_deg=step,
            method=method,
            progress=bar.update,
            memory_budget_bytes=memory_budget_bytes(),
            wing_joints_deg=joints,
        )
    rows = files.barrier_map_rows(bm)
    outd = Path(out)
    csv_path = files.write_rows_csv(rows, outd / "barrier_map.csv")
    grid_mj = bm.righting_j * MJ
    png = plots.render_barrier_map(
        ws,
        ls_,
        grid_mj,
        outd / "barrier_map.png",
        title=f"Minimal righting barrier, {robot.name}, "
        + ("exact" if method == "exact" else f"{step:g}° {method}")
        + (f", model set {pose_model}" if joints else ""),
    )
    click.echo(
        f"{len(rows)} poses in {time.perf_counter() - t0:.2f} s; "
        f"righting barrier {np.nanmin(grid_mj):.3f} .. {np.nanmax(grid_mj):.3f} mJ"
    )
    click.echo(f"wrote {csv_path} and {png}")
