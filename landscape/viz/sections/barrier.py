"""The barrier-vs-outcome section: the barrier of each setting against its trials' outcome."""

from __future__ import annotations

from pathlib import Path

from landscape.analysis import trials as an
from landscape.grid import DEFAULT_STEP_DEG
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    PAPER_PERIODS,
    paper_cells,
    trials_robot,
    trials_wing_joints,
    write_csv,
)


def section_barrier(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    robot: str | Path | None = None,
    step_deg: float = DEFAULT_STEP_DEG,
    phase: float | None = None,
) -> Section:
    """Barrier against outcome: Spearman rho with bootstrap intervals and a logistic fit, per Cv."""
    from landscape.viz.analysis_plots import plot_barrier_outcome

    title = "Barrier against outcome"
    pc = paper_cells(rows, phase, db)
    cells, phase = pc.cells, pc.phase
    if not cells:
        return Section("barrier", title, missing=pc.missing)
    used = [
        r for r in rows if r["attempts"] == 0 and (r["wing_period_s"], r["leg_period_s"]) == PAPER_PERIODS
    ]
    robot = trials_robot(used, robot)
    pairs = {(c.theta_w_deg, c.theta_l_deg) for c in cells}
    robot, joints, posed_by = trials_wing_joints(used, robot, {w for w, _ in pairs})
    barriers = an.landscape_barriers(robot, pairs, step_deg=step_deg, progress=True, wing_joints_deg=joints)
    res = an.barrier_outcome(cells, barriers)
    recs = []
    for r in res:
        for c, e, g in zip(r.cells, r.exact_mj, r.grid_mj, strict=True):
            recs.append(
                {
                    "theta_w_deg": c.theta_w_deg,
                    "theta_l_deg": c.theta_l_deg,
                    "cv": c.cv,
                    "n": c.n,
                    "successes": c.successes,
                    "p": c.p,
                    "ci_low": c.ci_low,
                    "ci_high": c.ci_high,
                    "exact_barrier_mj": float(e),
                    "grid_barrier_mj": float(g),
                    "mean_time_to_right_s": c.mean_time_to_right_s,
                }
            )
    stats = [
        {
            "cv": r.cv,
            "settings": len(r.cells),
            "spearman_rho": r.rho,
            "rho_ci_low": r.rho_low,
            "rho_ci_high": r.rho_high,
            "rho_p": r.rho_p,
            "rho_grid": r.rho_grid,
            "rho_time_to_right": r.rho_time,
            "rho_time_ci_low": r.rho_time_low,
            "rho_time_ci_high": r.rho_time_high,
            "logistic_a": r.fit.a,
            "logistic_b_per_mj": r.fit.b,
            "e50_mj": r.fit.e50_mj,
            "separated": r.fit.separated,
        }
        for r in res
    ]
    table = write_csv(out / "barrier_outcome.csv", recs)
    stats_csv = write_csv(out / "barrier_stats.csv", stats)
    png = plot_barrier_outcome(
        res, out / "barrier_outcome.png", title=f"Minimal righting barrier against outcome (φ1 = {phase:g})"
    )
    paras = [
        f"Barriers: exact (hull face–edge graph) and the 1° grid search, at θl on the +θl side, for "
        f"{len(barriers)} settings; outcomes: the paper-protocol trials at φ1 = {phase:g}. {posed_by}"
    ]
    for s in stats:
        paras.append(
            f"Cv {s['cv'] * 100:g} %: Spearman ρ(barrier, P) = {s['spearman_rho']:.2f} "
            f"[{s['rho_ci_low']:.2f}, {s['rho_ci_high']:.2f}] (p = {s['rho_p']:.2g}; grid barrier "
            f"{s['rho_grid']:.2f}); logistic E50 = {s['e50_mj']:.2f} mJ"
            + (" (outcomes separated by the barrier)" if s["separated"] else "")
            + "."
        )
    return Section(
        "barrier",
        title,
        tuple(paras),
        (Figure(png, "Barrier against outcome", png.with_suffix(".svg")),),
        (Table("Barrier and outcome per setting", table), Table("Statistics per Cv", stats_csv)),
    )
