"""The robot's time to right in its IMU's frame and in a body frame pitched against it (issue #15, the time to
right at 90 deg).

The upright rule (world-up's body-z component below zero for ``UPRIGHT_HOLD_S``, reaching ``UPRIGHT_DEPTH``;
``landscape.analysis.physical``) dates a righting from the first sample of its upright stretch. At the 90 deg
wing command the robot stands on its head at a pitch near 90 deg while its wings hold it, so that component
hovers near zero and its sign turns on a few degrees of pitch: the robot counts as upright as soon as its IMU's
pitch passes 90 deg. The IMU's frame and the body's differ by a pitch: ``landscape physical kinematics``
measures 2.6 deg from the robot's two rests (on its back and upright); the 11.5 deg a fit of the open hold asks
of the lab's CAD is a pose, not the IMU. This script reapplies
the rule to every recording with world-up turned about the body's y axis by each ``--mount`` angle (a body
pitched that much less than its IMU reads) and prints, per cell, the median time to right from the first opening
(and successes) for each angle (``landscape.analysis.physical.recording.up_z_mounted``, as ``landscape physical
validate --imu-mounting`` judges them); with ``--validation DIR`` (``landscape physical validate --out DIR``) the
simulated median beside them.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/time_to_right_frame.py [--data DIR] [--mount 0,2.6,11.5]
      [--validation DIR]
"""

from __future__ import annotations

import argparse
import json
import math
from collections import defaultdict
from dataclasses import replace
from pathlib import Path

import numpy as np

from geometry.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument(
        "--mount", default="0,2.6,11.5", help="pitches of the body against the IMU, degrees, a list"
    )
    ap.add_argument("--validation", default=None, help="a `landscape physical validate --out` directory")
    args = ap.parse_args(argv)
    from landscape.analysis.physical.outcome import MAX_IMU_MOUNT_DEG

    try:
        mounts = [float(x) for x in args.mount.split(",")]
        if not mounts or not all(math.isfinite(m) and abs(m) <= MAX_IMU_MOUNT_DEG for m in mounts):
            raise ValueError
    except ValueError:
        ap.exit(2, f"{ap.prog}: error: --mount must be angles within ±{MAX_IMU_MOUNT_DEG:g} degrees, e.g. 0,11.5; "
                f"got {args.mount!r}\n")  # fmt: skip
    sim = {}
    if args.validation is not None:
        from landscape.analysis.physical.validation import validation_from_json

        f = Path(args.validation) / "validation.json"
        try:
            v = validation_from_json(json.loads(f.read_text()))
        except (OSError, json.JSONDecodeError, UsageError) as exc:
            ap.exit(
                2,
                f"{ap.prog}: error: {f}: {exc}; give the --out directory of `landscape physical validate`\n",
            )
        sim = {(c.theta_w_cmd_deg, c.theta_l_deg): (c.sim_ttr_median_s, c.sim_k, c.sim_n) for c in v.cells}
        sim["name"] = v.model_set or "?"
    try:
        print(frame_table(args.data, mounts, sim))
    except UsageError as exc:  # bad data: one line, as the landscape command does
        ap.exit(2, f"{ap.prog}: error: {exc}\n")
    return 0


def frame_table(data: str, mounts: list[float], sim: dict) -> str:
    from landscape.analysis.physical.outcome import trial_outcome
    from landscape.analysis.physical.recording import read_recording, trial_files, up_z_mounted

    cells: dict[tuple[float, float], list[list]] = defaultdict(lambda: [[] for _ in mounts])
    for f in trial_files(data):
        rec = read_recording(f)
        for i, m in enumerate(mounts):
            t = trial_outcome(replace(rec, up_z=up_z_mounted(rec.quat_xyzw, m)))
            cells[(rec.theta_w_cmd_deg, rec.theta_l_deg)][i].append(t)
    head = " | ".join(f"robot, body pitched {m:g}° below its IMU" for m in mounts)
    extra = f" | {sim['name']} (simulated) |" if sim else " |"
    lines = [
        "median time to right from the first opening, s (righted/trials)",
        f"| wing cmd | leg | {head}{extra}",
        "|---|---|" + "---|" * len(mounts) + ("---|" if sim else ""),
    ]
    for (w, leg), per in sorted(cells.items()):
        row = []
        for trials in per:
            times = [t.time_to_right_s for t in trials if t.success]
            med = f"{np.median(times):.2f} s" if times else "–"
            row.append(f"{med} ({len(times)}/{len(trials)})")
        if sim:
            s = sim.get((w, leg))
            row.append("–" if s is None or not math.isfinite(s[0]) else f"{s[0]:.2f} s ({s[1]}/{s[2]})")
        lines.append(f"| {w:g}° | {leg:g}° | " + " | ".join(row) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    raise SystemExit(main())
