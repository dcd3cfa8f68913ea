"""Trajectories on the landscape (edge layer): the body pitch-roll paths of self-righting attempts drawn over the
3-D landscape and its contour map, with the minimal-barrier saddle and path, attempts that righted in one colour
and those that did not in another.

Attempts come in as plain arrays, one (L, 2) array of (pitch, roll) in degrees per attempt and one righted flag
each, so simulated traces (:func:`read_trace_csv`, written by ``landscape simulate --trace``) and recorded physical
attempts plug in alike. An attempt's orientations may be on any branch (a trace reports ``|pitch| <= 90``): each
path is laid on the pitch-roll torus continuously, starting on the copy of the double cover nearest the drawn
start minimum, and broken where it wraps round +-180 (:func:`attempt_path_deg`).

It is one concept, attempts drawn over a landscape (traces read, paths drawn, simulated and recorded), hence
its length.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib.patheffects as patheffects
import numpy as np
from numpy.typing import ArrayLike, NDArray

from geometry.errors import UsageError
from landscape.viz._mpl import plt, save
from landscape.viz.scene import pose_label, wrapped_path_deg

__all__ = [
    "NOT_RIGHTED_COLOUR",
    "RIGHTED_COLOUR",
    "TraceFile",
    "TraceFileError",
    "attempt_path_deg",
    "check_trace_robot",
    "read_trace_csv",
    "render_trajectories",
    "render_trajectories_contour",
    "render_trajectories_landscape",
    "PhysicalPose",
    "physical_poses",
    "physical_robot_note",
    "trace_meta_lines",
]

RIGHTED_COLOUR = "#00d5ff"
NOT_RIGHTED_COLOUR = "#ffffff"
UPRIGHT_HOLD_S = 0.3
"""The trial's rule (``sim.trial.UPRIGHT_HOLD_S``): righted = upright (u_z < 0) without a break for this long."""
MASS_RTOL = 1e-3
MJ_PER_J = 1e3


class TraceFileError(UsageError):
    """A trace file that cannot be drawn (missing, not a trace, or of another robot or pose)."""


# ------------------------------------------------------------------------------------------------ layout
def attempt_path_deg(
    pitch_deg: ArrayLike, roll_deg: ArrayLike, *, start_near_deg: ArrayLike = (0.0, 0.0)
) -> NDArray[np.float64]:
    """One attempt's orientations as a path on the drawn pitch-roll square: continuous on the double cover,
    starting on the copy nearest ``start_near_deg``, moved into [-180, 180) with a NaN row wherever it wraps.

    Each orientation (p, r) is also (180 - p, r + 180); of the two, each step takes the one nearest the previous
    point (modulo 360), so a path through pitch +-90 (where a trace switches branch) stays unbroken.

    Parameters
    ----------
    pitch_deg, roll_deg : array_like of shape (L,)
        Body pitch and roll, degrees, any branch.
    start_near_deg : array_like of shape (2,)
        (pitch, roll) the path should start next to, degrees (the start minimum drawn).

    Returns
    -------
    path_deg : ndarray of shape (L + breaks, 2)

    Raises
    ------
    UsageError
        If the arrays differ in length, are empty, or hold a non-finite angle.

    Examples
    --------
    A somersault over the tail: the trace's pitch rises to 90 and falls again while its roll jumps by 180.

    >>> attempt_path_deg([80.0, 89.0, 88.0, 80.0], [0.0, 0.0, 180.0, 180.0]).tolist()
    [[80.0, 0.0], [89.0, 0.0], [92.0, 0.0], [100.0, 0.0]]
    >>> attempt_path_deg([0.0, 0.0, 0.0], [170.0, 179.0, -172.0]).tolist()
    [[0.0, 170.0], [0.0, 179.0], [nan, nan], [0.0, -172.0]]
    """
    p = np.asarray(pitch_deg, dtype=np.float64).reshape(-1)
    r = np.asarray(roll_deg, dtype=np.float64).reshape(-1)
    if len(p) != len(r) or len(p) == 0:
        raise UsageError(
            f"an attempt needs as many pitch as roll angles, at least one; got {len(p)} and {len(r)}"
        )
    if not (np.isfinite(p).all() and np.isfinite(r).all()):
        raise UsageError("an attempt's pitch and roll angles must be finite degrees")
    near = np.asarray(start_near_deg, dtype=np.float64).reshape(2)
    twins = np.stack([np.column_stack([p, r]), np.column_stack([180.0 - p, r + 180.0])], axis=1)  # (L, 2, 2)

    def step(frm, cands):
        d = (cands - frm + 180.0) % 360.0 - 180.0
        k = int(np.argmin(np.hypot(d[:, 0], d[:, 1])))
        return d[k]

    out = np.zeros((len(p), 2))
    out[0] = near + step(near, twins[0])
    for i in range(1, len(p)):
        out[i] = out[i - 1] + step(out[i - 1], twins[i])
    return wrapped_path_deg(out)


# ------------------------------------------------------------------------------------------------ trace files
@dataclass(frozen=True)
class TraceFile:
    """A trial trace read from CSV.

    Attributes
    ----------
    path : Path
    columns : dict of str to ndarray of shape (N,)
        The columns of :attr:`sim.trial.Trace.COLUMNS`.
    theta_w_deg, theta_l_deg : float
        The trial's wing angle and leg amplitude, deg (from the file's notes, else the largest commands).
    righted : bool
        Whether the trial righted (from the file's notes, else the trial's rule on ``up_z``).
    robot_hash : str or None
        The simulated robot's hash, when the file records it.
    mass_kg : float
        The robot's mass, ``energy_j / (g com_height_m)``, kg.
    """

    path: Path
    columns: dict
    theta_w_deg: float
    theta_l_deg: float
    righted: bool
    robot_hash: str | None
    mass_kg: float

    @property
    def pitch_deg(self) -> NDArray[np.float64]:
        return self.columns["pitch_deg"]

    @property
    def roll_deg(self) -> NDArray[np.float64]:
        return self.columns["roll_deg"]


def trace_meta_lines(*, robot_hash: str, theta_w_deg: float, theta_l_deg: float, righted: bool) -> list[str]:
    """The notes ``landscape simulate --trace`` writes below a trace's header, read back by :func:`read_trace_csv`.

    Examples
    --------
    >>> trace_meta_lines(robot_hash="ab12", theta_w_deg=74.0, theta_l_deg=30.0, righted=True)
    ['# robot_hash=ab12', '# theta_w_deg=74', '# theta_l_deg=30', '# righted=1']
    """
    return [
        f"# robot_hash={robot_hash}",
        f"# theta_w_deg={theta_w_deg:.17g}",
        f"# theta_l_deg={theta_l_deg:.17g}",
        f"# righted={int(bool(righted))}",
    ]


def _righted_by_rule(t_s: NDArray[np.float64], up_z: NDArray[np.float64]) -> bool:
    """The trial's outcome rule applied to a trace: upright (u_z < 0) over its last ``UPRIGHT_HOLD_S``."""
    if not len(t_s) or up_z[-1] >= 0:
        return False
    up = np.flatnonzero(up_z >= 0)
    since = t_s[up[-1] + 1] if len(up) else t_s[0]
    sample = float(np.median(np.diff(t_s))) if len(t_s) > 1 else 0.0
    return t_s[-1] - since >= UPRIGHT_HOLD_S - sample - 1e-9


def read_trace_csv(path: str | Path, *, g_m_s2: float = 9.81) -> TraceFile:
    """Read a trace written by ``landscape simulate --trace FILE``.

    Raises
    ------
    TraceFileError
        If the file is missing, unreadable, not a trace (wrong header, non-numeric or empty rows).
    """
    from sim.trial import Trace

    path = Path(path)
    if not path.is_file():
        raise TraceFileError(
            f"trace file {path} not found; write one with `landscape simulate ... --trace {path}`"
        )
    try:
        lines = path.read_text().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise TraceFileError(
            f"trace file {path} cannot be read ({exc}); give a CSV from `landscape simulate --trace`"
        ) from None
    header = lines[0].strip().split(",") if lines else []
    if tuple(header) != Trace.COLUMNS:
        raise TraceFileError(
            f"{path} is not a trial trace: its header is {','.join(header)[:80]!r}, expected "
            f"{','.join(Trace.COLUMNS)!r}; write one with `landscape simulate --trace`"
        )
    meta, rows = {}, []
    for n, line in enumerate(lines[1:], start=2):
        if line.startswith("#"):
            key, _, value = line[1:].strip().partition("=")
            meta[key.strip()] = value.strip()
            continue
        if not line.strip():
            continue
        try:
            row = [float(x) for x in line.split(",")]
        except ValueError:
            row = []
        if len(row) != len(Trace.COLUMNS) or not all(map(math.isfinite, row)):
            raise TraceFileError(
                f"{path} line {n}: expected {len(Trace.COLUMNS)} finite numbers, got {line[:60]!r}"
            )
        rows.append(row)
    if not rows:
        raise TraceFileError(f"{path} has no rows; the trial recorded nothing (run it for at least 10 ms)")
    a = np.asarray(rows)
    cols = {c: a[:, k].copy() for k, c in enumerate(Trace.COLUMNS)}
    if len(a) > 1 and not (np.diff(cols["t_s"]) > 0).all():
        raise TraceFileError(
            f"{path}: times t_s are not increasing; is it a trace from `landscape simulate`?"
        )
    try:
        tw = float(meta["theta_w_deg"]) if "theta_w_deg" in meta else float(cols["wing_cmd_deg"].max())
        tl = float(meta["theta_l_deg"]) if "theta_l_deg" in meta else float(np.abs(cols["leg_cmd_deg"]).max())
        righted = (
            bool(int(meta["righted"])) if "righted" in meta else _righted_by_rule(cols["t_s"], cols["up_z"])
        )
    except ValueError:
        raise TraceFileError(f"{path}: a '# key=value' note is not a number: {meta}") from None
    h = cols["com_height_m"]
    ok = h > 1e-6
    mass = float(np.median(cols["energy_j"][ok] / (g_m_s2 * h[ok]))) if ok.any() else float("nan")
    return TraceFile(path, cols, tw, tl, righted, meta.get("robot_hash") or None, mass)


def check_trace_robot(trace: TraceFile, *, robot_hash: str, mass_kg: float, robot_name: str) -> None:
    """Refuse a trace of another robot: by its recorded robot hash, or, for a file without one, by its mass.

    Raises
    ------
    TraceFileError
    """
    if trace.robot_hash is not None and trace.robot_hash != robot_hash:
        raise TraceFileError(
            f"{trace.path} was simulated with another robot (hash {trace.robot_hash}) than "
            f"{robot_name} ({robot_hash}); give the --robot and --joints the trial ran with"
        )
    if not abs(trace.mass_kg - mass_kg) <= MASS_RTOL * mass_kg:
        raise TraceFileError(
            f"{trace.path} is of another robot: its energies and heights give a mass of "
            f"{trace.mass_kg * 1e3:.1f} g, {robot_name} has {mass_kg * 1e3:.1f} g; give the "
            "--robot the trial ran with"
        )


# ------------------------------------------------------------------------------------------------ figures
def _attempts(paths_deg, righted):
    paths = [np.asarray(p, dtype=np.float64).reshape(-1, 2) for p in paths_deg]
    flags = [bool(x) for x in righted]
    if len(paths) != len(flags):
        raise UsageError(f"give one righted flag per attempt; got {len(flags)} for {len(paths)} attempts")
    if not paths:
        raise UsageError("no attempts to draw; give at least one trace or attempt")
    return paths, flags


def _label(flag: bool, flags: list[bool]) -> str:
    n = sum(f == flag for f in flags)
    return f"{'righted' if flag else 'not righted'} ({n} attempt{'s' if n != 1 else ''})"


def render_trajectories_contour(
    energy_j: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    path: str | Path,
    *,
    paths_deg: Sequence[ArrayLike],
    righted: Sequence[bool],
    minimum_deg: ArrayLike | None = None,
    saddle_deg: ArrayLike | None = None,
    barrier_path_deg: ArrayLike | None = None,
    title: str = "",
    levels: int = 24,
) -> Path:
    """Contour map of the landscape (mJ) with the attempts' paths, the start minimum, the saddle and the barrier
    path (PNG, SVG or PDF by the suffix; in SVG the paths are groups ``attempt-K-righted`` or
    ``attempt-K-not-righted``).

    Parameters
    ----------
    energy_j : array_like of shape (P, R)
        Energy, J.
    pitch_deg, roll_deg : array_like of shape (P,) and (R,)
        Grid angles, degrees.
    path : path
        Figure file.
    paths_deg : sequence of array_like of shape (L_k, 2)
        Each attempt's (pitch, roll), degrees, within the grid; rows of NaN break it (:func:`attempt_path_deg`).
    righted : sequence of bool
        One flag per attempt.
    minimum_deg, saddle_deg : array_like of shape (2,), optional
        Start minimum and saddle, degrees.
    barrier_path_deg : array_like of shape (M, 2), optional
        Minimal-barrier path, degrees; rows of NaN break it.

    Returns
    -------
    Path

    Raises
    ------
    UsageError
        If no attempt is given or the flags do not match the attempts.
    ValueError
        If the grid's shapes disagree or an energy is not finite.
    """
    from landscape.viz import render as rd

    paths, flags = _attempts(paths_deg, righted)
    e, p, r = rd._check_surface(energy_j, pitch_deg, roll_deg)
    fig, ax = plt.subplots(figsize=(6.4, 5.2), dpi=150)
    e_mj = (e * MJ_PER_J).T
    filled = ax.contourf(p, r, e_mj, levels=levels, cmap="viridis")
    ax.contour(p, r, e_mj, levels=filled.levels, colors="k", linewidths=0.3, alpha=0.5)
    fig.colorbar(filled, ax=ax, label="energy (mJ)", format="%.0f")
    labelled = set()
    for k, (pd, ok) in enumerate(zip(paths, flags, strict=True)):
        (line,) = ax.plot(
            pd[:, 0],
            pd[:, 1],
            "-",
            color=RIGHTED_COLOUR if ok else NOT_RIGHTED_COLOUR,
            lw=1.0,
            alpha=0.9,
            label=None if ok in labelled else _label(ok, flags),
        )
        line.set_path_effects([patheffects.withStroke(linewidth=2.0, foreground="black")])
        line.set_gid(f"attempt-{k + 1}-{'righted' if ok else 'not-righted'}")
        labelled.add(ok)
    if barrier_path_deg is not None:
        bp = np.asarray(barrier_path_deg, dtype=np.float64).reshape(-1, 2)
        (line,) = ax.plot(bp[:, 0], bp[:, 1], "-", color=rd.PATH_COLOUR, lw=2.0, label="minimal-barrier path")
        line.set_path_effects([patheffects.withStroke(linewidth=3.5, foreground="black")])
        line.set_gid("barrier-path")
    for gid, text, marker, colour, at in (
        ("start-minimum", "start minimum", "o", rd.START_COLOUR, minimum_deg),
        ("saddle", "saddle", "X", rd.SADDLE_COLOUR, saddle_deg),
    ):
        if at is None:
            continue
        rd.mark_point(
            ax, np.asarray(at, dtype=np.float64).reshape(2), marker=marker, colour=colour, text=text, gid=gid
        )
    rd.pitch_roll_axes(ax, p, r)
    ax.set_xlim(p.min(), p.max())
    ax.set_ylim(r.min(), r.max())
    ax.set_aspect("equal")
    leg = ax.legend(loc="upper left", fontsize=7, framealpha=0.85)
    leg.get_frame().set_facecolor("#bdbdbd")
    ax.set_title(title or "Self-righting attempts on the landscape", fontsize=9)
    fig.tight_layout()
    return save(fig, path)


def render_trajectories_landscape(
    energy_j: ArrayLike,
    pitch_deg: ArrayLike,
    roll_deg: ArrayLike,
    path: str | Path,
    *,
    paths_deg: Sequence[ArrayLike],
    paths_j: Sequence[ArrayLike],
    righted: Sequence[bool],
    title: str = "",
    window_size: tuple[int, int] = (1280, 960),
    **marks,
) -> Path:
    """PNG of the 3-D landscape (:func:`landscape.viz.render.render_landscape`, whose marks ``marks`` are passed
    on) with each attempt's path on the surface.

    Parameters
    ----------
    paths_deg : sequence of array_like of shape (L_k, 2)
        Each attempt's (pitch, roll), degrees; rows of NaN break it.
    paths_j : sequence of array_like of shape (L_k,)
        The landscape's energy along each path, J (NaN on the break rows).
    righted : sequence of bool

    Raises
    ------
    UsageError
        If no attempt is given, or the flags or energies do not match the attempts.
    MissingDependencyError
        If pyvista is not installed.
    """
    from landscape.viz import render as rd

    paths, flags = _attempts(paths_deg, righted)
    energies = [np.asarray(j, dtype=np.float64).reshape(-1) for j in paths_j]
    if [len(j) for j in energies] != [len(pd) for pd in paths]:
        raise UsageError("give one energy per point of every attempt's path")
    pv = rd._pv()
    path = Path(path)
    e = np.asarray(energy_j, dtype=np.float64)
    lo_mj, span_mj = float(e.min()) * MJ_PER_J, float(np.ptp(e)) * MJ_PER_J or 1.0
    base_deg = float(
        max(np.ptp(np.asarray(pitch_deg, dtype=np.float64)), np.ptp(np.asarray(roll_deg, dtype=np.float64)))
    )
    z_per_mj = rd.RELIEF * base_deg / span_mj  # the scene's scale, as _landscape_plotter sets it
    lift = 0.006 * base_deg
    with rd._errors_only():
        pl = rd._landscape_plotter(
            energy_j,
            pitch_deg,
            roll_deg,
            title=title,
            off_screen=True,
            window_size=window_size,
            elevation_deg=marks.pop("elevation_deg", 40.0),
            azimuth_deg=marks.pop("azimuth_deg", -55.0),
            **{
                k: marks.get(k)
                for k in ("minimum_deg", "minimum_j", "saddle_deg", "saddle_j", "path_deg", "path_j")
            },
        )
        try:
            labelled = set()
            for pd, pj, ok in zip(paths, energies, flags, strict=True):
                for sl in rd._pieces(pd):
                    if sl.stop - sl.start < 2:
                        continue
                    pts = np.column_stack([pd[sl], (pj[sl] * MJ_PER_J - lo_mj) * z_per_mj + lift])
                    pl.add_mesh(
                        pv.lines_from_points(pts),
                        color=RIGHTED_COLOUR if ok else NOT_RIGHTED_COLOUR,
                        line_width=3,
                        render_lines_as_tubes=True,
                        label=None if ok in labelled else _label(ok, flags),
                    )
                    labelled.add(ok)
            pl.add_legend(bcolor="#bdbdbd", border=True, size=(0.42, 0.2), loc="upper left", face="circle")
        except BaseException:
            pl.close()
            raise
        return rd._screenshot(pl, path)


def render_trajectories(
    c,
    paths_deg: Sequence[ArrayLike],
    righted: Sequence[bool],
    out_dir: str | Path,
    *,
    robot_name: str,
    exit_kind: str = "righting",
    what: str = "simulated",
    landscape_3d: bool = True,
) -> list[Path]:
    """The attempts of one pose over its landscape: ``trajectories.png`` (3-D), ``trajectories_contour.png`` and
    ``.svg``, in ``out_dir``.

    Parameters
    ----------
    c : landscape.computation.Computation
        The landscape of the attempts' (theta_w, theta_l) (``landscape.compute``).
    paths_deg : sequence of array_like of shape (L_k, 2)
        Each attempt's body (pitch, roll), degrees, any branch, in time order (e.g. a trace's ``pitch_deg`` and
        ``roll_deg`` side by side, or a physical attempt's).
    righted : sequence of bool
        Whether each attempt righted.
    robot_name : str
        For the title.
    exit_kind : str
        Which barrier's saddle and path to mark (:data:`landscape.barriers.EXITS`).
    what : str
        Word for the attempts in the title ("simulated", "physical").
    landscape_3d : bool
        Also draw the 3-D ``trajectories.png`` (False: the contour maps only, e.g. where
        :func:`landscape.viz.render.off_screen_problem` says 3-D rendering cannot run).

    Returns
    -------
    list of Path
        The contour map (PNG, SVG) first, then the 3-D PNG (if ``landscape_3d``).

    Raises
    ------
    UsageError
        If no attempt is given, a flag is missing, or an angle is not finite.
    UsageError (geometry.errors)
        If 3-D rendering cannot run here; the contour maps are written first and named.
    """
    from landscape.barriers import EXITS
    from landscape.energy import height_at
    from landscape.viz import render as rd
    from landscape.viz.scene import landscape_marks

    raw, flags = _attempts(paths_deg, righted)
    marks = landscape_marks(c, exit_kind)
    start = marks["minimum_deg"]
    paths = [attempt_path_deg(a[:, 0], a[:, 1], start_near_deg=start) for a in raw]
    mg = c.mass_kg * c.landscape.g_m_s2
    energies = []
    for pd in paths:
        pj = np.full(len(pd), np.nan)
        ok = np.isfinite(pd[:, 0])
        pj[ok] = mg * height_at(c.pose, pd[ok, 0], pd[ok, 1])
        energies.append(pj)
    ex = getattr(c.barrier, EXITS[exit_kind])
    n_ok = sum(flags)
    barrier = (
        f"{exit_kind} barrier none" if ex is None else f"{exit_kind} barrier {ex.barrier_j * 1e3:.2f} mJ"
    )
    title = (
        f"{robot_name}  {pose_label(c)}  {barrier}\n"
        f"{len(flags)} {what} attempts: {n_ok} righted, {len(flags) - n_ok} not"
    )
    angles_deg, energy_j = c.landscape.inclusive()
    outd = Path(out_dir)
    written = [
        render_trajectories_contour(
            energy_j,
            angles_deg,
            angles_deg,
            outd / f"trajectories_contour.{s}",
            paths_deg=paths,
            righted=flags,
            minimum_deg=start,
            saddle_deg=marks["saddle_deg"],
            barrier_path_deg=marks["path_deg"],
            title=title,
        )
        for s in ("png", "svg")
    ]
    if not landscape_3d:
        return written
    problem = rd.off_screen_problem()
    if problem is not None:
        raise UsageError(f"{problem} (wrote only {', '.join(p.name for p in written)} in {outd})")
    written.append(
        render_trajectories_landscape(
            energy_j,
            angles_deg,
            angles_deg,
            outd / "trajectories.png",
            paths_deg=paths,
            paths_j=energies,
            righted=flags,
            title=title,
            **marks,
        )
    )
    return written


# ------------------------------------------------------------------------------------------------ physical robot
@dataclass(frozen=True)
class PhysicalPose:
    """The physical robot's recorded attempts at one commanded wing angle, and the pose to draw them on.

    Attributes
    ----------
    theta_w_cmd_deg : float
        Commanded wing angle, degrees.
    theta_w_deg : float
        The landscape's wing angle, degrees: the measured wing plateau to 0.1 degree, else the command.
    plateau_measured : bool
        Whether ``theta_w_deg`` is the measured plateau (False: none was recorded, it is the command).
    theta_l_deg : float
        The trials' leg amplitude, degrees (the landscape is drawn at theta_l 0, the leg's mean position).
    attempts : tuple of landscape.analysis.physical.attempts.PhysicalAttempt
    """

    theta_w_cmd_deg: float
    theta_w_deg: float
    plateau_measured: bool
    theta_l_deg: float
    attempts: tuple

    @property
    def note(self) -> str | None:
        """What to tell the reader when the landscape is not at the measured plateau."""
        if self.plateau_measured:
            return None
        return f"no measured wing plateau (robot_attempts.mat) for {self.theta_w_cmd_deg:g}°: landscape at the command"


def physical_poses(
    data_dir: str | Path, *, commands_deg: Sequence[float], theta_l_deg: float = 0.0
) -> list[PhysicalPose]:
    """The recorded attempts at each commanded wing angle (:func:`landscape.analysis.physical.attempts.physical_attempts`),
    all read before anything is drawn, with the landscape pose of each (``landscape render --physical`` and the
    report's physical section).

    Raises
    ------
    PhysicalDataError
        If the directory or a file is not in the lab's format, or no trial has a wing command and leg amplitude
        asked for (the message lists those recorded).
    """
    from landscape.analysis.physical.attempts import physical_attempts

    out = []
    for cmd in commands_deg:
        attempts = physical_attempts(data_dir, theta_w_cmd_deg=cmd, theta_l_deg=theta_l_deg)
        plateau = round(attempts[0].theta_w_measured_deg, 1)  # the servo's plateau, to 0.1 deg
        measured = math.isfinite(plateau)
        out.append(
            PhysicalPose(
                float(cmd), plateau if measured else float(cmd), measured, float(theta_l_deg), tuple(attempts)
            )
        )
    return out


def physical_robot_note(robot, theta_l_deg: float = 0.0) -> list[str]:
    """Notes for physical attempts drawn over ``robot``'s landscape: the attempts are the lab robot's, and a leg
    that oscillated is drawn at its mean position."""
    notes = []
    if robot.source is None or "lab" not in robot.name:
        notes.append(
            f"the recorded attempts are of the lab's robot, drawn over {robot.name}'s landscape; "
            "give --robot ../shared/ref/lab_robot/lab_robot.urdf for the lab robot's"
        )
    if theta_l_deg:
        notes.append(
            f"the trials' leg oscillates by ±{theta_l_deg:g}°; the landscape is at theta_l 0, the leg's mean position"
        )
    return notes


@dataclass(frozen=True)
class PhysicalRender:
    """What :func:`render_physical` drew for one commanded wing angle.

    Attributes
    ----------
    pose : PhysicalPose
        The command, the landscape's wing angle and the recorded attempts drawn.
    out_dir : pathlib.Path
        Where its files are.
    files : list of pathlib.Path
        The landscape's files, then the attempts' paths over it.
    notes : list of str
        What the reader should know about this landscape.
    """

    pose: PhysicalPose
    out_dir: Path
    files: list
    notes: list

    @property
    def summary(self) -> str:
        """One line: the command, the plateau, the attempts and trials drawn, and the files written."""
        a = self.pose.attempts
        return (
            f"wing {self.pose.theta_w_cmd_deg:g}° (measured plateau {self.pose.theta_w_deg:.1f}°), leg "
            f"{self.pose.theta_l_deg:g}°: {len(a)} attempts of {len({x.name for x in a})} trials, "
            f"{sum(x.righted for x in a)} righted; wrote {', '.join(p.name for p in self.files)} in {self.out_dir}"
        )


def render_physical(
    robot,
    poses: Sequence[PhysicalPose],
    out: str | Path,
    *,
    step_deg: float,
    method: str,
    exit_kind: str,
    one_dir: bool,
    memory_budget_bytes: int | None = None,
) -> list[PhysicalRender]:
    """Per commanded wing angle, the landscape at the pose's wing angle (the measured plateau) and theta_l 0, its
    files, and the recorded attempts drawn over it (``landscape render --physical``).

    Parameters
    ----------
    robot : geometry.Robot
    poses : sequence of PhysicalPose
        From :func:`physical_poses`, read before anything is drawn.
    out : path
        Output directory; with ``one_dir`` False each command gets ``out/wing_<command>``.
    step_deg, method, exit_kind :
        As :func:`landscape.computation.compute` and :func:`landscape.viz.scene.render_computation`.
    one_dir : bool
        Write into ``out`` itself (one command asked for).
    memory_budget_bytes : int, optional
        Passed to :func:`landscape.computation.compute`.

    Returns
    -------
    list of PhysicalRender
    """
    from landscape.computation import compute
    from landscape.viz.scene import render_computation

    done = []
    for pose in poses:
        c = compute(
            robot,
            theta_w_deg=pose.theta_w_deg,
            theta_l_deg=0.0,
            step_deg=step_deg,
            method=method,
            memory_budget_bytes=memory_budget_bytes,
        )
        od = Path(out) if one_dir else Path(out) / f"wing_{pose.theta_w_cmd_deg:g}"
        files, notes = render_computation(c, od, robot_name=robot.name, exit_kind=exit_kind)
        files += render_trajectories(
            c,
            [np.column_stack([a.pitch_deg, a.roll_deg]) for a in pose.attempts],
            [a.righted for a in pose.attempts],
            od,
            robot_name=robot.name,
            exit_kind=exit_kind,
            what="physical",
        )
        done.append(PhysicalRender(pose, od, files, ([pose.note] if pose.note else []) + list(notes)))
    return done
