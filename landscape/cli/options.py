"""Option parsing shared by the command modules: numbers inside their stated ranges, value lists, the robot
options.

Every numeric option is a :func:`ranged_option`: its type (:class:`RangedParam`) reads the value as typed and
refuses one outside its :class:`geometry.bounds.Bounds`, and its help states that range in the same words.
Bad input raises :class:`geometry.errors.UsageError` (re-exported here), which :func:`landscape.cli.main`
turns into one line on stderr and exit status 2. A value inside its range that looks like a slip of units
(:func:`geometry.bounds.radians_slip`, :func:`geometry.bounds.mass_slip`) gets one warning line (:func:`warn`).
"""

from __future__ import annotations

import math
from contextlib import contextmanager

import click

from geometry.bounds import (
    JOINT_ANGLE_DEG_BOUNDS,
    MASS_KG_BOUNDS,
    PLAUSIBLE_MAX_MASS_KG,
    Bounds,
    joint_angle_slips,
    mass_slip,
)
from geometry.errors import UsageError
from geometry.robots import DEFAULT_MESH_MASS_KG
from landscape.params import parse_bounded, parse_values
from sim.engine import DEFAULT_ENGINE, ENGINES
from sim.protocol import (
    CV_BOUNDS,
    DURATION_S_BOUNDS,
    PAPER_LEG_PERIOD_S,
    PAPER_WING_PERIOD_S,
    PERIOD_S_BOUNDS,
    SEED_BOUNDS,
)

MJ = 1e3
MM = 1e3

__all__ = [
    "MJ",
    "MM",
    "THETA_W_LANDSCAPE_HELP",
    "THETA_W_OUT_OF_JOINT_RANGE",
    "THETA_W_OUT_OF_RANGE",
    "RangedParam",
    "RobotParam",
    "UsageError",
    "angle_option",
    "check_driven",
    "check_theta_w",
    "engine_option",
    "finite",
    "grid_step_option",
    "joints_option",
    "leg_period_option",
    "load_robot",
    "method_option",
    "model_set_option",
    "no_progress_option",
    "parse_values",
    "pose_options",
    "ranged_option",
    "robot_from",
    "robot_option",
    "robot_options",
    "robot_urdf_arg",
    "uncertainty_from",
    "uncertainty_options",
    "validation_cv_option",
    "validation_duration_option",
    "validation_seed_option",
    "warn",
    "warn_radians",
    "wing_period_option",
    "wing_range_deg",
    "workers_option",
]

THETA_W_HELP = (
    "Wing opening angle, degrees, {range} and from 0 (closed) to the wing joints' limit (a trial opens the wings "
    "from closed)."
)
THETA_W_LANDSCAPE_HELP = (
    "Wing angle, degrees, {range} and anywhere within the wing joints' limits (below 0 too, where the joints "
    "allow it)."
)
ROBOT_HELP = "The robot: a URDF file or a registered name (builtin)."
JOINTS_HELP = (
    "Joint map 'wing=J1,J2,...;leg=J' for a URDF whose joint names differ [default: the lab robot's "
    "joint names]."
)
THETA_W_OUT_OF_RANGE = (
    "--theta-w {got:g} deg is outside [{lo:g}, {hi:g}] deg, the wing opening range of {robot} (from closed, 0 deg, "
    "to its wing joints' limit); choose a value inside it"
)
"""The one message every command that opens the wings from closed (a trial) refuses an out-of-range wing angle
with."""
THETA_W_OUT_OF_JOINT_RANGE = (
    "--theta-w {got:g} deg is outside [{lo:g}, {hi:g}] deg, the wing joints' range of {robot}; choose a value "
    "inside it"
)
"""The one message every landscape command (the whole joint range) refuses an out-of-range wing angle with."""


class RangedParam(click.ParamType):
    """A number inside its stated range (:class:`geometry.bounds.Bounds`), or with ``many`` a list ``70,72`` or
    range ``START:STOP:STEP`` of them (:func:`landscape.params.parse_bounded`).

    The value is read as typed (a percentage '10%' where the bounds take one, a word such as 'protocol' where
    they list it) and refused outside the range in one line naming the option, e.g. ``--cv 10 is outside [0,
    1]: Cv is sigma / Tl as a fraction; for 10 % give 0.1 or '10%'``.
    """

    def __init__(self, bounds: Bounds, *, many: bool = False):
        self.bounds = bounds
        self.many = many
        kind = "LIST" if many else ("INTEGER" if bounds.integer else "NUMBER")
        self.name = "|".join([kind, *(["N%"] if bounds.percent else []), *bounds.words])

    def convert(self, value, param, ctx):
        name = param.opts[0] if param is not None and param.opts else "value"
        if self.many:
            return parse_bounded(value, self.bounds, name)
        return self.bounds.parse(value, name)

    def __repr__(self) -> str:
        return f"RangedParam({self.bounds!r}, many={self.many})"


def ranged_option(*decls, bounds: Bounds, help: str, many: bool = False, **kw):
    """``click.option`` of a number (or with ``many`` a list of numbers) inside ``bounds``: its type is
    :class:`RangedParam` and ``{range}`` in ``help`` becomes the range as stated (``in [0, 1) s``), so the help
    and the refusal say the same. Every numeric option of the command line is one of these
    (tests/cli/test_ranges.py walks them)."""
    if "{range}" not in help:
        raise ValueError(f"the help of {decls} must state its range: put {{range}} where it goes")
    return click.option(
        *decls, type=RangedParam(bounds, many=many), help=help.replace("{range}", bounds.text), **kw
    )


def angle_option(*decls, help: str, many: bool = False, **kw):
    """A joint angle (theta_w, theta_l) in degrees: within one turn (:data:`geometry.bounds.JOINT_ANGLE_DEG_BOUNDS`),
    and within the robot's joint limits, which the command checks once it has the robot."""
    return ranged_option(*decls, bounds=JOINT_ANGLE_DEG_BOUNDS, help=help, many=many, **kw)


def warn(text: str | None) -> None:
    """One warning line on stderr (``landscape: warning: ...``); the command goes on."""
    if text:
        click.echo(f"landscape: warning: {text}", err=True)


def warn_radians(robot, **angles) -> None:
    """Warn of wing or leg angles given in radians by mistake (:func:`geometry.bounds.radians_slip`), for the
    angles ``theta_w=...``, ``theta_l=...`` (a value or a list) the running command was given explicitly and the
    robot's joints take."""
    given = given_angles()
    for text in joint_angle_slips(robot, {a: v for a, v in angles.items() if a in given}, ANGLE_OPTIONS):
        warn(text)


def finite(value: float | None, name: str) -> float | None:
    """``value`` unchanged if it is None or finite, else a :class:`UsageError` naming the option ``--name``."""
    if value is not None and not math.isfinite(value):
        raise UsageError(f"--{name} must be a finite number; got {value!r}")
    return value


def memory_budget_bytes() -> float:
    """The memory budget of one landscape computation: ``LANDSCAPE_MEMORY_GIB`` GiB if set, else the library's
    default (:data:`landscape.computation.MEMORY_BUDGET_BYTES`)."""
    import os

    text = os.environ.get("LANDSCAPE_MEMORY_GIB")
    if not text:
        from landscape.computation import MEMORY_BUDGET_BYTES

        return MEMORY_BUDGET_BYTES
    try:
        gib = float(text)
    except ValueError:
        raise UsageError(f"LANDSCAPE_MEMORY_GIB must be a number of GiB; got {text!r}") from None
    if not (math.isfinite(gib) and gib > 0):
        raise UsageError(f"LANDSCAPE_MEMORY_GIB must be a positive number of GiB; got {text!r}")
    return gib * 2**30


def grid_step_option(f):
    """``--step``: the grid step, degrees, inside :data:`landscape.grid.STEP_DEG_BOUNDS`, dividing 360; its default is
    :data:`landscape.grid.DEFAULT_STEP_DEG`, the one default of every interface."""
    from landscape.grid import DEFAULT_STEP_DEG, STEP_DEG_BOUNDS

    return ranged_option(
        "--step",
        bounds=STEP_DEG_BOUNDS,
        default=DEFAULT_STEP_DEG,
        show_default=True,
        help="Grid step, degrees, {range}; divides 360.",
    )(f)


def pose_options(f):
    """``--theta-w``, ``--theta-l`` (degrees, 0 by default) and ``--step`` of the commands that compute one
    landscape (``compute``, ``render``)."""
    opts = [
        angle_option("--theta-w", default=0.0, show_default=True, help=THETA_W_LANDSCAPE_HELP),
        angle_option(
            "--theta-l",
            default=0.0,
            show_default=True,
            help="Leg angle, degrees, {range} and within the leg joint's limits.",
        ),
        grid_step_option,
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def grid_step(step_deg: float) -> float:
    """``--step`` checked before any robot is loaded: finite and dividing 360 (:func:`landscape.grid.cells_per_turn`)."""
    from landscape.computation import check_memory
    from landscape.grid import cells_per_turn

    finite(step_deg, "step")
    cells_per_turn(step_deg)
    check_memory(step_deg, memory_budget_bytes())
    return step_deg


def load_robot(
    robot: str | None,
    mesh: str | None,
    *,
    com: str | None = None,
    mass: float | None = None,
    units: str = "m",
    com_model: str = "auto",
    joints: str | None = None,
):
    """The robot the options describe: a URDF, a single mesh, or the built-in robot
    (:func:`geometry.robots.load_robot`), refused with the options' names when they do not fit together. A
    mesh's units warning is left to :func:`robot_from`, which names ``--units``."""
    import warnings

    from geometry.robots import ImplausibleUnitsWarning
    from geometry.robots import load_robot as _load

    if robot is not None and mesh is not None:
        raise UsageError("give either --robot FILE.urdf or --mesh FILE, not both")
    if mesh is None:
        return _load(robot, joints=joints)
    if joints:
        raise UsageError("--joints applies to a URDF robot, not to a single --mesh body; drop it")
    c = None
    if com is not None:
        try:
            c = [float(x) for x in com.split(",")]
        except ValueError:
            raise UsageError(f"--com must be X,Y,Z in the mesh's units; got {com!r}") from None
        if len(c) != 3 or not all(math.isfinite(x) for x in c):
            raise UsageError(f"--com must be three finite numbers X,Y,Z; got {com!r}")
    finite(mass, "mass")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ImplausibleUnitsWarning)
        return _load(mesh=mesh, com=c, mass_kg=mass, units=units, com_model=com_model)


METHOD_HELP = (
    "Barrier method (landscape.barriers): exact: no discretisation error (hull face-edge graph); grid: "
    "the paper's grid search on the pitch-roll torus; sphere: the same search on an icosphere spaced "
    "about --step apart."
)


def method_option(f):
    """``--method``: a barrier method of the registry (:data:`landscape.barriers.METHODS`)."""
    from landscape.barriers import DEFAULT_METHOD, METHODS

    return click.option(
        "--method",
        type=click.Choice(list(METHODS)),
        default=DEFAULT_METHOD,
        show_default=True,
        help=METHOD_HELP,
    )(f)


class RobotParam(click.ParamType):
    """``--robot``: a registered robot name (:data:`geometry.robots.ROBOTS`) or an existing URDF file, as a str.

    The same type in every command, so ``landscape CMD --help`` shows ``URDF|NAME`` everywhere and a missing file
    is refused before any work, in one line.
    """

    name = "URDF|NAME"

    def convert(self, value, param, ctx):
        from pathlib import Path

        from geometry.robots import ROBOTS, is_mesh_file

        text = str(value)
        if text in ROBOTS:
            return text
        path = Path(text)
        if is_mesh_file(path):
            self.fail(
                f"{text} is a mesh file, not a URDF; give a single rigid body with --mesh {text} "
                "(and its --units, --mass)",
                param,
                ctx,
            )
        if path.is_dir():
            self.fail(f"{text} is a directory; give the .urdf file inside it", param, ctx)
        if not path.is_file():
            self.fail(
                f"URDF file {text} not found; give a .urdf file or a registered robot name "
                f"({', '.join(sorted(ROBOTS))})",
                param,
                ctx,
            )
        return text


def robot_option(f=None, *, extra_help: str = "", default_help: str = "the built-in robot"):
    """``--robot URDF|NAME``, the one robot option of every command (``extra_help`` follows its help, then
    ``[default: default_help]``)."""

    def deco(g):
        text = " ".join(x for x in (ROBOT_HELP, extra_help, f"[default: {default_help}].") if x)
        return click.option("--robot", type=RobotParam(), default=None, help=text)(g)

    return deco if f is None else deco(f)


def joints_option(f):
    """``--joints MAP``, the joint map of a URDF whose joint names differ from the lab robot's."""
    return click.option("--joints", type=str, default=None, help=JOINTS_HELP)(f)


def robot_urdf(robot: str | None):
    """The URDF path of a ``--robot`` value (a registered name, a path, or None for the built-in robot)."""
    from geometry.robots import robot_urdf_path

    return robot_urdf_path(robot)


def robot_urdf_arg(robot: str | None) -> str | None:
    """The URDF path of a given ``--robot`` value as a str, or None when it was not given (the library then
    uses its default robot)."""
    return None if robot is None else str(robot_urdf(robot))


# ------------------------------------------------------------------ options of the commands that run trials
model_set_option = click.option(
    "--model",
    "model_set",
    type=str,
    default="paper",
    show_default=True,
    help="Model parameter set: a shipped name (paper, physical, physical-head, physical-offset, physical-posed) or a .toml file (sim/model_set.py).",
)
"""``--model``: the model parameter set of ``simulate``, ``sweep`` and ``physical validate``."""
engine_option = click.option(
    "--engine",
    type=click.Choice(ENGINES),
    default=DEFAULT_ENGINE,
    show_default=True,
    help="Physics engine: pybullet, or mujoco (the optional extra: pip install 'selfrighting-landscape[mujoco]'). "
    "The engine and its parameters are part of the model set's identity (docs/sim.md).",
)
"""``--engine``: the physics engine of ``simulate``, ``sweep``, ``physical validate`` and ``physical calibrate``."""
WORKERS_BOUNDS = Bounds(1, math.inf, integer=True, meaning="a count of worker processes")
workers_option = ranged_option(
    "--workers",
    bounds=WORKERS_BOUNDS,
    default=None,
    help="Local worker processes, {range} [default: all cores].",
)
"""``--workers N``: local worker processes of a batch of trials."""
no_progress_option = click.option(
    "--no-progress",
    is_flag=True,
    help="No progress bar (it is also off when stderr is not a terminal, e.g. redirected to a log).",
)
"""``--no-progress``: no progress bar over a batch of trials."""
wing_period_option = ranged_option(
    "--wing-period",
    bounds=PERIOD_S_BOUNDS,
    default=PAPER_WING_PERIOD_S,
    show_default=True,
    help="Tw, time between wing openings, s, {range}.",
)
"""``--wing-period``: one Tw, s (``simulate``, ``analyze evolution``)."""
leg_period_option = ranged_option(
    "--leg-period",
    bounds=PERIOD_S_BOUNDS,
    default=PAPER_LEG_PERIOD_S,
    show_default=True,
    help="Tl, leg oscillation period, s, {range}.",
)
"""``--leg-period``: one Tl, s (``simulate``, ``analyze evolution``)."""
CV_HELP = "Noise Cv = sigma / Tl, a fraction {range}"
"""The help of every --cv: Cv is a fraction, a percentage only when written with '%'."""
validation_cv_option = ranged_option(
    "--cv", bounds=CV_BOUNDS, default=0.05, show_default=True, help=CV_HELP + "."
)
"""``--cv`` of the simulated physical-robot cells (``physical validate``, ``calibrate``)."""
validation_seed_option = ranged_option(
    "--seed", bounds=SEED_BOUNDS, default=0, show_default=True, help="Seed of phases and noise, {range}."
)
"""``--seed`` of the simulated physical-robot cells (``physical validate``, ``calibrate``)."""
validation_duration_option = ranged_option(
    "--duration",
    bounds=DURATION_S_BOUNDS,
    default=None,
    help="Simulated trial length, s, {range} [default: the paper's 10 s].",
)
"""``--duration`` of the simulated physical-robot cells (``physical validate``, ``calibrate``)."""


def wing_range_deg(theta_limits_deg: dict, *, opening: bool = True) -> tuple[float, float]:
    """The wing angles a command accepts, degrees: within the wing joints' limits
    (``theta_limits_deg["theta_w"]``, e.g. :meth:`geometry.Robot.theta_limits_deg`), and for a command whose
    trial opens the wings from closed (``opening``) from 0 up.

    The landscape commands (``compute``, ``barrier-map``, ``render``, ``bench``), the service and
    :func:`landscape.computation.compute` take the joints' whole range (``opening=False``); ``simulate`` and
    ``sweep`` open the wings from closed, so a negative wing angle is no opening.

    Examples
    --------
    >>> wing_range_deg({"theta_w": (-10.0, 95.0), "theta_l": (-60.0, 60.0)})
    (0.0, 95.0)
    >>> wing_range_deg({"theta_w": (-10.0, 95.0), "theta_l": (-60.0, 60.0)}, opening=False)
    (-10.0, 95.0)
    """
    lo, hi = theta_limits_deg["theta_w"]
    return (max(float(lo), 0.0) if opening else float(lo)), float(hi)


def check_theta_w(values_deg, theta_limits_deg: dict, robot_name: str, *, opening: bool = True) -> None:
    """Refuse a wing angle outside :func:`wing_range_deg` with :data:`THETA_W_OUT_OF_RANGE` (``opening``: a
    trial's) or :data:`THETA_W_OUT_OF_JOINT_RANGE` (a landscape's): one message per rule for every command.

    Raises
    ------
    UsageError
        If a value lies outside the range.
    """
    lo, hi = wing_range_deg(theta_limits_deg, opening=opening)
    message = THETA_W_OUT_OF_RANGE if opening else THETA_W_OUT_OF_JOINT_RANGE
    for v in values_deg if isinstance(values_deg, (list, tuple)) else [values_deg]:
        if not lo - 1e-9 <= v <= hi + 1e-9:
            raise UsageError(message.format(got=v, lo=lo, hi=hi, robot=robot_name))


ANGLE_OPTIONS = {"theta_w": "--theta-w", "theta_l": "--theta-l"}
"""The command line's option of each angle (the click parameter has the angle's name)."""


def given_angles() -> list[str]:
    """The angles (``theta_w``, ``theta_l``) the running command was given explicitly, not by default."""
    from click.core import ParameterSource

    ctx = click.get_current_context(silent=True)
    if ctx is None:
        return []
    return [
        a
        for a in ANGLE_OPTIONS
        if a in ctx.params and ctx.get_parameter_source(a) not in (None, ParameterSource.DEFAULT)
    ]


def check_driven(robot, angles=None) -> None:
    """Refuse ``--theta-w``/``--theta-l`` given to a robot none of whose joints that angle drives (a mesh, a URDF
    without a joint map, a joint map that leaves the group out): the one rule of every command, in one line
    naming the robot's movable joints and the ``--joints`` that would map them
    (:meth:`geometry.Robot.undriven`). ``angles``: those to check (default: the ones given explicitly).

    Raises
    ------
    UsageError
        If a given angle drives no joint.
    """
    for a in given_angles() if angles is None else angles:
        if not robot.drives(a):
            raise robot.undriven(a, option=ANGLE_OPTIONS[a])


def robot_options(f):
    """Options shared by every command that takes a robot."""
    opts = [
        robot_option,
        click.option(
            "--mesh",
            type=str,
            default=None,
            help="A single rigid body instead of a URDF: any mesh file trimesh reads [default: none].",
        ),
        click.option(
            "--com",
            type=str,
            default=None,
            help="With --mesh: CoM X,Y,Z in the mesh's units [default: from --com-model].",
        ),
        ranged_option(
            "--mass",
            bounds=MASS_KG_BOUNDS,
            default=None,
            help="With --mesh: mass, kg, {range} (above "
            f"{PLAUSIBLE_MAX_MASS_KG:g} kg a warning asks whether it was meant in grams) "
            f"[default: {DEFAULT_MESH_MASS_KG:g}].",
        ),
        click.option(
            "--units",
            type=click.Choice(["mm", "cm", "m"]),
            default=None,
            help="With --mesh: units of the mesh file [default: m].",
        ),
        click.option(
            "--com-model",
            type=click.Choice(["auto", "solid", "shell"]),
            default=None,
            help="With --mesh and no --com: solid (closed mesh), shell (thin surface) or auto "
            "[default: auto].",
        ),
        joints_option,
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def robot_from(kw: dict, *, theta_w_deg=None, theta_l_deg=None):
    """The robot of a landscape command's :func:`robot_options` keywords. An angle option given explicitly that
    no joint of the robot takes is refused (:func:`check_driven`); a wing angle ``theta_w_deg`` (a value or a
    list) is checked against the wing joints' whole range (:func:`check_theta_w` with ``opening=False``), and
    angles ``theta_w_deg``, ``theta_l_deg`` that look like radians get a warning (:func:`warn_radians`).

    Mesh-only options without ``--mesh`` are refused (they would be ignored). A mesh whose size is implausible
    in its units, or whose ``--mass`` is probably in grams, gets a warning on stderr naming the fix
    (:func:`geometry.robots.units_warning`, :func:`geometry.bounds.mass_slip`).
    """
    from geometry.robots import mesh_size_m, units_warning

    if kw["mesh"] is None:
        given = [
            f"--{k.replace('_', '-')}" for k in ("com", "mass", "units", "com_model") if kw[k] is not None
        ]
        if given:
            raise UsageError(
                f"{', '.join(given)} only apply to a single body given with --mesh FILE; "
                "a URDF robot takes its masses and CoM from its <inertial> elements"
            )
        robot = load_robot(kw["robot"], None, joints=kw["joints"])
    else:
        units = kw["units"] or "m"
        robot = load_robot(
            kw["robot"],
            kw["mesh"],
            com=kw["com"],
            mass=kw["mass"],
            units=units,
            com_model=kw["com_model"] or "auto",
            joints=kw["joints"],
        )
        warn(units_warning(mesh_size_m(robot), units, units_as="--units"))
        warn(mass_slip(kw["mass"], "--mass"))
    check_driven(robot)
    if theta_w_deg is not None and robot.drives("theta_w"):
        check_theta_w(theta_w_deg, robot.theta_limits_deg(), robot.name, opening=False)
    warn_radians(robot, theta_w=theta_w_deg, theta_l=theta_l_deg)
    return robot


def writable_dir(path, option: str) -> None:
    """Refuse up front an output directory that cannot be created or written (before any long computation)."""
    import os
    from pathlib import Path

    p = Path(path)
    probe = p
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir():
        raise UsageError(f"{option} {path}: {probe} is a file, not a directory; choose another {option}")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise UsageError(f"{option} {path} is not writable ({probe} is read-only); choose another {option}")


def writable_file(path, option: str, *, inputs=()) -> None:
    """Refuse up front an output file that cannot be written, or that is one of the command's ``inputs``."""
    from pathlib import Path

    p = Path(path)
    for src in inputs:
        if src is not None and Path(src).exists() and p.exists() and p.resolve() == Path(src).resolve():
            raise UsageError(
                f"{option} {path} is also an input of this command; writing it would destroy the "
                "input. Choose another file name"
            )
    if p.is_dir():
        raise UsageError(f"{option} {path} is a directory; give a file name")
    writable_dir(p.parent if str(p.parent) else ".", option)


pose_model_option = click.option(
    "--model",
    "pose_model",
    type=str,
    default=None,
    help="Pose the wings as a model set does: a set with a measured actuation profile (physical) holds each "
    "wing servo at its own measured plateau for the wing command --theta-w (60-90); an idealised set (paper) "
    "holds every wing joint at --theta-w, as without this option [default: every wing joint at --theta-w].",
)
"""``--model``: the model set whose wing-servo plateaus pose the robot in ``compute`` and ``barrier-map``."""


def pose_model_set(pose_model: str | None, robot):
    """The model set ``--model`` names for posing the robot's wings (:meth:`sim.model_set.ModelSet.wing_joints_deg`),
    or None; imports the model sets (and with them pybullet) only when a set is named.

    Raises
    ------
    UsageError
        If a set is named for a robot without joints (a ``--mesh`` body), or it cannot be loaded.
    """
    if pose_model is None:
        return None
    if not robot.has_joints:
        raise UsageError(
            f"--model {pose_model} poses wing joints, but {robot.name} is a rigid body without joints; "
            "drop --model or give a robot URDF"
        )
    from sim.model_set import load_model_set

    return load_model_set(pose_model)


def uncertainty_options(f):
    """``--com-uncertainty MM``, ``--mass-uncertainty G``, ``--samples N`` and ``--seed S``: barrier intervals
    (:mod:`landscape.uncertainty`, which holds their ranges); :func:`uncertainty_from` joins them."""
    from geometry.bounds import (
        COM_UNCERTAINTY_MM_BOUNDS,
        MASS_UNCERTAINTY_G_BOUNDS,
        MC_SEED_BOUNDS,
        SAMPLES_BOUNDS,
    )

    opts = [
        ranged_option(
            "--com-uncertainty",
            "com_uncertainty",
            bounds=COM_UNCERTAINTY_MM_BOUNDS,
            default=None,
            help="CoM uncertainty, mm, {range} (and less than the CoM's depth inside the body): give each barrier "
            "an interval, first order from its gradient, Monte-Carlo with --samples [default: none].",
        ),
        ranged_option(
            "--mass-uncertainty",
            "mass_uncertainty",
            bounds=MASS_UNCERTAINTY_G_BOUNDS,
            default=None,
            help="Mass uncertainty, g, {range} (and below the robot's mass): widens each barrier's interval "
            "[default: none].",
        ),
        ranged_option(
            "--samples",
            bounds=SAMPLES_BOUNDS,
            default=None,
            help="Monte-Carlo samples, {range}: recompute the barriers with the CoM --com-uncertainty off in that "
            "many random directions [default: none; 64 where a barrier has no first-order band].",
        ),
        ranged_option(
            "--seed",
            bounds=MC_SEED_BOUNDS,
            default=0,
            show_default=True,
            help="Seed of the Monte-Carlo directions, {range}.",
        ),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def uncertainty_from(com_mm: float | None, mass_g: float | None, samples: int | None, seed: int):
    """The :class:`landscape.uncertainty.Uncertainty` of :func:`uncertainty_options`' values (each already inside
    its range), or None when no uncertainty was given.

    Raises
    ------
    UsageError
        For ``--samples`` without ``--com-uncertainty``.
    """
    from landscape.uncertainty import Uncertainty

    if samples is not None and not com_mm:
        raise UsageError("--samples draws CoMs --com-uncertainty off; give --com-uncertainty MM (> 0) too")
    if com_mm is None and mass_g is None:
        return None
    return Uncertainty(
        com_m=(com_mm or 0.0) * 1e-3, mass_kg=(mass_g or 0.0) * 1e-3, samples=samples, seed=seed
    )


@contextmanager
def sweep_errors():
    """Run a sweep's library call: a sweep that stopped before its end (:class:`sim.sweep.SweepAborted`: workers
    kept dying, or a trial raised) is one line and exit status 1, not a bug report; what finished is stored and
    rerunning the command resumes it."""
    from sim.sweep import SweepAborted

    try:
        yield
    except SweepAborted as exc:
        raise click.ClickException(str(exc).splitlines()[0]) from None
