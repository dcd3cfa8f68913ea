"""The energy budget against time of one simulated and one recorded trial (docs/concepts/energy_budget.md).

Simulated: the built-in robot, model set ``paper``, theta_w 72 deg, theta_l 30 deg, Tw 2 s, Tl 0.6 s, phi_1 0.2,
no noise (a trial of the Fig. 8 study that fails its first two attempts and rights in its third). Recorded: the
physical robot's trial run5_60_60_60_60_30_2 (wing command 60 deg, leg 30 deg; it rights in its second opening),
posed on the lab robot by model set ``physical-head`` (needs ../shared/ref).

    .venv/bin/python figures/energy_budget.py [--out figures/energy_budget.png]

Prints every attempt's row (as energy.csv has it) and writes the PNG (and SVG).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared" / "ref"
DATA = SHARED / "physical_robot"
LAB = SHARED / "lab_robot" / "lab_robot.urdf"
RECORDED = "run5_60_60_60_60_30_2.bag.mat"
SIMULATED = dict(theta_w_deg=72.0, theta_l_deg=30.0, phase=0.2, cv=0.0, rng=0, duration_s=10.0)
LEG_PERIOD_S = 0.6


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(HERE / "energy_budget.png"))
    a = ap.parse_args(argv)
    from geometry.builtin import load_builtin_robot
    from geometry.robots import load_robot
    from landscape.analysis import energy as en
    from landscape.analysis.physical.motion import DEFAULT_PHYSICAL_SET, recorded_motions
    from landscape.viz.energy_plots import plot_energy_time
    from sim.model_set import load_model_set
    from sim.trial import run_trial

    paper = load_model_set("paper")
    act = paper.actuation(SIMULATED["theta_w_deg"], SIMULATED["theta_l_deg"], leg_period_s=LEG_PERIOD_S)
    res = run_trial(**SIMULATED, model_set=paper, actuation=act, trace=True)
    sim = en.simulated_motion(res, trial=f"72/30, Tw 2 s, Tl {LEG_PERIOD_S:g} s, phi1 0.2")
    _, (sim_et,), sim_rows = en.energy_budget([sim], en.body_model(load_builtin_robot(), paper))
    items = [(f"simulated (built-in robot, paper): rights in attempt {res.attempt}", sim, sim_et)]
    rows = list(sim_rows)
    if (DATA / RECORDED).is_file() and LAB.is_file():
        ms = load_model_set(DEFAULT_PHYSICAL_SET)
        lab = load_robot(str(LAB))
        rm = recorded_motions(DATA, lab, ms)  # every trial, for the mounting the two rests measure
        rec = next(m for m in rm.motions if m.trial == RECORDED)
        _, (rec_et,), rec_rows = en.energy_budget([rec], rm.body)
        won = [r.attempt for r in rec_rows if r.success]
        items.append(
            (f"recorded ({RECORDED}, lab robot, physical-head): rights in attempt {won[0]}", rec, rec_et)
        )
        rows += rec_rows
    else:
        print(f"{DATA / RECORDED} or {LAB} is absent: the simulated trial only", file=sys.stderr)
    cols = ("source", "attempt", "success", "phase", "ke_roll_mj", "ke_pitch_mj", "ke_peak_mj", "barrier_mj")
    print(" ".join(cols) + " margin_mj")
    for r in rows:
        d = r.row()
        print(
            " ".join(f"{d[c]:.3g}" if isinstance(d[c], float) else str(d[c]) for c in cols),
            f"{r.margin_mj:.3g}",
        )
    png = plot_energy_time(items, Path(a.out), window_s=(-0.5, 60.0))
    print(f"wrote {png} and {png.with_suffix('.svg')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
