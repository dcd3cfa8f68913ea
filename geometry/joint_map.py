"""Joint maps: which joints the wing angle theta_w and the leg angle theta_l drive, and their check against a
robot's joints."""

from __future__ import annotations

import logging
from dataclasses import dataclass

from .errors import GeometryError, UnknownJointError
from .kinematics import MOVABLE_JOINT_TYPES

log = logging.getLogger(__name__)

_JOINTS_HINT = (
    "declare the mapping 'wing=NAME,...;leg=NAME,...' (either group may be left out) with --joints on the command "
    "line, joints= in Python"
)
_GROUPS = {"theta_w": "wing", "theta_l": "leg"}
"""Each angle and the joint-map group it drives."""


@dataclass(frozen=True)
class JointMap:
    """Which joints the wing angle theta_w and the leg angle theta_l drive.

    Every joint in ``wing`` is set to theta_w (each wing's pitch and roll joints), every joint in ``leg`` to
    theta_l. The default names are those of the lab robot's URDF. A robot whose joints are named otherwise
    declares its own map: ``JointMap.parse("wing=a,b,c,d;leg=e")`` in Python, ``--joints "wing=a,b,c,d;leg=e"``
    on the command line. Either group may be left out (a body with wings and no leg, ``"wing=a,b"``, or a leg
    and no wings); then nothing drives that angle. At least one group names a joint.

    Examples
    --------
    >>> JointMap.parse("wing=wl,wr;leg=tail").leg
    ('tail',)
    >>> JointMap.parse("wing=wl,wr").leg
    ()
    """

    wing: tuple[str, ...] = ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right")
    leg: tuple[str, ...] = ("leg",)

    def __post_init__(self):
        seen: set[str] = set()
        for key in ("wing", "leg"):
            names = getattr(self, key)
            if isinstance(names, str) or not all(isinstance(n, str) for n in names):
                raise GeometryError(f"joint map {key} must be a tuple of joint names; got {names!r}")
            object.__setattr__(self, key, tuple(names))
            if not all(n.strip() for n in names):
                raise GeometryError(
                    f"joint map group '{key}' has an empty name ({','.join(names)!r}); name each joint, "
                    "e.g. 'wing=a,b,c,d;leg=e'"
                )
            for n in names:
                if n in seen:
                    raise GeometryError(
                        f"joint '{n}' is named twice in the joint map; each joint is driven by theta_w or theta_l, "
                        "not both: name it once"
                    )
                seen.add(n)
        if not seen:
            raise GeometryError(
                "the joint map names no joint; name the joints theta_w or theta_l drives, e.g. 'wing=a,b' "
                "or 'wing=a,b,c,d;leg=e'"
            )

    @classmethod
    def parse(cls, text: str) -> JointMap:
        """Parse ``'wing=NAME,...;leg=NAME,...'``; either group may be left out (nothing drives that angle),
        but at least one joint is named and none twice.

        Raises
        ------
        GeometryError
            If the text is not of that form.
        """
        groups: dict[str, tuple[str, ...]] = {}
        for item in filter(None, (s.strip() for s in text.split(";"))):
            key, sep, names = item.partition("=")
            key = key.strip()
            if not sep or key not in ("wing", "leg"):
                raise GeometryError(
                    f"joint map entry {item!r} is not 'wing=NAME,...' or 'leg=NAME,...'; e.g. 'wing=a,b,c,d;leg=e'"
                )
            if key in groups:
                raise GeometryError(f"joint map {text!r} gives '{key}=' twice; give each group once")
            groups[key] = tuple(n.strip() for n in names.split(","))
            if groups[key] == ("",):
                groups[key] = ()
        return cls(wing=groups.get("wing", ()), leg=groups.get("leg", ()))

    def text(self) -> str:
        """The map as ``'wing=NAME,...;leg=NAME,...'`` (what :meth:`parse` reads; an empty group left out).

        Examples
        --------
        >>> JointMap().text()
        'wing=wing_pitch_left,wing_pitch_right,wing_roll_left,wing_roll_right;leg=leg'
        >>> JointMap(leg=()).text()
        'wing=wing_pitch_left,wing_pitch_right,wing_roll_left,wing_roll_right'
        """
        return ";".join(
            f"{key}={','.join(names)}" for key, names in (("wing", self.wing), ("leg", self.leg)) if names
        )


def _checked_joint_map(joints, joint_map: JointMap | None, name: str) -> JointMap | None:
    """The joint map to use: an explicit one checked, else the default names if all are there, else None (rigid).

    Raises UnknownJointError if a named joint is absent or not movable, or only some default names are present.
    """
    types = {j.name: j.type for j in joints}
    movable = ", ".join(n for n, t in types.items() if t in MOVABLE_JOINT_TYPES) or "none"
    if joint_map is None:
        default = JointMap()
        wanted = (*default.wing, *default.leg)
        missing = [n for n in wanted if n not in types]
        if len(missing) == len(wanted):  # none of the default names: a rigid robot at its zero configuration
            log.info("%s: none of the default joints %s; treating the robot as rigid", name, wanted)
            return None
        if missing:
            raise UnknownJointError(
                f"'{name}' has {len(wanted) - len(missing)} of the {len(wanted)} default joints; missing: "
                f"{', '.join(missing)} (movable joints: {movable}); rename them in the URDF or {_JOINTS_HINT}"
            )
        joint_map = default
    for n in (*joint_map.wing, *joint_map.leg):
        if n not in types:
            raise UnknownJointError(
                f"joint '{n}' is not in '{name}' (movable joints: {movable}); {_JOINTS_HINT}"
            )
        if types[n] not in MOVABLE_JOINT_TYPES:
            raise UnknownJointError(
                f"joint '{n}' is {types[n]}, not movable (revolute or continuous), in '{name}' "
                f"(movable joints: {movable}); {_JOINTS_HINT}"
            )
    return joint_map
