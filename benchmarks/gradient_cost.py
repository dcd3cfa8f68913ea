"""What the barrier gradients and intervals cost: ``compute`` with gradients against without, in the same run, and
the Monte-Carlo interval's cost per sample.

Each tree is measured in its own child process (``PYTHONPATH`` set to the tree), as ``benchmarks/compute_speed.py``
does: this tree, and with ``--baseline REV`` the code at that commit (``git archive``; its ``compute`` has no
gradients, and its exact method keeps no contacts, so the ratio against it is the whole feature's cost). For each
robot (the built-in one; the lab robot when ``../shared`` holds it) and pose, every variant runs once untimed
(numba loads its cache), then ``--repeat`` rounds, the variants interleaved within each round so that a change of
machine load hits them alike; the best of the rounds is kept. Times are the process's CPU time
(``time.process_time``; ``compute`` runs in one thread), which other processes on a shared machine disturb far less
than wall time:

- ``compute(robot, theta_w_deg=W, theta_l_deg=L)`` of the baseline;
- this tree's ``compute(..., gradients=False)`` and ``compute(...)`` (gradients, the default);
- the Monte-Carlo range of ``--samples`` CoMs 1 mm off (:func:`landscape.uncertainty.barrier_intervals`), whose
  time divided by the samples is the cost per sample (every exit recomputed: exact righting and escape, the grid's
  pitch-wise and roll-wise sector searches).

Run:  PYTHONPATH=. .venv/bin/python benchmarks/gradient_cost.py [--baseline aad7130] [--repeat 15] [--samples 32]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
POSES = ((60.0, 30.0), (74.0, 30.0), (90.0, 30.0), (74.0, 0.0))
TARGET_RATIO = 1.10
"""``compute`` with gradients may cost at most this many times ``compute`` without."""


def _speed_module():
    """benchmarks/compute_speed.py (its ``export`` and ``LAB_URDFS``)."""
    spec = importlib.util.spec_from_file_location(
        "compute_speed", Path(__file__).with_name("compute_speed.py")
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def measure(lab: str | None, repeat: int, samples: int) -> dict:
    """In-process timings of the tree on ``sys.path`` (run in a child process): per robot and pose, the best
    seconds of each variant."""
    import inspect

    from geometry.robots import load_robot
    from landscape.computation import compute

    has_gradients = "gradients" in inspect.signature(compute).parameters
    robots = {"builtin": load_robot()} | ({"lab": load_robot(lab)} if lab else {})
    out = {}
    for name, robot in robots.items():
        for w, leg in POSES:
            variants = {"compute": lambda r=robot, w=w, leg=leg: compute(r, theta_w_deg=w, theta_l_deg=leg)}
            if has_gradients:
                variants["without"] = lambda r=robot, w=w, leg=leg: compute(
                    r, theta_w_deg=w, theta_l_deg=leg, gradients=False
                )
            best = {k: float("inf") for k in variants}
            for fn in variants.values():
                fn()
            for _ in range(repeat):
                for k, fn in variants.items():
                    t0 = time.process_time()
                    fn()
                    best[k] = min(best[k], time.process_time() - t0)
            row = dict(best)
            if has_gradients and samples:
                from landscape.uncertainty import Uncertainty, barrier_intervals

                c = compute(robot, theta_w_deg=w, theta_l_deg=leg)
                t0 = time.process_time()
                barrier_intervals(c, Uncertainty(com_m=1e-3, samples=samples))
                row["per_sample"] = (time.process_time() - t0) / samples
            out[f"{name} θw {w:g} θl {leg:g}"] = row
    return out


def run_tree(tree: Path, lab: Path | None, repeat: int, samples: int, cache: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), LANDSCAPE_CACHE=str(cache))
    cmd = [sys.executable, str(Path(__file__).resolve()), "--measure", "--repeat", str(repeat)]
    cmd += ["--samples", str(samples)] + (["--lab", str(lab)] if lab else [])
    res = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True, check=False)
    if res.returncode != 0:
        raise RuntimeError(f"measuring {tree} failed:\n{res.stderr}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def table(new: dict, old: dict | None, rev: str | None, samples: int) -> str:
    head = f"{'pose':26s} " + (f"{rev[:10]:>10s} " if old else "")
    head += f"{'without':>10s} {'gradients':>10s} {'ratio':>6s}  met" + ("  vs base" if old else "")
    head += f"  {'MC/sample':>10s} {'/compute':>8s}"
    rows = [head]
    worst = 0.0
    for pose, t in new.items():
        ratio = t["compute"] / t["without"]
        worst = max(worst, ratio)
        line = f"{pose:26s} " + (f"{old[pose]['compute'] * 1e3:7.2f} ms " if old else "")
        line += f"{t['without'] * 1e3:7.2f} ms {t['compute'] * 1e3:7.2f} ms {ratio:6.3f}  "
        line += f"{'yes' if ratio <= TARGET_RATIO else 'NO ':3s}"
        if old:
            line += f"  {t['compute'] / old[pose]['compute']:8.3f}"
        if "per_sample" in t:
            line += f"  {t['per_sample'] * 1e3:7.2f} ms {t['per_sample'] / t['compute']:8.2f}"
        rows.append(line)
    rows.append("")
    rows.append(
        f"ratio = compute with gradients / without, best of the rounds; target <= {TARGET_RATIO:.2f}; "
        f"worst {worst:.3f}"
    )
    if old:
        rows.append(
            f"vs base = compute with gradients / the {rev[:10]} tree's compute (no gradients, no contacts)"
        )
    rows.append(
        f"MC/sample = the Monte-Carlo interval's time per sample ({samples} CoMs 1 mm off, every exit "
        "recomputed); /compute = that over one compute"
    )
    return "\n".join(rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", default=None, help="also measure the code at this commit (e.g. aad7130)")
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--samples", type=int, default=32, help="Monte-Carlo samples timed per pose (0: none)")
    ap.add_argument("--lab", type=Path, default=None, help="lab URDF (default ../shared/ref/lab_robot)")
    ap.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    speed = _speed_module()
    lab = args.lab or next((p for p in speed.LAB_URDFS if p.is_file()), None)
    if args.measure:
        print(json.dumps(measure(str(lab) if lab else None, args.repeat, args.samples)))
        return
    with tempfile.TemporaryDirectory() as tmp:
        cache = Path(tmp) / "cache"
        old = None
        if args.baseline:
            base = speed.export(args.baseline, Path(tmp) / "base")
            old = run_tree(base, lab, args.repeat, 0, cache)
        new = run_tree(ROOT, lab, args.repeat, args.samples, cache)
    import platform

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(
        f"python {platform.python_version()}, {os.cpu_count()} CPUs, load {load:.2f}; CPU time, best of "
        f"{args.repeat} interleaved rounds"
    )
    print(table(new, old, args.baseline, args.samples))


if __name__ == "__main__":
    main()
