"""Latency and load of ``landscape serve`` on loopback: cached and uncached landscape p50, then C concurrent
clients x N requests mixing cached and uncached poses on two robots (the built-in one and an uploaded box).

Starts its own server on 127.0.0.1 with a fresh data directory, sends a bounded number of requests, stops the
server and prints one table. Targets (issue #13): cached p50 <= 5 ms, uncached built-in p50 <= 100 ms.

    .venv/bin/python benchmarks/service_load.py [--clients 32] [--requests 50] [--step 2]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx
import trimesh

ROOT = Path(__file__).resolve().parents[1]
LAB = (
    Path(os.environ.get("LANDSCAPE_SHARED") or ROOT.parent / "shared")
    / "ref"
    / "lab_robot"
    / "lab_robot.urdf"
)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _pct(xs: list[float], q: float) -> float:
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(round(q / 100 * (len(xs) - 1))))] if xs else float("nan")


def start(data: Path, port: int) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys; from landscape.cli import main; sys.exit(main())",
            "serve",
            "--port",
            str(port),
            "--data",
            str(data),
            "--log-level",
            "error",
        ],
        cwd=ROOT,
        env=env,
        start_new_session=True,
    )
    for _ in range(600):
        try:
            httpx.get(f"http://127.0.0.1:{port}/api/health", timeout=1).raise_for_status()
            return proc
        except httpx.HTTPError:
            time.sleep(0.1)
    os.killpg(proc.pid, signal.SIGTERM)
    raise SystemExit("server did not start")


def timed_get(client: httpx.Client, url: str, params: dict) -> float:
    t0 = time.perf_counter()
    r = client.get(url, params=params)
    dt = time.perf_counter() - t0
    r.raise_for_status()
    return dt


async def load(base: str, robots: list[str], clients: int, requests: int, step: float, seed: int = 0):
    """C clients x N requests; half ask a pose already cached (theta_w 60..79), half a new one (80..95 with a
    theta_l that no one asked before)."""
    rng = random.Random(seed)
    fresh = iter(range(10**6))
    lat: list[float] = []
    errors = 0

    async def client(k: int):
        nonlocal errors
        async with httpx.AsyncClient(base_url=base, timeout=120) as c:
            for _ in range(requests):
                robot = rng.choice(robots)
                if rng.random() < 0.5:
                    q = {"robot": robot, "theta_w": rng.randrange(60, 80), "theta_l": 0, "step": step}
                else:
                    n = next(fresh)
                    q = {
                        "robot": robot,
                        "theta_w": 80 + n % 16,
                        "theta_l": -89 + (n // 16) % 179,
                        "step": step,
                    }
                t0 = time.perf_counter()
                try:
                    r = await c.get("/api/landscape", params=q)
                    ok = r.status_code == 200
                except httpx.HTTPError:
                    ok = False
                lat.append(time.perf_counter() - t0)
                errors += not ok

    t0 = time.perf_counter()
    await asyncio.gather(*(client(k) for k in range(clients)))
    return lat, errors, time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--clients", type=int, default=32)
    ap.add_argument("--requests", type=int, default=50)
    ap.add_argument("--step", type=float, default=2.0, help="grid step of every request, degrees")
    ap.add_argument("--samples", type=int, default=40, help="requests per single-client latency measurement")
    args = ap.parse_args()
    port = _free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory() as d:
        proc = start(Path(d) / "data", port)
        try:
            with httpx.Client(base_url=base, timeout=120) as c:
                box = trimesh.creation.box(extents=(0.1, 0.06, 0.04)).export(file_type="stl")
                box_id = c.post("/api/robots", files={"file": ("box.stl", box)}).json()["id"]
                robots = ["builtin", box_id]
                url = "/api/landscape"
                timed_get(c, url, {"theta_w": 59, "step": args.step})  # warm the kernels and the continuation
                for tw in range(60, 80):  # the poses the load's cached half asks for
                    for r in robots:
                        timed_get(c, url, {"robot": r, "theta_w": tw, "step": args.step})
                cached = [
                    timed_get(c, url, {"theta_w": 60 + k % 20, "step": args.step})
                    for k in range(args.samples)
                ]
                uncached = [
                    timed_get(c, url, {"theta_w": 40 + (k % 20), "theta_l": 1 + k, "step": args.step})
                    for k in range(args.samples)
                ]
                slider = [
                    timed_get(c, url, {"theta_w": 20 + k * 0.5, "step": args.step})
                    for k in range(args.samples)
                ]
                lab = []
                if LAB.is_file():  # the lab robot, uploaded as a zip of its URDF and meshes
                    import io
                    import zipfile

                    buf = io.BytesIO()
                    with zipfile.ZipFile(buf, "w") as z:
                        for f in LAB.parent.iterdir():
                            if f.suffix in (".urdf", ".obj"):
                                z.write(f, f"lab_robot/{f.name}")
                    lab_id = c.post("/api/robots", files={"file": ("lab.zip", buf.getvalue())}).json()["id"]
                    timed_get(c, url, {"robot": lab_id, "theta_w": 59, "step": args.step})
                    lab = [
                        timed_get(
                            c,
                            url,
                            {"robot": lab_id, "theta_w": 40 + (k % 20), "theta_l": 1 + k, "step": args.step},
                        )
                        for k in range(args.samples)
                    ]
            lat, errors, wall = asyncio.run(load(base, robots, args.clients, args.requests, args.step))
            peak_mb = _peak_rss_mb(proc.pid)
        finally:
            os.killpg(proc.pid, signal.SIGTERM)
            proc.wait(timeout=30)
    rows = [
        (
            "cached landscape (built-in)",
            len(cached),
            None,
            statistics.median(cached),
            _pct(cached, 99),
            0,
            "<= 5",
        ),
        (
            "uncached, new theta_l (built-in)",
            len(uncached),
            None,
            statistics.median(uncached),
            _pct(uncached, 99),
            0,
            "<= 100",
        ),
        (
            "uncached, slider +0.5 deg (built-in)",
            len(slider),
            None,
            statistics.median(slider),
            _pct(slider, 99),
            0,
            "<= 100",
        ),
        (
            f"load {args.clients} clients x {args.requests}",
            len(lat),
            len(lat) / wall,
            statistics.median(lat),
            _pct(lat, 99),
            errors,
            "",
        ),
    ]
    if lab:
        rows.insert(
            3,
            (
                "uncached, new theta_l (lab robot)",
                len(lab),
                None,
                statistics.median(lab),
                _pct(lab, 99),
                0,
                "<= 100",
            ),
        )
    cli = _cli_seconds(args.step)
    rows.append(("baseline: `landscape compute` as a process", 3, None, cli, cli, 0, ""))
    print(f"landscape serve on loopback, step {args.step:g} deg, method exact, {os.cpu_count()} cores")
    print(
        f"{'run':<42} {'requests':>8} {'req/s':>8} {'p50 ms':>8} {'p99 ms':>8} {'errors':>6}  target p50 ms"
    )
    for name, n, thr, p50, p99, err, target in rows:
        print(
            f"{name:<42} {n:>8d} {'' if thr is None else f'{thr:.1f}':>8} {p50 * 1e3:>8.1f} {p99 * 1e3:>8.1f} "
            f"{err:>6d}  {target}"
        )
    print(
        f"server peak resident memory over the whole run: {peak_mb:.0f} MB (the in-memory cache is bounded)"
    )
    print(
        f"ratio: uncached built-in p50 / command-line process = {rows[1][3] / cli:.3f} "
        f"({cli / rows[1][3]:.0f}x faster); cached p50 / process = {rows[0][3] / cli:.4f}"
    )


def _peak_rss_mb(pid: int) -> float:
    """Peak resident memory (VmHWM) of the server process and its children, MB."""
    import psutil

    procs = [psutil.Process(pid), *psutil.Process(pid).children(recursive=True)]
    total = 0.0
    for pr in procs:
        try:
            with open(f"/proc/{pr.pid}/status") as f:
                total += next(int(line.split()[1]) for line in f if line.startswith("VmHWM")) / 1024
        except (OSError, StopIteration):
            pass
    return total


def _cli_seconds(step: float) -> float:
    """Median wall time of the same answer from the command line (a new process each time), s."""
    exe = Path(sys.executable).parent / "landscape"
    times = []
    for k in range(3):
        t0 = time.perf_counter()
        subprocess.run(
            [str(exe), "compute", "--theta-w", str(41 + k), "--theta-l", "7", "--step", str(step), "--json"],
            check=True,
            capture_output=True,
        )
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


if __name__ == "__main__":
    main()
