"""Stored trials run again with a trace (edge layer: joins the trial store's rows and :mod:`sim`).

A sweep stores each trial's row without its trace; the report's trajectory, prediction and energy sections rerun
chosen trials with every parameter of their row (as :func:`sim.sweep.run_spec` runs them) to get the trace, and
check that a rerun reproduces the stored outcome.
"""

from __future__ import annotations

from pathlib import Path

from geometry.errors import UsageError

RERUN_TTR_TOL_S = 1e-6
"""A rerun reproduces a stored time to right if they differ by at most this, s (far below any time step)."""


def rerun_trial(row: dict, *, robot_urdf: str | Path, heading_deg: float = 0.0, trace: bool = True):
    """A stored trial run again with a trace, with every parameter of its row (as :func:`sim.sweep.run_spec` runs
    it): same seed, protocol, model set, engine and robot; ``heading_deg`` turns it on the ground (a sweep runs
    every trial at 0, :class:`sim.trial.Trial`).

    Raises
    ------
    UsageError
        If the row's model set cannot be loaded or has changed since the trial ran.
    """
    from sim.engine import DEFAULT_ENGINE
    from sim.model_set import ModelSetError, load_model_set
    from sim.trial import run_trial

    name = row.get("model_set") or "paper"
    try:
        ms = load_model_set(name).with_engine(row.get("engine") or DEFAULT_ENGINE)
    except ModelSetError as exc:
        raise UsageError(f"cannot rerun trial {row['trial']}: {exc}") from None
    if row.get("model_set_hash") and ms.model_set_hash != row["model_set_hash"]:
        raise UsageError(
            f"cannot rerun trial {row['trial']}: model set {name} changed since it ran (hash "
            f"{ms.model_set_hash} != {row['model_set_hash']})"
        )
    act = ms.actuation(
        row["theta_w_deg"],
        row["theta_l_deg"],
        wing_period_s=row["wing_period_s"],
        leg_period_s=row["leg_period_s"],
    )
    return run_trial(
        row["theta_w_deg"],
        row["theta_l_deg"],
        phase=row["phase"],
        cv=row["cv"],
        rng=row["seed"],
        duration_s=row["duration_s"],
        dt_s=row["dt_s"],
        robot=robot_urdf,
        actuation=act,
        attempts=row["attempts"] or None,
        model_set=ms,
        trace=trace,
        heading_deg=heading_deg,
    )


def reproduces(row: dict, res) -> bool:
    """Whether a rerun ``res`` (:class:`sim.trial.TrialResult`) has the stored row's outcome and, if it righted, its
    time to right within ``RERUN_TTR_TOL_S``."""
    if bool(row["success"]) != bool(res.success):
        return False
    if not res.success:
        return True
    return abs(float(row["time_to_right_s"]) - float(res.time_to_right_s)) <= RERUN_TTR_TOL_S
