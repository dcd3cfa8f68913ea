"""Landscape answers: validated, estimated, computed in a thread pool by :func:`landscape.computation.compute`,
and cached by (robot hash, theta_w, theta_l, method, step, model set, wing joints) in a bounded in-memory LRU
and on disk.

Two requests for the same answer share one computation; a request still waiting at its time limit answers 503
and the computation finishes into the cache. A robot is posed by one thread at a time (posing moves the shared
URDF model), so different robots compute in parallel and one robot's requests queue.

The start orientation of a robot with joints is the quasi-static continuation of a slow opening from rest
(:func:`landscape.minima.metastable_orientation`). :class:`StartMemo` keeps the states along the continuation
paths already walked, so a slider that moves theta_w by one degree costs one descent, not seventy.
"""

from __future__ import annotations

import asyncio
import hashlib
import json
import logging
import math
import os
import shutil
import threading
import time
import uuid
from collections import OrderedDict
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from geometry.bounds import Bounds
from geometry.errors import UsageError

from .errors import TimeLimitError, TooCostlyError

log = logging.getLogger(__name__)

CACHE_FORMAT = 2
MAX_SAMPLES = 1000
"""Most Monte-Carlo samples one landscape request may ask for (each recomputes every barrier)."""
SERVICE_SAMPLES_BOUNDS = Bounds(1, MAX_SAMPLES, integer=True, meaning="a count of Monte-Carlo samples")
"""``samples`` of ``/api/landscape``: fewer than the command line takes, a server's answer being shared."""
DEFAULT_SECONDS_PER_CELL = 1e-6
"""Cost guess of one grid cell (landscape + barrier), s, until a robot's first computation measures its own."""


class StartMemo:
    """The metastable start orientation of one robot, remembering the continuation states already computed.

    :func:`landscape.minima.metastable_orientation` follows the local minimum along
    :func:`landscape.minima.opening_path` with :func:`landscape.minima.follow_minimum`, each step starting where the
    last ended. The memo keeps every state reached, in a trie keyed by the path's points, and resumes a new path
    from its longest walked prefix: the same descents in the same order, so the same answer.

    Not thread-safe: call it under the robot's lock.
    """

    def __init__(self, robot, *, max_nodes: int = 200_000):
        self.robot = robot
        self.max_nodes = max_nodes
        self._root: dict = {}
        self._nodes = 0

    def start_deg(self, theta_w_deg: float, theta_l_deg: float) -> tuple[float, float]:
        """(pitch, roll) where the robot rests after opening slowly to (theta_w, theta_l), degrees."""
        from landscape.minima import follow_minimum, opening_path

        self.robot.joint_values_rad(theta_w_deg, theta_l_deg)  # validate before the walk
        path = opening_path(theta_w_deg, theta_l_deg)
        if self._nodes > self.max_nodes:
            self._root, self._nodes = {}, 0
        children, state, i = self._root, (0.0, 0.0), 0
        while i < len(path) and path[i] in children:
            state, children = children[path[i]]
            i += 1
        rest = path[i:]
        for point, st in zip(
            rest, follow_minimum(self.robot, rest, pitch_deg=state[0], roll_deg=state[1]), strict=True
        ):
            node = (st, {})
            children[point] = node
            state, children = node
            self._nodes += 1
        return state


@dataclass
class Answer:
    """One cached landscape answer.

    Attributes
    ----------
    summary : dict
        :func:`landscape.viz.files.summary` (with the barrier paths).
    energy_j : ndarray of shape (N, N)
        The landscape on the torus, J.
    step_deg, mass_kg, g_m_s2 : float
    computation : Computation or None
        The computation itself while it is in memory (for file downloads).
    """

    summary: dict
    energy_j: np.ndarray
    step_deg: float
    mass_kg: float
    g_m_s2: float
    computation: object = None
    _bodies: dict = field(default_factory=dict, repr=False)

    @property
    def nbytes(self) -> int:
        return int(self.energy_j.nbytes * 2 + sum(len(b) for b in self._bodies.values()) + 4096)

    def body(self, *, grid: bool) -> bytes:
        """The JSON answer: ``landscape compute --json`` plus the barrier ``paths``; with ``grid`` the energy
        grid in mJ (-180..180 inclusive) and g."""
        if grid not in self._bodies:
            d = dict(self.summary)
            if grid:
                from landscape.energy import Landscape
                from landscape.grid import torus_angles_deg

                ls = Landscape(
                    self.step_deg, torus_angles_deg(self.step_deg), self.energy_j, self.mass_kg, self.g_m_s2
                )
                angles, energy = ls.inclusive()
                d["grid"] = {
                    "pitch_deg": angles.tolist(),
                    "roll_deg": angles.tolist(),
                    "energy_mj": np.round(energy * 1e3, 6).tolist(),
                    "g_m_s2": self.g_m_s2,
                }
            self._bodies[grid] = json.dumps(d).encode()
        return self._bodies[grid]


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("selfrighting-landscape")
    except PackageNotFoundError:  # pragma: no cover - a source tree
        return "unknown"


class ResultCache:
    """Answers by key: a bounded in-memory LRU in front of a directory (``root/v<format>-<version>/<hash>/``)."""

    def __init__(self, root: Path, *, max_bytes: int):
        self.root = Path(root) / f"v{CACHE_FORMAT}-{_version()}"
        self.root.mkdir(parents=True, exist_ok=True)
        self.max_bytes = max_bytes
        self._mem: OrderedDict[tuple, Answer] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()
        self.hits = {"memory": 0, "disk": 0, "miss": 0}

    def _dir(self, key: tuple) -> Path:
        return self.root / key[0] / hashlib.sha256(repr(key).encode()).hexdigest()[:24]

    def get(self, key: tuple) -> Answer | None:
        with self._lock:
            a = self._mem.get(key)
            if a is not None:
                self._mem.move_to_end(key)
                self.hits["memory"] += 1
                return a
        d = self._dir(key)
        try:
            summary = json.loads((d / "summary.json").read_text())
            energy = np.load(d / "energy_j.npy", allow_pickle=False)
        except (OSError, ValueError):
            with self._lock:
                self.hits["miss"] += 1
            return None
        meta = summary.pop("_cache")
        a = Answer(summary, energy, meta["step_deg"], meta["mass_kg"], meta["g_m_s2"])
        self._remember(key, a)
        with self._lock:
            self.hits["disk"] += 1
        return a

    def put(self, key: tuple, answer: Answer) -> None:
        self._remember(key, answer)
        d = self._dir(key)
        if (d / "summary.json").is_file():
            return
        tmp = d.parent / f".tmp-{uuid.uuid4().hex}"
        try:
            tmp.mkdir(parents=True)
            np.save(tmp / "energy_j.npy", answer.energy_j, allow_pickle=False)
            meta = {"step_deg": answer.step_deg, "mass_kg": answer.mass_kg, "g_m_s2": answer.g_m_s2}
            (tmp / "summary.json").write_text(json.dumps({**answer.summary, "_cache": meta}))
            os.rename(tmp, d)
        except OSError:  # another thread stored it first, or the disk is full: the memory copy serves
            shutil.rmtree(tmp, ignore_errors=True)

    def _remember(self, key: tuple, answer: Answer) -> None:
        with self._lock:
            old = self._mem.pop(key, None)
            if old is not None:
                self._bytes -= old.nbytes
            self._mem[key] = answer
            self._bytes += answer.nbytes
            while self._bytes > self.max_bytes and len(self._mem) > 1:
                _, a = self._mem.popitem(last=False)
                self._bytes -= a.nbytes


class Landscapes:
    """Validated, estimated, cached landscape answers of the robots of a registry."""

    def __init__(self, registry, cache: ResultCache, *, limits, threads: int = 4):
        self.registry = registry
        self.cache = cache
        self.limits = limits
        self.pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="landscape")
        self._inflight: dict[tuple, Future] = {}
        self._lock = threading.Lock()

    def close(self) -> None:
        self.pool.shutdown(wait=False, cancel_futures=True)

    def check(
        self,
        entry,
        theta_w_deg: float,
        theta_l_deg: float,
        method: str,
        step_deg: float,
        *,
        model: str | None = None,
        uncertainty=None,
    ) -> tuple:
        """Validate a request and return its cache key; UsageError (or TooCostlyError) for bad or costly input.

        ``model`` names a shipped model set that poses the wings (:func:`.model_sets.set_wing_joints_deg`) and may
        move the CoM; the key holds it, the wing joints' angles it gives and its hash (so a set whose content
        changes is not answered from a cached landscape of its old content). ``uncertainty``
        (:class:`landscape.uncertainty.Uncertainty`) adds each barrier's interval; the key holds it."""
        from landscape.barriers import method as barrier_method
        from landscape.grid import cells_per_turn

        from .model_sets import set_wing_joints_deg, shipped_model_set

        for name, v in (("theta_w", theta_w_deg), ("theta_l", theta_l_deg), ("step", step_deg)):
            if not math.isfinite(v):
                raise UsageError(f"{name} must be a finite number of degrees; got {v!r}")
        barrier_method(method)
        n = cells_per_turn(step_deg)
        cells = n * n
        if cells > self.limits.max_cells:
            smallest = 360.0 / math.isqrt(self.limits.max_cells)
            raise TooCostlyError(
                f"step {step_deg:g} deg means {cells:,} grid cells ({n} x {n}); the service computes "
                f"at most {self.limits.max_cells:,} (step >= {smallest:g} deg): use a coarser step"
            )
        est = self.estimate_s(entry, step_deg)
        if est > self.limits.max_request_s:
            raise TooCostlyError(
                f"step {step_deg:g} deg on robot {entry.id} would take about {est:.0f} s "
                f"({cells:,} cells); the limit is {self.limits.max_request_s:g} s: use a coarser step"
            )
        if entry.robot.has_joints:
            entry.robot.joint_values_rad(theta_w_deg, theta_l_deg)
            tw, tl = float(theta_w_deg), float(theta_l_deg)
        else:
            tw = tl = None
        ms = shipped_model_set(model)
        joints = set_wing_joints_deg(ms, entry.robot, theta_w_deg)
        joints_key = None if joints is None else tuple(joints.items())
        set_hash = ms.model_set_hash if ms is not None else None
        unc = None
        if uncertainty is not None:
            uncertainty.check()
            if (uncertainty.samples or 0) > MAX_SAMPLES:
                raise TooCostlyError(
                    f"samples = {uncertainty.samples} recomputes every barrier that often; the service takes at "
                    f"most {MAX_SAMPLES}: ask for fewer"
                )
            unc = (uncertainty.com_m, uncertainty.mass_kg, uncertainty.samples, uncertainty.seed)
        return (
            entry.robot.description_hash,
            tw,
            tl,
            method,
            float(step_deg),
            model,
            joints_key,
            set_hash,
            unc,
        )

    @staticmethod
    def estimate_s(entry, step_deg: float) -> float:
        """Estimated run time of one landscape, s: grid cells times the robot's measured cost per cell."""
        from landscape.grid import cells_per_turn

        n = cells_per_turn(step_deg)
        return n * n * (entry.seconds_per_cell or DEFAULT_SECONDS_PER_CELL)

    async def answer(self, entry, key: tuple, *, need_computation: bool = False) -> Answer:
        """The answer of a checked key, from the cache or computed (waiting at most the request time limit)."""
        if not need_computation:
            a = self.cache.get(key)
            if a is not None:
                return a
        fut = self.submit(entry, key, need_computation=need_computation)
        try:
            return await asyncio.wait_for(
                asyncio.shield(asyncio.wrap_future(fut)), self.limits.request_timeout_s
            )
        except asyncio.TimeoutError:
            raise TimeLimitError(
                f"still computing after {self.limits.request_timeout_s:g} s; the answer will be "
                "cached when done: retry later"
            ) from None

    def submit(self, entry, key: tuple, *, need_computation: bool = False) -> Future:
        """Start (or join) the computation of a key in the thread pool."""
        with self._lock:
            fut = self._inflight.get(key)
            if fut is not None:
                return fut
            fut = self.pool.submit(self._compute, entry, key, need_computation)
            self._inflight[key] = fut
        # outside the lock: a future that is already done runs the callback here at once, and _forget takes the
        # lock (a computation that failed at once used to deadlock the request)
        fut.add_done_callback(lambda _f, k=key: self._forget(k))
        return fut

    def _forget(self, key: tuple) -> None:
        with self._lock:
            self._inflight.pop(key, None)

    def _compute(self, entry, key: tuple, need_computation: bool) -> Answer:
        from landscape.computation import compute
        from landscape.viz import files

        a = None if need_computation else self.cache.get(key)
        if a is not None:
            return a
        from .model_sets import robot_for

        _, tw, tl, method, step, model, joints_key, _, unc = key
        joints = None if joints_key is None else dict(joints_key)
        robot = robot_for(model, entry.robot)  # a set may move the CoM, as `landscape compute --model` does
        with entry.lock:
            start = None
            if robot is entry.robot and robot.has_joints and joints is None:
                if entry.starts is None:
                    entry.starts = StartMemo(entry.robot)
                start = entry.starts.start_deg(tw, tl)
            # with wing joints of their own, compute finds the start as `landscape compute --model` does
            c = compute(
                robot,
                theta_w_deg=tw,
                theta_l_deg=tl,
                step_deg=step,
                method=method,
                start_deg=start,
                wing_joints_deg=joints,
            )
            change = None
            if robot is not entry.robot:  # the set moves the CoM: its effect, as `landscape compute --model`
                from landscape.uncertainty import com_change

                plain = compute(
                    entry.robot,
                    theta_w_deg=tw,
                    theta_l_deg=tl,
                    step_deg=step,
                    method=method,
                    wing_joints_deg=joints,
                )
                change = com_change(plain, c)
        if unc is not None:
            from landscape.uncertainty import Uncertainty, with_intervals

            c = with_intervals(c, Uncertainty(*unc))
        s = files.summary(
            c,
            robot_name=entry.robot.name,
            robot_source=entry.info.get("filename") or entry.id,
            robot_hash=robot.description_hash,
            com_source=robot.com_source,
        )
        if model is not None:  # as `landscape compute --model NAME --json`
            s = dict(s) | {"model_set": model, "wing_joints_deg": joints}
        if change is not None:
            s = s | {"model_set_change": change.to_dict()}
        cells = c.landscape.energy_j.size
        per_cell = (c.timing_s["landscape"] + c.timing_s["barrier"]) / cells
        prev = entry.seconds_per_cell
        entry.seconds_per_cell = per_cell if prev is None else 0.7 * prev + 0.3 * per_cell
        a = Answer(s, c.landscape.energy_j, c.step_deg, c.mass_kg, c.landscape.g_m_s2, c)
        t0 = time.perf_counter()
        self.cache.put(key, a)
        log.debug("stored %s in %.1f ms", key, (time.perf_counter() - t0) * 1e3)
        return a
