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
