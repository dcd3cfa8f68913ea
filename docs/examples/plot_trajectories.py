"""
Trajectories on the landscape
=============================

A trial's body pitch and roll, recorded every 10 ms, drawn over the landscape of its (θw, θl): what
``landscape simulate --trace t.csv`` records and ``landscape render --trace t.csv`` draws. The minimal barrier
says how high the lowest way out is; the trajectory shows which way the robot really went.

Quick version: two trials of at most 4 s. Full version (``LANDSCAPE_DOCS_FULL=1``): six trials of 10 s, as
``python figures/trajectory_examples.py`` draws for the README.
"""

import os

import matplotlib.pyplot as plt
import numpy as np

import landscape
from sim.trial import run_trial

full = os.environ.get("LANDSCAPE_DOCS_FULL") == "1"
theta_w_deg, theta_l_deg = 74.0, 30.0
c = landscape.compute(landscape.load_robot(), theta_w_deg=theta_w_deg, theta_l_deg=theta_l_deg)
trials = [
    run_trial(
        theta_w_deg, theta_l_deg, phase=0.7, cv=0.1, rng=seed, duration_s=10.0 if full else 4.0, trace=True
    )
    for seed in range(6 if full else 2)
]
for seed, r in enumerate(trials):
    print(f"seed {seed}: " + (f"righted at {r.time_to_right_s:.2f} s" if r.success else "not righted"))

# %%
# Paths are drawn as points because pitch and roll wrap round the torus at ±180°.
a = c.landscape.angles_deg
fig, ax = plt.subplots(figsize=(6.4, 5.2))
cs = ax.contourf(a, a, c.landscape.energy_j.T * 1e3, levels=30, cmap="Greys_r")
fig.colorbar(cs, ax=ax, label="potential energy (mJ)")
for seed, r in enumerate(trials):
    t = r.trace
    ax.plot(
        t.pitch_deg, t.roll_deg, ".", ms=2, label=f"seed {seed} ({'righted' if r.success else 'not righted'})"
    )
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
for seed, r in enumerate(trials):
    ax.plot(r.trace.t_s, r.trace.energy_j * 1e3, label=f"seed {seed}")
ax.axhline((c.minimum.energy_j + rt.barrier_j) * 1e3, color="tab:orange", ls="--", label="start + barrier")
ax.set(xlabel="time (s)", ylabel="potential energy (mJ)")
ax.legend(fontsize=7)
print(f"highest energy reached: {max(np.max(r.trace.energy_j) for r in trials) * 1e3:.1f} mJ")
