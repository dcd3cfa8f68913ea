"""How far does the first wing opening throw the body's nose? (issue #15: the time to right at 90 deg)

At the 90 deg command the robot holds its body about 7 deg short of vertical, standing on its head. Its opening
throws it further: the nose's pitch (``landscape.analysis.physical.recording.sagittal_pitch_deg``, which goes on past
90 deg where the ZYX pitch folds back) peaks past vertical, and then the leg's swing turns the body about its
own z axis, which there lies level: it falls to its side. This script puts, per cell, the robot's peak nose
pitch 0.2-0.6 s after its first opening starts, in the body frame (the IMU's reading minus the mounting the two
rests measure, ``mounting_from_rests``), beside each model set's in one simulated first opening at the phase the
lab's protocol gives the cell (``protocol_phases``; 0.17 with the leg still), no noise. Each entry: the peak
nose pitch and the rise time (from the opening's start to half-way from the rest to the hold), and how many
first openings passed vertical (robot: medians over its five, in brackets the peaks' range). A second table
gives where the body holds, the nose's median pitch 0.5-0.95 s after the opening starts in the same frame, robot
against each set (in brackets the set minus the robot's median): a set whose supports give in the simulation
(``[head_compliance]``, wing springs) holds where its simulation puts it, which the rigid landscape of ``landscape
physical kinematics`` does not show.

With ``--vary TABLE.KEY=V1,V2`` (repeatable) each value is also tried on its own in a copy of the first set
(``landscape.analysis.physical.calibration.variant_sets``), e.g. wing springs, friction or contact damping;
``--with TABLE.KEY=V`` (repeatable) sets a key in every variant (a damping while the stiffness varies).

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/nose_over.py [--data DIR] [--robot URDF]
      [--models physical-head,physical-offset] [--cells 90:0,90:30] [--vary TABLE.KEY=V1,V2 ...]
      [--with TABLE.KEY=V ...]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis.physical.calibration import add_set_options

ROOT = Path(__file__).resolve().parents[2]


def peak_nose_deg(response) -> float:
    """The highest nose pitch of an opening's transient window, degrees (its hold plus its overshoot)."""
    return response.hold_pitch_deg + response.overshoot_deg


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared/ref/physical_robot"))
    ap.add_argument("--robot", default=str(ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf"))
    ap.add_argument("--cells", default=None, help="WING:LEG,... [default: every recorded cell]")
    add_set_options(ap, "physical-head,physical-offset")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="nose_over_") as tmp:
        return _run(a, Path(tmp))


def _run(a, tmp: Path) -> int:
    from geometry.robots import load_robot
    from landscape.analysis.physical.calibration import sets_and_variants
    from landscape.analysis.physical.mounting import mounting_from_rests
    from landscape.analysis.physical.response import (
        PROTOCOL_PHASE,
        protocol_phases,
        recorded_first_openings,
        simulated_opening,
    )
    from landscape.analysis.physical.validation import parse_cells

    try:
        names, labels = sets_and_variants(a.models, a.vary, a.fixed, tmp)
        openings = recorded_first_openings(a.data)
        mount = mounting_from_rests(a.data, load_robot(a.robot)).mount_deg
        phases = protocol_phases(a.data)
        recorded = defaultdict(list)
        for o in openings:
            recorded[(o.theta_w_cmd_deg, o.theta_l_deg)].append(
                (peak_nose_deg(o.response) - mount, o.response.rise_s, o.response.hold_pitch_deg - mount)
            )
        cells = parse_cells(a.cells, recorded)
        rows = []
        for cell in cells:
            peaks = recorded[cell]
            sim = []
            for name in names:
                r = simulated_opening(
                    cell[0], cell[1], phase=phases.get(cell, PROTOCOL_PHASE), seed=0, robot=a.robot,
                    model_set=name,
                )  # fmt: skip
                sim.append((peak_nose_deg(r), r.rise_s, r.hold_pitch_deg))
            rows.append((cell, peaks, sim))
    except (UsageError, ValueError) as exc:  # PhysicalDataError, an unknown set, a bad number: one line
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(
        f"peak nose pitch 0.2-0.6 s after the first opening starts, body frame (the robot's IMU minus the "
        f"{mount:.1f} deg mounting its two rests measure), and the rise to half the hold; past vertical: > 90 deg"
    )
    print(f"| wing cmd | leg | robot (past vertical) | {' | '.join(labels)} |")
    print("|---|---|---|" + "---|" * len(labels))
    for (w, leg), peaks, sim in rows:
        p, rise, _ = np.asarray(peaks).T
        robot = (
            f"{np.median(p):.1f}° [{p.min():.1f}, {p.max():.1f}], {np.median(rise):.2f} s "
            f"({int((p > 90).sum())}/{len(p)})"
        )
        model = " | ".join(
            f"{pk:.1f}°, {rs:.2f} s ({'past' if pk > 90 else 'short of'} vertical)" for pk, rs, _ in sim
        )
        print(f"| {w:g}° | {leg:g}° | {robot} | {model} |")
    print(
        "\nthe hold: nose pitch 0.5-0.95 s after the first opening starts, same frame; in brackets set minus robot"
    )
    print(f"| wing cmd | leg | robot | {' | '.join(labels)} |")
    print("|---|---|---|" + "---|" * len(labels))
    for (w, leg), peaks, sim in rows:
        hold = np.asarray(peaks)[:, 2]
        mid = float(np.median(hold))
        model = " | ".join(f"{h:.1f}° ({h - mid:+.1f}°)" for _, _, h in sim)
        print(f"| {w:g}° | {leg:g}° | {mid:.1f}° [{hold.min():.1f}, {hold.max():.1f}] | {model} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
