"""The energy section: the energy budget of rerun multi-attempt trials and of the robot's recordings."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis.reruns import RERUN_TTR_TOL_S, reproduces, rerun_trial
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    PAPER_SWEEP,
    both_outcomes_first,
    trials_robot,
    write_csv,
)

ENERGY_TRIALS = 8
"""How many multi-attempt trials the energy section reruns with a trace, by default."""


def energy_reruns(
    rows: list[dict], db, *, sample: int | None = None, robot: str | Path | None = None, progress: bool = True
):
    """Up to ``sample`` (default :data:`ENERGY_TRIALS`) multi-attempt trials of ``rows``, both outcomes
    alternately in trial order, rerun with a trace (:func:`landscape.analysis.reruns.rerun_trial`) and checked against their stored
    outcome.

    Returns
    -------
    groups : list of (BodyModel, list of Motion)
        The reruns' motions, one group per model set, each with the robot as its set poses it.
    records : list of dict
        Per rerun: trial, seed, stored and rerun outcome and time to right, ``reproduced``.

    Raises
    ------
    UsageError
        If ``rows`` is empty or holds no multi-attempt trial, or ``sample`` is below 1 or above their number.
    """
    import sys

    from tqdm import tqdm

    from landscape.analysis import energy as en
    from sim.model_set import load_model_set

    if not rows:
        raise UsageError(f"'{db}' holds no trials; run `{PAPER_SWEEP.format(db=db)}` first")
    multi = [r for r in rows if r["status"] == "ok" and r["attempts"] == 0]
    if not multi:
        raise UsageError(
            f"'{db}' holds no multi-attempt trials (attempts without limit), whose attempts the energy budget "
            f"measures; run `{PAPER_SWEEP.format(db=db)}`"
        )
    if sample is not None and not 1 <= sample <= len(multi):
        raise UsageError(
            f"a sample of {sample} trials is not within the {len(multi)} multi-attempt trials of '{db}'; ask for "
            f"1 to {len(multi)}"
        )
    chosen = both_outcomes_first(multi, min(ENERGY_TRIALS if sample is None else sample, len(multi)))
    rb = trials_robot(chosen, robot)
    by_set: dict[str, list] = {}
    records = []
    for r in tqdm(chosen, desc="reruns", unit="trial", file=sys.stderr, disable=None if progress else True):
        res = rerun_trial(r, robot_urdf=rb.source)
        by_set.setdefault(r.get("model_set") or "paper", []).append(
            en.simulated_motion(res, trial=f"seed {r['seed']}")
        )
        records.append(
            {
                "trial": r["trial"],
                "seed": r["seed"],
                "model_set": r.get("model_set") or "paper",
                "stored_success": int(bool(r["success"])),
                "rerun_success": int(res.success),
                "stored_time_to_right_s": r["time_to_right_s"],
                "rerun_time_to_right_s": res.time_to_right_s,
                "reproduced": int(reproduces(r, res)),
            }
        )
    groups = [(en.body_model(rb, load_model_set(name)), motions) for name, motions in by_set.items()]
    return groups, records


def energy_files(out: Path, groups, *, title: str, progress: bool = True):
    """The energy budget of each (BodyModel, motions) group (:func:`landscape.analysis.energy.energy_budget`,
    one barrier table per group), written as ``out/energy.csv`` (one row per attempt) and ``out/energy.png``
    (and .svg). Returns the attempt rows, the traces (as (motion, trace) pairs), the CSV and the PNG."""
    import sys

    from tqdm import tqdm

    from landscape.analysis import energy as en
    from landscape.viz.energy_plots import plot_energy_attempts

    rows, traces = [], []
    for body, motions in groups:
        with tqdm(
            desc="barrier table", unit="pose", file=sys.stderr, disable=None if progress else True
        ) as bar:
            _, ets, attempt_rows = en.energy_budget(motions, body, progress=bar.update)
        rows += attempt_rows
        traces += list(zip(motions, ets, strict=True))
    csv_path = write_csv(out / "energy.csv", [r.row() for r in rows])
    png = plot_energy_attempts(rows, out / "energy.png", title=title)
    return rows, traces, csv_path, png


def energy_paragraphs(rows) -> list[str]:
    """One sentence per source: attempts, righted, and how often the margin's sign and the barrier alone match
    the outcome (Wilson 95 % intervals)."""
    from landscape.analysis import energy as en

    out = []
    for source in en.SOURCES:
        g = [r for r in rows if r.source == source]
        if not g:
            continue
        agree = en.sign_agreement(g)
        ratio = [r.ke_peak_mj / r.barrier_mj for r in g if math.isfinite(r.barrier_mj) and r.barrier_mj > 0]
        out.append(
            f"{source.capitalize()}: {len(g)} attempts of {len({r.trial for r in g})} trials, "
            f"{sum(r.success for r in g)} righted; peak kinetic energy in the barrier's direction over the barrier "
            f"median {np.median(ratio):.2g} (largest {max(ratio):.2g}). "
            + "; ".join(
                f"{a.name} matches the outcome in {a.correct}/{a.attempts} ({a.accuracy * 100:.0f} %, 95 % "
                f"[{a.ci_low * 100:.0f}, {a.ci_high * 100:.0f}] %)"
                for a in agree
            )
            + " (the barrier threshold is the best one on these same attempts)."
        )
    return out


ENERGY_METHOD = (
    "Per attempt, from the opening until the wings start closing or the body turns upright: kinetic energy of "
    "rotation about the CoM with the posed robot's inertia, split into body-axis shares (roll, pitch, yaw) that sum "
    "to it, plus the CoM's translation; the minimal righting barrier at the pose held (a barrier map over the poses "
    "visited, exact method, interpolated); the height above the basin's minimum. The margin is the largest value "
    "of kinetic energy in the barrier's direction plus height minus barrier; a positive margin says the attempt had "
    "the energy to cross. Simulated velocities come from the engine; recorded ones from the gyro (body frame: the "
    "IMU's mounting measured from the two rests), the CoM taken as rolling about the lowest hull point."
)


def section_energy(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    robot: str | Path | None = None,
    physical_dir: str | Path | None = None,
    sample: int | None = None,
    physical_set: str | None = None,
    progress: bool = True,
) -> Section:
    """The energy budget of up to ``sample`` (default :data:`ENERGY_TRIALS`) rerun multi-attempt trials
    (:func:`energy_reruns`) and, with ``physical_dir``, of the robot's recorded trials (model set
    ``physical_set``, default :data:`landscape.analysis.physical.motion.DEFAULT_PHYSICAL_SET`, on the lab robot of
    ``robot`` or the trials'), on one figure: ``out/energy.csv``, ``out/energy.png``, ``out/energy_reruns.csv``.
    A database without multi-attempt trials leaves the section missing (with the sweep to run)."""
    from landscape.analysis.physical.motion import DEFAULT_PHYSICAL_SET, recorded_motions
    from sim.model_set import load_model_set

    title = "Energy budget of the attempts"
    try:
        groups, records = energy_reruns(rows, db, sample=sample, robot=robot, progress=progress)
    except UsageError as exc:
        if sample is not None or physical_dir is None:
            return Section("energy", title, missing=str(exc))
        groups, records = [], []
    paras = [ENERGY_METHOD]
    tables = []
    if records:
        same = sum(x["reproduced"] for x in records)
        paras.append(
            f"{len(records)} multi-attempt trials rerun with a trace (seeds "
            f"{', '.join(str(x['seed']) for x in records)}): {same} of {len(records)} reproduce their stored outcome "
            f"(success and time to right within {RERUN_TTR_TOL_S * 1e6:g} µs)."
        )
        tables.append(
            Table("Reruns against the stored outcomes", write_csv(out / "energy_reruns.csv", records))
        )
    if physical_dir is not None:
        ms = load_model_set(physical_set or DEFAULT_PHYSICAL_SET)
        rec = recorded_motions(physical_dir, trials_robot(rows, robot), ms)
        groups = [*groups, (rec.body, rec.motions)]
        paras.append(
            f"Recorded: {len(rec.motions)} trials of the robot, posed by model set {rec.model_set}, IMU mounting "
            f"{rec.mount_deg:.1f}°."
        )
    attempt_rows, _, csv_path, png = energy_files(
        out,
        groups,
        title="Peak kinetic energy in the barrier's direction against the barrier",
        progress=progress,
    )
    paras += energy_paragraphs(attempt_rows)
    return Section(
        "energy",
        title,
        tuple(paras),
        (
            Figure(
                png,
                "Peak kinetic energy in the barrier's direction against the barrier",
                png.with_suffix(".svg"),
            ),
        ),
        (Table("One row per attempt", csv_path), *tables),
    )
