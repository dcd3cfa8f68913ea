"""pybullet's ``contactBreakingThreshold`` at the default dt: speed against the convergence criterion (a
benchmark; docs/sim.md, "Tried, not kept").

For each threshold: the largest world-up angle over the first second (and 2 s) against dt = 5e-5 with 50 solver
iterations and the same threshold (the three cases of ``sim_convergence.py``), and the core-seconds of a full
10 s trial that never rights (best of ``--repeat``).

Run:  .venv/bin/python benchmarks/sim_contact_threshold.py [--repeat 2]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from sim_convergence import REF_DT, REF_ITERATIONS, orientation_diff_deg, traces  # noqa: E402

import sim.world as world  # noqa: E402
from sim.trial import DEFAULT_DT_S, run_trial  # noqa: E402
from sim.world import Contact  # noqa: E402

CASE = dict(theta_w_deg=70.0, theta_l_deg=20.0, phase=0.7, cv=0.0, rng=1, duration_s=10.0, dt_s=DEFAULT_DT_S)
VARIANTS = (
    ("pybullet default (20 mm)", {}),
    ("5 mm", {"contactBreakingThreshold": 0.005}),
    ("1 mm", {"contactBreakingThreshold": 0.001}),
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    build = world.World._build
    print(
        f"| contactBreakingThreshold | first 1 s (deg) | first 2 s (deg) | core-s per 10 s trial (dt {DEFAULT_DT_S:g}) |"
    )
    print("|---|---:|---:|---:|")
    try:
        for name, params in VARIANTS:

            def patched(self, urdf, params=params):
                build(self, urdf)
                world.pb.setPhysicsEngineParameter(physicsClientId=self.cid, **params)

            world.World._build = patched
            ref = traces(REF_DT, contact=Contact(solver_iterations=REF_ITERATIONS))
            d1, d2 = orientation_diff_deg(traces(DEFAULT_DT_S), ref)
            cpu = min(run_trial(**CASE).cpu_s for _ in range(args.repeat))
            print(f"| {name} | {d1:.3f} | {d2:.3f} | {cpu:.3f} |", flush=True)
    finally:
        world.World._build = build


if __name__ == "__main__":
    main()
