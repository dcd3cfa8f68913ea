"""``landscape simulate``, ``sweep`` and ``export``: one trial, a resumable sweep into SQLite, and the stored trials
as CSV, in pybullet or MuJoCo (``--engine``). The engine loads only when a command runs."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import click

from landscape.cli.options import (
    CV_HELP,
    THETA_W_HELP,
    UsageError,
    angle_option,
    check_theta_w,
    engine_option,
    joints_option,
    leg_period_option,
    model_set_option,
    no_progress_option,
    ranged_option,
    robot_option,
    robot_urdf_arg,
    sweep_errors,
    warn,
    wing_period_option,
    workers_option,
    writable_file,
)
from sim.protocol import (
    ATTEMPTS_BOUNDS,
    CV_BOUNDS,
    DEFAULT_DT_S,
    DEFAULT_DURATION_S,
    DT_S_BOUNDS,
    DURATION_S_BOUNDS,
    HEADING_DEG_BOUNDS,
    MAX_TRIALS,
    MUJOCO_DT_S,
    MUJOCO_OTHER_ROBOT_DT_S,
    OTHER_ROBOT_DT_S,
    PAPER_LEG_PERIOD_S,
    PAPER_TRIALS,
    PAPER_WING_PERIOD_S,
    PERIOD_S_BOUNDS,
    PHASE_BOUNDS,
    SEED_BOUNDS,
    TRIALS_BOUNDS,
)

DURATION_OPT = ranged_option(
    "--duration",
    bounds=DURATION_S_BOUNDS,
    default=DEFAULT_DURATION_S,
    show_default=True,
    help="Trial length, s, {range}.",
)
DT_OPT = ranged_option(
    "--dt",
    bounds=DT_S_BOUNDS,
    default=None,
    help=f"Physics time step, s, {{range}} [default: pybullet {DEFAULT_DT_S:g}, MuJoCo {MUJOCO_DT_S:g} for the "
    f"built-in robot, {OTHER_ROBOT_DT_S:g} and {MUJOCO_OTHER_ROBOT_DT_S:g} for others: the largest steps that "
    "pass the convergence benchmark; a larger one gets a warning].",
)


def _warn_coarse_dt(dt: float | None, robot: str | None, engine: str = "pybullet") -> None:
    """A step coarser than the robot's converged default is allowed, with a warning that names the default."""
    if dt is None:
        return
    from sim.trial import default_dt_s

    converged = default_dt_s(robot, engine)
    if dt > converged * (1 + 1e-9):
        warn(
            f"--dt {dt:g} s is coarser than {converged:g} s, the largest step that passes "
            "the convergence benchmark for this robot (benchmarks/sim_convergence.py); outcomes may differ"
        )


def _check_wing(theta_w_deg, robot: str | None, joints: str | None, theta_l_deg=None) -> None:
    """Before any trial: the robot drives both angles (:func:`sim.model.check_trial_joints` says what a trial
    needs), and the wing angles lie in its wing opening range, from closed (0) to the joints' limit; angles that
    look like radians get a warning (:func:`landscape.cli.options.warn_radians`)."""
    from pathlib import Path

    from landscape.cli.options import load_robot, warn_radians
    from sim.model import check_trial_joints

    r = load_robot(robot, None, joints=joints)
    check_trial_joints(r, Path(r.source).name if r.source else r.name)
    check_theta_w(theta_w_deg, r.theta_limits_deg(), r.name, opening=True)
    warn_radians(r, theta_w=theta_w_deg, theta_l=theta_l_deg)


SCHEDULER_RE = re.compile(r"(tcp|tls|inproc|ucx)://[^\s:/]+(:\d{1,5})?")


def write_trace_csv(trace, path: Path, meta_lines: tuple[str, ...] = ()) -> Path:
    """Write a trial trace as CSV with a header row (SI units and degrees, as the column names say), then
    ``meta_lines`` ('# key=value' notes that ``np.loadtxt`` skips as comments)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(trace.COLUMNS)
        for line in meta_lines:
            f.write(line + "\n")
        for row in trace.as_array():
            w.writerow([f"{x:.9g}" for x in row])
    return path


def _human(r, robot: str) -> str:
    lines = [
        f"robot        {robot}",
        f"model set    {r.model_set} ({r.model_set_hash})",
        f"engine       {r.engine}",
        f"inputs       theta_w {r.theta_w_deg:g}°  theta_l {r.theta_l_deg:g}°  phase {r.phase:g}  Cv {r.cv:g}  "
        f"seed {r.seed}  duration {r.duration_s:g} s  dt {r.dt_s:g} s",
    ]
    if r.success:
        lines.append(f"outcome      RIGHTED at {r.time_to_right_s:.3f} s on attempt {r.attempt} by {r.mode}")
    else:
        lines.append(f"outcome      not righted in {r.duration_s:g} s ({len(r.phases)} attempts)")
    lines.append("phases       " + " ".join(f"{p:.3f}" for p in r.phases))
    lines.append(
        f"timing       {r.wall_s:.2f} s wall, {r.cpu_s:.2f} s CPU for {r.sim_s:.2f} s simulated; "
        f"max joint tracking error {r.max_tracking_error_deg:.2f}°"
    )
    return "\n".join(lines)


@click.command("simulate")
@angle_option("--theta-w", required=True, help=THETA_W_HELP)
@angle_option(
    "--theta-l",
    required=True,
    help="Leg oscillation amplitude, degrees, {range} and within the leg joint's limits.",
)
@ranged_option(
    "--phase",
    bounds=PHASE_BOUNDS,
    default=0.0,
    show_default=True,
    help="First attempt's phase phi_1 = dt_1 / Tl, {range}.",
)
@ranged_option("--cv", bounds=CV_BOUNDS, default=0.0, show_default=True, help=CV_HELP + ".")
@ranged_option(
    "--seed",
    bounds=SEED_BOUNDS,
    default=None,
    help="Random seed of the noise, {range} [default: a fresh seed, reported].",
)
@DURATION_OPT
@DT_OPT
@click.option(
    "--trace",
    "trace_path",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the pitch/roll/energy trace to this CSV file [default: no trace].",
)
@click.option(
    "--video",
    "video_path",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Render the trial to this .mp4 or .gif file (25 frames/s, real time, offscreen): the robot, the "
    "time, the wing and leg angles and the energy in mJ [default: no video].",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of a summary.")
@robot_option
@joints_option
@wing_period_option
@leg_period_option
@ranged_option(
    "--attempts",
    bounds=ATTEMPTS_BOUNDS,
    default=0,
    show_default=True,
    help="At most this many wing openings, {range} (1: a single attempt, ending one Tw after it); 0: no limit.",
)
@ranged_option(
    "--heading",
    bounds=HEADING_DEG_BOUNDS,
    default=0.0,
    show_default=True,
    help="The robot's heading on the ground, degrees about the vertical, {range}. It matters only because "
    "pybullet's friction is not isotropic (a quarter turn never changes a trial; see docs/sim.md).",
)
@model_set_option
@engine_option
def simulate(
    theta_w,
    theta_l,
    phase,
    cv,
    seed,
    duration,
    dt,
    trace_path,
    video_path,
    as_json,
    robot,
    joints,
    wing_period,
    leg_period,
    attempts,
    heading,
    model_set,
    engine,
):
    """Run one self-righting trial (pybullet or MuJoCo) and report its outcome."""
    from geometry import JointMap
    from landscape.viz.files import json_text
    from sim.engine import require_engine
    from sim.model import default_robot_urdf
    from sim.model_set import load_model_set
    from sim.trial import run_trial
    from sim.world import SimulationDiverged

    require_engine(engine)
    robot_path = robot_urdf_arg(robot) or str(default_robot_urdf())
    _check_wing(theta_w, robot_path, joints, theta_l)
    _warn_coarse_dt(dt, robot_path, engine)
    if trace_path is not None:
        writable_file(trace_path, "--trace", inputs=(robot_path,))
    ms = load_model_set(model_set).with_engine(engine)
    if video_path is not None:
        from landscape.viz.video import check_video_path

        writable_file(video_path, "--video", inputs=(robot_path, trace_path))
        check_video_path(video_path)
    try:
        act = ms.actuation(theta_w, theta_l, wing_period_s=wing_period, leg_period_s=leg_period)
        r = run_trial(
            theta_w,
            theta_l,
            phase=phase,
            cv=cv,
            rng=seed,
            duration_s=duration,
            dt_s=dt,
            robot=robot_path,
            joint_map=JointMap.parse(joints) if joints else None,
            trace=trace_path is not None or video_path is not None,
            actuation=act,
            attempts=attempts or None,
            model_set=ms,
            heading_deg=heading,
        )
    except SimulationDiverged as exc:
        raise click.ClickException(str(exc).splitlines()[0]) from None
    if trace_path is not None:
        from landscape.viz.trajectory import trace_meta_lines

        write_trace_csv(
            r.trace,
            trace_path,
            tuple(
                trace_meta_lines(
                    robot_hash=r.robot_hash,
                    theta_w_deg=r.theta_w_deg,
                    theta_l_deg=r.theta_l_deg,
                    righted=r.success,
                )
            ),
        )
    if video_path is not None:
        from landscape.viz.video import write_trial_video

        outcome = f"righted at {r.time_to_right_s:.2f} s" if r.success else "not righted"
        write_trial_video(
            r.trace,
            video_path,
            robot=robot_path,
            joint_map=JointMap.parse(joints) if joints else None,
            title=f"{Path(robot_path).stem}  wing {theta_w:g}°  leg {theta_l:g}°  {outcome}",
        )
    if as_json:
        d = r.to_dict()
        d["robot"] = robot_path
        click.echo(json_text(d))
    else:
        click.echo(_human(r, robot_path))
        if trace_path is not None:
            click.echo(f"trace        {trace_path}")
        if video_path is not None:
            click.echo(f"video        {video_path}")


@click.command("sweep")
@angle_option(
    "--theta-w",
    many=True,
    default="70,72,74,76",
    show_default=True,
    help="Wing opening angles, degrees, each {range} and from 0 (closed) to the wing joints' limit: list or "
    "START:STOP:STEP.",
)
@angle_option(
    "--theta-l",
    many=True,
    default="20,30,40,50",
    show_default=True,
    help="Leg amplitudes, degrees, each {range} and within the leg joint's limits: list or START:STOP:STEP.",
)
@ranged_option(
    "--cv",
    bounds=CV_BOUNDS,
    many=True,
    default="0,0.05,0.1,0.15,0.2,0.25",
    show_default=True,
    help="Noise levels Cv = sigma / Tl, each a fraction {range} (0%:25%:5%): list or START:STOP:STEP.",
)
@ranged_option(
    "--phase",
    bounds=PHASE_BOUNDS,
    many=True,
    default="0.7",
    show_default=True,
    help="First-attempt phases phi_1, each {range}: list or START:STOP:STEP.",
)
@ranged_option(
    "--trials",
    bounds=TRIALS_BOUNDS,
    default=PAPER_TRIALS,
    show_default=True,
    help=f"Trials per parameter combination, {{range}} (a whole sweep holds at most {MAX_TRIALS:,} trials).",
)
@ranged_option(
    "--wing-period",
    bounds=PERIOD_S_BOUNDS,
    many=True,
    default=f"{PAPER_WING_PERIOD_S:g}",
    show_default=True,
    help="Tw values, s (time between wing openings), each {range}.",
)
@ranged_option(
    "--leg-period",
    bounds=PERIOD_S_BOUNDS,
    many=True,
    default=f"{PAPER_LEG_PERIOD_S:g}",
    show_default=True,
    help="Tl values, s (leg oscillation period), each {range}.",
)
@ranged_option(
    "--attempts",
    bounds=ATTEMPTS_BOUNDS,
    default=0,
    show_default=True,
    help="At most this many wing openings per trial, {range} (1: single-attempt trials for the phase map); 0: "
    "no limit.",
)
@click.option(
    "--db", type=click.Path(dir_okay=False, path_type=Path), required=True, help="SQLite results file."
)
@DURATION_OPT
@DT_OPT
@ranged_option(
    "--seed",
    "base_seed",
    bounds=SEED_BOUNDS,
    default=0,
    show_default=True,
    help="Base seed mixed into every trial's seed, {range}.",
)
@workers_option
@click.option(
    "--scheduler",
    type=str,
    default=None,
    help="Dask scheduler address tcp://HOST:PORT [default: none, local worker processes].",
)
@robot_option
@joints_option
@no_progress_option
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object.")
@model_set_option
@engine_option
def sweep(
    theta_w,
    theta_l,
    cv,
    phase,
    trials,
    wing_period,
    leg_period,
    attempts,
    db,
    duration,
    dt,
    base_seed,
    workers,
    scheduler,
    robot,
    joints,
    no_progress,
    as_json,
    model_set,
    engine,
):
    """Run (or resume) a sweep of self-righting trials into an SQLite database."""
    from dataclasses import asdict

    from landscape.viz.files import json_text
    from sim.sweep import run_sweep, stored_rows, success_table, sweep_specs

    if workers is not None and scheduler is not None:
        raise UsageError("give either --workers N (local processes) or --scheduler ADDRESS (Dask), not both")
    if scheduler is not None and not SCHEDULER_RE.fullmatch(scheduler):
        raise UsageError(
            f"--scheduler {scheduler!r} is not a scheduler address; give tcp://HOST:PORT "
            "(as printed by `dask scheduler`)"
        )
    tw, tl, cvs, phs, wps, lps = theta_w, theta_l, cv, phase, wing_period, leg_period
    robot = robot_urdf_arg(robot)
    from sim.engine import require_engine

    require_engine(engine)
    _check_wing(tw, robot, joints, tl)
    _warn_coarse_dt(dt, robot, engine)
    specs = sweep_specs(
        tw,
        tl,
        cvs,
        phase=phs,
        trials=trials,
        duration_s=duration,
        dt_s=dt,
        robot=robot,
        base_seed=base_seed,
        wing_period_s=wps,
        leg_period_s=lps,
        attempts=attempts,
        joint_map=joints,
        model_set=model_set,
        engine=engine,
    )
    with sweep_errors():
        summary = run_sweep(specs, db=db, workers=workers, scheduler=scheduler, progress=not no_progress)
    if as_json:
        click.echo(json_text(asdict(summary)))
        return
    click.echo(
        f"{summary.total} trials: {summary.skipped} already in {db}, ran {summary.ran} "
        f"({summary.diverged} diverged) in {summary.wall_s:.1f} s on {summary.workers} workers "
        f"= {summary.trials_per_s:.2f} trials/s, {summary.cpu_s:.0f} trial CPU-s"
        + (f"; {summary.duplicates} repeated settings dropped" if summary.duplicates else "")
        + (f"; {summary.pool_restarts} lost workers replaced" if summary.pool_restarts else "")
    )
    click.echo("success   theta_w  theta_l  cv     rate")
    for (w, l_, c), (k, n) in success_table(stored_rows(db, specs)).items():
        click.echo(f"          {w:7g}  {l_:7g}  {c:5g}  {k:3d}/{n:<3d}")


@click.command("export")
@click.option(
    "--db", type=click.Path(dir_okay=False, path_type=Path), required=True, help="SQLite results file."
)
@click.option(
    "--csv",
    "csv_path",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="CSV file to write.",
)
def export(db, csv_path):
    """Export every stored trial to CSV."""
    from sim.store import export_csv

    if not Path(db).is_file():
        raise UsageError(f"database '{db}' not found; run `landscape sweep --db {db}` first")
    writable_file(csv_path, "--csv", inputs=(db,))
    n = export_csv(db, csv_path)
    click.echo(f"wrote {n} trials to {csv_path}")
