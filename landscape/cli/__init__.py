"""The ``landscape`` command. Parses, validates, calls one library function, writes files.

Bad input exits with status 2 and one line on stderr (``landscape: error: ...``), never a traceback.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import click
import numpy as np

from geometry import JointMap, Robot

from .options import InputError, parse_values

MJ = 1e3
MM = 1e3


def _finite(value: float | None, name: str) -> float | None:
    if value is not None and not np.isfinite(value):
        raise InputError(f"--{name} must be a finite number; got {value!r}")
    return value


def load_robot(robot: str | None, mesh: str | None, *, com: str | None = None, mass: float = 1.0,
               units: str = "m", com_model: str = "auto", joints: str | None = None) -> Robot:
    """The robot the options describe: a URDF, a single mesh, or the built-in robot."""
    if robot and mesh:
        raise InputError("give either --robot FILE.urdf or --mesh FILE, not both")
    if mesh:
        c = None
        if com is not None:
            try:
                c = [float(x) for x in com.split(",")]
            except ValueError:
                raise InputError(f"--com must be X,Y,Z in the mesh's units; got {com!r}") from None
            if len(c) != 3:
                raise InputError(f"--com must be three numbers X,Y,Z; got {com!r}")
        _finite(mass, "mass")
        return Robot.from_mesh(mesh, mass_kg=mass, com=c, units=units, com_model=com_model)
    jm = JointMap.parse(joints) if joints else None
    if robot:
        return Robot.from_urdf(robot, joint_map=jm)
    from geometry.builtin import builtin_urdf_path

    return Robot.from_urdf(builtin_urdf_path(), joint_map=jm)


def robot_options(f):
    """Options shared by every command that takes a robot."""
    opts = [
        click.option("--robot", type=str, default=None, help="URDF file (default: the built-in robot)."),
        click.option("--mesh", type=str, default=None, help="A single rigid body: any mesh file trimesh reads."),
        click.option("--com", type=str, default=None, help="With --mesh: CoM X,Y,Z in the mesh's units."),
        click.option("--mass", type=float, default=1.0, show_default=True, help="With --mesh: mass, kg."),
        click.option("--units", type=click.Choice(["mm", "cm", "m"]), default="m", show_default=True,
                     help="With --mesh: units of the mesh file."),
        click.option("--com-model", type=click.Choice(["auto", "solid", "shell"]), default="auto",
                     show_default=True,
                     help="With --mesh and no --com: solid (closed mesh), shell (thin surface) or auto."),
        click.option("--joints", type=str, default=None,
                     help="Joint map 'wing=J1,J2,...;leg=J' for a URDF whose joint names differ."),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def _robot_from(kw) -> Robot:
    return load_robot(kw["robot"], kw["mesh"], com=kw["com"], mass=kw["mass"], units=kw["units"],
                      com_model=kw["com_model"], joints=kw["joints"])


# ----------------------------------------------------------------------------------------------- commands
@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="selfrighting-landscape")
def cli():
    """Potential-energy landscapes, self-righting barriers and self-righting trials of legged/winged robots.

    Angles are degrees, energies are reported in mJ (files: J), lengths in mm (files: m).
    """


def _fmt_exit(name: str, x, mg: float) -> str:
    if x is None:
        return f"  {name:<12} none"
    return (f"  {name:<12} {x.barrier_j * MJ:9.3f} mJ  = CoM lift {x.barrier_j / mg * MM:7.3f} mm   "
            f"saddle ({x.saddle_pitch_deg:7.2f}, {x.saddle_roll_deg:7.2f})  {x.direction}")


def human_summary(c, robot: Robot) -> str:
    mg = c.mass_kg * c.landscape.g_m_s2
    tw = "-" if c.theta_w_deg is None else f"{c.theta_w_deg:g}°"
    tl = "-" if c.theta_l_deg is None else f"{c.theta_l_deg:g}°"
    lines = [
        f"robot        {robot.name}  ({robot.source or 'in memory'})",
        f"pose         theta_w {tw}  theta_l {tl}   grid step {c.step_deg:g}°   method {c.method}",
        f"mass         {c.mass_kg * 1e3:.1f} g",
        "CoM          ({:.2f}, {:.2f}, {:.2f}) mm  ({})".format(*(c.com_m * MM), robot.com_source),
        f"minimum      pitch {c.minimum.pitch_deg:.2f}°  roll {c.minimum.roll_deg:.2f}°  "
        f"E {c.minimum.energy_j * MJ:.3f} mJ  h {c.minimum.height_m * MM:.3f} mm",
        "barriers     (pitch, roll) of the saddle in degrees",
        _fmt_exit("righting", c.barrier.righting, mg),
        _fmt_exit("pitch-wise", c.barrier.pitch_wise, mg),
        _fmt_exit("roll-wise", c.barrier.roll_wise, mg),
        _fmt_exit("escape", c.barrier.escape, mg),
        "timing       " + "  ".join(f"{k} {v * 1e3:.1f} ms" for k, v in c.timing_s.items()),
    ]
    return "\n".join(lines)


@cli.command()
@click.option("--theta-w", type=float, default=0.0, show_default=True, help="Wing angle, degrees.")
@click.option("--theta-l", type=float, default=0.0, show_default=True, help="Leg angle, degrees.")
@click.option("--step", type=float, default=1.0, show_default=True, help="Grid step, degrees; divides 360.")
@click.option("--start-pitch", type=float, default=None, help="Start by descent from this pitch, degrees.")
@click.option("--start-roll", type=float, default=None, help="Start by descent from this roll, degrees.")
@click.option("--connectivity", type=click.Choice(["8", "4"]), default="8", show_default=True)
@click.option("--method", type=click.Choice(["exact", "grid", "sphere"]), default="exact", show_default=True,
              help="exact: no discretisation error (hull face-edge graph); grid: the paper's grid search on "
                   "the pitch-roll torus; sphere: the same search on an icosphere spaced about --step apart.")
@robot_options
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="Write landscape.npz, landscape.csv and summary.json here.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of the table.")
def compute(theta_w, theta_l, step, start_pitch, start_roll, connectivity, method, out, as_json, **kw):
    """Landscape, start minimum and minimal barriers at one (theta_w, theta_l)."""
    from . import io
    from .compute import compute as run

    for name, v in (("theta-w", theta_w), ("theta-l", theta_l), ("step", step), ("start-pitch", start_pitch),
                    ("start-roll", start_roll)):
        _finite(v, name)
    robot = _robot_from(kw)
    c = run(robot, theta_w_deg=theta_w, theta_l_deg=theta_l, step_deg=step, start_pitch_deg=start_pitch,
            start_roll_deg=start_roll, connectivity=int(connectivity), method=method)
    s = io.summary(c, robot_name=robot.name, robot_source=str(robot.source) if robot.source else None,
                   robot_hash=robot.description_hash, com_source=robot.com_source)
    if out:
        io.write_computation(c, s, Path(out))
    if as_json:
        s = dict(s)
        s.pop("paths")
        click.echo(json.dumps(s))
    else:
        click.echo(human_summary(c, robot))
        if out:
            click.echo(f"wrote        {out}/landscape.npz, landscape.csv, summary.json")


@cli.command("barrier-map")
@click.option("--theta-w", "theta_w", type=str, default="70:76:2", show_default=True,
              help="Wing angles: list 70,72 or range START:STOP:STEP (inclusive), degrees.")
@click.option("--theta-l", "theta_l", type=str, default="20:50:10", show_default=True,
              help="Leg angles: list or range, degrees.")
@click.option("--step", type=float, default=1.0, show_default=True, help="Grid step, degrees.")
@click.option("--method", type=click.Choice(["exact", "grid", "sphere"]), default="exact", show_default=True)
@robot_options
@click.option("--out", type=click.Path(file_okay=False), default="barrier-map", show_default=True)
def barrier_map(theta_w, theta_l, step, method, out, **kw):
    """Minimal barrier over theta_w x theta_l: CSV and heat map (the source paper's Fig. 5)."""
    from tqdm import tqdm

    from . import io, plots
    from .compute import compute as run
    from .compute import sweep_starts

    ws, ls_ = parse_values(theta_w, "theta-w"), parse_values(theta_l, "theta-l")
    robot = _robot_from(kw)
    if not robot.has_joints:
        raise InputError("barrier-map needs a robot with joints (--robot FILE.urdf or the built-in robot)")
    for w in ws:
        for leg in ls_:
            robot.joint_values_rad(w, leg)
    from .grid import cells_per_turn

    cells_per_turn(step)
    t0 = time.perf_counter()
    starts = sweep_starts(robot, ws, ls_)
    rows = []
    grid = np.full((len(ws), len(ls_)), np.nan)
    with tqdm(total=len(ws) * len(ls_), desc="barrier-map", unit="pose", file=sys.stderr,
              disable=None) as bar:
        for i, w in enumerate(ws):
            for j, leg in enumerate(ls_):
                c = run(robot, theta_w_deg=w, theta_l_deg=leg, step_deg=step, start_deg=starts[(w, leg)],
                        method=method)
                b = c.barrier
                r = b.righting
                grid[i, j] = np.nan if r is None else r.barrier_j * MJ
                rows.append({"theta_w_deg": w, "theta_l_deg": leg, "min_pitch_deg": c.minimum.pitch_deg,
                             "min_roll_deg": c.minimum.roll_deg, "min_energy_j": c.minimum.energy_j,
                             **io.barrier_fields(b)})
                bar.update()
    outd = Path(out)
    csv_path = io.write_rows_csv(rows, outd / "barrier_map.csv")
    png = plots.render_barrier_map(ws, ls_, grid, outd / "barrier_map.png",
                                   title=f"Minimal righting barrier, {robot.name}, "
                                         + ("exact" if method == "exact" else f"{step:g}° grid"))
    click.echo(f"{len(rows)} poses in {time.perf_counter() - t0:.2f} s; "
               f"righting barrier {np.nanmin(grid):.3f} .. {np.nanmax(grid):.3f} mJ")
    click.echo(f"wrote {csv_path} and {png}")


@cli.group()
def robot():
    """The built-in robot."""


@robot.command("export")
@click.option("--out", type=click.Path(file_okay=False), required=True, help="Directory for URDF + meshes.")
def robot_export(out):
    """Write the built-in robot's URDF and meshes (the same files the landscape and pybullet load)."""
    from geometry.builtin import builtin_description

    outd = Path(out)
    outd.mkdir(parents=True, exist_ok=True)
    files = builtin_description()
    for name, data in files.items():
        (outd / name).write_bytes(data)
    click.echo(f"wrote {len(files)} files to {outd} (URDF: {outd / 'robot.urdf'})")


@cli.command()
@click.argument("what", type=click.Choice(["landscape"]), default="landscape")
@click.option("--theta-w", type=float, default=74.0, show_default=True)
@click.option("--repeat", type=int, default=20, show_default=True, help="Timed repetitions of the fast methods.")
@robot_options
def bench(what, theta_w, repeat, **kw):
    """Speed and memory against the lab's brute-force method, measured in this run, as ratios."""
    from .bench import landscape_bench

    robot = _robot_from(kw)
    click.echo(landscape_bench(robot, theta_w_deg=theta_w, repeat=repeat))


# ----------------------------------------------------------------------------------------------- entry point
def _register_optional():
    from . import cli_render  # noqa: F401  (registers the render command; works in either import order)

    try:
        from . import cli_sim
    except ImportError:
        return
    for name in ("simulate", "sweep", "export"):  # sim commands
        cmd = getattr(cli_sim, name, None)
        if cmd is not None:
            cli.add_command(cmd)
    from . import cli_analyze

    cli_analyze.register(cli)


_register_optional()


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status (0 ok, 2 bad input)."""
    try:
        rv = cli.main(args=argv, prog_name="landscape", standalone_mode=False)
    except click.exceptions.Exit as exc:
        return int(exc.exit_code)
    except click.exceptions.Abort:
        click.echo("landscape: aborted", err=True)
        return 130
    except click.exceptions.ClickException as exc:
        click.echo(f"landscape: error: {exc.format_message()}", err=True)
        return 2
    except (ValueError, FileNotFoundError, OSError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        click.echo(f"landscape: error: {msg}", err=True)
        return 2
    return int(rv or 0)


if __name__ == "__main__":
    sys.exit(main())
