"""
A barrier map over θw × θl
==========================

The minimal righting barrier of the built-in robot over wing opening θw and leg amplitude θl (the source
paper's Fig. 5), as ``landscape barrier-map --theta-w 60:90:5 --theta-l 0:50:10`` computes it. Each pose is a
rigid body with its own landscape; the exact method needs no grid for the barrier.

Quick version: 5° in θw and 10° in θl (42 poses). Full version (``LANDSCAPE_DOCS_FULL=1``): 2° × 5° (176 poses),
the grid of the README's ``landscape barrier-map --theta-w 60:90:2 --theta-l 0:50:10`` refined in θl.
"""

import os

import matplotlib.pyplot as plt
import numpy as np

import landscape

full = os.environ.get("LANDSCAPE_DOCS_FULL") == "1"
theta_w_deg = np.arange(60.0, 90.0 + 1e-9, 2.0 if full else 5.0)
theta_l_deg = np.arange(0.0, 50.0 + 1e-9, 5.0 if full else 10.0)

robot = landscape.load_robot()
bm = landscape.barrier_map(robot, theta_w_deg, theta_l_deg, method="exact")
righting_mj = bm.righting_j * 1e3  # shape (W, L)
print(
    f"{righting_mj.size} poses; righting barrier {np.nanmin(righting_mj):.3f} .. {np.nanmax(righting_mj):.3f} mJ"
)

# %%
# Opening the wings lowers the barrier most; swinging the leg lowers it further, by a larger fraction where the
# wings alone leave a small barrier.
fig, ax = plt.subplots(figsize=(6.4, 4.8))
im = ax.pcolormesh(theta_l_deg, theta_w_deg, righting_mj, shading="nearest", cmap="magma_r")
fig.colorbar(im, ax=ax, label="minimal righting barrier (mJ)")
ax.set(xlabel="leg amplitude θl (°)", ylabel="wing opening θw (°)", title="built-in robot, exact barriers")
for i, w in enumerate(theta_w_deg):
    for j, leg in enumerate(theta_l_deg):
        value = righting_mj[i, j]
        dark = value > 0.5 * np.nanmax(righting_mj)
        if not full:
            ax.text(leg, w, f"{value:.1f}", ha="center", va="center", fontsize=7, color="w" if dark else "k")
for i in (0, -1):
    drop = 1 - righting_mj[i, -1] / righting_mj[i, 0]
    print(f"θw {theta_w_deg[i]:g}°: θl {theta_l_deg[-1]:g}° lowers the barrier by {100 * drop:.0f} %")

# %%
# The same map as rows, the CSV that ``landscape barrier-map`` writes: every ``Computation`` of the map keeps
# its start minimum and its exits.
for comp in bm.computations[:3]:
    r = comp.barrier.righting
    print(
        f"θw {comp.theta_w_deg:4.0f}° θl {comp.theta_l_deg:4.0f}°: minimum pitch {comp.minimum.pitch_deg:6.2f}°, "
        f"righting {r.barrier_j * 1e3:7.3f} mJ by {r.direction}"
    )
