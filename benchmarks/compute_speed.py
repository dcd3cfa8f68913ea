"""Speed of one computation (issue #12, section 1): this tree against the code at a baseline commit, same run.

The baseline commit's packages are exported with ``git archive`` into a temporary directory; each tree is then
measured in its own child process (``PYTHONPATH`` set to the tree), so both run the same public calls on the
same machine within a minute of each other. Every quantity runs once untimed first (numba compiles or loads
its cache; the built-in robot's files and the robot cache are written), then the best of ``--repeat`` rounds
is kept:

- start state: ``metastable_orientation(lab, 74, 30)`` (the quasi-static continuation), in process;
- compute: ``compute(lab, theta_w_deg=74, theta_l_deg=30)`` (pose, start, landscape, exact barriers), in process;
- barrier map: ``barrier_map(lab, theta_w -10..90 at 0.5, theta_l [0], method="exact")``, in process, one round
  (since issue #12's map work its poses are spread over worker processes, ``workers=None``: one per CPU);
- barrier map in one process: the same with ``workers=1`` (the baseline has no workers: its plain call);
- barrier map without sector exits: the default call with ``sector_exits=False`` (minima, righting and escape
  only; with them, since the lazy sector floods, no pose computes a whole landscape grid either), this tree only;
- ``landscape compute --theta-w 74`` and ``landscape --help``: whole processes (``python -m landscape``);
- the floor under the first: a bare interpreter importing numpy, scipy.spatial (qhull) and numba, which
  ``compute`` needs (before numba loads a single cached kernel).

Correctness columns: the start minimum's energy, the righting barrier, and the map's start energies, righting
barriers and pitch-wise and roll-wise barriers of the two trees, which must agree to 1e-9 J.

Run:  PYTHONPATH=. /work/main/.venv/bin/python benchmarks/compute_speed.py [--baseline 3ba33fb] [--repeat 5]
      [--no-map] [--lab PATH]

Last run (issue #12's map target: of equal exact saddles the one a rule on their geometry picks, so the exact
method reuses the pose hull's Qhull output instead of a second Qhull run; the hull sorts only its vertices;
compiled arc geometry; saddles' basins found on demand; ``--repeat 3`` at load 0.99, on a machine running
slower than in earlier runs: the baseline's map took 13.0 s)::

    python 3.11.7, 2 CPUs, load 0.99; best of 3 (map: one round); baseline 3ba33fb
    quantity                                       target    3ba33fb  this tree   ratio  met
    start state, lab θw 74 θl 30                 10.00 ms  139.15 ms    8.02 ms   17.35  yes
    compute, lab θw 74 θl 30 (exact)             40.00 ms  189.57 ms   25.33 ms    7.48  yes
    barrier map, lab θw -10..90/0.5 (exact)       2.000 s   13.023 s    1.947 s    6.69  yes
      the same map in one process                 2.000 s   14.762 s    3.608 s    4.09  NO
      the same map, sector_exits=False            2.000 s          —    1.376 s          yes
    landscape compute --theta-w 74 (process)     600.00 ms    2.361 s    1.498 s    1.58  NO
    landscape --help (process)                   300.00 ms   97.41 ms  112.67 ms    0.86  yes
      floor: import numpy, scipy.spatial, numba  600.00 ms  809.74 ms  741.90 ms    1.09  NO

    start minimum energy   |dE| = 0.00e+00 J
    righting barrier       |dB| = 7.11e-17 J
    barrier map (201 poses)  max |dE start| = 5.55e-17 J   max |dB righting| = 1.11e-16 J
      pitch-wise and roll-wise barriers  max |dB| = 1.11e-16 J

Where a map pose's time goes now (one process, lab robot, about 18 ms a pose in that run): one Qhull run (the
pose's hull of every part's hull vertices, whose triangles the exact method reuses); the exact landscape and its
searches in NumPy and Python; the sector floods; posing.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BRANCH_POINT = "3ba33fb"  # main when issue #12's speed work began (the face-following continuation, numpy)
LAB_URDFS = (
    ROOT.parent / "shared/ref/lab_robot/lab_robot.urdf",
    Path("/work/shared/ref/lab_robot/lab_robot.urdf"),
)
TARGETS_S = {
    "start": 0.010,
    "compute": 0.040,
    "map": 2.0,
    "map_serial": 2.0,
    "map_lean": 2.0,
    "cli_compute": 0.6,
    "cli_help": 0.3,
    "import_floor": 0.6,
}
LABELS = {
    "start": "start state, lab θw 74 θl 30",
    "compute": "compute, lab θw 74 θl 30 (exact)",
    "map": "barrier map, lab θw -10..90/0.5 (exact)",
    "map_serial": "  the same map in one process",
    "map_lean": "  the same map, sector_exits=False",
    "cli_compute": "landscape compute --theta-w 74 (process)",
    "cli_help": "landscape --help (process)",
    "import_floor": "  floor: import numpy, scipy.spatial, numba",
}


def _best(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def measure(lab: str, repeat: int, do_map: bool) -> dict:
    """In-process timings of the tree on ``sys.path`` (run in a child process)."""
    import numpy as np

    from geometry import Robot
    from landscape.computation import barrier_map, compute
    from landscape.minima import metastable_orientation

    robot = Robot.from_urdf(lab)
    out: dict = {}
    metastable_orientation(robot, 74.0, 30.0)
    out["start"] = _best(lambda: metastable_orientation(robot, 74.0, 30.0), repeat)
    c = compute(robot, theta_w_deg=74.0, theta_l_deg=30.0)
    out["compute"] = _best(lambda: compute(robot, theta_w_deg=74.0, theta_l_deg=30.0), repeat)
    out["start_energy_j"] = c.minimum.energy_j
    out["righting_j"] = c.barrier.righting.barrier_j if c.barrier.righting else None
    if do_map:
        ws = [float(x) for x in np.arange(-10.0, 90.0 + 1e-9, 0.5)]
        t0 = time.perf_counter()
        m = barrier_map(robot, ws, [0.0], method="exact")
        out["map"] = time.perf_counter() - t0
        out["map_righting_j"] = [None if not np.isfinite(x) else float(x) for x in m.righting_j.ravel()]
        out["map_start_j"] = [x.minimum.energy_j for x in m.computations]
        for k in ("pitch_wise", "roll_wise"):
            out[f"map_{k}_j"] = [_barrier_j(getattr(x.barrier, k)) for x in m.computations]
        t0 = time.perf_counter()
        try:
            m1 = barrier_map(robot, ws, [0.0], method="exact", workers=1)
        except TypeError:  # a tree from before the workers: its only way is one process
            m1 = barrier_map(robot, ws, [0.0], method="exact")
        out["map_serial"] = time.perf_counter() - t0
        out["map_serial_righting_j"] = [
            None if not np.isfinite(x) else float(x) for x in m1.righting_j.ravel()
        ]
        t0 = time.perf_counter()
        try:
            m2 = barrier_map(robot, ws, [0.0], method="exact", sector_exits=False)
            out["map_lean"] = time.perf_counter() - t0
            out["map_lean_righting_j"] = [
                None if not np.isfinite(x) else float(x) for x in m2.righting_j.ravel()
            ]
        except TypeError:  # a tree from before the option
            pass
    return out


def _barrier_j(x) -> float | None:
    return None if x is None or not math.isfinite(x.barrier_j) else float(x.barrier_j)


def _process_time(tree: Path, args: list[str], env: dict, repeat: int) -> float:
    cmd = [sys.executable, "-m", "landscape", *args]
    subprocess.run(cmd, cwd=tree, env=env, check=True, capture_output=True)  # numba cache, robot cache
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, cwd=tree, env=env, check=True, capture_output=True)
        best = min(best, time.perf_counter() - t0)
    return best


def run_tree(tree: Path, lab: Path, repeat: int, do_map: bool, cache: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), LANDSCAPE_CACHE=str(cache))
    cmd = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--measure",
        "--lab",
        str(lab),
        "--repeat",
        str(repeat),
    ]
    if not do_map:
        cmd.append("--no-map")
    res = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True, check=False)
    if res.returncode != 0:
        raise RuntimeError(f"measuring {tree} failed:\n{res.stderr}")
    out = json.loads(res.stdout.strip().splitlines()[-1])
    out["cli_compute"] = _process_time(tree, ["compute", "--theta-w", "74"], env, repeat)
    out["cli_help"] = _process_time(tree, ["--help"], env, repeat)
    out["import_floor"] = _import_time(["numpy", "scipy.spatial", "numba"], env, repeat)
    return out


def _import_time(modules: list[str], env: dict, repeat: int) -> float:
    """Best wall time of a bare interpreter importing ``modules`` (the libraries ``compute`` needs): the floor
    under any ``landscape compute`` process."""
    cmd = [sys.executable, "-c", "import " + ", ".join(modules)]
    subprocess.run(cmd, env=env, check=True, capture_output=True)
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, env=env, check=True, capture_output=True)
        best = min(best, time.perf_counter() - t0)
    return best


def export(rev: str, dest: Path) -> Path:
    """The tracked files of commit ``rev`` under ``dest`` (git archive)."""
    dest.mkdir(parents=True, exist_ok=True)
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest


def _diff(a, b) -> float:
    if a is None or b is None:
        return 0.0 if a is b else float("inf")
    return abs(a - b)


def table(old: dict, new: dict, rev: str) -> str:
    rows = [f"{'quantity':44s} {'target':>8s} {rev[:10]:>10s} {'this tree':>10s} {'ratio':>7s}  met"]
    for key, label in LABELS.items():
        if key not in new:
            continue
        t_old, t_new, target = old.get(key), new[key], TARGETS_S[key]
        was, ratio = ("—", "") if t_old is None else (_ms(t_old), f"{t_old / t_new:.2f}")
        rows.append(
            f"{label:44s} {_ms(target):>8s} {was:>10s} {_ms(t_new):>10s} {ratio:>7s}  "
            f"{'yes' if t_new <= target else 'NO'}"
        )
    rows.append("")
    rows.append(f"start minimum energy   |dE| = {_diff(old['start_energy_j'], new['start_energy_j']):.2e} J")
    rows.append(f"righting barrier       |dB| = {_diff(old['righting_j'], new['righting_j']):.2e} J")
    if "map" in old:
        d_b = max(_diff(a, b) for a, b in zip(old["map_righting_j"], new["map_righting_j"], strict=True))
        d_s = max(_diff(a, b) for a, b in zip(old["map_start_j"], new["map_start_j"], strict=True))
        for k in ("map_serial_righting_j", "map_lean_righting_j"):
            if k in new:
                d_b = max(d_b, *(_diff(a, b) for a, b in zip(old["map_righting_j"], new[k], strict=True)))
        rows.append(
            f"barrier map ({len(old['map_start_j'])} poses)  max |dE start| = {d_s:.2e} J   "
            f"max |dB righting| = {d_b:.2e} J"
        )
        d_x = [
            max(_diff(a, b) for a, b in zip(old[k], new[k], strict=True))
            for k in ("map_pitch_wise_j", "map_roll_wise_j")
            if k in old and k in new
        ]
        if d_x:
            rows.append(f"  pitch-wise and roll-wise barriers  max |dB| = {max(d_x):.2e} J")
    return "\n".join(rows)


def _ms(t: float) -> str:
    return f"{t * 1e3:.2f} ms" if t < 1 else f"{t:.3f} s"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--baseline", default=BRANCH_POINT, help="commit to compare against (default: branch point)"
    )
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-map", action="store_true", help="skip the barrier map (the baseline's takes ~20 s)")
    ap.add_argument("--lab", type=Path, default=None, help="lab URDF (default ../shared/ref/lab_robot)")
    ap.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    lab = args.lab or next((p for p in LAB_URDFS if p.is_file()), None)
    if lab is None:
        raise SystemExit("the lab robot is absent (../shared/ref/lab_robot); give --lab PATH")
    if args.measure:
        print(json.dumps(measure(str(lab), args.repeat, not args.no_map)))
        return
    with tempfile.TemporaryDirectory() as tmp:
        base = export(args.baseline, Path(tmp) / "baseline")
        cache = Path(tmp) / "cache"
        old = run_tree(base, lab, args.repeat, not args.no_map, cache)
        new = run_tree(ROOT, lab, args.repeat, not args.no_map, cache)
    rev = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", args.baseline],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    print(
        f"python {sys.version.split()[0]}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}; "
        f"best of {args.repeat} (map: one round); baseline {rev}"
    )
    print(table(old, new, rev))


if __name__ == "__main__":
    main()
