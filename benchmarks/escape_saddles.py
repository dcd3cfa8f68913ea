"""Are the exact method's escape saddles real saddles on noisy bodies? (issue #12, section 2)

Issue #12 reported that on a box with a slightly noisy bottom face ``--method exact`` gave an escape barrier
about 17 times below the righting barrier a few degrees from the start, at a point that was no saddle. This script
runs a corpus of noisy bodies (boxes and plates whose bottom-face vertices are jittered by a fraction of a
millimetre, at several sizes, subdivisions and seeds, and tessellated ellipsoids with an off-centre CoM) through
``landscape compute --method exact`` (the command the issue used, with ``--json``) and checks every reported
escape saddle by brute force over the body's hull points, without the hull graph the method uses:

1. the body rests on an edge: the lowest points at the saddle's up-direction are collinear;
2. rocking about that edge lowers the CoM both ways, tilting along it raises it both ways;
3. rolling down from the two rocked orientations (exact rolling on the points, ``landscape.minima.rest_face``)
   ends at two different minima, one of them the start's.

With ``--baseline COMMIT`` the same corpus also runs through that commit's code (exported with ``git archive``;
``ccfb727`` is main when the issue was filed) and the two answers are compared.

Run:  PYTHONPATH=. .venv/bin/python benchmarks/escape_saddles.py [--seeds 6] [--baseline ccfb727]

Last run (``--seeds 6 --baseline ccfb727``)::

    family                                       n not saddles escape <10° away   righting/escape    = ccfb727
    small box 20x15x8, 0.9 mm                    6           0                0      1.0–49.9            6/6
    box 100x60x30, 0.3 mm                        6           0                1      1.0–9493.0          6/6
    fine box 100x60x30 (x64 faces), 0.5 mm       6           0                0      1.0–1.0             6/6
    plate 100x80x10 (x16 faces), 0.3 mm          6           0                0      1.0–1.0             6/6
    ellipsoid 60x40x30 (320 faces)               6           0                5      1.0–250.4           6/6
    ellipsoid 60x40x30 (1280 faces)              6           0                6     43.9–831.1           5/6

Every reported escape saddle is a saddle between the start's basin and another (0 of 36 fail). Near the start
(the jittered boxes, the coarse ellipsoids) the escape barriers far below the righting barrier are real: a noisy
face has several shallow minima a few degrees apart, and the exact method finds the pass between two of them.
The code of ccfb727 gives the same barriers on 35 of 36 bodies; the other (a 1280-face ellipsoid) is the moving
start that issue #12 also reported, fixed since (``tests/landscape/test_minima.py``).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import trimesh

from geometry import up_vector
from geometry.robots import load_robot
from landscape.minima import rest_face

ROOT = Path(__file__).resolve().parents[1]


def jittered_box(extents_mm, subdivisions: int, amp_mm: float, seed: int) -> trimesh.Trimesh:
    """A box (mm) whose bottom-face vertices are moved by up to ``amp_mm`` in x, y and z."""
    rng = np.random.default_rng(seed)
    mesh = trimesh.creation.box(extents=extents_mm)
    for _ in range(subdivisions):
        mesh = mesh.subdivide()
    v = mesh.vertices.copy()
    bottom = v[:, 2] < v[:, 2].min() + 1e-9
    v[bottom] += rng.uniform(-amp_mm, amp_mm, size=(int(bottom.sum()), 3))
    return trimesh.Trimesh(v, mesh.faces, process=False)


def ellipsoid(subdivisions: int, seed: int) -> tuple[trimesh.Trimesh, list[float]]:
    """A tessellated 60 x 40 x 30 mm ellipsoid and a CoM up to 5 mm off its centre."""
    mesh = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    mesh.apply_scale((60.0, 40.0, 30.0))
    return mesh, list(np.random.default_rng(seed).uniform(-5.0, 5.0, 3))


def corpus(seeds: int) -> list[tuple[str, str, trimesh.Trimesh, list[float] | None]]:
    """(family, name, mesh, CoM in mm or None for the solid's centroid)."""
    bodies = []
    boxes = {
        "small box 20x15x8, 0.9 mm": ((20, 15, 8), 0, 0.9),
        "box 100x60x30, 0.3 mm": ((100, 60, 30), 0, 0.3),
        "fine box 100x60x30 (x64 faces), 0.5 mm": ((100, 60, 30), 3, 0.5),
        "plate 100x80x10 (x16 faces), 0.3 mm": ((100, 80, 10), 2, 0.3),
    }
    for family, (ext, sub, amp) in boxes.items():
        for seed in range(seeds):
            bodies.append((family, f"{family} seed {seed}", jittered_box(ext, sub, amp, seed), None))
    for sub in (2, 3):
        for seed in range(seeds):
            mesh, com = ellipsoid(sub, seed)
            family = f"ellipsoid 60x40x30 ({20 * 4**sub} faces)"
            bodies.append((family, f"{family} seed {seed}", mesh, com))
    return bodies


def run_compute(tree: Path, mesh_file: Path, com_mm: list[float] | None) -> dict:
    """``landscape compute --method exact --json`` with the packages of ``tree``."""
    cmd = [sys.executable, "-m", "landscape", "compute", "--mesh", str(mesh_file), "--units", "mm"]
    cmd += ["--method", "exact", "--json"]
    if com_mm is not None:
        cmd += ["--com", ",".join(f"{c:.6f}" for c in com_mm)]
    out = subprocess.run(
        cmd, capture_output=True, text=True, cwd=tree, env={"PYTHONPATH": str(tree)}, check=True
    )
    return json.loads(out.stdout)


def _height(com, points, u):
    return float(((com - points) @ u).max())


def _rotate(u, axis, angle_rad):
    axis = axis / np.linalg.norm(axis)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return u * c + np.cross(axis, u) * s + axis * (axis @ u) * (1 - c)


def check_saddle(points, com, start_deg, saddle_deg) -> str:
    """'' if the point is a saddle between the start's basin and another one, else what fails."""
    u_s = up_vector(*np.deg2rad(saddle_deg))
    hv = (com - points) @ u_s
    size = np.ptp(points, axis=0).max()
    on_edge = hv >= hv.max() - 1e-9 * size
    low = points[on_edge]
    # rock by less than the next point's clearance allows (a jittered face is within microns of the ground)
    gap = hv.max() - hv[~on_edge].max() if (~on_edge).any() else size
    angle = min(1e-3, 0.1 * gap / size)
    span = low - low[0]
    if len(low) < 2:
        return "rests on a single point"
    axis = span[int(np.argmax(np.linalg.norm(span, axis=1)))]
    axis = axis / np.linalg.norm(axis)
    if np.linalg.norm(np.cross(span, axis), axis=1).max() > 1e-9 * size:
        return "rests on a face, not an edge"
    tilt = np.cross(u_s, axis)
    u0, _ = rest_face(points, com, up_vector(*np.deg2rad(start_deg)))
    h_s = _height(com, points, u_s)
    ends = []
    for a in (angle, -angle):
        rocked = _rotate(u_s, axis, a)
        if _height(com, points, rocked) >= h_s:
            return "rocking about the edge does not lower the CoM"
        if _height(com, points, _rotate(u_s, tilt, a)) <= h_s:
            return "tilting along the edge does not raise the CoM"
        ends.append(rest_face(points, com, rocked)[0])
    same = [bool(np.dot(e, u0) > 1 - 1e-9) for e in ends]
    if np.dot(ends[0], ends[1]) > 1 - 1e-9:
        return "both sides roll into the same basin"
    if not any(same):
        return "neither side rolls into the start's basin"
    return ""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=6, help="Random bodies per family.")
    ap.add_argument("--baseline", help="Also run this commit's code on the same corpus and compare.")
    args = ap.parse_args(argv)
    bodies = corpus(args.seeds)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        base = None
        if args.baseline:
            base = tmp / "baseline"
            base.mkdir()
            archive = subprocess.run(
                ["git", "archive", args.baseline], cwd=ROOT, capture_output=True, check=True
            )
            subprocess.run(["tar", "-x", "-C", str(base)], input=archive.stdout, check=True)
        rows = {}
        for k, (family, name, mesh, com) in enumerate(bodies):
            f = tmp / f"body{k}.stl"
            mesh.export(f)
            d = run_compute(ROOT, f, com)
            robot = load_robot(mesh=str(f), units="mm", com=com)
            pose = robot.pose()
            b = d["barrier"]
            start = (d["minimum"]["pitch_deg"], d["minimum"]["roll_deg"])
            saddle = (b["escape_saddle_pitch_deg"], b["escape_saddle_roll_deg"])
            why = check_saddle(pose.hull_points_m, pose.com_m, start, saddle)
            same = None
            if base is not None:
                o = run_compute(base, f, com)["barrier"]
                same = (
                    abs(o["escape_j"] - b["escape_j"]) <= 1e-9
                    and abs(o["righting_j"] - b["righting_j"]) <= 1e-9
                )
            r = rows.setdefault(family, {"n": 0, "bad": [], "ratio": [], "same": 0, "near": 0})
            r["n"] += 1
            r["ratio"].append(b["righting_j"] / b["escape_j"])
            r["near"] += np.hypot(saddle[0] - start[0], saddle[1] - start[1]) < 10.0
            r["same"] += bool(same)
            if why:
                r["bad"].append(f"{name}: {why}")
    print(
        f"{'family':42} {'n':>3} {'not saddles':>11} {'escape <10° away':>16} {'righting/escape':>17}", end=""
    )
    print(f" {'= ' + args.baseline:>12}" if args.baseline else "")
    for family, r in rows.items():
        lo, hi = min(r["ratio"]), max(r["ratio"])
        line = f"{family:42} {r['n']:3d} {len(r['bad']):11d} {r['near']:16d} {lo:8.1f}–{hi:<8.1f}"
        print(line + (f" {r['same']:>8d}/{r['n']}" if args.baseline else ""))
    bad = [b for r in rows.values() for b in r["bad"]]
    for b in bad:
        print("  NOT A SADDLE:", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
