"""The phase-evolution section: the phases a multi-attempt trial visits over its attempts, without and with noise,
over the phase map."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from landscape.analysis import trials as an
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    PHASE_MAP_SWEEP,
    study_setting,
    write_csv,
)


def section_evolution(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    theta_w_deg: float | None = None,
    theta_l_deg: float | None = None,
    phase: float | None = None,
    cv: float = 0.15,
    seed: int = 1,
    wing_period_s: float = 2.0,
    leg_period_s: float = 0.8,
    attempts: int = 12,
) -> Section:
    """Fig. 9 analogue: phases visited over attempts without and with noise, over the single-attempt map.

    ``theta_w_deg``, ``theta_l_deg`` None: the prediction study's setting found in the data (the mapped setting
    with the most multi-attempt (Tw, Tl) pairs at Cv 0, else the most mixed mapped setting). ``phase`` None: a
    mapped phase from which the noise-free sequence never meets a good phase, else the most common phi_1 of
    the multi-attempt trials at that setting, else the map's first phase. ``cv`` and ``seed`` drive the noisy
    sequence; ``attempts`` is how many attempts are drawn."""
    from landscape.viz.analysis_plots import plot_evolution

    title = "Phase evolution over attempts"
    maps = an.phase_maps(rows)
    if theta_w_deg is None or theta_l_deg is None:
        study = study_setting(rows, maps, leg_period_s)
        if study is None:
            return Section(
                "evolution",
                title,
                missing=f"no single-attempt phase map at Tl {leg_period_s:g} s; run "
                f"`{PHASE_MAP_SWEEP.format(db=db)}`",
            )
        theta_w_deg = study[0] if theta_w_deg is None else theta_w_deg
        theta_l_deg = study[1] if theta_l_deg is None else theta_l_deg
    pm = maps.get((theta_w_deg, leg_period_s))
    if pm is None or not np.isclose(pm.theta_l_deg, theta_l_deg).any():
        return Section(
            "evolution",
            title,
            missing=f"no single-attempt phase map for θw {theta_w_deg:g}°, θl "
            f"{theta_l_deg:g}°, Tl {leg_period_s:g} s; run `{PHASE_MAP_SWEEP.format(db=db)}`",
        )
    n_distinct = an.distinct_phases(wing_period_s, leg_period_s)
    if phase is None:  # a start from which the noise-free sequence never meets a good phase, if there is one
        phase = next(
            (
                float(ph)
                for ph in pm.phases
                if not any(
                    pm.lookup(theta_l_deg, (ph + k * wing_period_s / leg_period_s) % 1.0)[0]
                    for k in range(n_distinct)
                )
            ),
            None,
        )
    if (
        phase is None
    ):  # every start meets a good phase: the trials' own phi_1 at this setting, else the map's first
        used = [
            r["phase"]
            for r in rows
            if r["status"] == "ok"
            and r["attempts"] == 0
            and (r["theta_w_deg"], r["theta_l_deg"]) == (theta_w_deg, theta_l_deg)
        ]
        phase = max(set(used), key=lambda ph: (used.count(ph), -ph)) if used else float(pm.phases[0])
    recs, seqs = [], []
    for label, c in (("no noise", 0.0), (f"Cv = {cv * 100:g} %, seed {seed}", cv)):
        duration = phase * leg_period_s + attempts * wing_period_s
        while (
            True
        ):  # noise can lengthen the holds: extend (same seed, same prefix) until there are enough attempts
            starts, phs = an.attempt_sequence(
                theta_w_deg,
                theta_l_deg,
                phase=phase,
                cv=c,
                seed=seed,
                duration_s=duration,
                wing_period_s=wing_period_s,
                leg_period_s=leg_period_s,
            )
            if len(starts) >= attempts:
                break
            duration *= 2.0
        starts, phs = starts[:attempts], phs[:attempts]
        good = [pm.lookup(theta_l_deg, float(p))[0] for p in phs]
        first = next((k + 1 for k, g in enumerate(good) if g), None)
        seqs.append(
            (f"{label}: {len(set(np.round(phs, 6)))} distinct phases in {len(phs)} attempts", phs, first)
        )
        recs += [
            {"noise_cv": c, "attempt": k + 1, "start_s": float(t), "phase": float(p), "good": bool(g)}
            for k, (t, p, g) in enumerate(zip(starts, phs, good, strict=True))
        ]
    csv_path = write_csv(out / "evolution.csv", recs)
    png = plot_evolution(
        pm,
        theta_l_deg,
        seqs,
        out / "evolution.png",
        title=f"θw {theta_w_deg:g}°, θl {theta_l_deg:g}°, Tw {wing_period_s:g} s, Tl "
        f"{leg_period_s:g} s, φ1 = {phase:g}",
    )
    paras = (
        f"Without noise the phase advances by Tw/Tl = {wing_period_s / leg_period_s:g} (mod 1) per attempt and "
        f"visits LCM(Tw, Tl)/Tw = {n_distinct} distinct phases; a start whose phases are all bad never rights. "
        "With noise the phase wanders and eventually lands on a good one.",
        f"First good phase: no noise {seqs[0][2] or 'never'}; with noise attempt {seqs[1][2] or 'never'} "
        f"(within {attempts} attempts).",
    )
    return Section(
        "evolution",
        title,
        paras,
        (Figure(png, "Phases visited over attempts", png.with_suffix(".svg")),),
        (Table("Phases per attempt", csv_path),),
    )
