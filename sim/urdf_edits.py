"""Edits of a URDF element tree for simulation (pure, in place): merging fixed links, the hinges a model set's
springs drive (a twisting body, a bending leg, a head that gives), and the set's geometric corrections (a moved
CoM, a moved joint). Each edit leaves every link where it was at zero deflection, unless it moves one on purpose.
"""

from __future__ import annotations

import numpy as np
from lxml import etree as ET
from numpy.typing import ArrayLike, NDArray

from geometry.errors import RobotDescriptionError, UnknownJointError
from geometry.frames import rpy_from_matrix
from geometry.urdf import origin_matrix


def _origin(el: ET._Element | None) -> NDArray[np.float64]:
    """4x4 transform of an element's ``<origin xyz rpy>`` (:func:`geometry.urdf.origin_matrix`)."""
    return origin_matrix(el)


def _set_origin(el: ET._Element, t: NDArray[np.float64]) -> None:
    o = el.find("origin")
    if o is None:
        o = ET.Element("origin")
        el.insert(0, o)
    rpy = np.zeros(3)
    if not np.allclose(t[:3, :3], np.eye(3), rtol=0.0, atol=1e-15):
        rpy = rpy_from_matrix(t[:3, :3])
    o.set("xyz", " ".join(f"{x:.17g}" for x in t[:3, 3]))
    o.set("rpy", " ".join(f"{x:.17g}" for x in rpy))


def _axis_text(v) -> str:
    """A unit axis as a URDF ``xyz`` attribute (components below 1e-12 written as 0)."""
    return " ".join(f"{x:.17g}" if abs(x) > 1e-12 else "0" for x in v)


def _joint(root: ET._Element, joint: str, purpose: str) -> ET._Element:
    """The URDF's joint element named ``joint``; ``purpose`` ("to shift") ends the error's first clause.

    Raises
    ------
    UnknownJointError
        Naming the robot's joints, if it has none of that name.
    """
    el = next((j for j in root.findall("joint") if j.get("name") == joint), None)
    if el is None:
        names = ", ".join(sorted(j.get("name") for j in root.findall("joint"))) or "none"
        raise UnknownJointError(f"the robot has no joint {joint!r} {purpose}; its joints are {names}")
    return el


def _inertial(link: ET._Element) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """(mass kg, CoM m, 3x3 inertia about the CoM kg m^2) of a link in its own frame."""
    el = link.find("inertial")
    if el is None or el.find("mass") is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    t = _origin(el)
    i = el.find("inertia")
    g = {
        k: float(i.get(k, "0")) if i is not None else 0.0 for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    }
    tensor = np.array(
        [[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]]
    )
    return float(el.find("mass").get("value")), t[:3, 3], t[:3, :3] @ tensor @ t[:3, :3].T


def _principal_frame(tensor: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Principal moments and axes (columns, a proper rotation as close to the identity as the axes allow)."""
    if np.abs(tensor - np.diag(np.diag(tensor))).max() <= 1e-12 * max(np.abs(tensor).max(), 1e-300):
        return np.diag(tensor).copy(), np.eye(3)
    w, v = np.linalg.eigh(tensor)
    order = np.argsort([int(np.argmax(np.abs(v[:, k]))) for k in range(3)])  # axis k ~ link axis k
    if sorted(int(np.argmax(np.abs(v[:, k]))) for k in range(3)) != [0, 1, 2]:
        order = np.arange(3)
    w, v = w[order], v[:, order]
    v = v * np.where(np.diag(v) < 0, -1.0, 1.0)
    if np.linalg.det(v) < 0:
        v[:, 2] *= -1
    return w, v


def merge_fixed_links(root: ET._Element) -> list[str]:
    """Merge every link hanging on a ``fixed`` joint into its parent, in place; return the merged link names.

    The parent gets the children's collision elements (origins composed with the joint's) and their joints
    (re-parented), and one ``<inertial>``: total mass, mass-weighted CoM, and the inertia about that CoM
    (parallel-axis theorem), written in its principal axes. pybullet's own ``URDF_MERGE_FIXED_LINKS`` puts a
    child's mass at the child's link origin, ignoring its ``<inertial><origin>`` (pybullet 3.2.7), so it is
    not used.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/>'
    ...         '</inertial></link><link name="b"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>'
    ...         '<inertia ixx="1" iyy="1" izz="1"/></inertial></link><joint name="j" type="fixed">'
    ...         '<parent link="a"/><child link="b"/><origin xyz="0.5 0 0"/></joint></robot>')
    >>> root = ET.fromstring(urdf)
    >>> merge_fixed_links(root)
    ['b']
    >>> el = root.find("link/inertial")
    >>> el.find("origin").get("xyz"), el.find("mass").get("value"), el.find("inertia").get("izz")
    ('0.5 0 0', '2', '2.5')
    """
    links = {lk.get("name"): lk for lk in root.findall("link")}
    merged: list[str] = []
    while True:
        fixed = next((j for j in root.findall("joint") if j.get("type") == "fixed"), None)
        if fixed is None:
            return merged
        parent = links[fixed.find("parent").get("link")]
        child = links.pop(fixed.find("child").get("link"))
        t_pc = _origin(fixed)
        for col in child.findall("collision"):
            _set_origin(col, t_pc @ _origin(col))
            parent.append(col)
        for j in root.findall("joint"):
            if j is not fixed and j.find("parent").get("link") == child.get("name"):
                j.find("parent").set("link", parent.get("name"))
                _set_origin(j, t_pc @ _origin(j))
        m_p, c_p, i_p = _inertial(parent)
        m_c, c_c, i_c = _inertial(child)
        c_c = t_pc[:3, :3] @ c_c + t_pc[:3, 3]
        i_c = t_pc[:3, :3] @ i_c @ t_pc[:3, :3].T
        mass = m_p + m_c
        if mass > 0:
            com = (m_p * c_p + m_c * c_c) / mass
            tensor = i_p + i_c
            for m, c in ((m_p, c_p), (m_c, c_c)):
                d = c - com
                tensor = tensor + m * (d @ d * np.eye(3) - np.outer(d, d))
            moments, axes = _principal_frame(tensor)
            old = parent.find("inertial")
            if old is not None:
                parent.remove(old)
            el = ET.SubElement(parent, "inertial")
            t = np.eye(4)
            t[:3, :3], t[:3, 3] = axes, com
            _set_origin(el, t)
            ET.SubElement(el, "mass", value=f"{mass:.17g}")
            ET.SubElement(
                el,
                "inertia",
                ixx=f"{moments[0]:.17g}",
                ixy="0",
                ixz="0",
                iyy=f"{moments[1]:.17g}",
                iyz="0",
                izz=f"{moments[2]:.17g}",
            )
        root.remove(fixed)
        root.remove(child)
        merged.append(child.get("name"))


TORSION_JOINT = "body_torsion"
"""Name of the revolute joint :func:`add_body_torsion` inserts (:class:`sim.compliance.BodyTorsion`)."""

TORSION_LINK = "body_torsion_frame"
"""Name of the massless link that carries the wing mounts behind ``TORSION_JOINT``."""

TORSION_LIMIT_RAD = 0.6
"""The inserted joint's range, +- rad: a twist beyond it means a broken body, not a soft one."""


def base_link(root: ET._Element) -> ET._Element:
    """The URDF's root link: the one no joint has as its child."""
    children = {j.find("child").get("link") for j in root.findall("joint")}
    return next(lk for lk in root.findall("link") if lk.get("name") not in children)


def _add_hinge(
    root: ET._Element,
    link: str,
    joint: str,
    parent: str,
    child: str,
    axis_xyz: str,
    limit_rad: float,
    *,
    mass_kg: float = 0.0,
) -> None:
    """Append a new link ``link`` (``mass_kg``, inertia ``mass_kg * 1e-6`` about each axis; 0: massless) and a
    revolute joint ``joint`` from ``parent`` to ``child`` at the parent's frame, about ``axis_xyz``, within
    ``±limit_rad``: the hinge of :func:`add_body_torsion` and :func:`add_leg_bend`, which a spring drives."""
    frame = ET.Element("link", name=link)
    inertial = ET.SubElement(frame, "inertial")
    i = mass_kg * 1e-6
    ET.SubElement(inertial, "mass", value=f"{mass_kg:.17g}")
    ET.SubElement(
        inertial, "inertia", ixx=f"{i:.17g}", ixy="0", ixz="0", iyy=f"{i:.17g}", iyz="0", izz=f"{i:.17g}"
    )
    hinge = ET.Element("joint", name=joint, type="revolute")
    ET.SubElement(hinge, "parent", link=parent)
    ET.SubElement(hinge, "child", link=child)
    ET.SubElement(hinge, "origin", xyz="0 0 0", rpy="0 0 0")
    ET.SubElement(hinge, "axis", xyz=axis_xyz)
    lim = f"{limit_rad:g}"
    ET.SubElement(hinge, "limit", lower=f"-{lim}", upper=lim, effort="1000", velocity="1000")
    root.append(frame)
    root.append(hinge)


def add_body_torsion(root: ET._Element, wing_joints: tuple[str, ...]) -> list[str]:
    """Let the part of the body that carries the wings twist against the rest, in place; return the re-hung
    joints.

    Every joint between the base link and a wing joint that starts at the base (the wing mounts; a wing joint
    itself if it starts at the base) is re-hung from a new massless link ``TORSION_LINK``, which a revolute
    joint ``TORSION_JOINT`` about the base frame's x axis, through its origin, carries. At zero twist every link
    sits where it did, so geometry, mass and CoM are unchanged. The base keeps everything else (head, leg and
    whatever is fixed to it).

    Raises
    ------
    RobotDescriptionError
        If the names are taken, or no wing joint hangs below the base.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="base"/><link name="m"/><link name="w"/><link name="h"/>'
    ...         '<joint name="mount" type="fixed"><parent link="base"/><child link="m"/></joint>'
    ...         '<joint name="wing" type="revolute"><parent link="m"/><child link="w"/></joint>'
    ...         '<joint name="head" type="fixed"><parent link="base"/><child link="h"/></joint></robot>')
    >>> root = ET.fromstring(urdf)
    >>> add_body_torsion(root, ("wing",))
    ['mount']
    >>> j = root.find("joint[@name='body_torsion']")
    >>> j.find("parent").get("link"), j.find("child").get("link"), j.find("axis").get("xyz")
    ('base', 'body_torsion_frame', '1 0 0')
    >>> root.find("joint[@name='mount']/parent").get("link"), root.find("joint[@name='head']/parent").get("link")
    ('body_torsion_frame', 'base')
    """
    joints = {j.get("name"): j for j in root.findall("joint")}
    links = {lk.get("name") for lk in root.findall("link")}
    if TORSION_JOINT in joints or TORSION_LINK in links:
        raise RobotDescriptionError(
            f"the robot already has a joint '{TORSION_JOINT}' or link '{TORSION_LINK}'; rename it to use "
            "[body_torsion]"
        )
    by_child = {j.find("child").get("link"): j for j in joints.values()}
    base = base_link(root).get("name")
    rehang: list[str] = []
    for name in wing_joints:
        j = joints.get(name)
        while j is not None and j.find("parent").get("link") != base:
            j = by_child.get(j.find("parent").get("link"))
        if j is not None and j.get("name") not in rehang:
            rehang.append(j.get("name"))
    if not rehang:
        raise RobotDescriptionError(
            f"no wing joint hangs below the base link '{base}'; [body_torsion] needs one"
        )
    _add_hinge(root, TORSION_LINK, TORSION_JOINT, base, TORSION_LINK, "1 0 0", TORSION_LIMIT_RAD)
    for name in rehang:
        joints[name].find("parent").set("link", TORSION_LINK)
    return rehang


BEND_JOINT = "leg_bend"
"""Name of the revolute joint :func:`add_leg_bend` inserts (:class:`sim.compliance.LegBend`)."""
BEND_LINK = "leg_bend_root"
"""Name of the (nearly) massless link between the leg joint and the leg behind ``BEND_JOINT``."""
BEND_LIMIT_RAD = 0.6
"""The bend's joint limit, rad (a stop far beyond any sag or ringing of a sensible spring)."""


def add_leg_bend(root: ET._Element, leg_joint: str) -> str:
    """Let the leg bend out of its swing plane, in place; return the name of the leg's link.

    The leg joint's child link (the leg) is re-hung from a new link ``BEND_LINK`` at the leg joint's frame, on a
    revolute joint ``BEND_JOINT`` through the leg's pivot about the axis perpendicular to both the leg joint's
    axis and the pivot-to-CoM line of the leg (for the lab robot: the horizontal axis across the rod, so the
    leg's end bobs up and down). At zero bend every link sits where it did, so geometry, mass and CoM are
    unchanged. ``BEND_LINK`` carries 1e-6 of the leg's mass (pybullet needs a mass on a moving link).

    Raises
    ------
    RobotDescriptionError
        If the names are taken, the leg joint is missing, or the leg's CoM lies on the leg joint's axis.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="b"/><link name="leg"><inertial><origin xyz="-0.06 0 0"/>'
    ...         '<mass value="0.05"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6"/></inertial></link>'
    ...         '<joint name="swing" type="revolute"><parent link="b"/><child link="leg"/>'
    ...         '<axis xyz="0 0 1"/></joint></robot>')
    >>> root = ET.fromstring(urdf)
    >>> add_leg_bend(root, "swing")
    'leg'
    >>> j = root.find("joint[@name='leg_bend']")
    >>> j.find("parent").get("link"), j.find("child").get("link"), j.find("axis").get("xyz")
    ('leg_bend_root', 'leg', '0 -1 0')
    >>> root.find("joint[@name='swing']/child").get("link")
    'leg_bend_root'
    """
    joints = {j.get("name"): j for j in root.findall("joint")}
    links = {lk.get("name"): lk for lk in root.findall("link")}
    if BEND_JOINT in joints or BEND_LINK in links:
        raise RobotDescriptionError(
            f"the robot already has a joint '{BEND_JOINT}' or link '{BEND_LINK}'; rename it to use [leg_bend]"
        )
    j = joints.get(leg_joint)
    if j is None:
        raise RobotDescriptionError(f"the robot has no leg joint '{leg_joint}'; [leg_bend] needs one")
    leg = str(j.find("child").get("link"))
    mass, com, _ = _inertial(links[leg])
    ax_el = j.find("axis")
    axis = (
        np.array([float(v) for v in ax_el.get("xyz").split()]) if ax_el is not None else np.array([1.0, 0, 0])
    )
    bend = np.cross(axis / np.linalg.norm(axis), com)
    if mass <= 0 or np.linalg.norm(bend) < 1e-9:
        raise RobotDescriptionError(
            f"the leg link '{leg}' has no mass off its joint's axis, so it has no bending axis; [leg_bend] needs one"
        )
    bend /= np.linalg.norm(bend)
    j.find("child").set("link", BEND_LINK)
    _add_hinge(
        root, BEND_LINK, BEND_JOINT, BEND_LINK, leg, _axis_text(bend), BEND_LIMIT_RAD, mass_kg=mass * 1e-6
    )
    return leg


def shift_com(root: ET._Element, offset_m: ArrayLike) -> str:
    """Move the whole robot's CoM by ``offset_m`` (base frame, m), in place, as
    :meth:`geometry.Robot.with_com_offset` does: the base link's inertial origin moves by ``offset_m * M / m_base``
    (M the total mass of every link); masses and inertias about each CoM stay. Return the base link's name.

    Raises
    ------
    RobotDescriptionError
        If the base link has no mass to move.

    Examples
    --------
    >>> urdf = ('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/>'
    ...         '</inertial></link><link name="b"><inertial><mass value="3"/><inertia ixx="1" iyy="1" izz="1"/>'
    ...         '</inertial></link><joint name="j" type="revolute"><parent link="a"/><child link="b"/></joint>'
    ...         '</robot>')
    >>> root = ET.fromstring(urdf)
    >>> shift_com(root, [0.0, 0.001, 0.0]), root.find("link/inertial/origin").get("xyz")
    ('a', '0 0.0040000000000000001 0')
    """
    d = np.asarray(offset_m, dtype=np.float64)
    base = base_link(root)
    total = sum(_inertial(lk)[0] for lk in root.findall("link"))
    m_base = _inertial(base)[0]
    if m_base <= 0:
        raise RobotDescriptionError(
            f"the base link '{base.get('name')}' has no mass, so there is none to move for a CoM offset"
        )
    el = base.find("inertial")
    t = _origin(el)
    t[:3, 3] += d * total / m_base
    _set_origin(el, t)
    return str(base.get("name"))


def shift_joint(root: ET._Element, joint: str, offset_m: ArrayLike) -> None:
    """Move one joint's origin by ``offset_m`` (m, in its parent link's frame), in place, as
    :meth:`geometry.Robot.with_joint_shift` does: its child link and everything below move with it.

    Raises
    ------
    UnknownJointError
        If the URDF has no joint of that name.

    Examples
    --------
    >>> root = ET.fromstring('<robot name="r"><joint name="j" type="fixed"><origin xyz="0.05 0 0.008"/></joint></robot>')
    >>> shift_joint(root, "j", [-0.018, 0.0, 0.0]); root.find("joint/origin").get("xyz")
    '0.032000000000000001 0 0.0080000000000000002'
    """
    el = _joint(root, joint, "to shift")
    t = _origin(el)
    t[:3, 3] += np.asarray(offset_m, dtype=np.float64)
    _set_origin(el, t)


def add_head_compliance(root: ET._Element, joint: str, *, slide: bool, axis: ArrayLike, travel: float) -> str:
    """Make the fixed joint that attaches the head give, in place (:class:`sim.head_compliance.HeadCompliance`): it
    becomes a slide along ``axis`` (``slide``, ``travel`` in m) or a hinge about it (``travel`` in rad), through
    its origin, stopped at ``±travel``; ``axis`` is in the joint's parent frame. At zero deflection every link sits
    where it did. Return the head's link name.

    Raises
    ------
    UnknownJointError
        If the URDF has no joint of that name.
    RobotDescriptionError
        If the joint is not fixed (it already moves: a wing or leg joint, say).

    Examples
    --------
    >>> root = ET.fromstring('<robot name="r"><link name="b"/><link name="h"/><joint name="head_mount" '
    ...                      'type="fixed"><parent link="b"/><child link="h"/><origin xyz="0.05 0 0"/></joint></robot>')
    >>> add_head_compliance(root, "head_mount", slide=True, axis=[1, 0, 0], travel=0.017)
    'h'
    >>> j = root.find("joint")
    >>> j.get("type"), j.find("axis").get("xyz"), j.find("limit").get("lower")
    ('prismatic', '1 0 0', '-0.017000000000000001')
    """
    try:
        el = _joint(root, joint, "for [head_compliance]")
    except UnknownJointError as exc:
        raise UnknownJointError(
            f"{exc}: give the joint that attaches the head as [head_compliance] joint"
        ) from None
    if el.get("type") != "fixed":
        raise RobotDescriptionError(
            f"[head_compliance] joint {joint!r} is {el.get('type')}, not fixed; give the fixed joint that attaches "
            "the head"
        )
    a = np.asarray(axis, dtype=np.float64).reshape(3)
    a = _origin(el)[:3, :3].T @ (a / np.linalg.norm(a))  # URDF axes are in the joint's own frame
    el.set("type", "prismatic" if slide else "revolute")
    for old in el.findall("axis") + el.findall("limit"):
        el.remove(old)
    ET.SubElement(el, "axis", xyz=_axis_text(a))
    t = f"{float(travel):.17g}"
    ET.SubElement(el, "limit", lower=f"-{t}", upper=t, effort="1000", velocity="1000")
    return str(el.find("child").get("link"))
