"""Files and tables of the physical robot's trials (:mod:`landscape.analysis.physical`): CSV and markdown."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path


def _fmt(v) -> str:
    if isinstance(v, bool):
        return str(int(v))
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:.6g}"
    return str(v)


def write_rows_csv(rows: Sequence, path: str | Path) -> Path:
    """Write frozen dataclasses with a ``CSV_COLUMNS`` attribute as CSV (booleans 0/1, nan as empty)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    cols = type(rows[0]).CSV_COLUMNS if rows else ()
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([_fmt(getattr(r, c)) for c in cols])
    return path


def _pct(x: float) -> str:
    return f"{100 * x:.0f}"


def cells_table(cells: Sequence, attempts: Sequence = ()) -> str:
    """Markdown table of :class:`~landscape.analysis.physical.PhysicalCell` (and per-attempt rates)."""
    lines = [
        "| wing cmd (measured) | leg | righted | Wilson 95 % | median time to right |",
        "|---|---|---|---|---|",
    ]
    for c in cells:
        t = "" if math.isnan(c.median_time_to_right_s) else f"{c.median_time_to_right_s:.2f} s"
        lines.append(
            f"| {c.theta_w_cmd_deg:g}° ({c.theta_w_measured_deg:.1f}°) | {c.theta_l_deg:g}° | "
            f"{c.successes}/{c.n} | [{_pct(c.ci_low)}, {_pct(c.ci_high)}] % | {t} |"
        )
    if attempts:
        lines += [
            "",
            "| wing cmd (measured) | successful attempts | rate | Wilson 95 % |",
            "|---|---|---|---|",
        ]
        for a in attempts:
            lines.append(
                f"| {a.theta_w_cmd_deg:g}° ({a.theta_w_measured_deg:.1f}°) | {a.successes}/{a.attempts} | "
                f"{_pct(a.p)} % | [{_pct(a.ci_low)}, {_pct(a.ci_high)}] % |"
            )
    return "\n".join(lines)


def resting_pitch_markdown(rows: Sequence, model_deg: Sequence[float] | None = None) -> str:
    """Markdown table of :class:`~landscape.analysis.physical.RestingPitch`, beside the model's pitch."""
    head = "| wing command | measured plateau | robot, median [IQR] (n) | first openings | closed again |"
    rule = "|---|---|---|---|---|"
    if model_deg is not None:
        head += " model's metastable pitch | model - robot |"
        rule += "---|---|"
    lines = [head, rule]
    for k, r in enumerate(rows):
        line = (
            f"| {r.theta_w_cmd_deg:g}° | {r.theta_w_measured_deg:.1f}° | {r.median_deg:.1f}° "
            f"[{r.q25_deg:.1f}, {r.q75_deg:.1f}] ({r.n}) | {r.first_opening_median_deg:.1f}° | {r.closed_median_deg:.1f}° |"
        )
        if model_deg is not None:
            line += f" {model_deg[k]:.1f}° | {model_deg[k] - r.median_deg:+.1f}° |"
        lines.append(line)
    return "\n".join(lines)
