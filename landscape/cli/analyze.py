"""``landscape analyze …`` and ``landscape report``: the source paper's analyses of a trial database
(:mod:`landscape.viz.sections`) as CSV tables, PNG/SVG figures and one self-contained HTML page."""

from __future__ import annotations

import json
import math
from dataclasses import asdict
from pathlib import Path

import click

from geometry.bounds import Bounds
from geometry.errors import UsageError
from landscape.cli.options import (
    CV_HELP,
    angle_option,
    grid_step_option,
    leg_period_option,
    no_progress_option,
    ranged_option,
    robot_option,
    wing_period_option,
)
from sim.protocol import (
    CV_BOUNDS,
    PAPER_LEG_PERIOD_S,
    PERIOD_S_BOUNDS,
    PHASE_BOUNDS,
    SEED_BOUNDS,
    TRIALS_BOUNDS,
)

TRIALS_ROBOT = robot_option(
    extra_help="The robot the trials ran on, if its stored URDF moved.",
    default_help="the stored path, else the built-in robot if the trials ran on it",
)


def _robot_file(robot: str | None):
    if robot is None:
        return None
    from landscape.cli.options import robot_urdf

    return robot_urdf(robot)


# ---------------------------------------------------------------------------------------------- commands
def _out(out: Path) -> Path:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return out


def _sections():
    from landscape.viz import sections

    return sections


def _echo_section(s) -> None:
    if s.missing:
        raise UsageError(f"{s.title}: {s.missing}")
    for p in s.paragraphs:
        click.echo(p)
    for f in s.figures:
        click.echo(f"wrote {f.png} and {f.svg}")
    for t in s.tables:
        click.echo(f"wrote {t.csv}")


DB_OPT = click.option(
    "--db",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="SQLite trial database (from `landscape sweep`).",
)
OUT_OPT = click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default="analysis",
    show_default=True,
    help="Output directory.",
)


def physical_dir_option(help_text: str):
    """``--physical DIR``: the lab's data-robot folder (an existing directory)."""
    return click.option(
        "--physical",
        "physical_dir",
        type=click.Path(exists=True, file_okay=False, path_type=Path),
        default=None,
        help=help_text,
    )


@click.group("analyze")
def analyze():
    """The source paper's analyses from a trial database (CSV + PNG/SVG)."""


TRIALS_PHASE_OPT = ranged_option(
    "--phase",
    bounds=PHASE_BOUNDS,
    default=None,
    help="phi_1 of the trials to use, a fraction of the leg period {range} [default: the most common].",
)
SAMPLE_BOUNDS = Bounds(1, math.inf, integer=True, meaning="a count of stored trials")
FOLLOWED_ATTEMPTS_BOUNDS = Bounds(1, math.inf, integer=True, meaning="wing openings to follow")


@analyze.command("probability")
@DB_OPT
@OUT_OPT
@TRIALS_PHASE_OPT
def probability_cmd(db, out, phase):
    """Self-righting probability over theta_w x theta_l per Cv, with Wilson 95 % intervals (Fig. 6)."""
    _echo_section(_sections().section_probability(_sections().load_rows(db), _out(out), db, phase=phase))


@analyze.command("phase-map")
@DB_OPT
@OUT_OPT
@ranged_option(
    "--leg-period",
    bounds=PERIOD_S_BOUNDS,
    default=PAPER_LEG_PERIOD_S,
    show_default=True,
    help="Tl, the leg period of the map, s, {range}.",
)
def phase_map_cmd(db, out, leg_period):
    """Single-attempt outcome against phase and theta_l, per theta_w (Fig. 7)."""
    _echo_section(
        _sections().section_phase_map(_sections().load_rows(db), _out(out), db, leg_period_s=leg_period)
    )


@analyze.command("prediction")
@DB_OPT
@OUT_OPT
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help="Print one JSON object per predictor (name, trials, correct, accuracy, "
    "ci95, held_out) and nothing else.",
)
@click.option(
    "--states",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="File of the study trials' opening states, appended as they are rerun (resumable) [default: DB.opening-"
    "states.jsonl beside the database].",
)
@TRIALS_ROBOT
@no_progress_option
def prediction_cmd(db, out, as_json, states, robot, no_progress):
    """Prediction of the first righting attempt against simulation (Fig. 8): the paper's phase map and a predictor
    that also knows the state each attempt starts from, both scored on held-out trials with 95 % intervals
    (reruns the study's trials with a trace once, resumably)."""
    from landscape.viz.sections.data import load_rows
    from landscape.viz.sections.prediction import prediction_scores, section_prediction

    rows = load_rows(db)
    kw = dict(states_path=states, robot=_robot_file(robot), progress=not no_progress)
    if as_json:
        res = prediction_scores(rows, db, **kw)
        click.echo(json.dumps([x.as_json() for x in res.scores], indent=1))
        return
    _echo_section(section_prediction(rows, _out(out), db, **kw))


@analyze.command("energy")
@DB_OPT
@OUT_OPT
@ranged_option(
    "--sample",
    bounds=SAMPLE_BOUNDS,
    default=None,
    help="Multi-attempt trials to rerun with a trace, {range}, at most those stored [default: 8, or all if "
    "fewer].",
)
@physical_dir_option(
    "The lab's data-robot folder: put the robot's recorded attempts beside the simulated ones (model set "
    "physical-head) [default: simulated only]."
)
@TRIALS_ROBOT
@no_progress_option
def energy_cmd(db, out, sample, physical_dir, robot, no_progress):
    """Kinetic energy against the barrier, attempt by attempt: reruns stored multi-attempt trials with a trace
    (checking each against its stored outcome), writes energy.csv (one row per attempt) and energy.png."""
    s = _sections()
    _echo_section(
        s.section_energy(
            s.load_rows(db),
            _out(out),
            db,
            sample=sample,
            robot=_robot_file(robot),
            physical_dir=physical_dir,
            progress=not no_progress,
        )
    )


@analyze.command("compare")
@click.option(
    "--db",
    "dbs",
    type=click.Path(dir_okay=False, path_type=Path),
    multiple=True,
    required=True,
    help="Two SQLite trial databases (from `landscape sweep`), given as --db A --db B: two engines, model sets or "
    "time steps over the same settings.",
)
@ranged_option(
    "--min-trials",
    bounds=TRIALS_BOUNDS,
    default=20,  # landscape.analysis.compare.MIN_TRIALS (kept out of this module's imports: the CLI loads lazily)
    show_default=True,
    help="Test a multi-attempt setting only if each database holds at least this many of its trials, {range} "
    "(a setting of one trial against one cannot tell two probabilities apart; the paper's sweep has 40).",
)
@OUT_OPT
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object and nothing else.")
def compare_cmd(dbs, min_trials, out, as_json):
    """Two databases setting by setting: each multi-attempt setting with enough trials in both by Fisher's exact
    test of its success counts (consistent when p >= 0.05) and the noise-free single attempts outcome for outcome;
    writes compare.csv."""
    import csv

    from landscape.analysis.compare import compare_probabilities, compare_single_attempts, source
    from landscape.analysis.trials import CONSISTENT_P

    if len(dbs) != 2:
        raise UsageError(f"compare takes two databases (--db A --db B); got {len(dbs)}")
    sections = _sections()
    rows_a, rows_b = (sections.load_rows(db) for db in dbs)
    cells, few = compare_probabilities(rows_a, rows_b, min_trials=min_trials)
    singles = compare_single_attempts(rows_a, rows_b)
    if not cells and not few and not singles.n:
        raise UsageError(
            f"'{dbs[0]}' and '{dbs[1]}' share no setting; sweep the same settings into both (only the engine, the "
            "model set or the step should differ)"
        )
    consistent = sum(c.consistent for c in cells)
    if as_json:
        doc = {
            "a": {"db": str(dbs[0]), "source": source(rows_a)},
            "b": {"db": str(dbs[1]), "source": source(rows_b)},
            "min_trials": min_trials,
            "settings": len(cells),
            "settings_with_fewer_trials": few,
            "consistent": consistent,
            "consistent_p": CONSISTENT_P,
            "cells": [asdict(c) for c in cells],
            "single_attempts": {k: v for k, v in asdict(singles).items() if k != "differ"},
        }
        click.echo(json.dumps(doc, indent=1))
        return
    out = _out(out)
    for label, db, rows in (("A", dbs[0], rows_a), ("B", dbs[1], rows_b)):
        click.echo(f"{label}: {db}  {source(rows)}")
    if cells:
        share = 100.0 * consistent / len(cells)
        click.echo(
            f"multi-attempt settings in both with at least {min_trials} trials each: {len(cells)}; Fisher's exact "
            f"test cannot tell A from B (p >= {CONSISTENT_P:g}) in {consistent} ({share:.1f} %)"
        )
    if few:
        click.echo(f"multi-attempt settings with fewer trials in either (not tested; --min-trials): {few}")
        odd = [c for c in cells if not c.consistent]
        if odd:
            click.echo("  theta_w  theta_l    cv  phase   Tw    Tl      A        B       p")
            for c in odd:
                click.echo(
                    f"  {c.theta_w_deg:7g}  {c.theta_l_deg:7g}  {c.cv:4g}  {c.phase:5g}  {c.wing_period_s:3g}  "
                    f"{c.leg_period_s:4g}  {c.k_a:3d}/{c.n_a:<3d}  {c.k_b:3d}/{c.n_b:<3d}  {c.fisher_p:.4f}"
                )
    if singles.n:
        click.echo(
            f"noise-free single attempts in both: {singles.n}; the same outcome in {singles.same} (righted: A "
            f"{singles.righted_a}, B {singles.righted_b})"
        )
    path = out / "compare.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["theta_w_deg", "theta_l_deg", "cv", "phase", "wing_period_s", "leg_period_s", "successes_a",
                    "trials_a", "successes_b", "trials_b", "fisher_p"])  # fmt: skip
        for c in cells:
            w.writerow([*asdict(c).values()])
    click.echo(f"wrote {path}")


@analyze.command("evolution")
@DB_OPT
@OUT_OPT
@angle_option(
    "--theta-w",
    default=None,
    help="Wing opening angle, degrees, {range} [default: the prediction study's].",
)
@angle_option(
    "--theta-l",
    default=None,
    help="Leg oscillation amplitude, degrees, {range} [default: the prediction study's].",
)
@ranged_option(
    "--phase",
    bounds=PHASE_BOUNDS,
    default=None,
    help="phi_1, the first attempt's phase, a fraction of the leg period {range} [default: a start "
    "that never rights without noise].",
)
@ranged_option(
    "--cv",
    bounds=CV_BOUNDS,
    default=0.15,
    show_default=True,
    help=f"{CV_HELP}: the noise of the noisy sequence.",
)
@ranged_option(
    "--seed",
    bounds=SEED_BOUNDS,
    default=1,
    show_default=True,
    help="Random seed of the noisy sequence, {range}.",
)
@wing_period_option
@leg_period_option
@ranged_option(
    "--attempts",
    bounds=FOLLOWED_ATTEMPTS_BOUNDS,
    default=12,
    show_default=True,
    help="Wing openings (attempts) to follow, {range}.",
)
def evolution_cmd(db, out, theta_w, theta_l, phase, cv, seed, wing_period, leg_period, attempts):
    """Phases visited over attempts, without and with noise, over the phase map (Fig. 9)."""
    _echo_section(
        _sections().section_evolution(
            _sections().load_rows(db),
            _out(out),
            db,
            theta_w_deg=theta_w,
            theta_l_deg=theta_l,
            phase=phase,
            cv=cv,
            seed=seed,
            wing_period_s=wing_period,
            leg_period_s=leg_period,
            attempts=attempts,
        )
    )


@analyze.command("barrier")
@DB_OPT
@OUT_OPT
@grid_step_option
@TRIALS_PHASE_OPT
@TRIALS_ROBOT
def barrier_cmd(db, out, step, phase, robot):
    """Minimal barrier against self-righting probability and time to right: Spearman rho, logistic fit."""
    from landscape.cli.options import grid_step

    grid_step(step)
    _echo_section(
        _sections().section_barrier(
            _sections().load_rows(db), _out(out), db, step_deg=step, phase=phase, robot=_robot_file(robot)
        )
    )


@click.command("report")
@DB_OPT
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default="report",
    show_default=True,
    help="Directory for index.html and every figure (PNG, SVG) and table (CSV) it shows.",
)
@click.option(
    "--check/--no-check",
    default=False,
    show_default=True,
    help="Open the page in headless Chromium: no console errors, every image loaded, a screenshot.",
)
@physical_dir_option(
    "The lab's data-robot folder (e.g. ../shared/ref/physical_robot): add a section with the physical "
    "robot's recorded attempts at each wing angle over the landscape at its measured wing plateau, and its "
    "trials' outcomes per setting, and its attempts to the energy section [default: no physical section]."
)
@click.option(
    "--validation",
    "validations",
    multiple=True,
    type=click.Path(exists=True, path_type=Path),
    help="An output directory (or validation.json) of `landscape physical validate` or `calibrate`: add the "
    "simulation-against-physical section (repeat for several model sets; with --physical, also the resting "
    "pitch table) [default: no validation section].",
)
@TRIALS_ROBOT
def report_cmd(db, out, check, physical_dir, validations, robot):
    """One self-contained HTML page with every analysis, its figures (PNG, SVG) and tables (CSV); with
    --physical, the physical robot's attempts too; with --validation, the simulation against the physical robot."""
    from landscape.viz.report import check_page
    from landscape.viz.sections import build_report

    out = _out(out)
    page, sections = build_report(
        db, out, robot=_robot_file(robot), physical_dir=physical_dir, validations=list(validations)
    )
    missing = [s.title for s in sections if s.missing]
    click.echo(
        f"wrote {page} ({len(sections) - len(missing)}/{len(sections)} analyses"
        + (f"; missing data for: {', '.join(missing)}" if missing else "")
        + ")"
    )
    if check:
        try:
            res = check_page(page, screenshot=out / "screenshot.png")
        except RuntimeError as exc:
            raise UsageError(str(exc)) from None
        click.echo(
            f"checked in {res.browser}: images {res.images_ok}/{res.images_total}, console errors "
            f"{len(res.console_errors)}, screenshot {res.screenshot}"
        )
        (out / "check.json").write_text(json.dumps(asdict(res), default=str, indent=1))
        if not res.ok:
            raise click.ClickException(
                "the report page failed the browser check: "
                + "; ".join(res.console_errors[:3] or ["images missing"])
            )
