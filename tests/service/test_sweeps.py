"""Sweep jobs: queued, run by run_sweep, reported, cancelled, refused when bad, and resumed by a restarted server
with no trial lost and none twice."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from .conftest import box_stl

ROOT = Path(__file__).resolve().parents[2]
TINY = {"theta_w": "74", "theta_l": "30", "cv": "0", "trials": 2, "duration": 1.0, "dt": 1e-3}


def _wait(get, until, timeout_s=240.0):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout_s:
        job = get()
        if until(job):
            return job
        time.sleep(0.2)
    raise AssertionError(f"timed out waiting; last state {job}")


@pytest.mark.e2e
def test_sweep_job_runs_and_reports(client):
    r = client.post("/api/sweeps", json=TINY)
    assert r.status_code == 201, r.text
    job = r.json()
    assert job["status"] == "queued" and job["total"] == 2
    done = _wait(lambda: client.get(f"/api/sweeps/{job['id']}").json(), lambda j: j["status"] == "done")
    assert done["done"] == done["total"] == 2
    assert [j["id"] for j in client.get("/api/sweeps").json()] == [job["id"]]
    page = client.get(f"/api/sweeps/{job['id']}/report")
    assert page.status_code == 200 and "<html" in page.text.lower()
    assert "/tmp/" not in page.text  # the database path is shown relative to the data directory
    assert client.delete(f"/api/sweeps/{job['id']}").json()["status"] == "done"  # finished jobs stay finished


def test_cancel_a_sweep(client):
    job = client.post("/api/sweeps", json={**TINY, "trials": 200}).json()
    cancelled = client.delete(f"/api/sweeps/{job['id']}").json()
    assert cancelled["status"] == "cancelled"
    time.sleep(0.5)
    assert client.get(f"/api/sweeps/{job['id']}").json()["status"] == "cancelled"


def test_a_cancel_while_the_runner_makes_the_specs_stops_the_job(client, monkeypatch):
    # the runner reads a queued job, makes its trials, then registers the run: a cancel in between was lost, and
    # the cancelled job ran all its trials
    import threading

    from sim.store import read_rows

    jobs = client.app.state.sweeps
    made = jobs.specs
    first = []
    posted = threading.Event()

    def specs_then_cancel(request):
        out = made(request)
        if threading.current_thread().name == "sweep-jobs" and int(request["trials"]) == 200:
            assert posted.wait(60)  # the runner may take the job before its POST has returned the id
            first.append(jobs.cancel(first[0]))
        return out

    monkeypatch.setattr(jobs, "specs", specs_then_cancel)
    first.append(client.post("/api/sweeps", json={**TINY, "trials": 200}).json()["id"])
    posted.set()
    later = client.post("/api/sweeps", json=TINY).json()  # the runner is free for the next job
    assert _wait(lambda: client.get(f"/api/sweeps/{later['id']}").json(), lambda j: j["status"] == "done")
    assert len(first) == 2 and first[1]["status"] == "cancelled"
    assert client.get(f"/api/sweeps/{first[0]}").json()["status"] == "cancelled"
    assert read_rows(jobs.root / first[0] / "trials.sqlite") == []


@pytest.mark.parametrize(
    "body, status, match",
    [
        ({"trials": 0}, 422, "trials 0 is outside [1, 1000000]: trials per setting"),
        ({"trials": "many"}, 422, "trials must be a whole number"),
        ({"duration": float("nan")}, 422, "duration must be a finite number; got nan"),
        ({"dt": -1}, 422, "dt -1 s is outside [1e-06, 0.01] s: the physics time step"),
        ({"phase": "1.5"}, 422, "phase 1.5 is outside [0, 1)"),
        (
            {"cv": "10"},
            422,
            "cv 10 is outside [0, 1]: Cv is sigma / Tl as a fraction; for 10 % give 0.1 or '10%'",
        ),
        ({"theta_w": "120"}, 422, "outside"),
        ({"theta_w": "x"}, 422, "not a list of numbers"),
        ({"cv": "0:1:0.0001", "trials": 1000}, 422, "a job may have at most"),
        ({"bogus": 1}, 422, "unknown sweep option 'bogus'"),
        ({"robot": "0123456789abcdef"}, 404, "unknown robot"),
    ],
)
def test_bad_sweeps(client, body, status, match):
    raw = json.dumps({**TINY, **body})  # allows NaN, as a hand-written request may
    r = client.post("/api/sweeps", content=raw, headers={"Content-Type": "application/json"})
    assert r.status_code == status, r.text
    assert match in r.json()["detail"]
    assert client.get("/api/sweeps").json() == []


def test_a_mesh_robot_cannot_be_swept(client):
    rid = client.post("/api/robots", files={"file": ("c.stl", box_stl())}).json()["id"]
    r = client.post("/api/sweeps", json={**TINY, "robot": rid})
    assert r.status_code == 422 and "single rigid mesh" in r.json()["detail"]


def test_unknown_sweep_is_404(client):
    for method, url in (
        ("get", "/api/sweeps/abc123"),
        ("delete", "/api/sweeps/abc123"),
        ("get", "/api/sweeps/abc123/report"),
        ("get", "/api/sweeps/..%2Fx"),
    ):
        assert getattr(client, method)(url).status_code == 404, url


# ---------------------------------------------------------------------------------------------- real server
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _call(port: int, method: str, path: str, body: dict | None = None, *, token: str | None = None) -> dict:
    headers = {"Content-Type": "application/json"}
    if token:
        headers["Authorization"] = f"Bearer {token}"
    req = urllib.request.Request(
        f"http://127.0.0.1:{port}{path}",
        method=method,
        data=None if body is None else json.dumps(body).encode(),
        headers=headers,
    )
    with urllib.request.urlopen(req, timeout=30) as resp:
        return json.loads(resp.read())


def start_server(data: Path, port: int, log: Path, *, token: str | None = None) -> subprocess.Popen:
    """``landscape serve`` in a process group of its own (its sweep workers die with it)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("LANDSCAPE_TOKEN", None)
    if token:
        env["LANDSCAPE_TOKEN"] = token  # not on the command line, where ps shows it
    with log.open("ab") as out:  # the child keeps its own descriptor
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
                "--workers",
                "1",
                "--log-level",
                "warning",
            ],
            cwd=ROOT,
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
    t0 = time.monotonic()
    while time.monotonic() - t0 < 60:
        try:
            _call(port, "GET", "/api/health", token=token)
            return proc
        except (urllib.error.URLError, ConnectionError):
            if proc.poll() is not None:
                raise AssertionError(f"server exited: {log.read_text()[-2000:]}") from None
            time.sleep(0.2)
    stop_server(proc)
    raise AssertionError("server did not start in 60 s")


def stop_server(proc: subprocess.Popen, sig=signal.SIGKILL) -> None:
    try:
        os.killpg(proc.pid, sig)
    except ProcessLookupError:
        pass
    proc.wait(timeout=30)


@pytest.mark.e2e  # a server process killed mid-sweep and a second one resuming it
def test_sweep_survives_a_server_crash(tmp_path):
    """Kill the server (and its workers) mid-sweep; the restarted server resumes the job, and the database ends
    with every trial of the sweep exactly once."""
    from sim.store import KEY_COLUMNS, TrialStore
    from sim.sweep import sweep_specs

    data, log = tmp_path / "data", tmp_path / "server.log"
    body = {"theta_w": "72,74", "theta_l": "20,30", "cv": "0", "trials": 3, "duration": 1.0, "dt": 1e-3}
    port = _free_port()
    proc = start_server(data, port, log)
    try:
        job = _call(port, "POST", "/api/sweeps", body)
        assert job["total"] == 12
        mid = _wait(lambda: _call(port, "GET", f"/api/sweeps/{job['id']}"), lambda j: j["done"] >= 2)
        assert mid["status"] == "running" and mid["done"] < 12, (
            "the sweep finished before the crash; make it longer"
        )
    finally:
        stop_server(proc)
    db = data / "sweeps" / job["id"] / "trials.sqlite"
    with TrialStore(db) as store:
        before = store.count()
    assert 2 <= before < 12
    port = _free_port()
    proc = start_server(data, port, log)
    try:
        done = _wait(
            lambda: _call(port, "GET", f"/api/sweeps/{job['id']}"), lambda j: j["status"] != "running"
        )
    finally:
        stop_server(proc, signal.SIGTERM)
    assert done["status"] == "done" and done["done"] == done["total"] == 12
    specs = sweep_specs([72, 74], [20, 30], [0], trials=3, duration_s=1.0, dt_s=1e-3)
    with TrialStore(db) as store:
        rows = store.rows()
    keys = [tuple(r[c] for c in KEY_COLUMNS) for r in rows]
    assert len(keys) == len(set(keys)) == 12
    assert set(keys) == {s.key() for s in specs}
