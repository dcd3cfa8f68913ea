"""What a service instance is given: where it keeps its data, where sweeps run, who may call it, its limits."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1", "[::1]")


@dataclass(frozen=True)
class Limits:
    """Bounds that keep one request from taking the service down.

    Attributes
    ----------
    max_upload_bytes : int
        Largest request body of an upload, bytes.
    max_unzipped_bytes, max_zip_entries : int
        Largest total size of a zip's files once extracted, bytes, and most entries in it.
    max_vertices : int
        Most mesh vertices in one robot (all its meshes together).
    max_cells : int
        Most pitch-roll grid cells of one landscape ((360 / step)^2; 2,073,600 is step 0.25 deg).
    max_request_s : float
        Longest estimated run time of one landscape request, s; over it the request is refused with the estimate.
    request_timeout_s : float
        A landscape request still computing after this long answers 503; the result lands in the cache.
    sync_map_s, max_map_s : float
        Barrier maps estimated to finish within ``sync_map_s`` are answered at once, those within ``max_map_s``
        run as a job with progress, longer ones are refused, s.
    max_map_poses : int
        Most (theta_w, theta_l) poses of one barrier map.
    max_sweep_trials : int
        Most trials of one sweep job.
    memory_cache_bytes : int
        Size of the in-memory LRU of landscape answers (energy grids), bytes.
    """

    max_upload_bytes: int = 50 * 2**20
    max_unzipped_bytes: int = 200 * 2**20
    max_zip_entries: int = 500
    max_vertices: int = 500_000
    max_cells: int = 1440 * 1440
    max_request_s: float = 30.0
    request_timeout_s: float = 60.0
    sync_map_s: float = 5.0
    max_map_s: float = 3600.0
    max_map_poses: int = 10_000
    max_sweep_trials: int = 1_000_000
    memory_cache_bytes: int = 256 * 2**20


@dataclass(frozen=True)
class ServiceConfig:
    """One service instance.

    Attributes
    ----------
    data_dir : Path
        Uploads, the landscape cache, sweep jobs and their databases live here (survive restarts).
    workers : int or None
        Local worker processes of sweeps (None: all cores).
    scheduler : str or None
        Dask scheduler address ``tcp://HOST:PORT`` that runs the sweeps instead.
    token : str or None
        When set, every ``/api`` request must send ``Authorization: Bearer TOKEN``.
    allowed_hosts : tuple of str or None
        Host names the ``Host`` header may carry (guards a localhost service against DNS rebinding); None: any.
    compute_threads : int
        Threads that run landscape computations.
    limits : Limits
    """

    data_dir: Path
    workers: int | None = None
    scheduler: str | None = None
    token: str | None = None
    allowed_hosts: tuple[str, ...] | None = None
    compute_threads: int = 4
    limits: Limits = field(default_factory=Limits)
