"""
Trajectories on the landscape
=============================

A trial's body pitch and roll, recorded every 10 ms, drawn over the landscape of its (θw, θl): what
``landscape simulate --trace t.csv`` records and ``landscape render --trace t.csv`` draws. The minimal barrier
says how high the lowest way out is; the trajectory shows which way the robot really went.

Quick version: three trials of at most 4 s. Full version (``LANDSCAPE_DOCS_FULL=1``): six phases, trials of
10 s.
"""

import os

import matplotlib.pyplot as plt
import numpy as np

import landscape
from sim.trial import run_trial

full = os.environ.get("LANDSCAPE_DOCS_FULL") == "1"
theta_w_deg, theta_l_deg = 74.0, 30.0
c = landscape.compute(landscape.load_robot(), theta_w_deg=theta_w_deg, theta_l_deg=theta_l_deg)
# The leg's phase at the first wing opening (phi_1) changes the way over: one trial per phase.
phases = (0.0, 1 / 6, 2 / 6, 3 / 6, 4 / 6, 5 / 6) if full else (0.1, 0.4, 0.7)
trials = [
    run_trial(theta_w_deg, theta_l_deg, phase=ph, cv=0.1, rng=0, duration_s=10.0 if full else 4.0, trace=True)
    for ph in phases
]
for ph, r in zip(phases, trials, strict=True):
    print(f"phase {ph:.2f}: " + (f"righted at {r.time_to_right_s:.2f} s" if r.success else "not righted"))

# %%
# Paths are drawn as points because pitch and roll wrap round the torus at ±180°.
a = c.landscape.angles_deg
fig, ax = plt.subplots(figsize=(6.4, 5.2))
cs = ax.contourf(a, a, c.landscape.energy_j.T * 1e3, levels=30, cmap="Greys_r")
fig.colorbar(cs, ax=ax, label="potential energy (mJ)")
for ph, r in zip(phases, trials, strict=True):
    label = f"phase {ph:.2f} ({'righted' if r.success else 'not righted'})"
    ax.plot(r.trace.pitch_deg, r.trace.roll_deg, ".", ms=2, label=label)
rt = c.barrier.righting
ax.plot(c.minimum.pitch_deg, c.minimum.roll_deg, "o", color="tab:red", label="start minimum")
ax.plot(
    rt.saddle_pitch_deg, rt.saddle_roll_deg, "X", color="tab:orange", ms=10, label="minimal-barrier saddle"
)
ax.set(
    xlabel="body pitch (°)",
    ylabel="body roll (°)",
    title=f"θw {theta_w_deg:g}°, θl {theta_l_deg:g}°, Cv 10 %",
)
ax.legend(fontsize=7, loc="lower left")

# %%
# The energy along each trial against time, with the start energy plus the minimal barrier as a line: a trial
# rights only after it has climbed past that level.
fig, ax = plt.subplots(figsize=(6.4, 3.4))
for ph, r in zip(phases, trials, strict=True):
    ax.plot(r.trace.t_s, r.trace.energy_j * 1e3, label=f"phase {ph:.2f}")
ax.axhline((c.minimum.energy_j + rt.barrier_j) * 1e3, color="tab:orange", ls="--", label="start + barrier")
ax.set(xlabel="time (s)", ylabel="potential energy (mJ)")
ax.legend(fontsize=7)
print(f"highest energy reached: {max(np.max(r.trace.energy_j) for r in trials) * 1e3:.1f} mJ")
