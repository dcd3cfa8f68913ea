"""The phase-map section: the single-attempt outcome against the first attempt's phase and the leg amplitude."""

from __future__ import annotations

import math
from pathlib import Path

from landscape.analysis import trials as an
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    PHASE_MAP_SWEEP,
    write_csv,
)


def section_phase_map(rows: list[dict], out: Path, db: Path, *, leg_period_s: float = 0.8) -> Section:
    """Fig. 7 analogue: single-attempt outcome against phase and theta_l, per theta_w, no noise."""
    from landscape.viz.analysis_plots import plot_phase_maps

    title = "Single-attempt phase map"
    maps = an.phase_maps(rows)
    sel = [m for (_, tl), m in maps.items() if math.isclose(tl, leg_period_s)]
    if not sel:
        return Section(
            "phase-map",
            title,
            missing="no single-attempt trials without noise at Tl = "
            f"{leg_period_s:g} s; run `{PHASE_MAP_SWEEP.format(db=db)}`",
        )
    recs = []
    for m in maps.values():
        for i, tl in enumerate(m.theta_l_deg):
            for j, ph in enumerate(m.phases):
                if m.n[i, j]:
                    recs.append(
                        {
                            "theta_w_deg": m.theta_w_deg,
                            "leg_period_s": m.leg_period_s,
                            "theta_l_deg": tl,
                            "phase": ph,
                            "n": int(m.n[i, j]),
                            "success": float(m.success[i, j]),
                            "delay_s": float(m.delay_s[i, j]),
                        }
                    )
    csv_path = write_csv(out / "phase_map.csv", recs)
    png = plot_phase_maps(
        sel,
        out / "phase_map.png",
        title=f"Outcome of one attempt against its phase (Tl = {leg_period_s:g} s, no noise)",
    )
    paras = [
        "Each cell is one single-attempt trial: the wings open once at phase φ of the leg cycle and the trial "
        "ends one wing period later. Green: the robot righted."
    ]
    for m in sel:
        for i, tl in enumerate(m.theta_l_deg):
            good = m.good_phases(tl)
            paras.append(
                f"θw {m.theta_w_deg:g}°, θl {tl:g}°: {len(good)}/{int((m.n[i] > 0).sum())} phases right"
                + (f" (φ {', '.join(f'{g * 100:.0f}' for g in good)} %)" if 0 < len(good) < 8 else "")
            )
    return Section(
        "phase-map",
        title,
        tuple(paras),
        (Figure(png, "Single-attempt phase map", png.with_suffix(".svg")),),
        (Table("Single-attempt outcomes (all Tl)", csv_path),),
    )
