"""Figures of a landscape and of the posed robot (edge layer): 3-D with pyvista, the 2-D contour map with matplotlib.

Every renderer takes finished arrays and a path, computes nothing and returns the path it wrote (STYLE §7).
Marks come in as plain coordinates: a path is an (L, 2) array of (pitch, roll) in degrees on -180..180 whose
rows of NaN break it into pieces (where it wraps round the torus), with its energies (L,) in J.

pyvista (the optional dependency ``render``) is imported on first use, so the contour map needs only
matplotlib. The interactive HTML export uses plotly (a dependency) and embeds plotly.js, so the page works offline.

Off-screen rendering without an X server works through the vtk wheel's EGL or OSMesa back end, which
loads the system's libraries at run time (Debian: ``libegl1 libegl-mesa0 libgl1-mesa-dri`` for EGL, or
``libosmesa6``). Where none is present vtk crashes the process, so :func:`off_screen_problem` tries it in a
child process first.

It is one concept, drawing one landscape and its posed robot (3-D, contour, robot views, VTK, HTML), hence its
length.
"""

from __future__ import annotations

import contextlib
import functools
import os
import re
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

import matplotlib.patheffects as patheffects
import numpy as np
from numpy.typing import ArrayLike, NDArray

from landscape.viz._mpl import plt, save

MJ_PER_J = 1e3
START_COLOUR = "#e41a1c"
SADDLE_COLOUR = "#ff7f00"
PATH_COLOUR = "#ff2bd6"
RELIEF = 0.3  # height of the 3-D relief as a fraction of the 360 deg base
OFF_SCREEN_HINT = (
    "install the EGL libraries (Debian/Ubuntu: apt-get install libegl1 libegl-mesa0 "
    "libgl1-mesa-dri) or OSMesa (libosmesa6, with VTK_DEFAULT_OPENGL_WINDOW=vtkOSOpenGLRenderWindow)"
)
PYVISTA_MISSING = (
    "3-D rendering needs pyvista and vtk, which the install brings; reinstall from the clone with "
    "`.venv/bin/pip install -e .` (or pip install pyvista vtk)"
)
PLOTLY_MISSING = (
    "the interactive HTML export needs plotly, which the install brings; reinstall from the clone "
    "with `.venv/bin/pip install -e .` (or pip install plotly)"
)


class MissingDependencyError(ImportError):
    """An optional package a figure needs is not installed."""


def _pv():
    try:
        import pyvista as pv
    except ImportError:
        raise MissingDependencyError(PYVISTA_MISSING) from None
    return pv


_PROBE = """
import numpy as np, pyvista as pv
pl = pv.Plotter(off_screen=True, window_size=(48, 32))
pl.add_mesh(pv.Sphere(), color="red")
img = pl.screenshot(return_img=True)
pl.close()
assert img.shape[:2] == (32, 48) and np.ptp(img) > 0, "blank image"
print(type(pl.render_window).__name__ if pl.render_window is not None else "ok")
"""


@functools.cache
def off_screen_problem(timeout_s: float = 120.0) -> str | None:
    """Why pyvista cannot render off-screen on this machine, or None if it can.

    Renders a small sphere in a child process (vtk segfaults where it finds no OpenGL at all), once per
    process.

    Returns
    -------
    str or None
        One line: what failed and what to install; None when a non-blank image came back.
    """
    try:
        import pyvista  # noqa: F401
    except ImportError:
        return PYVISTA_MISSING
    try:
        res = subprocess.run(
            [sys.executable, "-c", _PROBE],
            capture_output=True,
            text=True,
            timeout=timeout_s,
            env={**os.environ, "PYTHONWARNINGS": "ignore"},
        )
    except subprocess.TimeoutExpired:
        return f"off-screen test render took over {timeout_s:g} s; {OFF_SCREEN_HINT}"
    if res.returncode == 0:
        return None
    how = f"signal {-res.returncode}" if res.returncode < 0 else f"exit status {res.returncode}"
    lines = [re.sub(r"\x1b\[[0-9;]*m", "", ln).strip() for ln in res.stderr.splitlines()]
    lines = [ln.split("| ", 1)[-1] for ln in lines if ln]  # drop vtk's log prefix
    detail = f" ({lines[-1][:160]})" if lines else ""
    return f"vtk cannot render off-screen here: test render ended with {how}{detail}; {OFF_SCREEN_HINT}"


# ------------------------------------------------------------------------------------------------ helpers
@contextlib.contextmanager
def _errors_only():
    """Hide vtk's warnings (e.g. "bad X server connection" before it falls back to EGL); keep its errors."""
    from vtkmodules.vtkCommonCore import vtkLogger

    before = vtkLogger.GetCurrentVerbosityCutoff()
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
    try:
        yield
    finally:
        vtkLogger.SetStderrVerbosity(before)


def mark_point(ax, at_deg, *, marker: str, colour: str, text: str, gid: str) -> None:
    """A start or saddle mark on a pitch-roll map, labelled with its angles (SVG id ``gid``)."""
    (pt,) = ax.plot(
        at_deg[0],
        at_deg[1],
        marker,
        ms=10,
        mfc=colour,
        mec="black",
        mew=1.0,
        ls="none",
        label=f"{text} ({at_deg[0]:.1f}°, {at_deg[1]:.1f}°)",
    )
    pt.set_gid(gid)


PITCH_LABEL = "pitch (°)"
ROLL_LABEL = "roll (°)"
"""A pitch-roll map has pitch on x and roll on y, in every figure: the contour maps here and of the trajectories,
the 3-D landscape's axes, the HTML landscape, the report, the service's page and the gallery."""


def pitch_roll_axes(ax, pitch_deg, roll_deg) -> None:
    """Label a pitch-roll map's axes in degrees (pitch on x, roll on y), ticks every 90° inside the drawn range."""
    ax.set_xlabel(PITCH_LABEL)
    ax.set_ylabel(ROLL_LABEL)
    ticks = np.arange(-180, 181, 90)
    ax.set_xticks(ticks[(ticks >= np.min(pitch_deg)) & (ticks <= np.max(pitch_deg))])
    ax.set_yticks(ticks[(ticks >= np.min(roll_deg)) & (ticks <= np.max(roll_deg))])


def _screenshot(pl, path: Path) -> Path:
    """Write the plotter's image to ``path`` (creating the directory) and close the plotter whatever happens."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        pl.screenshot(str(path))
    finally:
        pl.close()
    return path


def _pieces(path_deg: NDArray[np.float64]) -> list[slice]:
    """Slices of the runs of finite rows in a NaN-separated path."""
    ok = np.isfinite(path_deg).all(axis=1)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(np.int8), [0]])))
    return [slice(a, b) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _check_surface(energy_j, pitch_deg, roll_deg):
    e = np.asarray(energy_j, dtype=np.float64)
    p = np.asarray(pitch_deg, dtype=np.float64)
    r = np.asarray(roll_deg, dtype=np.float64)
    if e.shape != (len(p), len(r)) or e.ndim != 2 or min(e.shape) < 2:
        raise ValueError(
            f"energy_j must have shape (len(pitch_deg), len(roll_deg)) >= (2, 2); got {e.shape} "
            f"for {len(p)} pitch and {len(r)} roll angles"
        )
    if not np.isfinite(e).all():
        raise ValueError("energy_j must be finite everywhere")
    return e, p, r


def _marks(minimum_deg, minimum_j, saddle_deg, saddle_j, path_deg, path_j):
    mark = {}
    for name, at, e in (("minimum", minimum_deg, minimum_j), ("saddle", saddle_deg, saddle_j)):
        if at is not None:
            mark[name] = (np.asarray(at, dtype=np.float64).reshape(2), None if e is None else float(e))
    path = None
    if path_deg is not None:
        pd = np.asarray(path_deg, dtype=np.float64).reshape(-1, 2)
        pj = None if path_j is None else np.asarray(path_j, dtype=np.float64).reshape(-1)
        if pj is not None and len(pj) != len(pd):
            raise ValueError(
                f"path_j must have one energy per path point; got {len(pj)} for {len(pd)} points"
            )
        path = (pd, pj)
    return mark, path


# ------------------------------------------------------------------------------------------------ 3-D landscape
def _landscape_plotter(
    energy_j,
    pitch_deg,
    roll_deg,
    *,
    minimum_deg,
    minimum_j,
    saddle_deg,
    saddle_j,
    path_deg,
    path_j,
    title,
    off_screen,
    window_size,
    elevation_deg,
    azimuth_deg,
):
    pv = _pv()
    e, p, r = _check_surface(energy_j, pitch_deg, roll_deg)
    mark, path = _marks(minimum_deg, minimum_j, saddle_deg, saddle_j, path_deg, path_j)
    e_mj = e * MJ_PER_J
    lo_mj, hi_mj = float(e_mj.min()), float(e_mj.max())
    span_mj = (hi_mj - lo_mj) or 1.0
    base_deg = float(max(np.ptp(p), np.ptp(r)))
    # Scene z is energy stretched so that the relief is a third of the base; the axes are labelled in mJ.
    z_per_mj = RELIEF * base_deg / span_mj

    def z_of(mj):
        return (np.asarray(mj, dtype=np.float64) - lo_mj) * z_per_mj

    pp, rr = np.meshgrid(p, r, indexing="ij")
    grid = pv.StructuredGrid(pp, rr, z_of(e_mj))
    grid.point_data["energy (mJ)"] = e_mj.ravel(order="F")
    pl = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
    pl.set_background("white")
    pl.add_mesh(
        grid,
        scalars="energy (mJ)",
        cmap="viridis",
        smooth_shading=True,
        specular=0.15,
        scalar_bar_args={
            "title": "energy (mJ)",
            "color": "black",
            "vertical": True,
            "position_x": 0.9,
            "position_y": 0.3,
            "height": 0.45,
            "width": 0.04,
            "fmt": "%.0f",
            "title_font_size": 16,
            "label_font_size": 14,
        },
    )
    lift = 0.01 * base_deg
    if path is not None and path[1] is not None:
        pd, pj = path
        label = "barrier path"
        for sl in _pieces(pd):
            if sl.stop - sl.start < 2:
                continue
            pts = np.column_stack([pd[sl], z_of(pj[sl] * MJ_PER_J) + lift])
            pl.add_mesh(
                pv.lines_from_points(pts),
                color=PATH_COLOUR,
                line_width=6,
                render_lines_as_tubes=True,
                label=label,
            )
            label = None
    labels = {"minimum": ("start minimum", START_COLOUR), "saddle": ("saddle", SADDLE_COLOUR)}
    for name, (at, ej) in mark.items():
        if ej is None:
            continue
        text, colour = labels[name]
        pt = np.array([[at[0], at[1], float(z_of(ej * MJ_PER_J)) + 2 * lift]])
        pl.add_points(
            pt,
            color=colour,
            point_size=24,
            render_points_as_spheres=True,
            label=f"{text} ({at[0]:.1f}, {at[1]:.1f}) deg, {ej * MJ_PER_J:.1f} mJ",
        )
    pl.show_grid(
        xtitle="pitch (deg)",
        ytitle="roll (deg)",
        ztitle="energy (mJ)",
        color="black",
        font_size=12,
        n_xlabels=5,
        n_ylabels=5,
        n_zlabels=3,
        fmt="%.0f",
        location="outer",
        axes_ranges=[p.min(), p.max(), r.min(), r.max(), lo_mj, hi_mj],
    )
    if mark or path is not None:
        pl.add_legend(bcolor="white", border=True, size=(0.42, 0.13), loc="upper left", face="circle")
    if title:
        pl.add_text(title, position="upper_edge", font_size=12, color="black")
    centre = np.array([(p.min() + p.max()) / 2, (r.min() + r.max()) / 2, RELIEF * base_deg / 2])
    el, az = np.deg2rad(elevation_deg), np.deg2rad(azimuth_deg)
    view = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    pl.camera.focal_point = tuple(centre)
    pl.camera.position = tuple(centre + 3.0 * base_deg * view)
    pl.camera.up = (0.0, 0.0, 1.0)
    pl.reset_camera()
    pl.camera.zoom(1.02)
    return pl


def render_landscape(
    energy_j: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    path: str | Path,
    *,
    minimum_deg: ArrayLike | None = None,
    minimum_j: float | None = None,
    saddle_deg: ArrayLike | None = None,
    saddle_j: float | None = None,
    path_deg: ArrayLike | None = None,
    path_j: ArrayLike | None = None,
    title: str = "",
    off_screen: bool = True,
    window_size: tuple[int, int] = (1280, 960),
    elevation_deg: float = 40.0,
    azimuth_deg: float = -55.0,
) -> Path:
    """PNG of the landscape surface over pitch and roll, height and colour = energy in mJ, with the marks.

    Parameters
    ----------
    energy_j : array_like of shape (P, R)
        Energy at pitch ``pitch_deg[i]``, roll ``roll_deg[j]``, J.
    pitch_deg, roll_deg : array_like of shape (P,) and (R,)
        Grid angles, degrees, increasing.
    path : path
        PNG to write; parent folders are created.
    minimum_deg, saddle_deg : array_like of shape (2,), optional
        (pitch, roll) of the start minimum and of the saddle, degrees; drawn with ``minimum_j``/``saddle_j``
        (their energies, J) as height.
    path_deg : array_like of shape (L, 2), optional
        Barrier path (pitch, roll), degrees, within the grid; rows of NaN break it.
    path_j : array_like of shape (L,), optional
        Energy along ``path_deg``, J (the line is drawn slightly above the surface).
    title : str
        Text at the top.
    off_screen : bool
        Render without a window.
    window_size : (int, int)
        Image width and height, pixels.
    elevation_deg, azimuth_deg : float
        Camera direction from the centre of the base: above the base plane, and round the vertical from the
        +pitch axis towards +roll, degrees. The default looks from high pitch and low roll.

    Returns
    -------
    Path
        The PNG written, ``window_size`` pixels.

    Raises
    ------
    ValueError
        If the arrays' shapes disagree or an energy is not finite.
    MissingDependencyError
        If pyvista is not installed.
    """
    path = Path(path)
    _pv()
    with _errors_only():
        pl = _landscape_plotter(
            energy_j,
            pitch_deg,
            roll_deg,
            minimum_deg=minimum_deg,
            minimum_j=minimum_j,
            saddle_deg=saddle_deg,
            saddle_j=saddle_j,
            path_deg=path_deg,
            path_j=path_j,
            title=title,
            off_screen=off_screen,
            window_size=window_size,
            elevation_deg=elevation_deg,
            azimuth_deg=azimuth_deg,
        )
        return _screenshot(pl, path)


def _html_title(title: str) -> str:
    return f"Energy landscape: {title}" if title else "Energy landscape"


def landscape_figure(
    energy_j: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    *,
    minimum_deg: ArrayLike | None = None,
    minimum_j: float | None = None,
    saddle_deg: ArrayLike | None = None,
    saddle_j: float | None = None,
    path_deg: ArrayLike | None = None,
    path_j: ArrayLike | None = None,
    title: str = "",
    elevation_deg: float = 40.0,
    azimuth_deg: float = -55.0,
):
    """The scene of :func:`render_landscape` as an interactive plotly figure (arguments alike): the surface with
    energy in mJ as height and colour, the barrier path and the marks.

    Returns
    -------
    plotly.graph_objects.Figure

    Raises
    ------
    ValueError
        If the arrays' shapes disagree or an energy is not finite.
    MissingDependencyError
        If plotly is not installed.
    """
    try:
        import plotly.graph_objects as go
    except ImportError:
        raise MissingDependencyError(PLOTLY_MISSING) from None
    e, p, r = _check_surface(energy_j, pitch_deg, roll_deg)
    mark, path = _marks(minimum_deg, minimum_j, saddle_deg, saddle_j, path_deg, path_j)
    e_mj = e * MJ_PER_J
    span_mj = float(np.ptp(e_mj)) or 1.0
    lift_mj = 0.01 * span_mj
    fig = go.Figure()
    # plotly's surface takes z[row = y][column = x]: roll down the rows, pitch across
    fig.add_trace(
        go.Surface(
            x=p,
            y=r,
            z=e_mj.T,
            colorscale="Viridis",
            name="energy",
            colorbar={"title": {"text": "energy (mJ)"}},
            hovertemplate="pitch %{x:.1f}°<br>roll %{y:.1f}°<br>%{z:.2f} mJ<extra></extra>",
        )
    )
    if path is not None and path[1] is not None:
        pd, pj = path
        fig.add_trace(
            go.Scatter3d(
                x=pd[:, 0],
                y=pd[:, 1],
                z=pj * MJ_PER_J + lift_mj,
                mode="lines",
                line={"color": PATH_COLOUR, "width": 8},
                name="barrier path",
                connectgaps=False,
            )
        )
    labels = {"minimum": ("start minimum", START_COLOUR), "saddle": ("saddle", SADDLE_COLOUR)}
    for name, (at, ej) in mark.items():
        if ej is None:
            continue
        text, colour = labels[name]
        fig.add_trace(
            go.Scatter3d(
                x=[at[0]],
                y=[at[1]],
                z=[ej * MJ_PER_J + 2 * lift_mj],
                mode="markers",
                marker={"size": 7, "color": colour, "line": {"color": "black", "width": 1}},
                name=f"{text} ({at[0]:.1f}°, {at[1]:.1f}°), {ej * MJ_PER_J:.1f} mJ",
            )
        )
    el, az = np.deg2rad(elevation_deg), np.deg2rad(azimuth_deg)
    eye = 2.0 * np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    fig.update_layout(
        title={"text": title or "Energy landscape"},
        scene={
            "xaxis": {"title": {"text": PITCH_LABEL}},
            "yaxis": {"title": {"text": ROLL_LABEL}},
            "zaxis": {"title": {"text": "energy (mJ)"}},
            "aspectmode": "manual",
            "aspectratio": {"x": 1.0, "y": float(np.ptp(r) / np.ptp(p)), "z": 3 * RELIEF},
            "camera": {"eye": {"x": eye[0], "y": eye[1], "z": eye[2]}},
        },
        legend={"x": 0.0, "y": 1.0},
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
    )
    return fig


def export_landscape_html(
    energy_j: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    path: str | Path,
    *,
    minimum_deg: ArrayLike | None = None,
    minimum_j: float | None = None,
    saddle_deg: ArrayLike | None = None,
    saddle_j: float | None = None,
    path_deg: ArrayLike | None = None,
    path_j: ArrayLike | None = None,
    title: str = "",
    elevation_deg: float = 40.0,
    azimuth_deg: float = -55.0,
) -> Path:
    """Interactive HTML of the same scene as :func:`render_landscape` (arguments alike): one self-contained page
    that works offline (plotly.js is embedded, nothing is fetched), titled "Energy landscape: ``title``".

    Returns
    -------
    Path
        The HTML file written; parent folders are created.

    Raises
    ------
    ValueError
        If the arrays' shapes disagree or an energy is not finite.
    MissingDependencyError
        If plotly is not installed; nothing is written then.
    """
    import html

    fig = landscape_figure(
        energy_j,
        pitch_deg,
        roll_deg,
        minimum_deg=minimum_deg,
        minimum_j=minimum_j,
        saddle_deg=saddle_deg,
        saddle_j=saddle_j,
        path_deg=path_deg,
        path_j=path_j,
        title=title,
        elevation_deg=elevation_deg,
        azimuth_deg=azimuth_deg,
    )
    page = fig.to_html(
        include_plotlyjs=True,
        full_html=True,
        include_mathjax=False,
        config={"displaylogo": False, "responsive": True},
        default_height="95vh",
    )
    head = f"<head><title>{html.escape(_html_title(title))}</title>"
    if "<head>" not in page:
        raise RuntimeError("plotly wrote a page without <head>; cannot title it")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(page.replace("<head>", head, 1), encoding="utf-8")
    return path


# ------------------------------------------------------------------------------------------------ VTK file
def write_vtk(energy_j: ArrayLike, pitch_deg: ArrayLike, roll_deg: ArrayLike, path: str | Path) -> Path:
    """The landscape as a VTK structured grid (.vts) for ParaView.

    Points are (pitch, roll, 0) in degrees on the plane, with point data ``energy_j`` (J) and ``energy_mJ``;
    use ParaView's "Warp By Scalar" on ``energy_mJ`` for the relief. Points run pitch fastest (VTK order), so
    ``energy_j[i, j]`` is point ``i + P * j``.

    Parameters
    ----------
    energy_j : array_like of shape (P, R)
        Energy, J.
    pitch_deg, roll_deg : array_like of shape (P,) and (R,)
        Grid angles, degrees.
    path : path
        File to write; must end in ``.vts``.

    Returns
    -------
    Path

    Raises
    ------
    ValueError
        If the shapes disagree, an energy is not finite, or the suffix is not .vts.
    """
    pv = _pv()
    path = Path(path)
    if path.suffix != ".vts":
        raise ValueError(f"a structured grid is written as .vts; got {path.name!r}")
    e, p, r = _check_surface(energy_j, pitch_deg, roll_deg)
    pp, rr = np.meshgrid(p, r, indexing="ij")
    grid = pv.StructuredGrid(pp, rr, np.zeros_like(pp))
    grid.point_data["energy_j"] = e.ravel(order="F")
    grid.point_data["energy_mJ"] = e.ravel(order="F") * MJ_PER_J
    path.parent.mkdir(parents=True, exist_ok=True)
    grid.save(str(path))
    return path


# ------------------------------------------------------------------------------------------------ robot
def _on_top(pl, actors) -> None:
    """Move actors to an overlay layer that shares the camera, so they show through opaque surfaces."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    overlay = vtkRenderer()
    overlay.SetLayer(1)
    overlay.SetActiveCamera(pl.renderer.GetActiveCamera())
    overlay.InteractiveOff()
    for a in actors:
        pl.renderer.RemoveActor(a)
        overlay.AddActor(a)
    pl.render_window.SetNumberOfLayers(2)
    pl.render_window.AddRenderer(overlay)


def render_robot(
    meshes_world: Sequence[tuple[ArrayLike, ArrayLike]],
    path: str | Path,
    *,
    com_m: ArrayLike | None = None,
    title: str = "",
    off_screen: bool = True,
    window_size: tuple[int, int] = (1024, 768),
    elevation_deg: float = 12.0,
    azimuth_deg: float = 35.0,
) -> Path:
    """PNG of the robot's parts on a ground plane at z = 0.

    Parameters
    ----------
    meshes_world : sequence of (vertices_m, faces)
        One triangle mesh per part, already placed in the world frame: vertices (V, 3) in m with z up and
        the ground at z = 0; faces (F, 3) vertex indices.
    path : path
        PNG to write.
    com_m : array_like of shape (3,), optional
        Centre of mass in the world frame, m; drawn as a dot with a plumb line to the ground.
    title : str
        Text at the top left (may hold line breaks).
    off_screen : bool
        Render without a window.
    window_size : (int, int)
        Image width and height, pixels.
    elevation_deg, azimuth_deg : float
        Camera above the ground plane and round the vertical from the -y side, degrees.

    Returns
    -------
    Path

    Raises
    ------
    ValueError
        If no mesh is given or a face index is out of range.
    MissingDependencyError
        If pyvista is not installed.
    """
    pv = _pv()
    path = Path(path)
    if len(meshes_world) == 0:
        raise ValueError("meshes_world is empty; give at least one (vertices_m, faces) pair")
    polys = []
    for k, (v, f) in enumerate(meshes_world):
        v = np.asarray(v, dtype=np.float64).reshape(-1, 3)
        f = np.asarray(f, dtype=np.int64).reshape(-1, 3)
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ValueError(f"mesh {k}: face index out of range 0..{len(v) - 1}")
        polys.append(pv.PolyData.from_regular_faces(v, f))
    lo = np.min([m.bounds[::2] for m in polys], axis=0)
    hi = np.max([m.bounds[1::2] for m in polys], axis=0)
    size = float(max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]))
    centre = (lo + hi) / 2
    palette = ["#8da0cb", "#66c2a5", "#fc8d62", "#e78ac3", "#a6d854", "#ffd92f", "#e5c494", "#b3b3b3"]
    with _errors_only():
        pl = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
        pl.set_background("white")
        ground = pv.Plane(
            center=(centre[0], centre[1], 0.0),
            direction=(0, 0, 1),
            i_size=1.6 * size,
            j_size=1.6 * size,
            i_resolution=8,
            j_resolution=8,
        )
        pl.add_mesh(ground, color="#d9d9d9", show_edges=True, edge_color="#a0a0a0")
        for k, m in enumerate(polys):
            pl.add_mesh(m, color=palette[k % len(palette)], smooth_shading=False, specular=0.3)
        if com_m is not None:
            c = np.asarray(com_m, dtype=np.float64).reshape(3)
            dot = pl.add_points(
                c[None],
                color=START_COLOUR,
                point_size=16,
                render_points_as_spheres=True,
                label="centre of mass (drawn through the body)",
            )
            plumb = pl.add_mesh(pv.Line(c, (c[0], c[1], 0.0)), color=START_COLOUR, line_width=3)
            pl.add_legend(bcolor="white", border=True, size=(0.4, 0.06), loc="lower left", face="circle")
            _on_top(pl, [dot, plumb])
        if title:
            pl.add_text(title, position="upper_left", font_size=11, color="black")
        pl.camera_position = "xz"
        pl.camera.elevation = elevation_deg
        pl.camera.azimuth = azimuth_deg
        pl.reset_camera()
        pl.camera.zoom(1.5)
        return _screenshot(pl, path)


# ------------------------------------------------------------------------------------------------ 2-D contour map
def render_contour(
    energy_j: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    path: str | Path,
    *,
    minimum_deg: ArrayLike | None = None,
    saddle_deg: ArrayLike | None = None,
    saddle_j: float | None = None,
    path_deg: ArrayLike | None = None,
    title: str = "",
    levels: int = 24,
) -> Path:
    """Contour map of the landscape over pitch (x) and roll (y) with the marks, for papers (PNG, SVG, PDF).

    The format follows the suffix of ``path``. In SVG output the marks are groups with the ids
    ``start-minimum``, ``saddle``, ``saddle-level`` and ``barrier-path``.

    Parameters
    ----------
    energy_j : array_like of shape (P, R)
        Energy, J (shown in mJ).
    pitch_deg, roll_deg : array_like of shape (P,) and (R,)
        Grid angles, degrees.
    path : path
        Figure file.
    minimum_deg, saddle_deg : array_like of shape (2,), optional
        (pitch, roll) of the start minimum and the saddle, degrees.
    saddle_j : float, optional
        Energy of the saddle, J: drawn as a dashed contour, the level at which the start basin opens.
    path_deg : array_like of shape (L, 2), optional
        Barrier path (pitch, roll), degrees; rows of NaN break it.
    title : str
        Axes title.
    levels : int
        Number of filled contour levels.

    Returns
    -------
    Path

    Raises
    ------
    ValueError
        If the shapes disagree or an energy is not finite.
    """
    path = Path(path)
    e, p, r = _check_surface(energy_j, pitch_deg, roll_deg)
    mark, trail = _marks(minimum_deg, None, saddle_deg, None, path_deg, None)
    fig, ax = plt.subplots(figsize=(6.4, 5.2), dpi=150)
    e_mj = (e * MJ_PER_J).T  # rows = roll (y), columns = pitch (x)
    filled = ax.contourf(p, r, e_mj, levels=levels, cmap="viridis")
    ax.contour(p, r, e_mj, levels=filled.levels, colors="k", linewidths=0.3, alpha=0.5)
    fig.colorbar(filled, ax=ax, label="energy (mJ)", format="%.0f")
    if saddle_j is not None:
        level = ax.contour(
            p,
            r,
            e_mj,
            levels=[float(saddle_j) * MJ_PER_J],
            colors=SADDLE_COLOUR,
            linewidths=1.2,
            linestyles="--",
        )
        level.set_gid("saddle-level")
        ax.plot([], [], "--", color=SADDLE_COLOUR, lw=1.2, label=f"saddle level {saddle_j * MJ_PER_J:.1f} mJ")
    if trail is not None:
        (line,) = ax.plot(
            trail[0][:, 0], trail[0][:, 1], "-", color=PATH_COLOUR, lw=2.0, label="barrier path"
        )
        line.set_path_effects([patheffects.withStroke(linewidth=3.5, foreground="black")])
        line.set_gid("barrier-path")
    styles = {
        "minimum": ("start-minimum", "start minimum", "o", START_COLOUR),
        "saddle": ("saddle", "saddle", "X", SADDLE_COLOUR),
    }
    for name, (at, _) in mark.items():
        gid, text, marker, colour = styles[name]
        mark_point(ax, at, marker=marker, colour=colour, text=text, gid=gid)
    pitch_roll_axes(ax, p, r)
    ax.set_aspect("equal")
    if mark or trail is not None:
        ax.legend(loc="upper left", fontsize=7, framealpha=0.85)
    ax.set_title(title or "Potential-energy landscape")
    fig.tight_layout()
    return save(fig, path)
