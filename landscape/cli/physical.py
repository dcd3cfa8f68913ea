"""``landscape physical …``: the physical robot's recorded trials (the lab's data-robot folder, given with
``--data``) as tables, its resting pose beside the model's, and simulated against physical outcomes."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import click

from geometry.bounds import Bounds
from landscape.cli.options import (
    angle_option,
    engine_option,
    joints_option,
    model_set_option,
    no_progress_option,
    ranged_option,
    robot_option,
    sweep_errors,
    validation_cv_option,
    validation_duration_option,
    validation_seed_option,
    workers_option,
)
from sim.protocol import DT_S_BOUNDS, PHASE_BOUNDS, TRIALS_BOUNDS

DATA_OPT = click.option(
    "--data",
    "data",
    type=click.Path(file_okay=False, path_type=Path),
    required=True,
    help="The lab's data-robot folder (run5_*.bag.mat, robot_attempts.mat, ...; e.g. "
    "../shared/ref/physical_robot).",
)
SIM_ROBOT = robot_option(
    extra_help="The simulated robot (the real robot's CAD is ../shared/ref/lab_robot/lab_robot.urdf)."
)
IMU_MOUNTING_DEG_BOUNDS = Bounds(
    -180.0, 180.0, unit="deg", meaning="a pitch of the body frame below the IMU's"
)
COUNT_BOUNDS = Bounds(1, math.inf, integer=True, meaning="a count")
PHASE_OR_PROTOCOL_BOUNDS = replace(PHASE_BOUNDS, words=("protocol",))
"""A first-attempt phase in [0, 1), or 'protocol': each cell at the phase the lab's protocol gives it."""


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
    from landscape.analysis.physical.cells import outcome_tables
    from landscape.cli.options import writable_dir
    from landscape.viz.physical_plots import cells_table, lateralisation_text, write_rows_csv

    writable_dir(out, "--out")
    t = outcome_tables(data)
    click.echo(cells_table(t.cells, t.attempts))
    click.echo("\n" + lateralisation_text(t.lateralisation))
    click.echo(f"wrote {write_rows_csv(t.trials, Path(out) / 'trials.csv')}")
    click.echo(f"wrote {write_rows_csv(t.cells, Path(out) / 'cells.csv')}")


@physical.command("energy")
@DATA_OPT
@robot_option(
    extra_help="The model the recordings are posed on (the lab's is ../shared/ref/lab_robot/lab_robot.urdf)."
)
@click.option(
    "--model",
    "model_set",
    type=str,
    default="physical-head",
    show_default=True,
    help="Model parameter set that poses the robot (its wing and leg timing, its geometry): a shipped name or a "
    ".toml file.",
)
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default="physical-energy",
    show_default=True,
    help="Output directory for energy.csv and energy.png.",
)
@no_progress_option
def energy_cmd(data, robot, model_set, out, no_progress):
    """Kinetic energy against the barrier in every recorded attempt: energy.csv (one row per attempt), energy.png,
    and how often the energy margin's sign matches the outcome beside the barrier alone."""
    from landscape.analysis.physical.motion import recorded_motions
    from landscape.cli.options import load_robot, writable_dir
    from landscape.viz.sections.energy import ENERGY_METHOD, energy_files, energy_paragraphs
    from sim.model_set import load_model_set

    writable_dir(out, "--out")
    rec = recorded_motions(data, load_robot(robot, None), load_model_set(model_set))
    rows, _, csv_path, png = energy_files(
        Path(out),
        [(rec.body, rec.motions)],
        title=f"The robot's attempts (model {rec.model_set})",
        progress=not no_progress,
    )
    click.echo(ENERGY_METHOD)
    click.echo(
        f"{len(rec.motions)} recorded trials; IMU mounting {rec.mount_deg:.1f} deg; model {rec.model_set}"
    )
    for p in energy_paragraphs(rows):
        click.echo(p)
    click.echo(f"wrote {csv_path}")
    click.echo(f"wrote {png} and {png.with_suffix('.svg')}")


@physical.command("kinematics")
@DATA_OPT
@robot_option(extra_help="The model to compare (the lab's is ../shared/ref/lab_robot/lab_robot.urdf).")
@joints_option
@model_set_option
@click.option("--no-model", is_flag=True, help="Only the robot's recorded pitch, no model.")
def kinematics_cmd(data, robot, joints, model_set, no_model):
    """Where the body holds while the wings are open (leg still), robot against model, in two frames; how each
    first opening moves the body; the protocol's leg timing; and to which side the robot rolls over.

    The model's hold is its metastable pitch with the wing joints at the measured plateau, or, for a model set
    with a measured actuation profile (--model physical), each wing servo at its own measured plateau."""
    from landscape.analysis.physical.kinematics import kinematics
    from landscape.viz.physical_plots import kinematics_text

    model = ms = None
    if not no_model:
        from landscape.cli.options import load_robot
        from sim.model_set import load_model_set

        ms = load_model_set(model_set)
        model = load_robot(robot, None, joints=joints)
    for block in kinematics_text(kinematics(data, robot=model, model_set=ms)):
        click.echo(block)


@physical.command("actuation")
@DATA_OPT
@click.option(
    "--out",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Also write the block to this file [default: print only].",
)
@click.option(
    "--servo-sides",
    type=click.Choice(["as-labelled", "mirrored"]),  # sim.model_set.SERVO_SIDES (imported lazily)
    default="as-labelled",
    show_default=True,
    help="Which wing joints the lab's left servos drive: the model's left ones, or its right ones (mirrored: "
    "what sim/models/physical.toml ships; the side the robot rolls over to favours it).",
)
def actuation_cmd(data, out, servo_sides):
    """The measured actuation profile: piecewise-linear knots fitted to each wing servo's and the leg's recorded
    traces (motor_pulse_v2.mat, vib_pulse_v2.mat), printed as the [actuation] block of a model set (the block
    sim/models/physical.toml ships, with --servo-sides mirrored), with each fit's largest error as comments."""
    from landscape.analysis.physical.measured import measured_actuation_toml

    if out is not None:
        from landscape.cli.options import writable_file

        writable_file(out, "--out")
    text = measured_actuation_toml(data, servo_sides=servo_sides)
    click.echo(text, nl=not text.endswith("\n"))
    if out is not None:
        Path(out).write_text(text)
        click.echo(f"wrote {out}")


def _report_validation(out: Path, validation, tables: dict, doc_name: str, doc: dict) -> None:
    """Print ``validation`` (:class:`landscape.analysis.physical.validation.Validation`) as a table, then write into
    ``out`` each of ``tables`` (file name -> rows) as CSV, ``doc`` as JSON to ``doc_name`` and the time-to-right
    figure, naming each file on stdout as it is written."""
    from landscape.viz.files import json_text
    from landscape.viz.physical_plots import time_to_right_figure, validation_markdown, write_rows_csv

    click.echo(validation_markdown(validation))
    outs = [write_rows_csv(rows, out / name) for name, rows in tables.items()]
    (out / doc_name).write_text(json_text(doc) + "\n")
    outs += [out / doc_name, time_to_right_figure(validation, out / "time_to_right.png")]
    for p in outs:
        click.echo(f"wrote {p}")


@physical.command("validate")
@DATA_OPT
@SIM_ROBOT
@joints_option
@model_set_option
@engine_option
@ranged_option(
    "--trials",
    bounds=TRIALS_BOUNDS,
    default=10,
    show_default=True,
    help="Simulated trials per cell, {range}, each with a random first-attempt phase (or all at --phase).",
)
@ranged_option(
    "--phase",
    bounds=PHASE_OR_PROTOCOL_BOUNDS,
    default=None,
    help="Every trial's first attempt at this phase phi_1, {range}: with 'protocol' each cell at the phase the "
    "lab's protocol gives it (the leg command's lead before the first opening, servo log, minus the measured "
    "leg's lag to the midline at its amplitude, vib_pulse_v2.mat; landscape physical kinematics) [default: a "
    "random phase per trial].",
)
@validation_cv_option
@validation_seed_option
@click.option(
    "--cells",
    type=str,
    default=None,
    help="Only these cells, WING:LEG in degrees of the wing command, e.g. 60:15,75:0 [default: all 12 recorded].",
)
@validation_duration_option
@ranged_option(
    "--dt",
    bounds=DT_S_BOUNDS,
    default=None,
    help="Physics time step, s, {range} [default: the robot's converged step].",
)
@ranged_option(
    "--robot-attempts",
    bounds=COUNT_BOUNDS,
    default=None,
    help="Count a robot trial as righted only within its first N wing openings, {range}, as the lab's "
    "per-attempt table "
    "counts its 10 s trials (5); the robot's recordings run up to 10 openings [default: every recorded opening].",
)
@ranged_option(
    "--imu-mounting",
    bounds=IMU_MOUNTING_DEG_BOUNDS,
    default=0.0,
    show_default=True,
    help="Judge the robot's uprightness (success, time to right) in a body frame pitched this many degrees, {range}, "
    "below "
    "its IMU's: at 90 deg the robot stands near 90 deg of pitch, and its IMU's frame counts it upright once the "
    "IMU's pitch passes 90 deg (landscape physical kinematics measures it from the robot's two rests).",
)
@workers_option
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default="validation",
    show_default=True,
    help="Output directory: validation.csv, validation.json, time_to_right.png/.svg and the trial store "
    "(trials_<set>_<hash>.sqlite; rerunning resumes it).",
)
@no_progress_option
def validate_cmd(
    data,
    robot,
    joints,
    model_set,
    engine,
    trials,
    phase,
    cv,
    seed,
    cells,
    duration,
    dt,
    robot_attempts,
    imu_mounting,
    workers,
    out,
    no_progress,
):
    """Simulate the physical robot's cells with a model set and compare: success per cell (Wilson 95 %, fit
    cells leg 0/30 and held-out cells leg 15/45 apart), per-attempt rates, righting side, time to right."""
    from dataclasses import asdict

    from landscape.analysis.physical.validation import validate
    from landscape.cli.options import robot_urdf, robot_urdf_arg, writable_dir
    from sim.engine import require_engine
    from sim.model_set import load_model_set

    require_engine(engine)
    writable_dir(out, "--out")
    phase = _phase_arg(phase, data)
    ms = load_model_set(model_set).with_engine(engine)
    Path(out).mkdir(parents=True, exist_ok=True)
    db = Path(out) / f"trials_{ms.name}_{ms.model_set_hash}.sqlite"
    with sweep_errors():
        v, summary = validate(
            data,
            db=db,
            robot=robot_urdf_arg(robot),
            model_set=model_set,
            trials=trials,
            cv=cv,
            seed=seed,
            cells=cells,
            duration_s=duration,
            dt_s=dt,
            joint_map=joints,
            workers=workers,
            progress=not no_progress,
            phase=phase,
            robot_attempts=robot_attempts,
            imu_mount_deg=imu_mounting,
            engine=engine,
        )
    click.echo(
        f"{summary.total} simulated trials: {summary.skipped} already in {db}, ran {summary.ran} in "
        f"{summary.wall_s:.1f} s ({summary.cpu_s:.0f} trial CPU-s)"
    )
    doc = asdict(v) | {
        "robot": str(robot_urdf(robot)),
        "trials": trials,
        **_phase_doc(phase),
        "cv": cv,
        "seed": seed,
        "store": str(db),
        "engine": engine,
    }
    _report_validation(Path(out), v, {"validation.csv": list(v.cells)}, "validation.json", doc)


def _phase_doc(phase) -> dict:
    """How a validation or calibration set its first-attempt phases, for its JSON: ``phase`` (None for random, a
    number, or ``protocol``) and, for the protocol, ``cell_phases`` keyed ``WING:LEG``."""
    protocol = isinstance(phase, dict)
    return {
        "phase": "protocol" if protocol else phase,
        "cell_phases": {f"{w:g}:{leg:g}": p for (w, leg), p in phase.items()} if protocol else None,
    }


def _phase_arg(phase, data):
    """``--phase``: None, a number in [0, 1), or ``protocol`` (each cell's phase under the lab's protocol,
    :func:`landscape.analysis.physical.response.protocol_phases`, printed as it is used)."""
    if phase is None or not isinstance(phase, str):
        return phase
    if phase == "protocol":
        from landscape.analysis.physical.response import protocol_phases

        phases = protocol_phases(data)
        shown = sorted({(leg, round(p, 3)) for (_, leg), p in phases.items()})
        click.echo(
            "first-attempt phases by the protocol: " + ", ".join(f"leg {leg:g}° {p:.3f}" for leg, p in shown)
        )
        return phases
    raise AssertionError(f"--phase {phase!r}: RangedParam returns a number or 'protocol'")


@physical.command("calibrate")
@DATA_OPT
@SIM_ROBOT
@click.option(
    "--base",
    type=str,
    default="physical",
    show_default=True,
    help="The model set the candidates start from: a shipped name or a .toml file.",
)
@click.option(
    "--vary",
    multiple=True,
    required=True,
    help="TABLE.KEY=V1,V2,... of the base set to search, e.g. contact.lateral_friction=0.5,0.75,1; a value "
    "with slashes is a list, e.g. actuation.wing_extra_deg=15/12/3,15/15/3 (one per wing command); repeat for "
    "more keys: every combination is a candidate.",
)
@ranged_option(
    "--trials",
    bounds=TRIALS_BOUNDS,
    default=6,
    show_default=True,
    help="Simulated trials per fit cell and candidate, {range}.",
)
@ranged_option(
    "--validate-trials",
    bounds=TRIALS_BOUNDS,
    default=10,
    show_default=True,
    help="Simulated trials per cell when the best candidate is validated on every cell, {range}.",
)
@angle_option(
    "--fit-legs",
    many=True,
    default="0,30",
    show_default=True,
    help="Leg amplitudes (degrees, each {range}) of the fit cells; the others (15, 45) are held out.",
)
@click.option(
    "--openings/--outcomes-only",
    default=False,
    show_default=True,
    help="Also score how each candidate's first opening moves against the robot's (the hold's wobble, the tilt "
    "at closing, the roll past 45°; one opening per fit cell at --opening-phase), not only its outcomes.",
)
@ranged_option(
    "--opening-phase",
    bounds=PHASE_BOUNDS,
    default=None,
    help="Leg phase of the scored openings, {range} [default: the protocol's, 0.17].",
)
@click.option(
    "--side/--no-side",
    default=False,
    show_default=True,
    help="Also score the side of the roll-overs: the robot's on the fit cells (how many went to +roll) under each "
    "candidate's simulated fraction.",
)
@click.option(
    "--time-to-right/--no-time-to-right",
    default=False,
    show_default=True,
    help="Also score the time to right: the robot's median in each fit cell where both right under the "
    "candidate's (a spread of a factor of about 1.4).",
)
@ranged_option(
    "--phase",
    bounds=PHASE_OR_PROTOCOL_BOUNDS,
    default=None,
    help="Every simulated trial's first attempt (candidates' and the best one's validation) at this phase phi_1, "
    "{range}: with 'protocol' each cell at the phase the lab's protocol gives it (as validate --phase "
    "protocol) [default: a random phase per trial].",
)
@validation_cv_option
@validation_seed_option
@validation_duration_option
@engine_option
@workers_option
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default="calibration",
    show_default=True,
    help="Output directory: candidates/, one trial store per candidate (rerunning resumes), best.toml, "
    "calibration.csv/.json and the best set's validation.",
)
@no_progress_option
def calibrate_cmd(
    data, robot, base, vary, trials, validate_trials, fit_legs, openings, opening_phase, side, time_to_right, phase,
    cv, seed, duration, engine, workers, out, no_progress,
):  # fmt: skip
    """Fit a model set to the physical outcomes: every combination of the --vary values is simulated on the fit
    cells and scored by the log-likelihood of the recorded outcomes (with --openings also of the recorded first
    openings); the best is written as best.toml and validated on every cell, the held-out cells reported on
    their own."""
    from dataclasses import asdict

    from geometry.errors import UsageError
    from landscape.analysis.physical.calibration import calibrate, format_value, parse_vary
    from landscape.cli.options import robot_urdf_arg, writable_dir
    from landscape.viz.files import json_text
    from sim.engine import require_engine

    require_engine(engine)
    if opening_phase is not None and not openings:
        raise UsageError("--opening-phase sets the phase of the scored openings; give --openings as well")
    writable_dir(out, "--out")
    grid = parse_vary(vary)
    phase = _phase_arg(phase, data)
    Path(out).mkdir(parents=True, exist_ok=True)

    def done(c, i, n):
        changes = ", ".join(f"{k} = {format_value(v)}" for k, v in c.overrides.items())
        scored = f", openings {c.opening_log_likelihood:.2f}" if openings else ""
        scored += f", side {c.side_log_likelihood:.2f}" if side else ""
        scored += f", time to right {c.time_log_likelihood:.2f}" if time_to_right else ""
        scored += f" (score {c.score:.2f})" if openings or side or time_to_right else ""
        click.echo(
            f"[{i}/{n}] {c.name} ({changes}): log-likelihood {c.log_likelihood:.2f}, {c.agree}/{c.cells} agree"
            + scored
        )

    with sweep_errors():
        cal = calibrate(
            data,
            out_dir=out,
            vary=grid,
            base=base,
            robot=robot_urdf_arg(robot),
            trials=trials,
            validate_trials=validate_trials,
            cv=cv,
            seed=seed,
            fit_legs_deg=fit_legs,
            duration_s=duration,
            workers=workers,
            progress=not no_progress,
            on_candidate=done,
            openings=openings,
            opening_phase=opening_phase,
            side=side,
            phase=phase,
            time_to_right=time_to_right,
            engine=engine,
        )
    best = cal.candidates[0]
    click.echo(f"\nbest: {best.name} ({best.overrides}) -> {cal.best_file}; validated on every cell:\n")
    rows = [c.__class__(**{**asdict(c), "overrides": json_text(c.overrides)}) for c in cal.candidates]
    tables = {"calibration.csv": rows, "validation.csv": list(cal.validation.cells)}
    doc = asdict(cal) | _phase_doc(phase)
    _report_validation(Path(out), cal.validation, tables, "calibration.json", doc)
