"""Sweeps of self-righting trials over (theta_w, theta_l, Cv, phi_1) with deterministic per-trial seeds, run on a
local process pool or a Dask distributed cluster (the same ``concurrent.futures`` code path: a
``ProcessPoolExecutor`` or ``distributed.Client.get_executor()``), stored in SQLite (:mod:`sim.store`).

Seeds: ``trial_seed`` hashes the trial's parameters (theta_w, theta_l, Cv, phi_1, trial index and a base seed)
with SHA-256, so a trial has the same noise whatever else is in the sweep, on any machine, and a resumed
sweep reruns nothing. The time step, duration and robot are part of the stored key but not of the seed, so the
same trial at another ``dt`` sees the same noise (common random numbers).

Resuming: trials whose key is already in the database are skipped. At most ``window`` trials (2 per worker)
are submitted at a time and each result is committed when it arrives, so an interrupted sweep loses at most
those in flight.

It is one concept, running a sweep (specs, seeds, the pool or cluster, resuming), hence its length.
"""

from __future__ import annotations

import hashlib
import itertools
import logging
import multiprocessing
import os
import sys
import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from geometry import JointMap
from geometry.errors import UsageError

from .actuation import Actuation
from .engine import DEFAULT_ENGINE, require_engine
from .model import default_robot_urdf, sim_model
from .protocol import (
    MAX_TRIALS,
    PAPER_LEG_PERIOD_S,
    PAPER_TRIALS,
    PAPER_WING_PERIOD_S,
)
from .store import KEY_COLUMNS, RESULT_COLUMNS, TrialStore
from .trial import (
    DEFAULT_DURATION_S,
    Trial,
    TrialInputError,
    check_trial_cost,
    default_dt_s,
    simulate_trial,
)
from .world import SimulationDiverged

log = logging.getLogger(__name__)


def package_version() -> str:
    try:
        return version("selfrighting-landscape")
    except PackageNotFoundError:  # pragma: no cover - running from a source tree
        return "unknown"


def trial_seed(
    theta_w_deg: float,
    theta_l_deg: float,
    cv: float,
    phase: float,
    trial: int,
    *,
    base_seed: int = 0,
    wing_period_s: float = PAPER_WING_PERIOD_S,
    leg_period_s: float = PAPER_LEG_PERIOD_S,
    attempts: int = 0,
) -> int:
    """Deterministic seed in [0, 2**63) of one trial, from its parameters.

    The periods and the attempt limit enter only when they differ from the paper's protocol (Tw 2 s, Tl 0.8 s,
    unlimited), so the paper sweep's seeds do not depend on them.

    Examples
    --------
    >>> trial_seed(74.0, 30.0, 0.1, 0.7, 3) == trial_seed(74, 30, 0.1, 0.7, 3)
    True
    >>> trial_seed(74.0, 30.0, 0.1, 0.7, 3) != trial_seed(74.0, 30.0, 0.1, 0.7, 4)
    True
    """
    text = f"{float(theta_w_deg)!r}|{float(theta_l_deg)!r}|{float(cv)!r}|{float(phase)!r}|{int(trial)}|{int(base_seed)}"
    if (float(wing_period_s), float(leg_period_s), int(attempts)) != (
        PAPER_WING_PERIOD_S,
        PAPER_LEG_PERIOD_S,
        0,
    ):
        text += f"|{float(wing_period_s)!r}|{float(leg_period_s)!r}|{int(attempts)}"
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:8], "big") >> 1


@dataclass(frozen=True)
class TrialSpec:
    """One trial of a sweep (everything a worker needs).

    ``robot_hash`` is ``geometry.Robot.robot_hash``: the robot's files and, when ``joints`` is not the default
    map, the joint map too, so the resume key tells apart the same URDF driven through different joints.
    ``joints`` is the joint map's text (``JointMap.text()``; "" for the default names). ``engine`` is the physics
    engine (:data:`sim.engine.ENGINES`); ``model_set_hash`` is the set's hash in that engine, so it travels to the
    workers (local or Dask) with the spec and keys the stored row.
    """

    theta_w_deg: float
    theta_l_deg: float
    cv: float
    phase: float
    trial: int
    seed: int
    duration_s: float
    dt_s: float
    robot: str
    robot_hash: str
    wing_period_s: float = PAPER_WING_PERIOD_S
    leg_period_s: float = PAPER_LEG_PERIOD_S
    attempts: int = 0
    joints: str = ""
    model_set: str = "paper"
    model_set_hash: str = ""
    engine: str = DEFAULT_ENGINE

    def joint_map(self) -> JointMap | None:
        """The joint map to simulate with (None: the robot's default joint names)."""
        return JointMap.parse(self.joints) if self.joints else None

    def key(self) -> tuple:
        """Primary key in ``sim.store.KEY_COLUMNS`` order."""
        return tuple(getattr(self, c) for c in KEY_COLUMNS)


def _sweep_grids(
    theta_w_deg, theta_l_deg, cv, phase, wing_period_s, leg_period_s, *, trials: int, attempts: int
) -> dict[str, list[float]]:
    """The sweep's value lists, checked: none empty, all finite, Cv >= 0, phases in [0, 1), the whole sweep
    within ``MAX_TRIALS``, and every (Tw, Tl, theta_w) an actuation cycle that fits its period."""
    grids = {
        "theta-w": [float(x) for x in theta_w_deg],
        "theta-l": [float(x) for x in theta_l_deg],
        "cv": [float(x) for x in cv],
        "phase": [float(x) for x in phase],
        "wing-period": [float(x) for x in wing_period_s],
        "leg-period": [float(x) for x in leg_period_s],
    }
    for name, vals in grids.items():
        if not vals:
            raise TrialInputError(f"--{name} is empty; the sweep needs at least one value")
        if not np.isfinite(vals).all():
            raise TrialInputError(f"--{name} values must be finite; got {vals}")
    if any(c < 0 for c in grids["cv"]):
        raise TrialInputError(f"--cv values must be >= 0; got {grids['cv']}")
    if any(not 0 <= p < 1 for p in grids["phase"]):
        raise TrialInputError(f"--phase values must be in [0, 1); got {grids['phase']}")
    if trials < 1:
        raise TrialInputError(f"--trials must be >= 1; got {trials}")
    n_trials = int(np.prod([len(v) for v in grids.values()], dtype=object)) * int(trials)
    if n_trials > MAX_TRIALS:
        raise TrialInputError(
            f"the sweep has {n_trials:,} trials, more than MAX_TRIALS = {MAX_TRIALS:,} (the "
            "paper's has 3,840); sweep fewer values or --trials, or split it into several sweeps"
        )
    if int(attempts) != attempts or attempts < 0:
        raise TrialInputError(f"--attempts must be a whole number >= 0 (0: no limit); got {attempts}")
    for tw_s, tl_s in itertools.product(grids["wing-period"], grids["leg-period"]):
        for tw_deg in grids["theta-w"]:
            try:
                Actuation(tw_deg, 0.0, wing_period_s=tw_s, leg_period_s=tl_s)
            except ValueError as exc:
                raise TrialInputError(f"--wing-period {tw_s:g} / --leg-period {tl_s:g}: {exc}") from None
    return grids


def _check_joint_ranges(grids: dict[str, list[float]], theta_limits_deg: dict) -> None:
    """Every theta_w and theta_l inside [0, the joints' upper limit] (trials open from closed)."""
    for name, key in (("theta-w", "theta_w"), ("theta-l", "theta_l")):
        lo, hi = theta_limits_deg[key]
        bad = [v for v in grids[name] if not (max(lo, 0.0) <= v <= hi)]
        if bad:
            raise TrialInputError(
                f"--{name} {bad[0]:g} is outside [{max(lo, 0.0):g}, {hi:g}] deg allowed by the robot's joints"
            )


def sweep_specs(
    theta_w_deg: Iterable[float],
    theta_l_deg: Iterable[float],
    cv: Iterable[float],
    *,
    phase: Iterable[float] = (0.7,),
    trials: int = PAPER_TRIALS,
    duration_s: float = DEFAULT_DURATION_S,
    dt_s: float | None = None,
    robot: str | Path | None = None,
    base_seed: int = 0,
    wing_period_s: Iterable[float] = (PAPER_WING_PERIOD_S,),
    leg_period_s: Iterable[float] = (PAPER_LEG_PERIOD_S,),
    attempts: int = 0,
    joint_map: JointMap | str | None = None,
    model_set: str | Path = "paper",
    engine: str = DEFAULT_ENGINE,
) -> list[TrialSpec]:
    """Every trial of a full-factorial sweep, in a fixed order.

    ``joint_map`` (a :class:`geometry.JointMap` or its text ``'wing=NAME,...;leg=NAME,...'``) names the joints
    theta_w and theta_l drive, for a robot whose joints are not named like the lab robot's; it is checked
    against the robot here and becomes part of every trial's ``robot_hash``.

    ``dt_s`` None takes the robot's default (:func:`sim.trial.default_dt_s`). ``wing_period_s`` (Tw) and
    ``leg_period_s`` (Tl) are swept too; ``attempts`` > 0 limits every trial to that
    many wing openings (1: single-attempt trials for the phase map). ``model_set`` names a shipped model
    parameter set or a TOML file (:func:`sim.model_set.load_model_set`); ``engine`` the physics engine
    (:data:`sim.engine.ENGINES`); the set's hash in that engine goes with every trial.

    Raises
    ------
    TrialInputError
        If a parameter list is empty, ``trials`` < 1 or a value is out of range.
    EngineError
        If the engine is unknown, not installed, or cannot express one of the set's modifiers.
    GeometryError
        If the robot cannot be loaded or the joint map does not fit it (``RobotDescriptionError``,
        ``UnknownJointError``; all are ValueError).
    """
    if isinstance(joint_map, str):
        joint_map = JointMap.parse(joint_map)
    require_engine(engine)
    grids = _sweep_grids(
        theta_w_deg, theta_l_deg, cv, phase, wing_period_s, leg_period_s, trials=trials, attempts=attempts
    )
    path = Path(robot) if robot is not None else default_robot_urdf()
    from .model_set import MODELS_DIR, load_model_set

    ms = load_model_set(model_set).with_engine(engine)
    # refuses a joint or part it lacks, every modifier's included
    model = sim_model(path, joint_map=joint_map, modifiers=ms.modifiers)
    joints = "" if joint_map is None or joint_map == JointMap() else joint_map.text()
    _check_joint_ranges(grids, model.theta_limits_deg)
    ms_ref = ms.name if Path(ms.source).parent == MODELS_DIR else str(Path(ms.source).resolve())
    robot_str = str(path.resolve())
    n_att = int(attempts)
    dt_s = default_dt_s(path, engine) if dt_s is None else dt_s
    return [
        TrialSpec(
            tw,
            tl,
            c,
            ph,
            k,
            trial_seed(
                tw, tl, c, ph, k, base_seed=base_seed, wing_period_s=wp, leg_period_s=lp, attempts=n_att
            ),
            float(duration_s),
            float(dt_s),
            robot_str,
            model.robot_hash,
            wp,
            lp,
            n_att,
            joints,
            ms_ref,
            ms.model_set_hash,
            engine,
        )
        for wp, lp, tw, tl, c, ph, k in itertools.product(
            grids["wing-period"],
            grids["leg-period"],
            grids["theta-w"],
            grids["theta-l"],
            grids["cv"],
            grids["phase"],
            range(trials),
        )
    ]


def run_spec(spec: TrialSpec) -> dict:
    """Run one trial (in a worker) and return its database row; a diverged trial is a row with status
    ``"diverged"``."""
    row = {c: getattr(spec, c) for c in KEY_COLUMNS}
    row.update(
        robot=spec.robot,
        version=package_version(),
        error=None,
        created_utc=datetime.now(timezone.utc).isoformat(timespec="seconds"),
        side=None,
        engine=spec.engine,
    )
    from .model_set import load_model_set

    ms = load_model_set(spec.model_set).with_engine(spec.engine)
    if spec.model_set_hash and ms.model_set_hash != spec.model_set_hash:
        raise RuntimeError(
            f"model set {spec.model_set} changed during the sweep (hash {ms.model_set_hash} != "
            f"{spec.model_set_hash}); restart the sweep"
        )
    row.update(model_set=ms.name, model_set_hash=ms.model_set_hash)
    try:
        act = ms.actuation(
            spec.theta_w_deg,
            spec.theta_l_deg,
            wing_period_s=spec.wing_period_s,
            leg_period_s=spec.leg_period_s,
        )
        trial = Trial(
            spec.theta_w_deg,
            spec.theta_l_deg,
            spec.phase,
            spec.cv,
            rng=spec.seed,
            duration_s=spec.duration_s,
            dt_s=spec.dt_s,
            robot=spec.robot,
            joint_map=spec.joint_map(),
            attempts=spec.attempts or None,
            actuation=act,
        )
        r = simulate_trial(trial, model_set=ms)
    except SimulationDiverged as exc:
        row.update(status="diverged", error=str(exc))
        return row
    d = r.to_dict()
    row.update({k: d[k] for k in RESULT_COLUMNS})
    row["success"] = int(r.success)
    row["side"] = r.side
    row["status"] = "ok"
    if r.robot_hash != spec.robot_hash:
        raise RuntimeError(
            f"robot file {spec.robot} changed during the sweep (hash {r.robot_hash} != "
            f"{spec.robot_hash}); restart the sweep"
        )
    return row


@dataclass(frozen=True)
class SweepSummary:
    """What a sweep did.

    Attributes
    ----------
    total, skipped, ran, diverged : int
        Distinct trials in the sweep (repeated specs count once), already in the database (at the start or stored
        by another sweep before this one reached them), stored now, and diverged among those stored.
    wall_s : float
        Wall-clock time of the run, s.
    trials_per_s : float
        ``ran / wall_s``.
    cpu_s : float
        Sum of the trials' own CPU time, s (every trial simulated, ``duplicates`` included).
    workers : int
        Worker processes (or Dask worker threads) used.
    db : str
    duplicates : int
        Trials simulated here whose row another sweep stored first (kept as it was; not counted in ``ran``).
    pool_restarts : int
        Times the local pool was recreated after a worker died (its unfinished trials were run again).
    """

    total: int
    skipped: int
    ran: int
    diverged: int
    wall_s: float
    trials_per_s: float
    cpu_s: float
    workers: int
    db: str
    duplicates: int = 0
    pool_restarts: int = 0


MAX_POOL_RESTARTS = 3
"""A local pool whose worker died (killed, out of memory) is recreated and its unfinished trials submitted again
at most this many times per sweep; then the sweep stops with :class:`SweepAborted`, its stored trials kept."""
PARENT_POLL_S = 0.5
"""How often a local worker checks that the sweep that started it is alive, s (it exits when it is not)."""


class SweepAborted(RuntimeError):
    """The sweep stopped before its end (workers kept dying, or a trial raised); the trials stored are kept and
    rerunning the same sweep resumes it."""


def _exit_with_parent(parent_pid: int) -> None:
    """Pool initializer: end this worker when the sweep process that started it dies (even by SIGKILL, which
    runs no cleanup), instead of waiting for work forever."""
    import threading

    def _watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(PARENT_POLL_S)
        os._exit(1)

    threading.Thread(target=_watch, name="exit-with-parent", daemon=True).start()


def _local_executor(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_exit_with_parent,
        initargs=(os.getpid(),),
    )


def _stop_local(executor: ProcessPoolExecutor, *, wait_s: float = 10.0) -> None:
    """Stop a local pool at once (error path): cancel queued trials, terminate the workers, reap them."""
    procs = list((getattr(executor, "_processes", None) or {}).values())
    executor.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        if proc.is_alive():
            proc.terminate()
    for proc in procs:
        proc.join(wait_s)
        if proc.is_alive():
            proc.kill()
            proc.join(wait_s)
    executor.shutdown(wait=True)


def _unique(specs: Sequence[TrialSpec]) -> list[TrialSpec]:
    """The specs with a repeated key dropped (first kept), in order."""
    seen: dict[tuple, TrialSpec] = {}
    for s in specs:
        seen.setdefault(s.key(), s)
    return list(seen.values())


def _check_sweep_cost(specs: Sequence[TrialSpec]) -> None:
    """Refuse a sweep larger than ``MAX_TRIALS`` or with a trial over the bounds of :func:`sim.trial.run_trial`
    before anything runs."""
    if len(specs) > MAX_TRIALS:
        raise TrialInputError(
            f"the sweep has {len(specs):,} trials, more than MAX_TRIALS = {MAX_TRIALS:,} (the "
            "paper's has 3,840); sweep fewer values or --trials, or split it into several sweeps"
        )
    for duration_s, dt_s, robot, joints in sorted({(s.duration_s, s.dt_s, s.robot, s.joints) for s in specs}):
        jm = sim_model(robot, joint_map=JointMap.parse(joints) if joints else None).joint_map
        check_trial_cost(duration_s, dt_s, n_joints=len(jm.wing) + len(jm.leg))


def run_sweep(
    specs: Sequence[TrialSpec],
    *,
    db: str | Path,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    on_result: Callable[[dict], None] | None = None,
) -> SweepSummary:
    """Run the trials of ``specs`` that are not yet in ``db``, storing each as it finishes.

    Repeated specs run once. Every bound is checked and the database opened (and its robot hashes compared)
    before the first trial starts. A local worker that dies (killed, out of memory) costs only time: the pool is
    recreated and its unfinished trials submitted again, at most ``MAX_POOL_RESTARTS`` times. At the end the
    workers are waited for (local) or the client closed and waited for (Dask), so no process is left behind;
    a local worker also exits by itself when the sweep's process dies.

    Parameters
    ----------
    specs : sequence of TrialSpec
        From :func:`sweep_specs`.
    db : path
        SQLite database (created if absent; see :class:`sim.store.TrialStore`).
    workers : int, optional
        Local worker processes (default: all cores). Ignored with ``scheduler``.
    scheduler : str, optional
        Address of a Dask distributed scheduler (``tcp://HOST:PORT``); the trials run on its workers.
    progress : bool
        Show a tqdm progress bar (rate and ETA) on stderr when stderr is a terminal.
    on_result : callable, optional
        Called with each newly stored row (after its commit).

    Returns
    -------
    SweepSummary

    Raises
    ------
    TrialInputError
        If there are no trials, more than ``MAX_TRIALS``, a trial over the bounds of :func:`sim.trial.run_trial`,
        or ``workers`` < 1.
    StoreError
        If ``db`` is not a writable trial store, holds trials of another engine or model set, or a robot file
        changed since it was swept into ``db`` (:class:`sim.store.RobotChangedError`).
    EngineError
        If the specs' engine is not installed.
    SweepAborted
        If local workers died more than ``MAX_POOL_RESTARTS`` times, or a trial raised on a worker; the trials
        stored until then are kept.
    """
    if not specs:
        raise TrialInputError("the sweep has no trials; give at least one value per parameter")
    engines = sorted({s.engine for s in specs})
    if len(engines) > 1:
        raise TrialInputError(
            f"the sweep mixes engines ({', '.join(engines)}); sweep each engine into its own --db"
        )
    require_engine(engines[0])
    specs = _unique(specs)
    _check_sweep_cost(specs)
    if not scheduler:
        n_workers = int(workers or os.cpu_count() or 1)
        if n_workers < 1:
            raise TrialInputError(f"--workers must be >= 1; got {workers}")
    t0 = time.perf_counter()
    with TrialStore(db) as store:
        for robot, robot_hash in sorted({(s.robot, s.robot_hash) for s in specs}):
            store.check_robot(robot, robot_hash)
        store.check_engine(engines[0])
        for name, ms_hash in sorted({(s.model_set, s.model_set_hash) for s in specs}):
            store.check_model_set(name, ms_hash)
        done = store.done_keys()
        todo = [s for s in specs if s.key() not in done]
        run = _Sweep(store, str(db), on_result, skipped=len(specs) - len(todo))
        client = None
        ok = False
        try:
            if scheduler:
                from distributed import Client

                client = Client(scheduler, timeout="30s", set_as_default=False)
                run.executor = client.get_executor(pure=False)
                n_workers = max(1, sum(client.nthreads().values()))
            elif todo:
                run.executor = _local_executor(n_workers)
            if progress:
                run.bar = _progress_bar(len(specs), run.skipped)
            run.loop(todo, window=2 * n_workers, new_pool=lambda: _local_executor(n_workers))
            ok = True
        finally:
            run.close(client, ok)
    wall = time.perf_counter() - t0
    return SweepSummary(
        len(specs),
        run.skipped,
        run.ran,
        run.diverged,
        wall,
        run.ran / wall if wall > 0 else 0.0,
        run.cpu,
        n_workers,
        str(db),
        run.duplicates,
        run.restarts,
    )


def _progress_bar(total: int, initial: int):
    from tqdm import tqdm

    # disable=None: no bar when stderr is not a terminal (a redirected log gets no bar frames)
    return tqdm(
        total=total,
        initial=initial,
        unit="trial",
        dynamic_ncols=True,
        smoothing=0.05,
        file=sys.stderr,
        disable=None,
    )


class _Sweep:
    """One :func:`run_sweep` in progress: the store, the executor, the progress bar and the counts."""

    def __init__(self, store: TrialStore, db: str, on_result: Callable[[dict], None] | None, *, skipped: int):
        self.store, self.db, self.on_result = store, db, on_result
        self.executor = self.bar = None
        self.skipped = skipped
        self.ran = self.diverged = self.duplicates = self.restarts = 0
        self.cpu = 0.0

    def loop(
        self, todo: Sequence[TrialSpec], *, window: int, new_pool: Callable[[], ProcessPoolExecutor]
    ) -> None:
        """Keep ``window`` trials in flight until every trial of ``todo`` is stored; a dead local worker costs
        a new pool and the resubmission of its unfinished trials."""
        queue = deque(todo)
        pending: dict[Future, TrialSpec] = {}
        while True:
            broken = self._submit(queue, pending, window)
            if not pending and not broken:
                return
            finished = wait(pending, return_when=FIRST_COMPLETED)[0] if pending else set()
            if broken or any(isinstance(f.exception(), BrokenProcessPool) for f in finished):
                # a worker died: every unfinished future of this pool fails; keep the results that came in
                # and submit the rest again to a new pool
                wait(pending)
                finished = set(pending)
                broken = True
            for fut in finished:
                self._collect(fut, pending.pop(fut), queue)
            if broken:
                self._restart(queue, new_pool)

    def _submit(self, queue: deque, pending: dict, window: int) -> bool:
        """Fill the window; True if the pool broke while submitting."""
        while len(pending) < window and queue:
            spec = queue.popleft()
            if self.store.has(spec.key()):  # stored meanwhile by another sweep on this database
                self.skipped += 1
                self._tick()
                continue
            try:
                pending[self.executor.submit(run_spec, spec)] = spec
            except BrokenProcessPool:
                queue.appendleft(spec)
                return True
        return False

    def _collect(self, fut: Future, spec: TrialSpec, queue: deque) -> None:
        exc = fut.exception()
        if isinstance(exc, BrokenProcessPool):
            queue.appendleft(spec)
            return
        if isinstance(exc, UsageError):  # the spec's own input refused on the worker (e.g. an unstable set)
            raise exc
        if exc is not None:
            raise SweepAborted(
                f"trial (theta_w {spec.theta_w_deg:g}, theta_l {spec.theta_l_deg:g}, cv {spec.cv:g}, "
                f"phase {spec.phase:g}, trial {spec.trial}) failed on a worker ({type(exc).__name__}: "
                f"{(str(exc).splitlines() or [''])[0]}); the {self.store.count()} trials in "
                f"'{self.db}' are kept: fix the cause and rerun the same sweep to resume"
            ) from exc
        row = fut.result()
        self.cpu += row.get("cpu_s") or 0.0
        if not self.store.add(row):
            self.duplicates += 1
            self.skipped += 1
        else:
            self.ran += 1
            self.diverged += row["status"] == "diverged"
            if self.on_result is not None:
                self.on_result(row)
        self._tick()

    def _restart(self, queue: deque, new_pool: Callable[[], ProcessPoolExecutor]) -> None:
        self.restarts += 1
        self.executor.shutdown(wait=True)
        self.executor = None
        if self.restarts > MAX_POOL_RESTARTS:
            raise SweepAborted(
                f"worker processes died {self.restarts} times (killed, or out of memory?); the "
                f"{self.store.count()} trials in '{self.db}' are kept: rerun the same sweep to resume "
                "(with fewer --workers if memory ran out)"
            )
        log.warning(
            "a worker process died; restarting the pool and running its %d unfinished trials again (%d/%d)",
            len(queue),
            self.restarts,
            MAX_POOL_RESTARTS,
        )
        self.executor = new_pool()

    def _tick(self) -> None:
        if self.bar is not None:
            self.bar.update(1)

    def close(self, client, ok: bool) -> None:
        """Close the bar; wait for the workers (local) or the client (Dask), or stop them after an error."""
        if self.bar is not None:
            self.bar.close()
        if client is not None:
            if self.executor is not None:
                self.executor.shutdown(wait=ok)  # no future is left on success; on error cancel the rest
            client.close(timeout=30)
        elif self.executor is not None:
            if ok:
                self.executor.shutdown(wait=True)
            else:
                _stop_local(self.executor)


def stored_rows(db: str | Path, specs: Iterable[TrialSpec]) -> list[dict]:
    """The stored rows of these specs' trials (by their keys), in the database's order.

    Parameters
    ----------
    db : path
        The sweep's SQLite file.
    specs : iterable of TrialSpec
        The trials asked for; rows of other trials in the same database are left out.
    """
    from .store import read_rows

    keys = {s.key() for s in specs}
    return [r for r in read_rows(db) if tuple(r[c] for c in KEY_COLUMNS) in keys]


def success_table(rows: Iterable[dict]) -> dict[tuple[float, float, float], tuple[int, int]]:
    """(theta_w, theta_l, Cv) -> (successes, trials) over stored rows with status ``ok`` (pooled over every other
    parameter: pass the rows of one protocol)."""
    out: dict[tuple[float, float, float], list[int]] = {}
    for r in rows:
        if r["status"] != "ok":
            continue
        k = (r["theta_w_deg"], r["theta_l_deg"], r["cv"])
        acc = out.setdefault(k, [0, 0])
        acc[0] += int(bool(r["success"]))
        acc[1] += 1
    return {k: (v[0], v[1]) for k, v in sorted(out.items())}
