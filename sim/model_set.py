"""Named, versioned model parameter sets: the actuation profile and the contact model a trial runs with.

A set is a small TOML file; the package ships ``sim/models/paper.toml`` (the source paper's idealised profiles
and the default contact: the default, identical to trials made before model sets existed) and the physical
robot's sets (``physical``: the lab's measured servo and leg profiles; ``physical-posed`` and ``physical-offset``:
posed further over, with compliant wing joints, and the latter with its CoM off the midline; ``physical-head``:
resting where the robot rests, its head further back; each file's header says how it was chosen). ``--model NAME``
picks a shipped set, ``--model FILE.toml`` any other. Each optional table switches on one modifier
(:mod:`sim.modifier`; :data:`OPTIONAL_TABLES`: ``[compliance]``, ``[body_torsion]``, ``[leg_compliance]``,
``[leg_bend]``, ``[head_compliance]``, ``[mass]`` and ``[geometry]``). Layout::

    name = "paper"
    version = 1
    description = "..."
    [actuation]
    profile = "idealised"        # the only profile so far
    wing_open_deg_s = 300.0
    wing_close_deg_s = 250.0
    wing_close_start_s = 1.05
    leg_cross_s = 0.15
    [contact]
    lateral_friction = 1.0
    restitution = 0.1
    stiffness_n_m = 1e4          # both omitted: pybullet's rigid contact
    damping_n_s_m = 100.0
    solver_iterations = 20
    friction_axes = "body"       # optional (the default): the robot kept at heading 0; "world": pybullet's own (sim.world)
    [mujoco]                     # optional: MuJoCo's parameters (sim.engine.MujocoParams), any subset
    solref_time_s = 0.004

Every key is required except the two soft-contact keys (omit both for rigid contact) and the optional keys
(:data:`OPTIONAL_KEYS`); an unknown key is refused,
so a typo cannot silently leave a parameter at its default. The set's ``model_set_hash`` hashes its parsed
content (not the file's bytes: comments and formatting do not change it), so two files with the same parameters
are the same model.

The engine is part of the identity: a set loads for pybullet (``ModelSet.engine``), and
:meth:`ModelSet.with_engine` gives the same set for another engine, with its own hash. pybullet's hash is the one
above, whatever ``[mujoco]`` holds; MuJoCo's hashes the engine's name, its parameters (the set's ``[mujoco]``
over :data:`sim.engine.MUJOCO_DEFAULTS`) and the content pybullet's own contact keys left out (restitution, the
soft contact spring, solver iterations, friction axes: MuJoCo does not read them).

One concept, reading a set: its required tables (actuation, measured knots included, and contact) are read here
and each optional one by its modifier (:mod:`sim.modifier`); hence over 600 lines.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .actuation import Actuation, MeasuredActuation
from .compliance import BodyTorsion, Compliance, LegBend, LegCompliance
from .engine import DEFAULT_ENGINE, MUJOCO_DEFAULTS, MUJOCO_KEYS, EngineError, MujocoParams, check_engine
from .head_compliance import HeadCompliance
from .joint_shift import MAX_JOINT_SHIFT_MM
from .mass import MAX_COM_OFFSET_MM
from .modifier import ModelSetError, Modifier, registered
from .modifier import check_keys as _check_keys
from .modifier import number as _number
from .world import DEFAULT_FRICTION_AXES, FRICTION_AXES, MAX_ROLLING_FRICTION, Contact

__all__ = [
    "MAX_COM_OFFSET_MM",
    "MAX_JOINT_SHIFT_MM",
    "MODELS_DIR",
    "ModelSet",
    "ModelSetError",
    "OPTIONAL_KEYS",
    "OPTIONAL_TABLES",
    "load_model_set",
    "read_toml",
    "shipped_model_sets",
    "wing_extra_knots_deg",
]

MODELS_DIR = Path(__file__).resolve().parent / "models"
DEFAULT_MODEL_SET = "paper"
PROFILES = ("idealised", "measured")
OPTIONAL_TABLES = tuple(registered())
"""The tables a set may add to its required ``[actuation]`` and ``[contact]``: each switches one
:class:`sim.modifier.Modifier` on."""
_REQUIRED_TOP = {"name", "version", "actuation", "contact"}
SHARED_CONTACT_KEYS = ("lateral_friction", "rolling_friction", "spinning_friction")
"""The ``[contact]`` keys every engine reads (the rest are pybullet's own and leave MuJoCo's hash alone)."""
_ACTUATION = {"profile", "wing_open_deg_s", "wing_close_deg_s", "wing_close_start_s", "leg_cross_s"}
_MEASURED = {"profile", "wing_command_deg", "leg_command_deg", "wing", "leg", "servo_sides", "wing_extra_deg"}
MAX_WING_EXTRA_DEG = 20.0
"""Largest ``[actuation] wing_extra_deg`` (one number, or one per wing command), degrees: a pose correction, not a
new wing command."""
SERVO_SIDES = ("as-labelled", "mirrored")
"""How a measured set's servos (the lab's LP, RP, LR, RR) drive the robot's wing joints (the joint map's left
pitch, right pitch, left roll, right roll): as labelled, or mirrored (the lab's left servos drive the model's
right joints; docs/physical/side.md)."""
_SERVOS = ("LP", "RP", "LR", "RR")
MIRRORED = (1, 0, 3, 2)
"""Mirrored sides: the servo (index into LP, RP, LR, RR) that drives each of the joint map's wing joints."""
OPTIONAL_KEYS = frozenset(
    {
        "contact.rolling_friction",
        "contact.spinning_friction",
        "contact.wing_stiffness_n_m",
        "contact.wing_damping_n_s_m",
        "contact.friction_axes",
        "actuation.wing_extra_deg",
        *(f"{table}.{key}" for table, cls in registered().items() for key in cls.KEYS),
    }
)
"""Dotted keys a set may omit (and a calibration candidate may add): rolling and spinning friction and the wings'
own soft contact (both of its keys); where the friction directions are fixed; the wing pose correction; and every key of every modifier's table
(:data:`OPTIONAL_TABLES`; what each requires once its table is there is the modifier's own rule)."""
_CONTACT = {
    "lateral_friction",
    "restitution",
    "stiffness_n_m",
    "damping_n_s_m",
    "solver_iterations",
    "rolling_friction",
    "spinning_friction",
    "wing_stiffness_n_m",
    "wing_damping_n_s_m",
    "friction_axes",
}


@dataclass(frozen=True)
class ModelSet:
    """A model parameter set.

    Attributes
    ----------
    name : str
    version : int
    description : str
    source : str
        The file it was read from.
    profile : str
        Actuation profile kind (``"idealised"``).
    wing_open_deg_s, wing_close_deg_s, wing_close_start_s, leg_cross_s : float
        Profile timing (:class:`sim.actuation.Actuation`).
    contact : Contact
    model_set_hash : str
        16 hex digits of the SHA-256 of the parsed content.
    measured : MeasuredActuation or None
        The per-joint knots of a ``profile = "measured"`` set.
    modifiers : tuple of sim.modifier.Modifier
        What the set adds to the rigid robot, one per optional table it has, in :data:`OPTIONAL_TABLES` order
        (:mod:`sim.modifier`). The properties below read them by table.
    engine : {"pybullet", "mujoco"}
        The engine its trials run in (:meth:`with_engine`); ``model_set_hash`` is this engine's.
    mujoco : sim.engine.MujocoParams
        MuJoCo's parameters: the ``[mujoco]`` table over :data:`sim.engine.MUJOCO_DEFAULTS`.
    canonical_json : str
        The parsed content pybullet's hash is taken of (JSON, keys sorted).
    """

    name: str
    version: int
    description: str
    source: str
    profile: str
    wing_open_deg_s: float
    wing_close_deg_s: float
    wing_close_start_s: float
    leg_cross_s: float
    contact: Contact
    model_set_hash: str
    measured: MeasuredActuation | None = None
    modifiers: tuple[Modifier, ...] = ()
    engine: str = DEFAULT_ENGINE
    mujoco: MujocoParams = MUJOCO_DEFAULTS
    canonical_json: str = field(default="", repr=False, compare=False)

    def with_engine(self, engine: str) -> ModelSet:
        """This set run in ``engine``: the same content, that engine's ``model_set_hash``.

        Raises
        ------
        sim.engine.EngineError
            If the engine is unknown, or cannot express one of the set's modifiers (each names the engines it
            runs in, :attr:`sim.modifier.Modifier.ENGINES`) or its contact (MuJoCo: the wings' own soft contact).

        Examples
        --------
        >>> paper = load_model_set("paper")
        >>> mj = paper.with_engine("mujoco")
        >>> mj.engine, mj.model_set_hash != paper.model_set_hash, mj.with_engine("pybullet") == paper
        ('mujoco', True, True)
        """
        check_engine(engine)
        if engine != DEFAULT_ENGINE and self.contact.wing_stiffness_n_m is not None:
            raise EngineError(
                f"model set '{self.name}': the {engine} engine cannot express [contact] wing_stiffness_n_m and "
                "wing_damping_n_s_m (the wings' own soft contact); use --engine pybullet or drop them"
            )
        for m in self.modifiers:
            if engine not in m.ENGINES:
                raise EngineError(
                    f"model set '{self.name}': the {engine} engine cannot express [{m.TABLE}] ({type(m).__name__}; "
                    f"it runs in {', '.join(m.ENGINES)}); use --engine {m.ENGINES[0]} or drop [{m.TABLE}]"
                )
        if engine == self.engine:
            return self
        digest = engine_hash(json.loads(self.canonical_json), engine, self.mujoco)
        return replace(self, engine=engine, model_set_hash=digest)

    def modifier(self, table: str) -> Modifier | None:
        """The set's modifier of ``table`` (``"compliance"``, ``"mass"``, ...), or None without that table."""
        return next((m for m in self.modifiers if m.TABLE == table), None)

    @property
    def compliance(self) -> Compliance | None:
        """Compliant wing joints (``[compliance]``); None: rigid wings."""
        return self.modifier("compliance")

    @property
    def body_torsion(self) -> BodyTorsion | None:
        """A body that twists about its long axis (``[body_torsion]``); None: a rigid body."""
        return self.modifier("body_torsion")

    @property
    def leg_compliance(self) -> LegCompliance | None:
        """A leg whose swing gives (``[leg_compliance]``); None: the leg follows its profile."""
        return self.modifier("leg_compliance")

    @property
    def leg_bend(self) -> LegBend | None:
        """A leg that bends out of its swing plane (``[leg_bend]``); None: a rigid leg."""
        return self.modifier("leg_bend")

    @property
    def head_compliance(self) -> HeadCompliance | None:
        """A head whose attachment gives (``[head_compliance]``; simulation only); None: a rigid head."""
        return self.modifier("head_compliance")

    @property
    def com_offset_y_mm(self) -> float:
        """The whole body's CoM moved along the body's y axis (``[mass]``), mm; 0: the description's CoM."""
        m = self.modifier("mass")
        return 0.0 if m is None else m.com_offset_y_mm

    @property
    def joint_shift_mm(self) -> tuple[str, tuple[float, float, float]] | None:
        """One joint's origin moved (``[geometry]``): (joint, mm in its parent frame), or None."""
        m = self.modifier("geometry")
        return None if m is None else (m.joint, m.shift_mm)

    @property
    def com_offset_m(self) -> tuple[float, float, float]:
        """The set's CoM offset as a body-frame vector, m."""
        return (0.0, self.com_offset_y_mm * 1e-3, 0.0)

    @property
    def joint_shift_m(self) -> tuple[str, tuple[float, float, float]] | None:
        """The set's joint shift as (joint, parent-frame vector in m), or None."""
        m = self.modifier("geometry")
        return None if m is None else m.shift_m

    def robot_for(self, robot):
        """``robot`` as this set models it: each modifier's :meth:`~sim.modifier.Modifier.edit_robot` in turn
        (one joint shifted by :attr:`joint_shift_m`, then its CoM moved by :attr:`com_offset_m`), or ``robot``
        itself when the set moves nothing.

        Raises
        ------
        geometry.errors.UnknownJointError
            If the set shifts a joint the robot lacks.
        """
        for m in sorted(self.modifiers, key=lambda m: m.URDF_ORDER):
            robot = m.edit_robot(robot)
        return robot

    def wing_joints_deg(self, joint_names, theta_w_deg: float) -> dict[str, float] | None:
        """The wing joints' angles (degrees) this set holds at the wing command ``theta_w_deg``: each servo at
        its own measured plateau (:meth:`MeasuredActuation.wing_plateaus_deg`) for a measured profile, None
        (every joint at theta_w) for an idealised one. ``joint_names``: the robot's wing joints in the joint
        map's order (LP, RP, LR, RR).

        Raises
        ------
        ModelSetError
            If the robot drives another number of wing joints than the set measures.
        UsageError
            If the command lies outside the measured ones.
        """
        if self.measured is None:
            return None
        plateaus = self.measured.wing_plateaus_deg(theta_w_deg)
        names = tuple(joint_names)
        if len(names) != len(plateaus):
            raise ModelSetError(
                f"the model set {self.name} measures {len(plateaus)} wing servos, but the robot drives "
                f"{len(names)} wing joints ({', '.join(names)}); use an idealised set or none"
            )
        return dict(zip(names, plateaus.tolist(), strict=True))

    def wing_joints_by_theta_w(self, joint_names, theta_w_deg) -> dict[float, dict[str, float]] | None:
        """:meth:`wing_joints_deg` at each wing command of a list (a barrier map's ``wing_joints_deg``); None for
        an idealised set (every wing joint at theta_w)."""
        if self.measured is None:
            return None
        return {float(w): self.wing_joints_deg(joint_names, w) for w in theta_w_deg}

    def actuation(
        self,
        theta_w_deg: float,
        theta_l_deg: float,
        *,
        wing_period_s: float | None = None,
        leg_period_s: float | None = None,
    ) -> Actuation:
        """The set's :class:`Actuation` at (theta_w, theta_l) (periods: the protocol's unless given)."""
        kw = {} if wing_period_s is None else {"wing_period_s": wing_period_s}
        if leg_period_s is not None:
            kw["leg_period_s"] = leg_period_s
        return Actuation(
            theta_w_deg,
            theta_l_deg,
            wing_open_deg_s=self.wing_open_deg_s,
            wing_close_deg_s=self.wing_close_deg_s,
            wing_close_start_s=self.wing_close_start_s,
            leg_cross_s=self.leg_cross_s,
            measured=self.measured,
            **kw,
        )

    @property
    def label(self) -> str:
        """``name vVERSION (hash)``, with `` [mujoco]`` for a set run in another engine than pybullet."""
        tag = "" if self.engine == DEFAULT_ENGINE else f" [{self.engine}]"
        return f"{self.name} v{self.version} ({self.model_set_hash}){tag}"

    def summary(self) -> dict:
        """What the set is, as ``landscape models --json`` and ``GET /api/model-sets`` list it.

        Returns
        -------
        summary : dict
            ``name``, ``version``, ``model_set_hash`` (16 hex digits of its parsed content), ``label``
            (``name vVERSION (hash)``), ``description``, ``profile`` (idealised or measured); ``poses_wings``:
            whether it holds each wing joint at its own measured plateau (True) or every wing joint at theta_w
            (False); ``wing_command_deg``: the wing commands it measured (theta_w must lie within them), degrees,
            or None; ``com_offset_y_mm``: how far it moves the CoM along the body's y axis, mm, and
            ``moves_com``; ``joint_shift``: the joint it moves and how far (``{"joint": ..., "shift_mm": [x, y,
            z]}``) or None; ``elements``: the optional model elements it switches on, by table (``compliance``,
            ``body_torsion``, ``leg_compliance``, ``leg_bend``, ``head_compliance``, ``mass``, ``geometry``).

        Examples
        --------
        >>> s = load_model_set("physical-offset").summary()
        >>> s["label"], s["elements"], s["com_offset_y_mm"]
        ('physical-offset v2 (12ee2dcaffb82b60)', ['compliance', 'mass'], -2.0)
        """
        return {
            "name": self.name,
            "version": self.version,
            "model_set_hash": self.model_set_hash,
            "label": self.label,
            "description": self.description,
            "profile": self.profile,
            "poses_wings": self.measured is not None,
            "wing_command_deg": None
            if self.measured is None
            else [float(w) for w in self.measured.wing_command_deg],
            "com_offset_y_mm": float(self.com_offset_y_mm),
            "moves_com": bool(self.com_offset_y_mm),
            "joint_shift": None
            if self.joint_shift_mm is None
            else {"joint": self.joint_shift_mm[0], "shift_mm": list(self.joint_shift_mm[1])},
            "elements": [m.TABLE for m in self.modifiers if m.active],
        }


def engine_hash(canonical: dict, engine: str, mujoco: MujocoParams = MUJOCO_DEFAULTS) -> str:
    """The ``model_set_hash`` of a set's parsed content ``canonical`` run in ``engine``: 16 hex digits of the
    SHA-256 of its JSON, for pybullet the content itself; for MuJoCo the content with only the
    :data:`SHARED_CONTACT_KEYS` of its contact, the engine's name and every MuJoCo parameter.

    Examples
    --------
    >>> c = {"name": "x", "contact": {"lateral_friction": 1.0, "restitution": 0.1}}
    >>> engine_hash(c, "mujoco") == engine_hash({**c, "contact": {"lateral_friction": 1.0}}, "mujoco")
    True
    >>> engine_hash(c, "pybullet") == engine_hash({**c, "contact": {"lateral_friction": 1.0}}, "pybullet")
    False
    """
    if check_engine(engine) != DEFAULT_ENGINE:
        contact = {k: v for k, v in canonical.get("contact", {}).items() if k in SHARED_CONTACT_KEYS}
        canonical = {**canonical, "contact": contact, "engine": engine, engine: mujoco.canonical()}
    return hashlib.sha256(json.dumps(canonical, sort_keys=True).encode()).hexdigest()[:16]


def shipped_model_sets() -> list[str]:
    """Names of the sets shipped in ``sim/models/``.

    Examples
    --------
    >>> shipped_model_sets()
    ['paper', 'physical', 'physical-head', 'physical-offset', 'physical-posed']
    """
    return sorted(p.stem for p in MODELS_DIR.glob("*.toml"))


def _resolve(name_or_file: str | Path) -> Path:
    text = str(name_or_file)
    if text in shipped_model_sets():
        return MODELS_DIR / f"{text}.toml"
    path = Path(text)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise ModelSetError(
                f"model set file '{path}' not found; give a shipped set "
                f"({', '.join(shipped_model_sets())}) or an existing .toml file"
            )
        return path
    raise ModelSetError(
        f"unknown model set {text!r}; give a shipped set ({', '.join(shipped_model_sets())}) or a .toml file"
    )


def read_toml(path: str | Path) -> dict:
    """The TOML file's tables (``tomllib``; ``tomli`` on Python 3.10).

    Raises
    ------
    ModelSetError
        If the file is not valid UTF-8 TOML.
    """
    try:
        import tomllib
    except ImportError:  # pragma: no cover - Python 3.10
        import tomli as tomllib  # type: ignore[no-redef]

    try:
        return tomllib.loads(Path(path).read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ModelSetError(f"model set '{path}' is not valid TOML: {exc}") from None


def load_model_set(name_or_file: str | Path = DEFAULT_MODEL_SET) -> ModelSet:
    """Read a model set by shipped name or TOML file.

    Raises
    ------
    ModelSetError
        If it cannot be found or parsed, a key is unknown or missing, or a value is out of range.

    Examples
    --------
    >>> ms = load_model_set("paper")
    >>> ms.name, ms.wing_open_deg_s, ms.contact.friction
    ('paper', 300.0, 1.0)
    """
    path = _resolve(name_or_file)
    data = read_toml(path)
    where = f"model set '{path}'"
    # the tables of every registered modifier, one registered after this import too
    _check_keys(data, _REQUIRED_TOP | {"description", "mujoco", *registered()}, _REQUIRED_TOP, where)
    if not isinstance(data["name"], str) or not data["name"].strip():
        raise ModelSetError(f"{where}: name must be a non-empty string; got {data['name']!r}")
    if isinstance(data["version"], bool) or not isinstance(data["version"], int) or data["version"] < 0:
        raise ModelSetError(f"{where}: version must be a whole number >= 0; got {data['version']!r}")
    act = data["actuation"]
    measured_profile = isinstance(act, dict) and act.get("profile") == "measured"
    keys = _MEASURED if measured_profile else _ACTUATION
    act = _check_keys(act, keys, keys - {"servo_sides", "wing_extra_deg"}, f"{where} [actuation]")
    if act["profile"] not in PROFILES:
        raise ModelSetError(
            f"{where} [actuation]: profile must be one of {', '.join(PROFILES)}; got {act['profile']!r}"
        )
    con = _check_keys(
        data["contact"],
        _CONTACT,
        _CONTACT
        - {
            "stiffness_n_m",
            "damping_n_s_m",
            "rolling_friction",
            "spinning_friction",
            "wing_stiffness_n_m",
            "wing_damping_n_s_m",
            "friction_axes",
        },
        f"{where} [contact]",
    )
    soft = [k for k in ("stiffness_n_m", "damping_n_s_m") if k in con]
    if len(soft) == 1:
        raise ModelSetError(
            f"{where} [contact]: give both stiffness_n_m and damping_n_s_m (soft contact) or "
            "neither (rigid contact)"
        )
    w = f"{where} [contact]"
    wing_soft = [k for k in ("wing_stiffness_n_m", "wing_damping_n_s_m") if k in con]
    if len(wing_soft) == 1:
        raise ModelSetError(
            f"{w}: give both wing_stiffness_n_m and wing_damping_n_s_m (the wings' own soft contact) or neither"
        )
    iters = con["solver_iterations"]
    if isinstance(iters, bool) or not isinstance(iters, int) or iters < 1:
        raise ModelSetError(f"{w}: solver_iterations must be a whole number >= 1; got {iters!r}")
    rolling = {}
    for k in ("rolling_friction", "spinning_friction"):
        if k in con:
            v = _number(con, k, w, allow_zero=True)
            if v > MAX_ROLLING_FRICTION:
                raise ModelSetError(f"{w}: {k} must be in [0, {MAX_ROLLING_FRICTION:g}]; got {v!r}")
            rolling[k] = v
    axes = con.get("friction_axes", DEFAULT_FRICTION_AXES)
    if axes not in FRICTION_AXES:
        raise ModelSetError(f"{w}: friction_axes must be one of {', '.join(FRICTION_AXES)}; got {axes!r}")
    contact = Contact(
        **rolling,
        friction_axes=axes,
        friction=_number(con, "lateral_friction", w, allow_zero=True),
        restitution=_number(con, "restitution", w, allow_zero=True),
        stiffness_n_m=_number(con, "stiffness_n_m", w) if soft else None,
        damping_n_s_m=_number(con, "damping_n_s_m", w, allow_zero=True) if soft else None,
        solver_iterations=int(iters),
        wing_stiffness_n_m=_number(con, "wing_stiffness_n_m", w) if wing_soft else None,
        wing_damping_n_s_m=_number(con, "wing_damping_n_s_m", w, allow_zero=True) if wing_soft else None,
    )
    if contact.restitution > 1:
        raise ModelSetError(f"{w}: restitution must be in [0, 1]; got {contact.restitution!r}")
    wa = f"{where} [actuation]"
    if measured_profile:
        measured = _measured(act, wa)
        # the idealised timing fields are unused; Actuation's defaults keep them valid
        d = Actuation(0.0, 0.0)
        timing = {
            k: getattr(d, k)
            for k in ("wing_open_deg_s", "wing_close_deg_s", "wing_close_start_s", "leg_cross_s")
        }
        act_canon = {
            "profile": "measured",
            "wing_command_deg": list(measured.wing_command_deg),
            "leg_command_deg": list(measured.leg_command_deg),
            "wing": {
                s: {"knots_s": measured.wing_knots_s[i], "knots_deg": measured.wing_knots_deg[i]}
                for i, s in enumerate(_SERVOS)
            },
            "leg": {"knots_s": measured.leg_knots_s, "knots_deg": measured.leg_knots_deg},
        }
        sides = act.get("servo_sides", SERVO_SIDES[0])
        if sides not in SERVO_SIDES:
            raise ModelSetError(f"{wa}: servo_sides must be one of {', '.join(SERVO_SIDES)}; got {sides!r}")
        if sides == "mirrored":  # enters the hash only when set, so the sets of before keep their hashes
            act_canon["servo_sides"] = sides
            measured = replace(
                measured,
                wing_knots_s=tuple(measured.wing_knots_s[i] for i in MIRRORED),
                wing_knots_deg=tuple(measured.wing_knots_deg[i] for i in MIRRORED),
            )
        if "wing_extra_deg" in act:  # likewise
            extra = _wing_extra(act["wing_extra_deg"], len(measured.wing_command_deg), wa)
            act_canon["wing_extra_deg"] = extra
            measured = replace(measured, wing_knots_deg=wing_extra_knots_deg(measured.wing_knots_deg, extra))
    else:
        measured = None
        timing = {
            k: _number(act, k, wa)
            for k in ("wing_open_deg_s", "wing_close_deg_s", "wing_close_start_s", "leg_cross_s")
        }
        act_canon = {"profile": act["profile"], **timing}
    con_canon = {
        "lateral_friction": contact.friction,
        "restitution": contact.restitution,
        "stiffness_n_m": contact.stiffness_n_m,
        "damping_n_s_m": contact.damping_n_s_m,
        "solver_iterations": contact.solver_iterations,
    }
    # the new keys enter the hash only when set, so the sets of before keep their hashes
    con_canon.update({k: v for k, v in rolling.items() if v != 0})
    if wing_soft:
        con_canon["wing_stiffness_n_m"] = contact.wing_stiffness_n_m
        con_canon["wing_damping_n_s_m"] = contact.wing_damping_n_s_m
    if axes != "world":  # "world" was the default once: sets that ask for it keep the hashes they had
        con_canon["friction_axes"] = axes
    canonical = {
        "name": data["name"],
        "version": data["version"],
        "actuation": act_canon,
        "contact": con_canon,
    }
    # each table enters the hash only when present, so the sets of before keep their hashes
    modifiers = []
    for table, cls in registered().items():
        if table in data:
            m = cls.from_toml(data[table], f"{where} [{table}]")
            canonical[table] = m.canonical()
            modifiers.append(m)
    mujoco = _mujoco(data["mujoco"], f"{where} [mujoco]") if "mujoco" in data else MUJOCO_DEFAULTS
    ms = ModelSet(
        data["name"],
        int(data["version"]),
        str(data.get("description", "")),
        str(path),
        act["profile"],
        contact=contact,
        model_set_hash=engine_hash(canonical, DEFAULT_ENGINE),
        measured=measured,
        modifiers=tuple(modifiers),
        mujoco=mujoco,
        canonical_json=json.dumps(canonical, sort_keys=True),
        **timing,
    )
    try:
        if measured is None:
            ms.actuation(0.0, 0.0)
        else:
            ms.actuation(measured.wing_command_deg[0], 0.0, leg_period_s=measured.leg_period_s)
    except ValueError as exc:
        raise ModelSetError(f"{wa}: {exc}") from None
    return ms


def _mujoco(table, where: str) -> MujocoParams:
    """The ``[mujoco]`` table over :data:`sim.engine.MUJOCO_DEFAULTS` (any subset of
    :data:`sim.engine.MUJOCO_KEYS`; ``solimp`` a list of five numbers)."""
    tab = dict(_check_keys(table, MUJOCO_KEYS, set(), where))

    def as_float(v):  # a whole number written without a point hashes as the same float
        return float(v) if isinstance(v, int) and not isinstance(v, bool) else v

    if isinstance(tab.get("solimp"), list):
        tab["solimp"] = tuple(as_float(x) for x in tab["solimp"])
    for k in ("solref_time_s", "solref_dampratio", "margin_m", "servo_kv_n_m_s_rad", "impratio"):
        if k in tab:
            tab[k] = as_float(tab[k])
    try:
        return replace(MUJOCO_DEFAULTS, **tab)
    except EngineError as exc:
        raise ModelSetError(f"{where}: {str(exc).removeprefix('mujoco ')}") from None


def _knot_table(table, n_cmd: int, where: str, *, closed_ends: bool, period_s: float | None = None):
    """Validated ``knots_s`` and ``knots_deg`` of one joint: one row per command, same length, times from 0
    increasing, the closed angle (or 0 and the period, for the leg) at both ends."""
    _check_keys(table, {"knots_s", "knots_deg"}, {"knots_s", "knots_deg"}, where)
    rows = {}
    for key in ("knots_s", "knots_deg"):
        v = table[key]
        ok = isinstance(v, list) and len(v) == n_cmd and all(isinstance(r, list) for r in v)
        ok = ok and all(
            not isinstance(x, bool) and isinstance(x, (int, float)) and math.isfinite(x) for r in v for x in r
        )
        if not ok:
            raise ModelSetError(f"{where}: {key} must be {n_cmd} lists of finite numbers, one per command")
        rows[key] = tuple(tuple(float(x) for x in r) for r in v)
    for ks, kd in zip(rows["knots_s"], rows["knots_deg"], strict=True):
        if len(ks) != len(kd) or len(ks) < 3 or len(ks) != len(rows["knots_s"][0]):
            raise ModelSetError(f"{where}: every row of knots_s and knots_deg needs the same length (>= 3)")
        if ks[0] != 0 or not (np.diff(ks) > 0).all():
            raise ModelSetError(f"{where}: knots_s must start at 0 and increase; got {list(ks)}")
        if kd[0] != kd[-1] or (not closed_ends and kd[0] != 0):
            raise ModelSetError(
                f"{where}: knots_deg must end where it starts (the closed angle{'' if closed_ends else ', 0'}); "
                f"got {kd[0]:g} and {kd[-1]:g}"
            )
        if period_s is not None and ks[-1] != period_s:
            raise ModelSetError(f"{where}: every row of knots_s must end at the same period; got {ks[-1]:g}")
    return rows["knots_s"], rows["knots_deg"]


def _commands(act: dict, key: str, where: str) -> tuple[float, ...]:
    v = act[key]
    ok = isinstance(v, list) and len(v) >= (2 if key.startswith("wing") else 1)
    ok = ok and all(not isinstance(x, bool) and isinstance(x, (int, float)) and math.isfinite(x) for x in v)
    if not ok or not (np.diff(v) > 0).all() or v[0] <= 0:
        raise ModelSetError(f"{where}: {key} must be increasing angles > 0 deg (at least two for the wing)")
    return tuple(float(x) for x in v)


def _wing_extra(value, n_commands: int, where: str):
    """``[actuation] wing_extra_deg``: one number, or one per wing command, each in [0, MAX_WING_EXTRA_DEG]."""
    values = value if isinstance(value, list) else [value]
    if isinstance(value, list) and len(values) != n_commands:
        raise ModelSetError(
            f"{where}: wing_extra_deg must be one number or one per wing command ({n_commands}); got {value!r}"
        )
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 <= v <= MAX_WING_EXTRA_DEG:
            raise ModelSetError(
                f"{where}: wing_extra_deg must be in [0, {MAX_WING_EXTRA_DEG:g}] (one number or one per wing "
                f"command); got {value!r}"
            )
    return [float(v) for v in values] if isinstance(value, list) else float(value)


def wing_extra_knots_deg(wing_knots_deg, extra_deg) -> tuple:
    """Measured wing knots opened ``extra_deg`` further at each row's plateau, in proportion to how far each knot
    is open (``a * (1 + extra / plateau)`` for ``a > 0``; the closed knots stay): ``[actuation] wing_extra_deg``,
    one value for every wing command (row) or a sequence of one per row.

    A pose correction. The body holds where its support (head and wing edges) puts it, and a set whose wings open
    further holds it further over; the recorded pitch says the robot holds further over than the CAD at its
    measured servo angles (docs/physical/resting-pose.md), whatever the part that does it.

    Examples
    --------
    >>> wing_extra_knots_deg(((( -1.0, 30.0, 60.0, -1.0),),), 6.0)
    (((-1.0, 33.0, 66.0, -1.0),),)
    >>> wing_extra_knots_deg((((-1.0, 60.0, -1.0), (-1.0, 80.0, -1.0)),), [6.0, 0.0])
    (((-1.0, 66.0, -1.0), (-1.0, 80.0, -1.0)),)
    """
    n_rows = len(wing_knots_deg[0]) if len(wing_knots_deg) else 0
    extras = list(extra_deg) if isinstance(extra_deg, (list, tuple)) else [float(extra_deg)] * n_rows
    return tuple(
        tuple(
            tuple(a * (1.0 + e / max(row)) if a > 0 else a for a in row)
            for row, e in zip(servo, extras, strict=True)
        )
        for servo in wing_knots_deg
    )


def _measured(act: dict, where: str) -> MeasuredActuation:
    wing_cmd = _commands(act, "wing_command_deg", where)
    leg_cmd = _commands(act, "leg_command_deg", where)
    wing = _check_keys(act["wing"], set(_SERVOS), set(_SERVOS), f"{where[:-1]}.wing]")
    ws, wd = zip(
        *(_knot_table(wing[s], len(wing_cmd), f"{where[:-1]}.wing.{s}]", closed_ends=True) for s in _SERVOS),
        strict=True,
    )
    leg = act["leg"]
    lw = f"{where[:-1]}.leg]"
    period = leg.get("knots_s", [[None]])[0][-1] if isinstance(leg, dict) else None
    ls, ld = _knot_table(leg, len(leg_cmd), lw, closed_ends=False, period_s=period)
    return MeasuredActuation(wing_cmd, tuple(ws), tuple(wd), leg_cmd, ls, ld)
