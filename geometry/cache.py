"""The per-user disk cache of parsed robots: each link's hull vertices, mesh points and mass properties and the
joints, so a later load of the same description reads no mesh.

A cached file is ``robot-<description hash>-<code key>.npz`` (plain arrays, no pickles). The code key covers the
source of every module that builds a robot from its files and the versions of the libraries that load meshes and
take hulls, so a change to either misses old files rather than misreading them.
"""

from __future__ import annotations

import hashlib
import logging
import os
from functools import cache, lru_cache
from pathlib import Path

import numpy as np

from .kinematics import JointSpec
from .mass import MassProperties
from .pose import Part

log = logging.getLogger(__name__)

ROBOT_CACHE_VERSION = "1"
_SOURCES = ("robot.py", "pose.py", "kinematics.py", "meshes.py", "cache.py", "hull.py", "mass.py", "urdf.py")
"""The modules (in this package) whose source is part of the code key."""


def robot_cache_dir() -> Path | None:
    """Where :meth:`geometry.robot.Robot.from_urdf` keeps parsed robots: ``$LANDSCAPE_CACHE/robots`` or
    ``~/.cache/selfrighting-landscape/robots``; None (no cache) when ``LANDSCAPE_CACHE`` is ``off``."""
    env = os.environ.get("LANDSCAPE_CACHE")
    if env == "off":
        return None
    return (Path(env) if env else Path.home() / ".cache" / "selfrighting-landscape") / "robots"


def _payload_digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for key in sorted(arrays):
        if key == "payload_sha256":
            continue
        a = np.ascontiguousarray(arrays[key])
        h.update(f"{key}\0{a.dtype.str}\0{a.shape}\0".encode())
        h.update(a.tobytes())
    return h.hexdigest()


@cache
def installed_version(dist: str) -> str:
    """Version of an installed distribution from its ``*.dist-info`` directory name on ``sys.path`` (a directory
    listing, not ``importlib.metadata``'s scan, which costs tens of ms); "unknown" if none is found."""
    import sys

    prefix = dist.lower().replace("-", "_") + "-"
    for entry in sys.path:
        try:
            names = os.listdir(entry or ".")
        except OSError:
            continue
        for name in names:
            if name.endswith(".dist-info") and name.lower().startswith(prefix):
                return name[len(prefix) : -len(".dist-info")]
    return "unknown"


@lru_cache(maxsize=1)
def _code_key() -> str:
    """What a cached robot depends on besides its files: the source of the modules that read a robot's files
    into parts and joints and the versions of the libraries that load meshes and take hulls (12 hex digits of
    SHA-256), so a change to either misses old caches."""
    h = hashlib.sha256(f"v{ROBOT_CACHE_VERSION}".encode())
    for dist in ("trimesh", "yourdfpy", "scipy", "numpy"):
        h.update(f"\0{dist}={installed_version(dist)}".encode())
    for name in _SOURCES:
        h.update(f"\0{name}\0".encode() + (Path(__file__).parent / name).read_bytes())
    return h.hexdigest()[:12]


def _cache_path(cache_dir: Path, description_hash: str) -> Path:
    return Path(cache_dir) / f"robot-{description_hash}-{_code_key()}.npz"


def _save_cache(
    cache_dir: Path,
    *,
    name: str,
    description_hash: str,
    base_link: str,
    parts: tuple[Part, ...],
    joints: tuple[JointSpec, ...],
) -> None:
    """Write a robot's parts and joints (atomically; a failure to write only logs)."""
    arrays = {
        "description_hash": np.array(description_hash),
        "code_key": np.array(_code_key()),
        "name": np.array(name),
        "base_link": np.array(base_link),
        "link": np.array([p.link for p in parts], dtype=str),
        "mass_kg": np.array([p.mass.mass_kg for p in parts], dtype=np.float64),
        "com_m": np.array([p.mass.com_m for p in parts], dtype=np.float64).reshape(-1, 3),
        "inertia_kg_m2": np.array([p.mass.inertia_kg_m2 for p in parts], dtype=np.float64).reshape(-1, 3, 3),
        "mass_model": np.array([p.mass.model for p in parts], dtype=str),
        "hull_ptr": np.cumsum([0] + [len(p.hull_link_m) for p in parts]).astype(np.int64),
        "hull_m": np.concatenate([p.hull_link_m.reshape(-1, 3) for p in parts]).astype(np.float64),
        "points_ptr": np.cumsum([0] + [len(p.points_link_m) for p in parts]).astype(np.int64),
        "points_m": np.concatenate([p.points_link_m.reshape(-1, 3) for p in parts]).astype(np.float64),
        "joint_text": np.array(
            [[j.name, j.type, j.parent, j.child, j.mimic] for j in joints], dtype=str
        ).reshape(-1, 5),
        "joint_origin": np.array([j.origin for j in joints], dtype=np.float64).reshape(-1, 4, 4),
        "joint_axis": np.array([j.axis for j in joints], dtype=np.float64).reshape(-1, 3),
        "joint_values": np.array(
            [[j.lower_rad, j.upper_rad, j.multiplier, j.offset] for j in joints], dtype=np.float64
        ).reshape(-1, 4),
    }
    arrays["payload_sha256"] = np.array(_payload_digest(arrays))
    path = _cache_path(cache_dir, description_hash)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, path)
    except OSError as exc:
        log.info("robot cache not written (%s): %s", path, exc)
        tmp.unlink(missing_ok=True)


def _load_cache(cache_dir: Path, description_hash: str):
    """(name, base_link, parts, joints) from the cache if it holds this description, verified, else None."""
    path = _cache_path(cache_dir, description_hash)
    try:
        with np.load(path, allow_pickle=False) as z:
            a = {k: z[k] for k in z.files}
    except (OSError, ValueError, KeyError, EOFError) as exc:
        if path.exists():
            log.info("robot cache %s unreadable (%s); rebuilding", path, exc)
        return None
    try:
        ok = (
            str(a["description_hash"]) == description_hash
            and str(a["code_key"]) == _code_key()
            and str(a["payload_sha256"]) == _payload_digest(a)
        )
    except KeyError:
        ok = False
    if not ok:
        log.info("robot cache %s does not match its description or contents; rebuilding", path)
        return None
    parts = []
    for i, link in enumerate(a["link"]):
        h0, h1 = a["hull_ptr"][i], a["hull_ptr"][i + 1]
        p0, p1 = a["points_ptr"][i], a["points_ptr"][i + 1]
        mp = MassProperties(
            float(a["mass_kg"][i]),
            a["com_m"][i].copy(),
            a["inertia_kg_m2"][i].copy(),
            str(a["mass_model"][i]),
        )
        parts.append(Part(str(link), mp, a["hull_m"][h0:h1].copy(), a["points_m"][p0:p1].copy()))
    joints = tuple(
        JointSpec(
            str(t[0]),
            str(t[1]),
            str(t[2]),
            str(t[3]),
            o.copy(),
            ax.copy(),
            float(v[0]),
            float(v[1]),
            str(t[4]),
            float(v[2]),
            float(v[3]),
        )
        for t, o, ax, v in zip(
            a["joint_text"], a["joint_origin"], a["joint_axis"], a["joint_values"], strict=True
        )
    )
    return str(a["name"]), str(a["base_link"]), tuple(parts), joints
