"""Figures of :mod:`landscape.analysis.energy` (edge layer, matplotlib Agg): each writes a PNG and an SVG and returns
the PNG path."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from landscape.analysis.energy import AttemptEnergy, EnergyTrace, Motion
from landscape.viz._mpl import plt, save

SOURCE_COLOURS = {"simulated": "#2166ac", "recorded": "#b2182b"}
FLOOR_MJ = 1e-3
"""Energies below this are drawn at it (log axes), mJ."""


def plot_energy_attempts(rows: Sequence[AttemptEnergy], png: Path, *, title: str = "") -> Path:
    """Peak kinetic energy in the barrier's direction against the barrier, one point per attempt (mJ, log axes):
    filled = righted, open = failed, one colour per source (simulated, recorded), and the line KE = barrier."""
    fig, ax = plt.subplots(figsize=(5.6, 4.6), constrained_layout=True)
    ok = [r for r in rows if np.isfinite(r.barrier_mj)]
    lo, hi = FLOOR_MJ, 1.0
    for source in ("simulated", "recorded"):
        for success in (True, False):
            g = [r for r in ok if r.source == source and r.success == success]
            if not g:
                continue
            x = np.maximum([r.barrier_mj for r in g], FLOOR_MJ)
            y = np.maximum([r.ke_peak_mj for r in g], FLOOR_MJ)
            hi = max(hi, float(x.max()), float(y.max()))
            c = SOURCE_COLOURS[source]
            ax.scatter(
                x,
                y,
                s=26,
                marker="o" if source == "simulated" else "s",
                facecolors=c if success else "none",
                edgecolors=c,
                linewidths=1.0,
                label=f"{source}, {'righted' if success else 'failed'} ({len(g)})",
            )
    line = np.array([lo, hi * 2])
    ax.plot(line, line, color="0.3", lw=1.0, ls="--", label="KE = barrier")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(max(lo, 0.5 * min((max(r.barrier_mj, FLOOR_MJ) for r in ok), default=lo)), hi * 2)
    ax.set_ylim(lo, hi * 2)
    ax.set_xlabel("minimal righting barrier during the attempt (mJ)")
    ax.set_ylabel("peak kinetic energy in the barrier's direction (mJ)")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    if title:
        ax.set_title(title, fontsize=9)
    return save(fig, png, svg_too=True, dpi=130, bbox_inches="tight")


def plot_energy_time(
    items: Sequence[tuple[str, Motion, EnergyTrace]],
    png: Path,
    *,
    window_s: tuple[float, float] | None = None,
) -> Path:
    """One panel per trace: kinetic energy in the barrier's direction, the whole kinetic energy, height above the
    basin, their sum (barrier's direction) and the barrier, mJ, against time; the attempts' openings marked."""
    fig, axes = plt.subplots(
        len(items), 1, figsize=(7.0, 2.6 * len(items)), squeeze=False, constrained_layout=True
    )
    for ax, (label, m, et) in zip(axes[:, 0], items, strict=True):
        lo, hi = (-np.inf, np.inf) if window_s is None else window_s
        up = np.flatnonzero(m.up_z < 0)
        if len(up):
            hi = min(hi, float(m.t_s[up[0]]))
        sel = (et.t_s >= lo) & (et.t_s <= hi)
        t = et.t_s[sel]
        along = et.ke_along_j()[sel] * 1e3
        ax.plot(t, et.ke_j[sel] * 1e3, color="0.6", lw=0.8, label="kinetic energy, whole")
        ax.plot(t, along, color="#2166ac", lw=1.2, label="kinetic energy in the barrier's direction")
        ax.plot(t, et.height_j[sel] * 1e3, color="#1a9850", lw=1.0, label="height above the basin")
        ax.plot(t, along + et.height_j[sel] * 1e3, color="k", lw=1.2, label="sum (barrier's direction)")
        ax.plot(t, et.barrier_j[sel] * 1e3, color="#d7301f", lw=1.2, ls="--", label="barrier")
        for s, ok in zip(m.attempt_starts_s, m.attempt_success, strict=True):
            if t.size and t[0] <= s <= t[-1]:
                ax.axvline(s, color="#1a9850" if ok else "0.5", lw=0.8, ls=":")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_ylim(-1.0, None)
        ax.set_ylabel("energy (mJ)")
        ax.set_title(label, fontsize=9)
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, ncols=3, loc="outside lower center")
    return save(fig, png, svg_too=True, dpi=130, bbox_inches="tight")
