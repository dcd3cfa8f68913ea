"""``landscape physical …``: the physical robot's recorded trials (the lab's data-robot folder, given with
``--data``) as tables, its resting pose beside the model's, and simulated against physical outcomes."""

from __future__ import annotations

from pathlib import Path

import click

from landscape.cli.options import joints_option, robot_option

DATA_OPT = click.option(
    "--data",
    "data",
    type=click.Path(file_okay=False, path_type=Path),
    required=True,
    help="The lab's data-robot folder (run5_*.bag.mat, robot_attempts.mat, ...; e.g. "
    "../shared/ref/physical_robot).",
)


@click.group("physical")
def physical():
    """The physical robot's recorded trials: outcome tables, resting pose, validation of a model."""


@physical.command("table")
@DATA_OPT
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default="physical",
    show_default=True,
    help="Output directory for trials.csv and cells.csv.",
)
def table_cmd(data, out):
    """One row per trial (trials.csv) and per (theta_w, theta_l) cell with Wilson 95 % intervals (cells.csv)."""
    from landscape.analysis import physical as ph
    from landscape.cli.options import writable_dir
    from landscape.viz.physical_plots import cells_table, write_rows_csv

    writable_dir(out, "--out")
    trials = ph.physical_trials(data)
    cells = ph.physical_cells(trials)
    attempts = ph.attempt_outcomes(trials)
    click.echo(cells_table(cells, attempts))
    lat = ph.lateralisation(trials)
    click.echo(
        f"\nroll-overs to + roll: {lat.positive} of {lat.positive + lat.negative} "
        f"(Wilson 95 % [{100 * lat.ci_low:.0f}, {100 * lat.ci_high:.0f}] %)"
    )
    click.echo(f"wrote {write_rows_csv(trials, Path(out) / 'trials.csv')}")
    click.echo(f"wrote {write_rows_csv(cells, Path(out) / 'cells.csv')}")


@physical.command("kinematics")
@DATA_OPT
@robot_option(extra_help="The model to compare (the lab's is ../shared/ref/lab_robot/lab_robot.urdf).")
@joints_option
@click.option("--no-model", is_flag=True, help="Only the robot's resting pitch.")
def kinematics_cmd(data, robot, joints, no_model):
    """Body pitch while the wings are held open (leg still), robot against the model's metastable pitch at the
    measured plateau; and to which side the robot rolls over."""
    import math

    from landscape.analysis import physical as ph
    from landscape.viz.physical_plots import resting_pitch_markdown

    rows = ph.resting_pitch_table(data)
    model = None
    if not no_model:
        from landscape.cli.options import load_robot

        r = load_robot(robot, None, joints=joints)
        plateaus = [
            row.theta_w_measured_deg if math.isfinite(row.theta_w_measured_deg) else row.theta_w_cmd_deg
            for row in rows
        ]
        model = ph.model_plateau_pitch_deg(r, plateaus)
        click.echo(f"model: {r.name} ({r.source}); pitch at each measured plateau minus pitch at theta_w = 0")
    click.echo(
        "pitch 0.5-0.95 s after each opening starts minus the rest in the 0.3 s before the first opening "
        "(leg amplitude 0, openings before the robot first becomes upright)"
    )
    click.echo(resting_pitch_markdown(rows, model))
    lat = ph.lateralisation(ph.physical_trials(data))
    click.echo(
        f"\nroll-overs to + roll: {lat.positive} of {lat.positive + lat.negative} "
        f"(Wilson 95 % [{100 * lat.ci_low:.0f}, {100 * lat.ci_high:.0f}] %); a mirror-symmetric model "
        "has 50 %"
    )
