"""The probability section: self-righting probability per setting, with Wilson 95 % intervals."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

from landscape.analysis import trials as an
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    paper_cells,
    write_csv,
)


def _mixed_sentence(cells: list[an.ProbabilityCell]) -> str:
    """What the data say about repeatability: how many settings righted in some trials and not in others."""
    mixed = sum(0 < c.successes < c.n for c in cells)
    return (
        f"{mixed} of {len(cells)} settings righted in some of their trials and not in others (same setting, "
        "different seeds), so a setting's outcome is a probability, estimated over its trials; the brackets "
        "are Wilson 95 % intervals."
    )


def section_probability(rows: list[dict], out: Path, db: Path, *, phase: float | None = None) -> Section:
    """Fig. 6 analogue: P(self-right) over theta_w x theta_l per Cv, n and Wilson 95 % intervals."""
    from landscape.viz.analysis_plots import plot_probability

    title = "Self-righting probability over θw × θl for each noise level Cv"
    pc = paper_cells(rows, phase, db)
    cells, phase = pc.cells, pc.phase
    if not cells:
        return Section("probability", title, missing=pc.missing)
    csv_path = write_csv(out / "probability.csv", [asdict(c) for c in cells])
    png = plot_probability(
        cells,
        out / "probability.png",
        title=f"Self-righting probability (φ1 = {phase:g}, {pc.protocol_text})",
    )
    n = sum(c.n for c in cells)
    wins = sum(c.successes for c in cells)
    by_cv = {}
    for c in cells:
        k, m = by_cv.get(c.cv, (0, 0))
        by_cv[c.cv] = (k + c.successes, m + c.n)
    paras = (
        f"{n} trials ({len(cells)} settings, φ1 = {phase:g}, {pc.protocol_text}): {wins} righted "
        f"({wins / n * 100:.1f} %)."
        + (
            f" {pc.other_protocol_trials} trials of other durations, time steps or model sets are not pooled with "
            "them."
            if pc.other_protocol_trials
            else ""
        ),
        "Overall by Cv: "
        + "; ".join(
            f"Cv {cv * 100:g} %: {k}/{m} = {k / m * 100:.1f} %" for cv, (k, m) in sorted(by_cv.items())
        )
        + ".",
        _mixed_sentence(cells),
    )
    return Section(
        "probability",
        title,
        paras,
        (Figure(png, "Self-righting probability per Cv", png.with_suffix(".svg")),),
        (Table("Probability per setting", csv_path),),
    )
