"""What the attempts after a failed one start from, in the prediction study (docs/concepts/energy_budget.md).

Reads the opening states `landscape analyze prediction` wrote (its ``--states`` file) and the database's phase
maps, and prints: how many attempts after a failed one start with the body nearly still (rotational kinetic
energy below 0.1 and 0.01 mJ), how often the single-attempt map from rest gets those attempts wrong, and, per
trial that fails its first attempt, the pairs of its attempts that open at the same phase from the same state
(roll, pitch within 0.01 deg, angular velocity within 0.001 rad/s) and end differently, with the robot's heading on
the ground at each (modulo 90 degrees: pybullet's friction, benchmarks/studies/heading.py).

Run:  PYTHONPATH=. .venv/bin/python benchmarks/studies/prediction_states.py --db DB [--states DB.opening-states.jsonl]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

STILL_MJ = (0.1, 0.01)
SAME_DEG, SAME_RAD_S = 0.01, 1e-3


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--db", required=True)
    ap.add_argument("--states", default=None)
    a = ap.parse_args(argv)
    from landscape.analysis import trials as an
    from sim.store import read_rows

    path = Path(a.states or f"{a.db}.opening-states.jsonl")
    if not path.is_file():
        print(
            f"error: {path} not found; run `landscape analyze prediction --db {a.db}` first", file=sys.stderr
        )
        return 2
    maps = an.phase_maps(read_rows(a.db))
    trials = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    later, same_state = [], []
    for t in trials:
        parts = t["key"].split("/")
        w, tl_deg, leg_period = float(parts[2]), float(parts[3]), float(parts[5][2:])
        pm = maps[(w, leg_period)]
        sts = t["states"]
        for s in sts:
            if s["attempt"] > 1:
                later.append((s, pm.lookup(tl_deg, s["phase"])[0]))
        for i, s in enumerate(sts):
            for u in sts[i + 1 :]:
                if (
                    abs((s["phase"] - u["phase"] + 0.5) % 1 - 0.5) < 1e-6
                    and abs(s["roll_deg"] - u["roll_deg"]) <= SAME_DEG
                    and abs(s["pitch_deg"] - u["pitch_deg"]) <= SAME_DEG
                    and all(abs(s[k] - u[k]) <= SAME_RAD_S for k in ("omega_x", "omega_y", "omega_z"))
                    and s["success"] != u["success"]
                ):
                    same_state.append((t["key"], s, u))
    print(f"{len(trials)} trials, {len(later)} attempts after a failed one")
    for lim in STILL_MJ:
        still = [(s, good) for s, good in later if s["ke_rot_mj"] < lim]
        wrong = sum(good != s["success"] for s, good in still)
        print(
            f"  starting with rotational kinetic energy below {lim:g} mJ: {len(still)}; the map from rest gets "
            f"{wrong} of them wrong"
        )
    moving = [(s, good) for s, good in later if s["ke_rot_mj"] >= STILL_MJ[0]]
    print(
        f"  starting with {STILL_MJ[0]:g} mJ or more: {len(moving)}; the map gets "
        f"{sum(good != s['success'] for s, good in moving)} wrong"
    )
    print(f"pairs of attempts of one trial opening at the same phase from the same state, ending differently: "
          f"{len(same_state)}")  # fmt: skip
    turned = [_turn(s, u) for _, s, u in same_state if "heading_deg" in s and "heading_deg" in u]
    if turned:
        print(f"  of them, headings (modulo 90 deg) more than 1 deg apart: {sum(t > 1.0 for t in turned)} of "
              f"{len(turned)}")  # fmt: skip
    for key, s, u in same_state[:10]:
        hd = f" (headings {_turn(s, u):.1f} deg apart)" if "heading_deg" in s and "heading_deg" in u else ""
        print(f"  {key}: attempts {s['attempt']} and {u['attempt']}{hd}")
    return 0


def _turn(s: dict, u: dict) -> float:
    """How far apart two attempts' headings are, modulo 90 degrees."""
    return abs((s["heading_deg"] - u["heading_deg"] + 45.0) % 90.0 - 45.0)


if __name__ == "__main__":
    raise SystemExit(main())
