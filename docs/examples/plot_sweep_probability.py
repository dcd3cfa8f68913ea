"""
A small sweep and its probability table
=======================================

Self-righting trials in pybullet with randomised wing-leg timing (coefficient of variation Cv of the
periods), stored in SQLite as they finish, then read back into the per-setting probability table with Wilson
95 % intervals: the library calls behind
``landscape sweep --theta-w 74 --theta-l 20,30,50 --cv 0.1 --trials 2 --duration 4`` and
``landscape analyze probability``.

Quick version: 2 trials per setting of at most 4 s each (6 trials). Full version (``LANDSCAPE_DOCS_FULL=1``):
10 trials of 10 s (the paper's protocol length) per setting. Only probabilities over many trials mean
anything near the success boundary, so the quick table shows the workflow, not a result.
"""

import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from landscape.analysis.trials import probability_table
from sim.store import read_rows
from sim.sweep import run_sweep, sweep_specs

full = os.environ.get("LANDSCAPE_DOCS_FULL") == "1"
db = Path(tempfile.mkdtemp()) / "trials.sqlite"
specs = sweep_specs(
    [74.0], [20.0, 30.0, 50.0], [0.1], trials=10 if full else 2, duration_s=10.0 if full else 4.0
)
# run_sweep runs trials in worker processes, started by spawn: they import this script again, so the calls
# that run trials sit under the usual ``if __name__ == "__main__":`` guard.
if __name__ == "__main__":
    summary = run_sweep(specs, db=db, workers=1, progress=False)
    print(f"{summary.ran} trials ran, {summary.diverged} diverged")

# %%
# A rerun of the same sweep runs nothing: the database already holds every trial (a killed sweep resumes).
if __name__ == "__main__":
    print(f"rerun: {run_sweep(specs, db=db, workers=1, progress=False).ran} trials ran")

# %%
# The probability table: one cell per setting, with its Wilson interval.
cells = probability_table(read_rows(db)) if db.exists() else []
for cell in cells:
    print(
        f"θw {cell.theta_w_deg:g}° θl {cell.theta_l_deg:g}° Cv {cell.cv:g}: {cell.successes}/{cell.n} righted, "
        f"p {cell.p:.2f} [{cell.ci_low:.2f}, {cell.ci_high:.2f}]"
    )

if __name__ == "__main__":
    fig, ax = plt.subplots(figsize=(5.6, 3.8))
    x = [c.theta_l_deg for c in cells]
    p = [c.p for c in cells]
    err = [[c.p - c.ci_low for c in cells], [c.ci_high - c.p for c in cells]]
    ax.errorbar(x, p, yerr=err, fmt="o", capsize=4)
    ax.set(
        xlabel="leg amplitude θl (°)",
        ylabel="self-righting probability",
        ylim=(-0.05, 1.05),
        title=f"built-in robot, θw 74°, Cv 10 %, {cells[0].n} trials a setting",
    )
