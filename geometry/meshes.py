"""Reading a link's geometry as a triangle mesh: mesh files (unprocessed, vertices checked finite) and the URDF
primitives (box, cylinder, sphere)."""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .errors import RobotDescriptionError
from .urdf import MeshRef

if TYPE_CHECKING:  # trimesh and yourdfpy load only where meshes are read (not for a cached robot)
    import trimesh
    import yourdfpy


def _check_vertices(verts: NDArray[np.float64], what: str) -> None:
    if not np.isfinite(verts).all():
        i = int(np.flatnonzero(~np.isfinite(verts).all(axis=1))[0])
        raise RobotDescriptionError(f"{what}: vertex {i} is not finite ({verts[i].tolist()}); fix the mesh")


def _load_mesh_bytes(data: bytes, path: Path, prefix: str = "") -> trimesh.Trimesh:
    """A mesh file's bytes as an unprocessed trimesh (nothing merged or dropped), vertices checked finite;
    ``prefix`` (e.g. ``"link 'head': "``) starts the error messages."""
    import trimesh

    try:
        mesh = trimesh.load(
            io.BytesIO(data),
            file_type=path.suffix.lstrip(".").lower(),
            force="mesh",
            process=False,
            resolver=trimesh.resolvers.FilePathResolver(str(path.parent)),
        )
    except Exception as exc:  # trimesh's loaders raise many types (ValueError, KeyError, IndexError, ...)
        raise RobotDescriptionError(
            f"{prefix}cannot read mesh '{path}': {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}; "
            "give a mesh file (STL, OBJ, PLY, ...)"
        ) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.vertices) == 0:
        raise RobotDescriptionError(
            f"{prefix}'{path}' holds no triangle mesh; give a mesh file (STL, OBJ, PLY, ...)"
        )
    _check_vertices(np.asarray(mesh.vertices, dtype=np.float64), f"{prefix}mesh '{path.name}'")
    return mesh


def _geometry_mesh(geom: yourdfpy.Geometry, ref: MeshRef | None, link: str) -> trimesh.Trimesh | None:
    import trimesh

    if geom.mesh is not None:
        mesh = _load_mesh_bytes(ref.data, ref.path, f"link '{link}': ")
        scale = ref.scale
        mesh.apply_scale(scale[0]) if np.allclose(scale, scale[0]) else mesh.apply_transform(
            np.diag([*scale, 1.0])
        )
        return mesh
    if geom.box is not None:
        return trimesh.creation.box(extents=np.asarray(geom.box.size, float))
    if geom.cylinder is not None:
        return trimesh.creation.cylinder(
            radius=geom.cylinder.radius, height=geom.cylinder.length, sections=64
        )
    if geom.sphere is not None:
        return trimesh.creation.icosphere(subdivisions=3, radius=geom.sphere.radius)
    return None
