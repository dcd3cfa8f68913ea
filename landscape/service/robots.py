"""The robots a service knows: the built-in one and uploads stored under ``DATA/robots/ID/``.

An upload is a .zip of a URDF and its meshes, or one mesh file. It is unpacked into a private temporary folder,
checked (zip entries confined to the folder, the URDF's XML parsed without a DTD or entities, every mesh the
URDF names resolved inside the upload, vertex count and finiteness of every mesh), loaded with
:func:`geometry.robots.load_robot`, and renamed to ``DATA/robots/<description_hash>``. The rename is atomic, so
two simultaneous uploads of one robot leave one copy. A robot's id is its description hash; ``builtin`` names the
built-in robot too.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import shutil
import stat
import threading
import uuid
import warnings
import zipfile
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path, PurePosixPath
from typing import BinaryIO

from geometry.robots import DEFAULT_MESH_MASS_KG, ImplausibleUnitsWarning, mesh_size_m, units_warning

from .errors import ConflictError, NotFoundError, TooLargeError, UploadError

log = logging.getLogger(__name__)

BUILTIN = "builtin"
MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb")
"""Mesh files accepted: formats trimesh reads from the file alone (no XML, no external buffers)."""
_CHUNK = 1 << 20


@dataclass
class RobotEntry:
    """A loaded robot and what the service keeps with it.

    Attributes
    ----------
    id : str
        ``builtin`` or the description hash.
    robot : geometry.Robot
    info : dict
        What ``GET /api/robots/{id}`` answers.
    source : Path or None
        URDF or mesh file (None for the built-in robot, whose URDF :mod:`geometry.robots` finds).
    meta : dict
        The stored upload's ``meta.json`` (empty for the built-in robot).
    lock : threading.Lock
        Held while the robot is posed: posing moves the shared URDF model, so one thread at a time.
    """

    id: str
    robot: object
    info: dict
    source: Path | None
    meta: dict = field(default_factory=dict)
    lock: threading.Lock = field(default_factory=threading.Lock)
    starts: object = None
    seconds_per_cell: float | None = None


def _finite_or_none(x: float) -> float | None:
    import math

    return x if math.isfinite(x) else None


def robot_info(
    robot,
    robot_id: str,
    kind: str,
    filename: str | None = None,
    *,
    mass_default: bool = False,
    warnings: list[str] | None = None,
) -> dict:
    """The public description of a robot (no server paths): ``mass_default`` says the mass is the default of a
    mesh whose mass was not given; ``warnings`` holds what the upload should be told (e.g. implausible units)."""
    limits = None
    if robot.has_joints:
        limits = {
            k: [_finite_or_none(lo), _finite_or_none(hi)] for k, (lo, hi) in robot.theta_limits_deg().items()
        }
    n_vertices = int(sum(len(p.points_link_m) for p in robot.parts))
    return {
        "id": robot_id,
        "name": robot.name,
        "description_hash": robot.description_hash,
        "kind": kind,
        "filename": filename,
        "has_joints": bool(robot.has_joints),
        "theta_limits_deg": limits,
        "mass_kg": float(robot.total_mass_kg),
        "mass_default": bool(mass_default),
        "com_source": robot.com_source,
        "vertices": n_vertices,
        "warnings": list(warnings or []),
    }


def upload_warnings(robot, kind: str, units: str) -> list[str]:
    """What an upload's answer warns of: a mesh implausibly large or small in its ``units`` (the form field),
    as ``landscape compute --mesh`` warns."""
    if kind != "mesh":
        return []
    text = units_warning(mesh_size_m(robot), units, units_as="units")
    return [] if text is None else [text]


class RobotRegistry:
    """The built-in robot and the uploads under ``root``; robots load on first use and stay loaded."""

    def __init__(self, root: Path, *, limits):
        self.root = Path(root)
        self.tmp = self.root.parent / "tmp"
        self.root.mkdir(parents=True, exist_ok=True)
        self.tmp.mkdir(parents=True, exist_ok=True)
        self.limits = limits
        self._loaded: dict[str, RobotEntry] = {}
        self._lock = threading.Lock()
        self._builtin_hash: str | None = None

    # ------------------------------------------------------------------ lookup
    def builtin(self) -> RobotEntry:
        return self.get(BUILTIN)

    def resolve_id(self, robot_id: str) -> str:
        """The canonical id (``builtin`` for the built-in robot's hash too); NotFoundError if unknown."""
        if robot_id == BUILTIN:
            return BUILTIN
        if self._builtin_hash is None:
            self.builtin()
        if robot_id == self._builtin_hash:
            return BUILTIN
        if (
            not (robot_id.isalnum() and len(robot_id) <= 64)
            or not (self.root / robot_id / "meta.json").is_file()
        ):
            raise NotFoundError(
                f"unknown robot {robot_id!r}; GET /api/robots lists the ids (or use 'builtin')"
            )
        return robot_id

    def get(self, robot_id: str) -> RobotEntry:
        """The loaded robot of an id (loading it on first use)."""
        with self._lock:
            if robot_id in self._loaded:
                return self._loaded[robot_id]
        rid = robot_id if robot_id == BUILTIN else self.resolve_id(robot_id)
        with self._lock:
            if rid in self._loaded:
                self._loaded.setdefault(robot_id, self._loaded[rid])
                return self._loaded[rid]
        entry = self._load(rid)
        with self._lock:
            entry = self._loaded.setdefault(rid, entry)
            if rid == BUILTIN:
                self._builtin_hash = entry.robot.description_hash
        return entry

    def fresh_robot(self, robot_id: str):
        """A new Robot object of an id (for a long job that must not hold the shared robot's lock)."""
        entry = self.get(robot_id)
        return self._load_robot(entry.meta, entry.source)

    def urdf_path(self, robot_id: str) -> Path | None:
        """The URDF file a sweep simulates (None: the built-in robot); UploadError for a mesh robot."""
        entry = self.get(robot_id)
        if entry.id == BUILTIN:
            return None
        if entry.meta.get("kind") != "urdf" or not entry.robot.has_joints:
            raise UploadError(
                f"robot {entry.id} is a single rigid mesh; sweeps simulate a URDF robot with joints "
                "(upload a .zip of a URDF and its meshes)"
            )
        return entry.source

    def list(self) -> list[dict]:
        """Every robot: the built-in first, then uploads by upload time."""
        out = [self.builtin().info]
        metas = []
        for d in self.root.iterdir():
            meta_path = d / "meta.json"
            if meta_path.is_file():
                try:
                    metas.append(json.loads(meta_path.read_text()))
                except (OSError, ValueError):
                    log.warning("skipping unreadable robot metadata in %s", d.name)
        for m in sorted(metas, key=lambda m: m.get("uploaded_utc", "")):
            out.append(m["info"])
        return out

    def _load(self, rid: str) -> RobotEntry:
        if rid == BUILTIN:
            from geometry.robots import load_robot

            robot = load_robot()
            return RobotEntry(BUILTIN, robot, robot_info(robot, BUILTIN, "builtin"), None)
        d = self.root / rid
        meta = json.loads((d / "meta.json").read_text())
        source = d / "files" / meta["entry"]
        robot = self._load_robot(meta, source)
        return RobotEntry(rid, robot, meta["info"], source, meta)

    @staticmethod
    def _load_robot(meta: dict, source: Path | None):
        from geometry.robots import load_robot

        if not meta:
            return load_robot()
        if meta["kind"] == "urdf":
            return load_robot(str(source))
        with warnings.catch_warnings():  # said once, in the upload's answer (robot_info's warnings)
            warnings.simplefilter("ignore", ImplausibleUnitsWarning)
            return load_robot(
                mesh=str(source), com=meta.get("com"), mass_kg=meta["mass_kg"], units=meta["units"]
            )

    # ------------------------------------------------------------------ upload
    def add_upload(
        self,
        filename: str,
        data: BinaryIO,
        *,
        units: str = "m",
        mass_kg: float | None = None,
        com: list[float] | None = None,
    ) -> tuple[dict, bool]:
        """Check, load and store an upload; return (its info, whether it is new).

        A mesh's mass defaults to :data:`geometry.robots.DEFAULT_MESH_MASS_KG` (its info then says
        ``mass_default``), and a mesh implausibly large or small in ``units`` gets a warning in its info
        (:func:`geometry.robots.units_warning`), as the command line warns.

        Raises
        ------
        UploadError, TooLargeError, ConflictError
            For an unusable or oversized file, or a different robot with the same description hash.
        """
        name = PurePosixPath((filename or "").replace("\\", "/")).name
        suffix = Path(name).suffix.lower()
        if suffix != ".zip" and suffix not in MESH_SUFFIXES:
            raise UploadError(
                f"upload {name or '(no name)'!r} is neither a .zip of a URDF and its meshes nor a mesh "
                f"file ({', '.join(MESH_SUFFIXES)})"
            )
        work = self.tmp / uuid.uuid4().hex
        files = work / "files"
        files.mkdir(parents=True)
        try:
            if suffix == ".zip":
                raw = work / "upload.zip"
                self._copy_limited(data, raw, self.limits.max_upload_bytes, what="upload")
                self._unzip(raw, files)
                raw.unlink()
                entry, kind = self._find_entry(files)
            else:
                entry, kind = Path(name), "mesh"
                self._copy_limited(data, files / entry, self.limits.max_upload_bytes, what="upload")
            if kind == "urdf":
                meshes = self._urdf_meshes(files, files / entry)
            else:
                meshes = [files / entry]
            n_vertices = sum(self._check_mesh(m, files) for m in meshes)
            if n_vertices > self.limits.max_vertices:
                raise UploadError(
                    f"the robot's meshes have {n_vertices:,} vertices in all; the service accepts at "
                    f"most {self.limits.max_vertices:,}: simplify the meshes (e.g. a convex hull)"
                )
            meta = {
                "kind": kind,
                "entry": entry.as_posix(),
                "units": units,
                "mass_kg": float(DEFAULT_MESH_MASS_KG if mass_kg is None else mass_kg),
                "mass_default": kind == "mesh" and mass_kg is None,
                "com": com,
                "filename": name,
            }
            robot = self._load_robot(meta, files / entry)
            rid = robot.description_hash
            if not (rid.isalnum() and 8 <= len(rid) <= 64):  # pragma: no cover - the library's hash is hex
                raise RuntimeError(f"unexpected description hash {rid!r}")
            meta.update(
                id=rid,
                content_sha256=_tree_digest(files, meta),
                uploaded_utc=datetime.now(timezone.utc).isoformat(timespec="seconds"),
                info=robot_info(
                    robot,
                    rid,
                    kind,
                    name,
                    mass_default=meta["mass_default"],
                    warnings=upload_warnings(robot, kind, units),
                ),
            )
            (work / "meta.json").write_text(json.dumps(meta, indent=1))
            final = self.root / rid
            try:
                os.rename(work, final)
            except OSError:
                if not (final / "meta.json").is_file():
                    raise
                old = json.loads((final / "meta.json").read_text())
                if old.get("content_sha256") != meta["content_sha256"]:
                    raise ConflictError(
                        f"a different robot with description hash {rid} is stored already (same geometry and CoM, "
                        "other mass or files); the hash does not tell them apart: change the mass in the file's "
                        "description or use the stored robot"
                    ) from None
                return old["info"], False
            return meta["info"], True
        finally:
            shutil.rmtree(work, ignore_errors=True)

    @staticmethod
    def _copy_limited(src: BinaryIO, dst: Path, limit: int, *, what: str) -> int:
        n = 0
        with open(dst, "wb") as out:
            while chunk := src.read(_CHUNK):
                n += len(chunk)
                if n > limit:
                    raise TooLargeError(
                        f"{what} is over the limit of {limit / 2**20:g} MiB; upload a smaller file"
                    )
                out.write(chunk)
        if n == 0:
            raise UploadError(f"{what} is empty; choose a mesh file or a .zip of a URDF and its meshes")
        return n

    def _unzip(self, raw: Path, dest: Path) -> None:
        try:
            zf = zipfile.ZipFile(raw)
        except zipfile.BadZipFile:
            raise UploadError("the .zip upload is not a readable zip archive") from None
        with zf:
            infos = zf.infolist()
            if len(infos) > self.limits.max_zip_entries:
                raise UploadError(
                    f"the zip has {len(infos)} entries; at most {self.limits.max_zip_entries} allowed"
                )
            total = 0
            for info in infos:
                rel = _safe_member(info)
                if rel is None:
                    continue
                target = dest / rel
                target.parent.mkdir(parents=True, exist_ok=True)
                with zf.open(info) as src, open(target, "xb") as out:
                    while chunk := src.read(_CHUNK):
                        total += len(chunk)
                        if total > self.limits.max_unzipped_bytes:
                            raise TooLargeError(
                                f"the zip unpacks to more than "
                                f"{self.limits.max_unzipped_bytes / 2**20:g} MiB; upload less"
                            )
                        out.write(chunk)

    @staticmethod
    def _find_entry(files: Path) -> tuple[Path, str]:
        urdfs = sorted(p for p in files.rglob("*") if p.is_file() and p.suffix.lower() == ".urdf")
        if len(urdfs) > 1:
            names = ", ".join(p.relative_to(files).as_posix() for p in urdfs)
            raise UploadError(f"the zip holds several URDF files ({names}); put exactly one in it")
        if urdfs:
            return urdfs[0].relative_to(files), "urdf"
        meshes = sorted(p for p in files.rglob("*") if p.is_file() and p.suffix.lower() in MESH_SUFFIXES)
        if len(meshes) == 1:
            return meshes[0].relative_to(files), "mesh"
        raise UploadError(
            "the zip holds no .urdf file (and not exactly one mesh); zip a URDF with its meshes"
        )

    @staticmethod
    def _urdf_meshes(files: Path, urdf: Path) -> list[Path]:
        """Every mesh file the URDF names, resolved as the library resolves it and confined to the upload."""
        import defusedxml.ElementTree as DET
        import yourdfpy
        from defusedxml import DefusedXmlException

        text = urdf.read_bytes()
        try:
            root = DET.fromstring(text, forbid_dtd=True, forbid_entities=True, forbid_external=True)
        except DefusedXmlException:
            raise UploadError(
                f"{urdf.name}: DTDs and XML entities are not accepted in an uploaded URDF; "
                "remove the <!DOCTYPE> declaration"
            ) from None
        except DET.ParseError as exc:
            raise UploadError(f"{urdf.name} is not well-formed XML: {exc}") from None
        if root.tag != "robot":
            raise UploadError(f"{urdf.name}: the root element is <{root.tag}>, not <robot>; upload a URDF")
        top = files.resolve()
        out = []
        for el in root.iter("mesh"):
            fname = el.get("filename", "")
            if Path(fname).suffix.lower() not in MESH_SUFFIXES:
                raise UploadError(
                    f"{urdf.name}: mesh {fname!r} is not one of {', '.join(MESH_SUFFIXES)}; convert it"
                )
            found = Path(yourdfpy.filename_handler_magic(fname, dir=str(urdf.parent)))
            found = (found if found.is_absolute() else Path.cwd() / found).resolve()
            if not found.is_relative_to(top) or not found.is_file():
                raise UploadError(
                    f"{urdf.name}: mesh {fname!r} is not a file inside the upload; put every mesh in "
                    "the zip and name it by a path relative to the URDF"
                )
            out.append(found)
        return out

    def _check_mesh(self, path: Path, files: Path) -> int:
        """Vertex count of a mesh file, after checking it is a non-empty, finite triangle mesh under the limit."""
        import numpy as np
        import trimesh

        rel = path.relative_to(files.resolve()) if path.is_absolute() else path.relative_to(files)
        if path.stat().st_size == 0:
            raise UploadError(f"mesh {rel.as_posix()!r} is empty; upload a mesh file with triangles")
        try:
            mesh = trimesh.load(str(path), force="mesh", process=False)
        except Exception:  # trimesh raises many types for unreadable files
            raise UploadError(
                f"{rel.as_posix()!r} is not a readable mesh (STL, OBJ, PLY, OFF, GLB)"
            ) from None
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.vertices) == 0 or len(mesh.faces) == 0:
            raise UploadError(f"{rel.as_posix()!r} holds no triangle mesh; upload a mesh file with triangles")
        n = len(mesh.vertices)
        if n > self.limits.max_vertices:
            raise UploadError(
                f"mesh {rel.as_posix()!r} has {n:,} vertices; the service accepts at most "
                f"{self.limits.max_vertices:,}: simplify it"
            )
        if not np.isfinite(np.asarray(mesh.vertices)).all():
            raise UploadError(
                f"mesh {rel.as_posix()!r} has vertices that are not finite (NaN or inf); fix the mesh"
            )
        return n


def _safe_member(info: zipfile.ZipInfo) -> PurePosixPath | None:
    """The relative path of a zip entry to extract (None for a directory); UploadError for an unsafe one."""
    name = info.filename
    mode = info.external_attr >> 16
    if stat.S_ISLNK(mode):
        raise UploadError(f"zip entry {name!r} is a symbolic link; zip the files themselves")
    p = PurePosixPath(name.replace("\\", "/"))
    if name.startswith(("/", "\\")) or p.is_absolute() or (p.parts and ":" in p.parts[0]):
        raise UploadError(f"zip entry {name!r} has an absolute path; zip files by relative paths")
    if ".." in p.parts:
        raise UploadError(
            f"zip entry {name!r} climbs out of the archive with '..'; zip files by relative paths"
        )
    if info.is_dir() or not p.parts:
        return None
    return p


def _tree_digest(files: Path, meta: dict) -> str:
    """SHA-256 over the mass options and every file's relative path and bytes (a mesh: its bytes only)."""
    h = hashlib.sha256(json.dumps([meta["units"], meta["mass_kg"], meta["com"]]).encode())
    if meta["kind"] == "mesh":  # one mesh: its bytes, whatever the file is called
        h.update(hashlib.sha256((files / meta["entry"]).read_bytes()).digest())
        return h.hexdigest()
    for p in sorted(files.rglob("*")):
        if p.is_file():
            h.update(p.relative_to(files).as_posix().encode() + b"\0")
            h.update(hashlib.sha256(p.read_bytes()).digest())
    return h.hexdigest()
