"""Long work as jobs: barrier maps (in memory, one at a time) and sweeps of self-righting trials (persisted).

A sweep job is a folder ``DATA/sweeps/ID/`` with ``job.json`` (the request and the status) and
``trials.sqlite``. One background thread runs the queued sweeps one after another with
:func:`sim.sweep.run_sweep` on the local process pool or the Dask scheduler the service was started with. A
sweep is resumable by construction (trials already in the database are skipped), so a server that stops or dies
mid-sweep picks it up on its next start: every job whose status is ``queued`` or ``running`` is queued again.
"""

from __future__ import annotations

import json
import logging
import math
import os
import queue
import threading
import time
import uuid
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

from geometry.bounds import JOINT_ANGLE_DEG_BOUNDS
from geometry.errors import UsageError
from sim import protocol

from .errors import NotFoundError, TooCostlyError

log = logging.getLogger(__name__)


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


class _Interrupted(Exception):
    """Raised from a progress callback to stop a job (cancelled, or the server stopping)."""


def _write_json(path: Path, data: dict) -> None:
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex}")
    tmp.write_text(json.dumps(data, indent=1))
    os.replace(tmp, path)


# ---------------------------------------------------------------------------------------------- barrier maps
@dataclass
class MapJob:
    """A barrier map running (or run) in the background."""

    id: str
    robot_id: str
    theta_w_deg: list[float]
    theta_l_deg: list[float]
    step_deg: float
    method: str
    total: int
    model: str | None = None
    wing_joints_deg: dict[float, dict[str, float]] | None = None
    done: int = 0
    status: str = "queued"
    rows: list | None = None
    error: str | None = None
    started: float | None = None
    finished: float | None = None
    cancel: threading.Event = field(default_factory=threading.Event)

    def public(self) -> dict:
        rate = eta = None
        if self.started is not None and self.done:
            rate = self.done / ((self.finished or time.monotonic()) - self.started)
            eta = (self.total - self.done) / rate if self.status == "running" else 0.0
        return {
            "id": self.id,
            "kind": "barrier-map",
            "robot": self.robot_id,
            "status": self.status,
            "done": self.done,
            "total": self.total,
            "rate_per_s": rate,
            "eta_s": eta,
            "error": self.error,
            "theta_w_deg": self.theta_w_deg,
            "theta_l_deg": self.theta_l_deg,
            "step_deg": self.step_deg,
            "method": self.method,
            "model_set": self.model,
            "wing_joints_deg": None
            if self.wing_joints_deg is None
            else [self.wing_joints_deg[w] for w in self.theta_w_deg],
            "rows": self.rows,
        }


class MapJobs:
    """Barrier maps over theta_w x theta_l: checked and estimated up front, small ones answered at once, large
    ones run as a job with progress. Each runs on a robot object of its own, so it never holds the interactive
    robot's lock."""

    def __init__(self, registry, *, limits, keep: int = 50):
        self.registry = registry
        self.limits = limits
        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="barrier-map")
        self.jobs: dict[str, MapJob] = {}
        self.keep = keep
        self._robots: dict[str, object] = {}

    def close(self) -> None:
        for j in self.jobs.values():
            j.cancel.set()
        self.pool.shutdown(wait=False, cancel_futures=True)

    def check(self, entry, ws: list[float], ls: list[float], step_deg: float, method: str) -> float:
        """Validate a map request; return its estimated run time, s (TooCostlyError over the limits)."""
        from landscape.barriers import method as barrier_method
        from landscape.grid import cells_per_turn

        from .landscapes import Landscapes

        if not entry.robot.has_joints:
            raise UsageError(
                f"robot {entry.id} has no joints; a barrier map varies theta_w and theta_l of a URDF robot"
            )
        n = len(ws) * len(ls)
        if n > self.limits.max_map_poses:
            raise TooCostlyError(
                f"a barrier map of {len(ws)} x {len(ls)} = {n:,} poses is over the limit of "
                f"{self.limits.max_map_poses:,}; use fewer theta_w or theta_l values"
            )
        barrier_method(method)
        cells_per_turn(step_deg)
        for w in ws:
            for x in ls:
                entry.robot.joint_values_rad(w, x)
        start_s = 0.003 * (max(abs(w) for w in ws) + len(ws) * max(abs(x) for x in ls))
        est = n * Landscapes.estimate_s(entry, step_deg) + start_s + n * 0.01
        if est > self.limits.max_map_s:
            raise TooCostlyError(
                f"this barrier map ({n:,} poses at step {step_deg:g} deg) would take about "
                f"{est:.0f} s; the limit is {self.limits.max_map_s:g} s: use fewer poses or a "
                "coarser step"
            )
        return est

    def start(
        self,
        entry,
        ws: list[float],
        ls: list[float],
        step_deg: float,
        method: str,
        *,
        model: str | None = None,
        wing_joints_deg: dict[float, dict[str, float]] | None = None,
    ) -> MapJob:
        """Queue a checked map; ``model`` names the shipped set whose wing joints per theta_w
        (:func:`.model_sets.map_wing_joints_deg`) pose the robot."""
        done = [k for k, j in self.jobs.items() if j.status in ("done", "failed", "cancelled")]
        for k in done[: max(0, len(self.jobs) - self.keep)]:
            del self.jobs[k]
        job = MapJob(
            uuid.uuid4().hex[:12],
            entry.id,
            ws,
            ls,
            float(step_deg),
            method,
            len(ws) * len(ls),
            model=model,
            wing_joints_deg=wing_joints_deg,
        )
        self.jobs[job.id] = job
        job.future = self.pool.submit(self._run, job)
        return job

    def get(self, job_id: str) -> MapJob:
        if job_id not in self.jobs:
            raise NotFoundError(
                f"unknown barrier-map job {job_id!r} (jobs are kept in memory until the server stops)"
            )
        return self.jobs[job_id]

    def _run(self, job: MapJob) -> None:
        from landscape.computation import barrier_map
        from landscape.viz import files

        if job.cancel.is_set():
            job.status = "cancelled"
            return
        job.status, job.started = "running", time.monotonic()

        def progress(k: int) -> None:
            job.done += k
            if job.cancel.is_set():
                raise _Interrupted

        try:
            robot = self._robots.get(job.robot_id)
            if robot is None:
                robot = self._robots[job.robot_id] = self.registry.fresh_robot(job.robot_id)
            from .model_sets import robot_for

            bm = barrier_map(
                robot_for(job.model, robot),
                job.theta_w_deg,
                job.theta_l_deg,
                step_deg=job.step_deg,
                method=job.method,
                progress=progress,
                wing_joints_deg=job.wing_joints_deg,
            )
            job.rows = files.barrier_map_rows(bm)
            job.status = "done"
        except _Interrupted:
            job.status = "cancelled"
        except UsageError as exc:
            job.status, job.error = "failed", str(exc).splitlines()[0]
        except Exception:
            log.exception("barrier-map job %s failed", job.id)
            job.status, job.error = "failed", "internal error (see the server log)"
        finally:
            job.finished = time.monotonic()


# ---------------------------------------------------------------------------------------------- sweeps
SWEEP_DEFAULTS = {
    "theta_w": "70,72,74,76",
    "theta_l": "20,30,40,50",
    "cv": "0,0.05,0.1,0.15,0.2,0.25",
    "phase": "0.7",
    "trials": 40,
    "wing_period": "2",
    "leg_period": "0.8",
    "attempts": 0,
    "duration": 10.0,
    "dt": None,
    "seed": 0,
    "robot": "builtin",
    "model": "paper",
    "engine": "pybullet",
}
"""The options of ``landscape sweep`` (same names, same defaults) that a sweep job takes; ``model`` only a
shipped model set's name, ``engine`` one of :data:`sim.engine.ENGINES` that is installed."""


SWEEP_BOUNDS = {
    "theta_w": (JOINT_ANGLE_DEG_BOUNDS, True),
    "theta_l": (JOINT_ANGLE_DEG_BOUNDS, True),
    "cv": (protocol.CV_BOUNDS, True),
    "phase": (protocol.PHASE_BOUNDS, True),
    "trials": (protocol.TRIALS_BOUNDS, False),
    "wing_period": (protocol.PERIOD_S_BOUNDS, True),
    "leg_period": (protocol.PERIOD_S_BOUNDS, True),
    "attempts": (protocol.ATTEMPTS_BOUNDS, False),
    "duration": (protocol.DURATION_S_BOUNDS, False),
    "dt": (protocol.DT_S_BOUNDS, False),
    "seed": (protocol.SEED_BOUNDS, False),
}
"""The range of each numeric option of a sweep job and whether it takes a list: those of ``landscape sweep``
(:mod:`sim.protocol`), in the same words. ``dt`` may be null (the robot's default)."""
SWEEP_TEXT = {"robot": "a robot id", "model": "a shipped model set's name", "engine": "pybullet or mujoco"}
"""The options of a sweep job that are not numbers."""


def checked_engine(engine) -> str:
    """A sweep request's ``engine``: the name of a known engine that is installed here.

    Raises
    ------
    sim.engine.EngineError
        If it is not a known engine's name (a number or null included) or its package is not installed here.
    """
    from sim.engine import ENGINES, EngineError, require_engine

    if not isinstance(engine, str):
        raise EngineError(f"engine must be one of {', '.join(ENGINES)}; got {engine!r}")
    require_engine(engine)
    return engine


@dataclass
class _Run:
    """Counters of the run in progress."""

    done: int
    total: int
    ran: int = 0
    started: float = field(default_factory=time.monotonic)
    cancel: threading.Event = field(default_factory=threading.Event)


class SweepJobs:
    """Persistent sweep jobs under ``root``, run one at a time by a background thread."""

    def __init__(
        self,
        root: Path,
        registry,
        *,
        limits,
        workers: int | None = None,
        scheduler: str | None = None,
        scrub=lambda s: s,
    ):
        self.root = Path(root)
        self.root.mkdir(parents=True, exist_ok=True)
        self.registry = registry
        self.limits = limits
        self.workers = workers
        self.scheduler = scheduler
        self.scrub = scrub
        self._queue: queue.Queue = queue.Queue()
        self._runs: dict[str, _Run] = {}
        self._lock = threading.Lock()
        self._report_lock = threading.Lock()
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None

    # ------------------------------------------------------------------ life cycle
    def start(self) -> list[str]:
        """Start the runner and queue every unfinished job (resumed where its database stands); return their ids."""
        resumed = []
        jobs = [self._read(d.name) for d in self.root.iterdir() if (d / "job.json").is_file()]
        for job in sorted(jobs, key=lambda j: j["created_utc"]):
            if job["status"] in ("queued", "running"):
                self._queue.put(job["id"])
                resumed.append(job["id"])
        self._thread = threading.Thread(target=self._runner, name="sweep-jobs", daemon=True)
        self._thread.start()
        if resumed:
            log.info("resuming sweep jobs %s", ", ".join(resumed))
        return resumed

    def stop(self, timeout_s: float = 30.0) -> None:
        """Stop the runner; a running sweep stays ``running`` in its job file and resumes on the next start."""
        self._stopping.set()
        with self._lock:
            for r in self._runs.values():
                r.cancel.set()
        self._queue.put(None)
        if self._thread is not None:
            self._thread.join(timeout_s)

    # ------------------------------------------------------------------ requests
    def specs(self, request: dict):
        """The trials of a request (:func:`sim.sweep.sweep_specs`), after checking what sweep_specs does not."""
        from sim.sweep import sweep_specs

        from .inputs import request_numbers
        from .model_sets import shipped_model_set

        # a job stored before an option existed takes its default
        r = request_numbers({**SWEEP_DEFAULTS, **request}, SWEEP_BOUNDS)
        model = r["model"]
        shipped_model_set(str(model))  # a name, never a file: null or a number is refused too
        engine = checked_engine(r["engine"])
        lists = {k: r[k] for k in ("theta_w", "theta_l", "cv", "phase", "wing_period", "leg_period")}
        trials = r["trials"]
        n = math.prod(len(v) for v in lists.values()) * trials
        if n > self.limits.max_sweep_trials:
            raise TooCostlyError(
                f"this sweep has {n:,} trials; a job may have at most "
                f"{self.limits.max_sweep_trials:,}: use fewer values or trials"
            )
        dur, dt = r["duration"], r["dt"]
        urdf = self.registry.urdf_path(r["robot"])
        return sweep_specs(
            lists["theta_w"],
            lists["theta_l"],
            lists["cv"],
            phase=lists["phase"],
            trials=trials,
            duration_s=float(dur),
            dt_s=None if dt is None else float(dt),
            robot=None if urdf is None else str(urdf),
            base_seed=r["seed"],
            wing_period_s=lists["wing_period"],
            leg_period_s=lists["leg_period"],
            attempts=r["attempts"],
            model_set=model,
            engine=engine,
        )

    def create(self, request: dict) -> dict:
        """Check a request, store it as a job and queue it; return the job's status."""
        unknown = sorted(set(request) - set(SWEEP_DEFAULTS))
        if unknown:
            raise UsageError(
                f"unknown sweep option {unknown[0]!r}; the options are {', '.join(SWEEP_DEFAULTS)}"
            )
        req = {**SWEEP_DEFAULTS, **request}
        req["robot"] = self.registry.resolve_id(str(req["robot"]))
        specs = self.specs(req)
        from .inputs import angle_warnings, request_numbers

        angles = request_numbers({k: req[k] for k in ("theta_w", "theta_l")}, SWEEP_BOUNDS)
        warnings = angle_warnings(self.registry.get(req["robot"]).robot, **angles)
        job_id = uuid.uuid4().hex[:12]
        d = self.root / job_id
        d.mkdir()
        from .model_sets import shipped_model_set

        job = {
            "id": job_id,
            "request": req,
            # the set as it is when the job is made (name, version, hash): a later version does not relabel it
            "model_set_label": shipped_model_set(str(req["model"])).with_engine(req["engine"]).label,
            "status": "queued",
            "error": None,
            "done": 0,
            "total": len(specs),
            "created_utc": _now(),
            "started_utc": None,
            "finished_utc": None,
            "warnings": warnings,
        }
        _write_json(d / "job.json", job)
        self._queue.put(job_id)
        return self.status(job_id)

    def list(self) -> list[dict]:
        ids = [d.name for d in self.root.iterdir() if (d / "job.json").is_file()]
        return sorted((self.status(i) for i in ids), key=lambda j: j["created_utc"])

    def status(self, job_id: str) -> dict:
        job = self._read(job_id)
        with self._lock:
            run = self._runs.get(job_id)
        rate = eta = None
        if run is not None and job["status"] == "running":
            job["done"], job["total"] = run.done, run.total
            elapsed = time.monotonic() - run.started
            if run.ran and elapsed > 0:
                rate = run.ran / elapsed
                eta = (run.total - run.done) / rate
        job.update(
            rate_per_s=rate,
            eta_s=eta,
            report_url=f"/api/sweeps/{job_id}/report",
            model_set=job["request"].get("model", SWEEP_DEFAULTS["model"]),
            engine=job["request"].get("engine", SWEEP_DEFAULTS["engine"]),  # stored before engines: pybullet
            model_set_label=job.get("model_set_label"),  # None for a job stored before labels were
            warnings=job.get("warnings", []),  # angles that look like radians (the command line's warnings)
        )
        return job

    def cancel(self, job_id: str) -> dict:
        with self._lock:
            job = self._read(job_id)  # as the runner last wrote it (unknown: NotFoundError)
            run = self._runs.get(job_id)
            if run is not None:
                run.cancel.set()
            if job["status"] in ("queued", "running"):
                job.update(status="cancelled", finished_utc=_now())
                _write_json(self.root / job_id / "job.json", job)
        return self.status(job_id)

    def report(self, job_id: str) -> Path:
        """The HTML report of a job's database (:func:`landscape.viz.sections.build_report`), rebuilt when the
        database has grown since the last one."""
        from landscape.viz.sections import build_report
        from sim.store import TrialStore

        job = self._read(job_id)
        d = self.root / job_id
        db = d / "trials.sqlite"
        if not db.is_file():
            raise NotFoundError(f"sweep {job_id} has no trials yet; wait until some finish")
        with self._report_lock:
            with TrialStore(db) as store:
                n = store.count()
            out = d / "report"
            stamp = out / ".trials"
            page = out / "index.html"
            if page.is_file() and stamp.is_file() and stamp.read_text() == str(n):
                return page
            urdf = self.registry.urdf_path(job["request"]["robot"])
            page, _ = build_report(db, out, robot=urdf)
            page.write_text(self.scrub(page.read_text()))
            stamp.write_text(str(n))
            return page

    # ------------------------------------------------------------------ running
    def _read(self, job_id: str) -> dict:
        p = self.root / job_id / "job.json"
        if not (job_id.isalnum() and p.is_file()):
            raise NotFoundError(f"unknown sweep job {job_id!r}; GET /api/sweeps lists them")
        return json.loads(p.read_text())

    def _set(self, job_id: str, **changes) -> dict:
        with self._lock:
            job = self._read(job_id)
            if job["status"] == "cancelled" and changes.get("status") not in (None, "cancelled"):
                return job
            job.update(changes)
            _write_json(self.root / job_id / "job.json", job)
            return job

    def _runner(self) -> None:
        while not self._stopping.is_set():
            job_id = self._queue.get()
            if job_id is None or self._stopping.is_set():
                return
            try:
                self._run(job_id)
            except Exception:  # a bug: keep the runner alive for the other jobs
                log.exception("sweep job %s failed", job_id)
                self._set(
                    job_id, status="failed", error="internal error (see the server log)", finished_utc=_now()
                )

    def _run(self, job_id: str) -> None:
        from sim.store import TrialStore
        from sim.sweep import run_sweep

        job = self._read(job_id)
        if job["status"] not in ("queued", "running"):
            return
        db = self.root / job_id / "trials.sqlite"
        try:
            specs = self.specs(job["request"])
        except UsageError as exc:  # e.g. the robot file is gone
            self._set(
                job_id, status="failed", error=self.scrub(str(exc).splitlines()[0]), finished_utc=_now()
            )
            return
        keys = {s.key() for s in specs}
        with TrialStore(db) as store:
            done = len(keys & store.done_keys())
        run = _Run(done, len(specs))
        with self._lock:  # a cancel or a stop that came while the specs were made must not be lost
            if self._stopping.is_set() or self._read(job_id)["status"] not in ("queued", "running"):
                return
            self._runs[job_id] = run
        self._set(
            job_id, status="running", done=done, total=len(specs), started_utc=job["started_utc"] or _now()
        )

        def on_result(row: dict) -> None:
            run.done += 1
            run.ran += 1
            if run.cancel.is_set():
                raise _Interrupted

        try:
            run_sweep(
                specs,
                db=db,
                workers=self.workers,
                scheduler=self.scheduler,
                progress=False,
                on_result=on_result,
            )
        except _Interrupted:
            pass
        except UsageError as exc:
            self._set(
                job_id, status="failed", error=self.scrub(str(exc).splitlines()[0]), finished_utc=_now()
            )
            return
        finally:
            with self._lock:
                self._runs.pop(job_id, None)
        with TrialStore(db) as store:
            done = len(keys & store.done_keys())
        if self._read(job_id)["status"] == "cancelled":
            self._set(job_id, done=done)
            return
        if done < len(specs):
            self._set(job_id, done=done)  # interrupted by the server stopping: resumed on the next start
            return
        self._set(job_id, status="done", done=done, finished_utc=_now())
