"""Mass properties of parts: solid (volume) or thin shell (surface) models."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import GeometryError, NotAVolumeError

if TYPE_CHECKING:  # only the meshes passed in are trimesh objects; the module itself loads without trimesh
    import trimesh

COM_MODELS = ("auto", "solid", "shell")


@dataclass(frozen=True)
class MassProperties:
    """Mass, centre of mass and inertia of one rigid body.

    Attributes
    ----------
    mass_kg : float
        Mass, kg.
    com_m : ndarray of shape (3,)
        Centre of mass, m, in the frame of the geometry it was computed from.
    inertia_kg_m2 : ndarray of shape (3, 3)
        Inertia tensor about the CoM, kg m^2, in the same frame's axes.
    model : str
        How it was computed: ``"solid"`` (volume centroid), ``"shell"`` (area centroid of a thin shell),
        ``"given"`` (from a URDF ``<inertial>`` or the user) or ``"point"``.
    """

    mass_kg: float
    com_m: NDArray[np.float64]
    inertia_kg_m2: NDArray[np.float64]
    model: str


def shell_mass_properties(mesh: trimesh.Trimesh, *, mass_kg: float) -> MassProperties:
    """Mass properties of a uniform thin shell: mass spread over the surface area.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Surface, open or closed, metres.
    mass_kg : float
        Total mass, kg (> 0).

    Returns
    -------
    MassProperties
        CoM at the area centroid; inertia from the exact second moment of each triangle,
        ``A/12 (a a^T + b b^T + c c^T + s s^T)`` with ``s = a + b + c``.

    Examples
    --------
    >>> import trimesh
    >>> sphere = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    >>> mp = shell_mass_properties(sphere, mass_kg=3.0)
    >>> bool(np.allclose(mp.com_m, 0.0, atol=1e-12)), round(float(mp.inertia_kg_m2[0, 0]), 2)
    (True, 2.0)
    """
    tri = np.asarray(mesh.triangles, dtype=np.float64)
    area = np.asarray(mesh.area_faces, dtype=np.float64)
    total = float(area.sum())
    if not total > 0.0:
        raise GeometryError("shell CoM needs a surface with non-zero area; got total area 0")
    com = (area[:, None] * tri.mean(axis=1)).sum(axis=0) / total
    s = tri.sum(axis=1)
    second = np.einsum(
        "f,fij->ij", area / 12.0, np.einsum("fki,fkj->fij", tri, tri) + s[:, :, None] * s[:, None, :]
    )
    second *= mass_kg / total
    second_c = second - mass_kg * np.outer(com, com)
    inertia = np.trace(second_c) * np.eye(3) - second_c
    return MassProperties(float(mass_kg), com, inertia, "shell")


def solid_mass_properties(mesh: trimesh.Trimesh, *, mass_kg: float, name: str = "mesh") -> MassProperties:
    """Mass properties of a uniform solid bounded by a closed mesh.

    Raises
    ------
    NotAVolumeError
        If the mesh does not bound a volume (not watertight, inconsistent winding or zero volume).

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    >>> mp = solid_mass_properties(box, mass_kg=12.0)
    >>> round(float(mp.inertia_kg_m2[0, 0]), 9)   # m (b^2 + c^2) / 12
    13.0
    """
    if not mesh.is_volume:
        raise NotAVolumeError(
            f"{name}: a solid's CoM needs a closed mesh; watertight={mesh.is_watertight}, "
            f"winding_consistent={mesh.is_winding_consistent}, volume={mesh.volume:.3g} m^3. "
            "Repair it (trimesh.repair.fill_holes / fix_normals), or use the thin-shell model (--com-model shell)."
        )
    m = mesh.copy()
    m.density = mass_kg / m.volume
    return MassProperties(
        float(mass_kg),
        np.asarray(m.center_mass, dtype=np.float64),
        np.asarray(m.moment_inertia, dtype=np.float64),
        "solid",
    )


def mesh_mass_properties(
    mesh: trimesh.Trimesh, *, mass_kg: float, com_model: str = "auto", name: str = "mesh"
) -> MassProperties:
    """Solid or shell mass properties of a mesh.

    ``com_model="auto"`` takes the solid model when the mesh bounds a volume and the thin-shell model
    otherwise; ``"solid"`` refuses an open mesh; ``"shell"`` always uses the surface.

    Examples
    --------
    >>> import trimesh
    >>> open_box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    >>> open_box.update_faces(np.arange(len(open_box.faces)) > 1)   # drop one side: not closed any more
    >>> mesh_mass_properties(open_box, mass_kg=1.0).model
    'shell'
    """
    if com_model not in COM_MODELS:
        raise GeometryError(f"com_model must be one of {', '.join(COM_MODELS)}; got {com_model!r}")
    if not (np.isfinite(mass_kg) and mass_kg > 0.0):
        raise GeometryError(f"mass must be a positive number of kg; got {mass_kg!r}")
    if com_model == "solid" or (com_model == "auto" and mesh.is_volume):
        return solid_mass_properties(mesh, mass_kg=mass_kg, name=name)
    return shell_mass_properties(mesh, mass_kg=mass_kg)


def combine(parts: list[MassProperties]) -> MassProperties:
    """Mass properties of several bodies expressed in one frame (parallel-axis theorem).

    Examples
    --------
    >>> a = MassProperties(1.0, np.array([1.0, 0, 0]), np.zeros((3, 3)), "point")
    >>> b = MassProperties(1.0, np.array([-1.0, 0, 0]), np.zeros((3, 3)), "point")
    >>> c = combine([a, b])
    >>> c.com_m.tolist(), c.inertia_kg_m2.diagonal().tolist()
    ([0.0, 0.0, 0.0], [0.0, 2.0, 2.0])
    """
    total = float(sum(p.mass_kg for p in parts))
    com = sum(p.mass_kg * np.asarray(p.com_m) for p in parts) / total
    inertia = np.zeros((3, 3))
    for p in parts:
        d = np.asarray(p.com_m) - com
        inertia += p.inertia_kg_m2 + p.mass_kg * (d @ d * np.eye(3) - np.outer(d, d))
    return MassProperties(total, np.asarray(com, dtype=np.float64), inertia, "combined")


def as_point(com_m: ArrayLike, mass_kg: float) -> MassProperties:
    """A point mass."""
    return MassProperties(float(mass_kg), np.asarray(com_m, dtype=np.float64), np.zeros((3, 3)), "point")
