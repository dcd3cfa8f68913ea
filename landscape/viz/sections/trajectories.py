"""The trajectories section: trials of the most uncertain setting rerun with a trace and drawn over its landscape."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis.reruns import RERUN_TTR_TOL_S, reproduces, rerun_trial
from landscape.grid import DEFAULT_STEP_DEG
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    PAPER_PERIODS,
    both_outcomes_first,
    mixed_cell,
    paper_cells,
    trials_robot,
    write_csv,
)

TRAJECTORY_TRIALS = 8
"""How many trials of the chosen setting the trajectories section reruns with a trace, by default."""


def three_d_note() -> tuple[bool, str | None]:
    """Whether 3-D rendering runs here, and if not, the sentence that says why."""
    from landscape.viz import render as rd

    problem = rd.off_screen_problem()
    if problem is None:
        return True, None
    return False, f"3-D rendering is unavailable here ({problem}), so only the contour map is drawn."


def trajectory_figures(files: list[Path], caption: str) -> tuple[Figure, ...]:
    """The contour map (PNG with its SVG) and, if drawn, the 3-D landscape of :func:`render_trajectories`."""
    figs = [Figure(files[0], f"{caption}: contour map", files[1])]
    if len(files) > 2:
        figs.append(Figure(files[2], f"{caption}: over the 3-D landscape"))
    return tuple(figs)


def section_trajectories(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    robot: str | Path | None = None,
    max_trials: int = TRAJECTORY_TRIALS,
    step_deg: float = DEFAULT_STEP_DEG,
) -> Section:
    """Trajectories of the sweep's trials at its most uncertain setting, drawn over that setting's landscape.

    The setting is the paper protocol's (Tw 2 s, Tl 0.8 s, no attempt limit, the φ1 and trial protocol with most
    trials) whose trials disagree most (largest minority outcome fraction, then most trials). Up to
    ``max_trials`` (default :data:`TRAJECTORY_TRIALS`) of its trials, both outcomes alternately, are rerun with a
    trace (:func:`landscape.analysis.reruns.rerun_trial`); each rerun is checked against the stored outcome and time to right. The paths
    are drawn by :func:`landscape.viz.trajectory.render_trajectories` on a ``step_deg`` grid, into
    ``out/trajectories``; without off-screen 3-D rendering, the contour map only.
    """
    from landscape.computation import compute
    from landscape.viz.trajectory import render_trajectories

    title = "Trajectories of simulated trials over the landscape"
    if max_trials < 1:
        raise UsageError(f"max_trials must be at least 1; got {max_trials}")
    pc = paper_cells(rows, None, db)
    if not pc.cells:
        return Section("trajectories", title, missing=pc.missing)
    cell = mixed_cell(pc.cells)
    at = [
        r
        for r in rows
        if r["status"] == "ok"
        and r["attempts"] == 0
        and (r["wing_period_s"], r["leg_period_s"]) == PAPER_PERIODS
        and (r["duration_s"], r["dt_s"], r.get("model_set") or "paper", r.get("engine") or "pybullet")
        == (pc.duration_s, pc.dt_s, pc.model_set, pc.engine)
        and (r["theta_w_deg"], r["theta_l_deg"], r["cv"], r["phase"])
        == (cell.theta_w_deg, cell.theta_l_deg, cell.cv, cell.phase)
    ]
    try:
        rb = trials_robot(at, robot)
    except UsageError as exc:
        return Section("trajectories", title, missing=str(exc))
    chosen = both_outcomes_first(at, max_trials)
    results = [rerun_trial(r, robot_urdf=rb.source) for r in chosen]
    recs = []
    for r, res in zip(chosen, results, strict=True):
        recs.append(
            {
                "trial": r["trial"],
                "seed": r["seed"],
                "stored_success": int(bool(r["success"])),
                "rerun_success": int(res.success),
                "stored_time_to_right_s": r["time_to_right_s"],
                "rerun_time_to_right_s": res.time_to_right_s,
                "attempt": res.attempt,
                "mode": res.mode,
                "reproduced": int(reproduces(r, res)),
            }
        )
    same = sum(x["reproduced"] for x in recs)
    csv_path = write_csv(out / "trajectories.csv", recs)
    c = compute(rb, theta_w_deg=cell.theta_w_deg, theta_l_deg=cell.theta_l_deg, step_deg=step_deg)
    three_d, note = three_d_note()
    files = render_trajectories(
        c,
        [np.column_stack([res.trace.pitch_deg, res.trace.roll_deg]) for res in results],
        [res.success for res in results],
        out / "trajectories",
        robot_name=rb.name,
        what="simulated",
        landscape_3d=three_d,
    )
    n_ok = sum(res.success for res in results)
    paras = [
        f"The setting closest to the boundary: θw {cell.theta_w_deg:g}°, θl {cell.theta_l_deg:g}°, Cv "
        f"{cell.cv * 100:g} %, φ1 = {cell.phase:g} ({pc.protocol_text}), where {cell.successes} of {cell.n} "
        f"trials righted, the most mixed outcomes of the {len(pc.cells)} settings of the paper protocol.",
        f"{len(results)} of its trials (trials {', '.join(str(r['trial']) for r in chosen)}; seeds in the table) "
        f"were run again with a trace: {n_ok} righted, {len(results) - n_ok} did not. "
        + (
            f"Every rerun reproduces its stored outcome (success and time to right within "
            f"{RERUN_TTR_TOL_S * 1e6:g} µs)."
            if same == len(recs)
            else f"Only {same} of {len(recs)} reruns reproduce their stored outcome (success and time to right "
            f"within {RERUN_TTR_TOL_S * 1e6:g} µs): the simulation here differs from the one that filled the "
            "database (package versions in the inputs table)."
        ),
        "Each path is the body's (pitch, roll) from the end of settling until the trial stopped, over the "
        f"landscape of the setting's pose (grid step {step_deg:g}°), with the minimal righting barrier's saddle "
        "and path.",
    ]
    if note:
        paras.append(note)
    return Section(
        "trajectories",
        title,
        tuple(paras),
        trajectory_figures(
            files, f"{len(results)} simulated trials at θw {cell.theta_w_deg:g}°, θl {cell.theta_l_deg:g}°"
        ),
        (Table("Reruns against the stored outcomes", csv_path),),
    )
