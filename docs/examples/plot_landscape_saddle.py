"""
A landscape and its saddle
==========================

The potential energy of the built-in robot lying on its back with its wings opened to θw = 74°, over body
pitch and roll, with the metastable minimum it rests in and the saddle of the lowest way out (the minimal
righting barrier). This is what ``landscape compute --theta-w 74`` prints and ``landscape render`` draws.
"""

import matplotlib.pyplot as plt

import landscape

robot = landscape.load_robot()  # the built-in robot; a URDF path or mesh=... for your own
c = landscape.compute(robot, theta_w_deg=74.0, theta_l_deg=0.0, method="exact")
righting = c.barrier.righting
print(
    f"minimum  pitch {c.minimum.pitch_deg:.2f}°  roll {c.minimum.roll_deg:.2f}°  E {c.minimum.energy_j * 1e3:.3f} mJ"
)
print(
    f"righting {righting.barrier_j * 1e3:.3f} mJ by {righting.direction}, saddle at "
    f"({righting.saddle_pitch_deg:.2f}°, {righting.saddle_roll_deg:.2f}°)"
)

# %%
# The landscape is a grid on the pitch-roll torus (``angles_deg`` for both axes, energy in J). The contour map
# marks the start minimum, the saddle and the barrier path (a grid path from the start; it may wrap round the
# torus, so it is drawn as points).
a = c.landscape.angles_deg
e_mj = c.landscape.energy_j * 1e3
fig, ax = plt.subplots(figsize=(6.4, 5.2))
cs = ax.contourf(a, a, e_mj.T, levels=30, cmap="viridis")  # rows: pitch, columns: roll
fig.colorbar(cs, ax=ax, label="potential energy (mJ)")
path = righting.path_deg
ax.plot(path[:, 0], path[:, 1], ".", color="white", ms=2, label="barrier path")
ax.plot(c.minimum.pitch_deg, c.minimum.roll_deg, "o", color="tab:red", label="start minimum")
ax.plot(righting.saddle_pitch_deg, righting.saddle_roll_deg, "X", color="tab:orange", ms=10, label="saddle")
ax.set(xlabel="body pitch (°)", ylabel="body roll (°)", title="built-in robot, θw 74°, θl 0°")
ax.legend(loc="lower left", fontsize=8)

# %%
# The barrier is the energy at the saddle minus the energy at the minimum, E = m·g·h, so it is also a lift of
# the centre of mass:
lift_mm = righting.barrier_j / (c.mass_kg * c.landscape.g_m_s2) * 1e3
print(
    f"CoM lift {lift_mm:.3f} mm; the grid method on the same pose gives "
    f"{landscape.compute(robot, theta_w_deg=74.0, method='grid').barrier.righting.barrier_j * 1e3:.3f} mJ"
)
