"""matplotlib figures (edge layer): the barrier map and 2-D landscape maps."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from landscape.viz._mpl import plt, save


def render_barrier_map(theta_w_deg, theta_l_deg, barrier_mj, path: Path, *, title: str = "") -> Path:
    """Heat map of the minimal righting barrier (mJ) over theta_w x theta_l, or a line plot for one theta_l."""
    tw = np.asarray(theta_w_deg, float)
    tl = np.asarray(theta_l_deg, float)
    b = np.asarray(barrier_mj, float)  # (len(tw), len(tl))
    fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=120)
    if len(tl) == 1 or len(tw) == 1:
        x, lab = (tw, "wing angle θw (°)") if len(tl) == 1 else (tl, "leg angle θl (°)")
        ax.plot(x, b.ravel(), "-", lw=1.5)
        ax.set_xlabel(lab)
        ax.set_ylabel("righting barrier (mJ)")
        ax.grid(alpha=0.3)
    else:

        def edges(v):
            if len(v) == 1:
                return np.array([v[0] - 0.5, v[0] + 0.5])
            mid = (v[1:] + v[:-1]) / 2
            return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])

        m = ax.pcolormesh(edges(tl), edges(tw), b, cmap="viridis", shading="flat")
        for i, w in enumerate(tw):
            for j, leg in enumerate(tl):
                if len(tw) * len(tl) <= 64:
                    ax.text(leg, w, f"{b[i, j]:.1f}", ha="center", va="center", color="w", fontsize=8)
        fig.colorbar(m, ax=ax, label="righting barrier (mJ)")
        ax.set_xlabel("leg angle θl (°)")
        ax.set_ylabel("wing angle θw (°)")
    ax.set_title(title or "Minimal righting barrier")
    fig.tight_layout()
    return save(fig, path)


def render_barrier_bands(theta_w_deg, theta_l_deg, curves: dict, path: Path, *, title: str = "") -> Path:
    """Each exit's barrier against theta_w (or theta_l, for one theta_w), one curve per other angle, with its band.

    Parameters
    ----------
    theta_w_deg, theta_l_deg : sequence of float
        The map's axes, degrees.
    curves : dict of str to dict
        Per exit label: ``barrier_mj``, ``low_mj``, ``high_mj`` (arrays of shape (W, L); nan where none) and
        ``monte_carlo`` (bool (W, L): the band there is the Monte-Carlo range, drawn with an open marker, because
        the barrier is not differentiable there).
    path : Path
        The PNG to write.
    """
    tw = np.asarray(theta_w_deg, float)
    tl = np.asarray(theta_l_deg, float)
    along_w = len(tw) > 1 or len(tl) == 1
    x, other, lab, other_lab = (
        (tw, tl, "wing angle θw (°)", "θl") if along_w else (tl, tw, "leg angle θl (°)", "θw")
    )
    fig, axes = plt.subplots(2, 2, figsize=(10.0, 7.0), dpi=110, sharex=True)
    for ax, (name, c) in zip(axes.ravel(), curves.items(), strict=False):
        for k, v in enumerate(other):
            sel = (slice(None), k) if along_w else (k, slice(None))
            b, lo, hi = (np.asarray(c[key], float)[sel] for key in ("barrier_mj", "low_mj", "high_mj"))
            mc = np.asarray(c["monte_carlo"], bool)[sel]
            (line,) = ax.plot(x, b, "-", lw=1.4, label=f"{other_lab} {v:g}°")
            ax.fill_between(x, lo, hi, color=line.get_color(), alpha=0.2, lw=0)
            if mc.any():
                ax.plot(x[mc], b[mc], "o", mfc="none", color=line.get_color(), ms=5)
        ax.set_title(name)
        ax.set_ylabel("barrier (mJ)")
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel(lab)
    axes[0, 0].legend(fontsize=7, loc="best")
    fig.suptitle(
        (title or "Barriers with their bands")
        + "\nband: first order from the gradient; open circles: not differentiable, band from the Monte-Carlo range",
        fontsize=9,
    )
    fig.tight_layout()
    return save(fig, path)
