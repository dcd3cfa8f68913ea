"""Laying a computation out for the renderers: torus paths broken where they wrap, the twin of an orientation
nearest a drawn path, the robot's part meshes in the world frame. Plain arrays in, plain arrays out."""

from __future__ import annotations

import numpy as np
import trimesh
from numpy.typing import NDArray
from scipy.spatial import QhullError

from geometry import Pose
from geometry.frames import body_to_world
from landscape.barriers import EXITS


def pose_label(c) -> str:
    """The joint angles of a computation as a figure says them, e.g. "wing 74°, leg 30°"; an angle no joint takes
    (None) is left out ("" for a rigid body).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> pose_label(SimpleNamespace(theta_w_deg=74.0, theta_l_deg=None))
    'wing 74°'
    """
    parts = [(name, v) for name, v in (("wing", c.theta_w_deg), ("leg", c.theta_l_deg)) if v is not None]
    return ", ".join(f"{name} {v:g}°" for name, v in parts)


def wrapped_path_deg(path_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """A continuous (unwrapped) torus path moved into [-180, 180), with a NaN row wherever it wraps.

    Examples
    --------
    >>> wrapped_path_deg(np.array([[170.0, 0.0], [179.0, 0.0], [188.0, 0.0]])).tolist()
    [[170.0, 0.0], [179.0, 0.0], [nan, nan], [-172.0, 0.0]]
    """
    w = (np.asarray(path_deg, dtype=np.float64).reshape(-1, 2) + 180.0) % 360.0 - 180.0
    breaks = np.flatnonzero((np.abs(np.diff(w, axis=0)) > 180.0).any(axis=1)) + 1
    return np.insert(w, breaks, np.nan, axis=0)


def nearest_twin_deg(pitch_deg: float, roll_deg: float, near_deg: NDArray[np.float64]) -> tuple[float, float]:
    """Of the two torus points of one orientation, (p, r) and (180 - p, r + 180), the one nearer ``near_deg``.

    The landscape over the full pitch-roll square shows every orientation twice; a mark belongs on the copy
    the drawn path passes.

    Examples
    --------
    >>> nearest_twin_deg(70.0, 10.0, np.array([[100.0, -170.0]]))
    (110.0, -170.0)
    """
    near = np.asarray(near_deg, dtype=np.float64).reshape(-1, 2)
    near = near[np.isfinite(near).all(axis=1)]
    twins = np.array([[pitch_deg, roll_deg], [180.0 - pitch_deg, roll_deg + 180.0]])
    twins = (twins + 180.0) % 360.0 - 180.0
    if not len(near):
        return float(twins[0, 0]), float(twins[0, 1])
    d = (np.abs(twins[:, None, :] - near[None, :, :]) + 180.0) % 360.0 - 180.0
    k = int(np.argmin(np.linalg.norm(d, axis=-1).min(axis=1)))
    return float(twins[k, 0]), float(twins[k, 1])


def posed_meshes_world(
    pose: Pose, pitch_deg: float, roll_deg: float
) -> tuple[list[tuple[NDArray[np.float64], NDArray[np.int64]]], NDArray[np.float64]]:
    """The posed robot's part meshes resting on the ground at body pitch and roll.

    Each part is drawn as the convex hull of its geometry (the hull is what decides the contact). Parts are
    placed by their link transforms, rotated by ``body_to_world(p, r)`` and shifted so the lowest point is
    at z = 0 and the CoM above the origin.

    Returns
    -------
    meshes : list of (vertices_m (V, 3), faces (F, 3))
        World frame, m.
    com_m : ndarray of shape (3,)
        CoM in the world frame, m; ``com_m[2]`` is the CoM height above the ground.
    """
    rot = body_to_world(np.deg2rad(pitch_deg), np.deg2rad(roll_deg))
    meshes = []
    for part in pose.parts:
        if len(part.hull_link_m) < 4:
            continue
        try:
            hull = trimesh.convex.convex_hull(part.hull_link_m)
        except QhullError:  # flat or degenerate part: nothing to draw
            continue
        T = pose.link_transforms[part.link]
        v = (np.asarray(hull.vertices) @ T[:3, :3].T + T[:3, 3]) @ rot.T
        meshes.append((v, np.asarray(hull.faces, dtype=np.int64)))
    com = rot @ pose.com_m
    low = min(float(v[:, 2].min()) for v, _ in meshes)
    shift = np.array([com[0], com[1], low])
    return [(v - shift, f) for v, f in meshes], com - shift


# ------------------------------------------------------------------------------------------------ command


def landscape_marks(c, exit_kind: str = "righting") -> dict:
    """The start minimum, saddle and barrier path of one exit of a computation, placed on the drawn torus copy.

    Returns
    -------
    marks : dict
        ``minimum_deg``, ``minimum_j``, ``saddle_deg``, ``saddle_j``, ``path_deg`` (a NaN row where the path
        wraps), ``path_j`` (J): the keywords of :func:`landscape.viz.render.render_landscape`.
    """
    from landscape.energy import height_at

    ex = getattr(c.barrier, EXITS[exit_kind])
    marks = {
        "minimum_deg": (c.minimum.pitch_deg, c.minimum.roll_deg),
        "minimum_j": c.minimum.energy_j,
        "saddle_deg": None,
        "saddle_j": None,
        "path_deg": None,
        "path_j": None,
    }
    if ex is not None:
        mg = c.mass_kg * c.landscape.g_m_s2
        path_deg = wrapped_path_deg(ex.path_deg)
        ok = np.isfinite(path_deg[:, 0])
        path_j = np.full(len(path_deg), np.nan)
        path_j[ok] = mg * height_at(c.pose, path_deg[ok, 0], path_deg[ok, 1])
        marks.update(
            path_deg=path_deg,
            path_j=path_j,
            saddle_j=c.minimum.energy_j + ex.barrier_j,
            saddle_deg=nearest_twin_deg(ex.saddle_pitch_deg, ex.saddle_roll_deg, path_deg),
            minimum_deg=nearest_twin_deg(c.minimum.pitch_deg, c.minimum.roll_deg, path_deg[:1]),
        )
    return marks


def render_computation(c, out_dir, *, robot_name: str, exit_kind: str = "righting") -> tuple[list, list[str]]:
    """Every figure of one computation into ``out_dir``: the contour map (PNG, SVG), the landscape as a VTK grid
    and a 3-D PNG, the robot at its start and at the saddle (PNG), and the interactive HTML page (offline, plotly).

    Returns
    -------
    written : list of Path
    notes : list of str
        What was skipped and why (e.g. the HTML export without plotly).

    Raises
    ------
    UsageError
        If 3-D rendering cannot run here (pyvista/vtk missing or no off-screen OpenGL); the 2-D files are
        written first and named in the message.
    """
    from pathlib import Path

    from geometry.errors import UsageError
    from landscape.viz import render as rd

    angles_deg, energy_j = c.landscape.inclusive()
    ex = getattr(c.barrier, EXITS[exit_kind])
    marks = landscape_marks(c, exit_kind)
    pose_text = pose_label(c)
    pose_text = f"  {pose_text}" if pose_text else ""
    barrier_text = (
        f"{exit_kind} barrier none" if ex is None else f"{exit_kind} barrier {ex.barrier_j * 1e3:.2f} mJ"
    )
    title = f"{robot_name}{pose_text}  {barrier_text}"
    outd = Path(out_dir)
    written, notes = [], []
    contour = {k: marks[k] for k in ("minimum_deg", "saddle_deg", "saddle_j", "path_deg")}
    for suffix in ("png", "svg"):
        written.append(
            rd.render_contour(
                energy_j, angles_deg, angles_deg, outd / f"contour.{suffix}", title=title, **contour
            )
        )
    try:
        written.append(rd.write_vtk(energy_j, angles_deg, angles_deg, outd / "landscape.vts"))
        problem = rd.off_screen_problem()
    except rd.MissingDependencyError as exc:
        problem = str(exc)
    if problem is not None:
        raise UsageError(f"{problem} (wrote only {', '.join(p.name for p in written)} in {outd})")
    written.append(
        rd.render_landscape(energy_j, angles_deg, angles_deg, outd / "landscape.png", title=title, **marks)
    )
    robots = [("start", "start minimum", c.minimum.pitch_deg, c.minimum.roll_deg)]
    if ex is not None:
        robots.append(("saddle", f"{exit_kind} saddle", ex.saddle_pitch_deg, ex.saddle_roll_deg))
    for name, what, p, r in robots:
        meshes, com = posed_meshes_world(c.pose, p, r)
        written.append(
            rd.render_robot(
                meshes,
                outd / f"robot_{name}.png",
                com_m=com,
                title=f"{robot_name}{pose_text}\n{what}: pitch {p:.1f}°, roll {r:.1f}°\n"
                f"CoM {com[2] * 1e3:.1f} mm above the ground",
            )
        )
    try:
        written.append(
            rd.export_landscape_html(
                energy_j, angles_deg, angles_deg, outd / "landscape.html", title=title, **marks
            )
        )
    except rd.MissingDependencyError as exc:
        notes.append(f"skipped landscape.html: {exc}")
    return written, notes
