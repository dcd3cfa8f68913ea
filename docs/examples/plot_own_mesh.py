"""
Your own mesh
=============

Any single rigid body trimesh can read (STL, OBJ, PLY, GLB, ...) has a landscape and barriers. Here a
300 × 200 × 100 mm box, written to an STL in millimetres as a CAD tool would, is read with ``units="mm"`` and a
mass of 1 kg, the same as ``landscape compute --mesh box.stl --units mm --mass 1``. A box has closed-form
barriers, so the exact method can be checked: tipping over a 200 mm-wide face lifts the CoM from 50 mm to
sqrt(100² + 50²) mm.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import trimesh

import landscape

out = Path(tempfile.mkdtemp())
box_mm = trimesh.creation.box(extents=(300.0, 200.0, 100.0))
box_mm.export(out / "box.stl")

robot = landscape.load_robot(mesh=out / "box.stl", units="mm", mass_kg=1.0)
c = landscape.compute(robot, method="exact")
closed_form_j = 1.0 * c.landscape.g_m_s2 * (np.hypot(0.100, 0.050) - 0.050)
print(f"mass {c.mass_kg} kg, CoM {np.round(c.com_m * 1e3, 3)} mm (solid: the mesh is closed)")
print(f"righting {c.barrier.righting.barrier_j * 1e3:.6f} mJ exact; closed form {closed_form_j * 1e3:.6f} mJ")

# %%
# The CoM decides the landscape. A body whose mass sits off its centroid (a battery at one end) is given
# ``com`` in the mesh's units. Moved 60 mm along +x, the CoM is 90 mm from the +x end, and tipping over that
# end lifts it by sqrt(90² + 50²) − 50 = 52.96 mm, less than the 61.80 mm of tipping sideways:
shifted = landscape.load_robot(mesh=out / "box.stl", units="mm", mass_kg=1.0, com=(60.0, 0.0, 0.0))
cs = landscape.compute(shifted, method="exact")
print(
    f"CoM at x = 60 mm: righting {cs.barrier.righting.barrier_j * 1e3:.3f} mJ by {cs.barrier.righting.direction}"
)

fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
for ax, comp, title in zip(axes, (c, cs), ("CoM at the centroid", "CoM 60 mm towards +x"), strict=True):
    a = comp.landscape.angles_deg
    im = ax.contourf(a, a, comp.landscape.energy_j.T * 1e3, levels=30, cmap="viridis")
    r = comp.barrier.righting
    ax.plot(comp.minimum.pitch_deg, comp.minimum.roll_deg, "o", color="tab:red")
    ax.plot(r.saddle_pitch_deg, r.saddle_roll_deg, "X", color="tab:orange", ms=10)
    ax.set(xlabel="pitch (°)", title=f"{title}: {r.barrier_j * 1e3:.1f} mJ")
axes[0].set_ylabel("roll (°)")
fig.colorbar(im, ax=axes, label="energy (mJ)")
