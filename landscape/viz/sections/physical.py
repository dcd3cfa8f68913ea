"""The physical-robot section: the recorded attempts over the landscape at each wing command, and the recorded
outcomes per cell."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.grid import DEFAULT_STEP_DEG
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    trials_robot,
    write_csv,
)
from landscape.viz.sections.trajectories import three_d_note, trajectory_figures


def section_physical(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    data_dir: str | Path,
    robot: str | Path | None = None,
    step_deg: float = DEFAULT_STEP_DEG,
) -> Section:
    """The physical robot's recorded attempts at each commanded wing angle, over the landscape at the measured wing
    plateau and theta_l 0 (as ``landscape render --physical`` draws them, into ``out/physical/wing_W``), and
    the physical trials' outcomes per (theta_w, theta_l) with Wilson intervals.

    The landscape is the robot of the trials (``robot``, else as :func:`trials_robot` finds it); a note says so when
    it is not the lab robot.

    Raises
    ------
    PhysicalDataError
        If ``data_dir`` is not the lab's data directory.
    """
    from landscape.analysis.physical.cells import PhysicalCell, physical_cells
    from landscape.analysis.physical.outcome import physical_trials
    from landscape.analysis.physical.recording import WING_COMMANDS_DEG
    from landscape.computation import compute
    from landscape.viz.trajectory import physical_poses, physical_robot_note, render_trajectories

    title = "The physical robot's attempts over the landscape"
    cells = physical_cells(physical_trials(data_dir))
    csv_path = write_csv(
        out / "physical_cells.csv", [{k: getattr(c, k) for k in PhysicalCell.CSV_COLUMNS} for c in cells]
    )
    poses = physical_poses(data_dir, commands_deg=WING_COMMANDS_DEG, theta_l_deg=0.0)
    try:
        rb = trials_robot(rows, robot)
    except UsageError as exc:
        return Section("physical", title, missing=str(exc))
    three_d, note = three_d_note()
    paras = [
        f"Every recorded attempt (one per wing opening, up to the one that righted) of the trials with the leg "
        f"still (θl 0°), per commanded wing angle, over {rb.name}'s landscape at the measured wing plateau "
        f"(grid step {step_deg:g}°)."
    ]
    paras += [n[0].upper() + n[1:] + "." for n in physical_robot_note(rb)]
    figures: list[Figure] = []
    for pose in poses:
        c = compute(rb, theta_w_deg=pose.theta_w_deg, theta_l_deg=0.0, step_deg=step_deg)
        files = render_trajectories(
            c,
            [np.column_stack([a.pitch_deg, a.roll_deg]) for a in pose.attempts],
            [a.righted for a in pose.attempts],
            out / "physical" / f"wing_{pose.theta_w_cmd_deg:g}",
            robot_name=rb.name,
            what="physical",
            landscape_3d=three_d,
        )
        n_ok = sum(a.righted for a in pose.attempts)
        paras.append(
            f"Wing command {pose.theta_w_cmd_deg:g}° (landscape at {pose.theta_w_deg:.1f}°"
            + ("" if pose.plateau_measured else ", the command: no measured plateau")
            + f"): {len(pose.attempts)} attempts of {len({a.name for a in pose.attempts})} trials, {n_ok} righted."
        )
        figures += trajectory_figures(files, f"Physical attempts, wing command {pose.theta_w_cmd_deg:g}°")
    if note:
        paras.append(note)
    return Section(
        "physical",
        title,
        tuple(paras),
        tuple(figures),
        (Table("Physical trials per wing angle and leg amplitude (Wilson 95 % intervals)", csv_path),),
    )
