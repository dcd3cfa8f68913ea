"""The built-in robot: the source paper's 260 g self-righting robot, built from primitives by code.

Parts (all dimensions and placements in :class:`BuiltinParameters`):

- **Shell.** Head and two wings are cut from one thin shell, the lower half of an axis-aligned ellipsoid
  ``z = zc - c sqrt(1 - ((x - cx)/a)^2 - (y/b)^2)`` (body frame, wings closed), flat at rim height where the plan
  outline reaches beyond the ellipsoid's rim. Its five parameters were fitted by
  ``benchmarks/fit_builtin_shell.py`` to 16 landmarks of the lab robot's part hulls in ``../shared/ref`` (the
  script prints the fit's residuals; the lab's shell bottom is flattened, which no ellipsoid follows). The plan
  outline (half-width at stations along x) and the pieces' extents carry over the lab's: the head is a horseshoe
  band ``5.4 <= x <= 134.5 mm``, from an inner half-width (open middle) out to ``|y| <= 71.3 mm``; each wing spans
  ``-125.4 <= x <= 98.2 mm, |y| >= 21.8 mm`` out to the outline. Like the lab's meshes, head and wings overlap in
  plan where the lab's do.
- **Motors.** Five solid boxes 23 x 20 x 30 mm (the lab's motor size) at the lab's places and orientations.
- **Leg.** A rod 70 x 8 x 1.6 mm and a solid sphere of radius 14 mm on the leg joint.
- **Joints.** The lab URDF's names, origins, axes and limits (wings [-10, 95] deg, leg [-90, 90] deg,
  1 N m, 20 rad/s), so the default joint map applies and the landscape and pybullet see the same robot.

**Masses** are the paper's (head 13.4 g, leg rod 4.3 g, leg added mass 51.5 g, leg motor 28.6 g, wings 28.7 g
each, wing pitch motors 28.0 g each, wing roll motors 24.4 g each: 260 g).

**Centres of mass and inertias.** Motors, rod and sphere are uniform solids (closed-form CoM and inertia). For
the head and wings the landscape needs the *lab's* mass distribution to reproduce the lab's barriers, and the lab
places those masses at the mean of its mesh vertices, not at the area centroid (a uniform shell would put each
wing's CoM further outboard). So their ``<inertial>`` origins carry over the lab's CoMs (the head's y set to 0,
its area-centroid value: the lab's nonzero y comes from uneven tessellation), while their inertia tensors are
those of the uniform thin-shell pieces moved to that CoM (parallel-axis theorem): physically sized (1e-5 kg m^2
scale), unlike the lab URDF's placeholder tensors.

Every mesh is written in its link's frame in metres; each convex part is its own collision element, so pybullet's
per-element convex hulls are exact for contact with flat ground.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .errors import RobotDescriptionError
from .frames import rpy_matrix
from .mass import MassProperties, combine, shell_mass_properties, solid_mass_properties

if TYPE_CHECKING:
    import trimesh

URDF_NAME = "robot.urdf"
GENERATOR_VERSION = "1"


@dataclass(frozen=True)
class BuiltinParameters:
    """Every dimension and mass of the built-in robot (SI units; body frame = leg-motor frame, wings closed)."""

    # shell: lower half of an ellipsoid (fitted by benchmarks/fit_builtin_shell.py)
    shell_center_x_m: float = -11.42e-3
    shell_a_m: float = 123.87e-3
    shell_b_m: float = 133.26e-3
    shell_rim_z_m: float = 21.16e-3
    shell_depth_m: float = 35.47e-3
    shell_grid: int = 22
    # plan outline of the shell: half-width (|y|) at stations along x, read off the lab's meshes
    outline_x_m: tuple[float, ...] = tuple(
        np.round(np.r_[-125.4, np.arange(-120.0, 131.0, 10.0), 134.5] * 1e-3, 6)
    )
    outline_half_width_m: tuple[float, ...] = tuple(
        np.array(
            [
                58.3,
                69.1,
                79.7,
                88.5,
                94.1,
                98.8,
                102.6,
                105.7,
                107.2,
                109.0,
                109.4,
                109.8,
                109.0,
                107.8,
                106.6,
                103.6,
                99.8,
                95.3,
                92.1,
                86.0,
                75.7,
                68.3,
                61.2,
                57.5,
                50.8,
                39.6,
                26.2,
                11.5,
            ]
        )
        * 1e-3
    )
    head_x_m: tuple[float, float] = (5.4e-3, 134.5e-3)
    head_y_max_m: float = 71.3e-3
    # the head is a horseshoe band: its inner half-width at stations along x (open middle), from the lab's mesh
    head_inner_x_m: tuple[float, ...] = tuple(
        np.array([5.4, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 134.5]) * 1e-3
    )
    head_inner_half_width_m: tuple[float, ...] = tuple(
        np.array([46.0, 47.9, 52.3, 55.5, 56.6, 57.0, 55.9, 53.7, 50.2, 45.7, 36.3, 24.9, 0.0, 0.0]) * 1e-3
    )
    wing_x_m: tuple[float, float] = (-125.4e-3, 98.2e-3)
    wing_y_min_m: float = 21.8e-3
    # masses (the paper's Table 1)
    head_kg: float = 0.0134
    wing_kg: float = 0.0287
    leg_motor_kg: float = 0.0286
    pitch_motor_kg: float = 0.0280
    roll_motor_kg: float = 0.0244
    rod_kg: float = 0.0043
    leg_mass_kg: float = 0.0515
    # motors: box (mesh axes) and placements (the lab's)
    motor_box_m: tuple[float, float, float] = (0.023, 0.020, 0.030)
    base_motor_rpy: tuple[float, float, float] = (0.0, np.pi / 2, 0.0)
    head_origin_m: tuple[float, float, float] = (0.05052, 0.0, 0.00812)
    pitch_motor_origin_m: tuple[float, float, float] = (0.027, 0.026, -0.003)  # left (+y); right mirrors y
    pitch_joint_origin_m: tuple[float, float, float] = (0.00591, 0.0, 0.00163)
    roll_motor_offset_m: tuple[float, float, float] = (0.0371, 0.002, 0.00651)  # left; right mirrors y
    roll_motor_rpy: tuple[float, float, float] = (np.pi / 2, np.deg2rad(74.0), 0.0)
    roll_joint_origin_m: tuple[float, float, float] = (0.0371, -0.00721, 0.00651)  # left; right mirrors y
    # centres of mass carried over from the lab (link frames)
    head_com_m: tuple[float, float, float] = (0.02694, 0.0, -0.000934)
    wing_com_m: tuple[float, float, float] = (-0.07942, 0.0398, -0.00706)  # left; right mirrors y
    # leg
    leg_pivot_m: tuple[float, float, float] = (0.0, 0.0, 0.015)
    rod_box_m: tuple[float, float, float] = (0.070, 0.008, 0.0016)
    rod_center_m: tuple[float, float, float] = (-0.035, 0.0, 0.0)
    sphere_radius_m: float = 0.014
    sphere_center_m: tuple[float, float, float] = (-0.0645, 0.0, 0.0)
    # joints
    wing_limits_rad: tuple[float, float] = (np.deg2rad(-10.0), np.deg2rad(95.0))
    leg_limits_rad: tuple[float, float] = (np.deg2rad(-90.0), np.deg2rad(90.0))
    effort_n_m: float = 1.0
    velocity_rad_s: float = 20.0

    @property
    def total_mass_kg(self) -> float:
        return (
            self.head_kg
            + 2 * self.wing_kg
            + self.leg_motor_kg
            + 2 * self.pitch_motor_kg
            + 2 * self.roll_motor_kg
            + self.rod_kg
            + self.leg_mass_kg
        )


def builtin_parameters() -> BuiltinParameters:
    """The built-in robot's parameters (the defaults of :class:`BuiltinParameters`)."""
    return BuiltinParameters()


# ---------------------------------------------------------------------------------------------- geometry helpers
def _mirror_y(v):
    return (v[0], -v[1], v[2])


def _shell_piece(p: BuiltinParameters, x_range, side: str) -> trimesh.Trimesh:
    """A piece of the shell over ``x_range`` (body frame, m): ``side`` "head_left"/"head_right" span the head's
    horseshoe band inner(x) <= |y| <= min(head half-width, outline(x)), "left"/"right" the wings
    wing_y_min <= |y| <= outline(x), on +y / -y. The surface is the half-ellipsoid;
    where the outline reaches beyond the ellipsoid's rim it continues flat at rim height (a brim)."""
    n = p.shell_grid
    xs = np.linspace(*x_range, n)
    half = np.interp(xs, p.outline_x_m, p.outline_half_width_m)
    if side.startswith("head"):
        lo = np.interp(xs, p.head_inner_x_m, p.head_inner_half_width_m)
        hi = np.maximum(np.minimum(half, p.head_y_max_m), lo + 1e-4)
    else:
        lo, hi = np.full(n, p.wing_y_min_m), np.maximum(half, p.wing_y_min_m + 1e-4)
    if side.endswith("right"):
        lo, hi = -hi, -lo
    t = np.linspace(0.0, 1.0, n)
    X = np.repeat(xs[:, None], n, axis=1)
    Y = lo[:, None] + t[None, :] * (hi - lo)[:, None]
    rho2 = ((X - p.shell_center_x_m) / p.shell_a_m) ** 2 + (Y / p.shell_b_m) ** 2
    Z = p.shell_rim_z_m - p.shell_depth_m * np.sqrt(np.clip(1.0 - rho2, 0.0, None))
    verts = np.stack([X, Y, Z], axis=-1).reshape(-1, 3)
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    import trimesh

    mesh = trimesh.Trimesh(verts, faces, process=True)
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    return mesh


def _box(extents, rpy=(0.0, 0.0, 0.0), center=(0.0, 0.0, 0.0)) -> trimesh.Trimesh:
    import trimesh

    m = trimesh.creation.box(extents=np.asarray(extents, float))
    T = np.eye(4)
    T[:3, :3] = rpy_matrix(rpy)
    T[:3, 3] = center
    m.apply_transform(T)
    return m


def _moved(mp: MassProperties, com_m) -> MassProperties:
    """The same body's inertia about another point (parallel-axis theorem), reported as its CoM."""
    d = np.asarray(com_m, float) - mp.com_m
    inertia = mp.inertia_kg_m2 + mp.mass_kg * (d @ d * np.eye(3) - np.outer(d, d))
    return MassProperties(mp.mass_kg, np.asarray(com_m, float), inertia, mp.model)


# ---------------------------------------------------------------------------------------------- the description
@dataclass(frozen=True)
class _Link:
    name: str
    meshes: dict[str, trimesh.Trimesh]  # file name -> mesh in link frame (one collision element each)
    inertial: MassProperties


def _links(p: BuiltinParameters) -> list[_Link]:
    zero = (0.0, 0.0, 0.0)
    motor = _box(p.motor_box_m, p.base_motor_rpy)
    links = [
        _Link(
            "base_link",
            {"base_link.obj": motor},
            solid_mass_properties(motor, mass_kg=p.leg_motor_kg, name="leg motor"),
        )
    ]
    head_origin = np.asarray(p.head_origin_m)
    halves = [_shell_piece(p, p.head_x_m, side) for side in ("head_left", "head_right")]
    for h in halves:
        h.apply_translation(-head_origin)
    import trimesh

    head = trimesh.util.concatenate(halves)
    links.append(
        _Link(
            "head",
            {"head_left.obj": halves[0], "head_right.obj": halves[1]},
            _moved(shell_mass_properties(head, mass_kg=p.head_kg), p.head_com_m),
        )
    )
    for side, sign, pitch_motor, roll_motor, wing in (
        ("left", 1.0, "motor4", "motor2", "wing2"),
        ("right", -1.0, "motor3", "motor1", "wing1"),
    ):

        def m(v, sign=sign):
            return v if sign > 0 else _mirror_y(v)

        pm = _box(p.motor_box_m, p.base_motor_rpy)
        links.append(
            _Link(
                pitch_motor,
                {f"{pitch_motor}.obj": pm},
                solid_mass_properties(pm, mass_kg=p.pitch_motor_kg, name=pitch_motor),
            )
        )
        rm = _box(p.motor_box_m, p.roll_motor_rpy, m(p.roll_motor_offset_m))
        links.append(
            _Link(
                roll_motor,
                {f"{roll_motor}.obj": rm},
                solid_mass_properties(rm, mass_kg=p.roll_motor_kg, name=roll_motor),
            )
        )
        wing_origin = (
            np.asarray(m(p.pitch_motor_origin_m))
            + np.asarray(p.pitch_joint_origin_m)
            + np.asarray(m(p.roll_joint_origin_m))
        )
        piece = _shell_piece(p, p.wing_x_m, side)
        piece.apply_translation(-wing_origin)
        links.append(
            _Link(
                wing,
                {f"{wing}.obj": piece},
                _moved(shell_mass_properties(piece, mass_kg=p.wing_kg), m(p.wing_com_m)),
            )
        )
    rod = _box(p.rod_box_m, zero, p.rod_center_m)
    import trimesh

    ball = trimesh.creation.icosphere(subdivisions=2, radius=p.sphere_radius_m)
    ball.apply_translation(p.sphere_center_m)
    r = p.sphere_radius_m
    ball_mp = MassProperties(
        p.leg_mass_kg, np.asarray(p.sphere_center_m, float), 0.4 * p.leg_mass_kg * r * r * np.eye(3), "solid"
    )
    links.append(
        _Link(
            "pendulum",
            {"pendulum_rod.obj": rod, "pendulum_sphere.obj": ball},
            combine([solid_mass_properties(rod, mass_kg=p.rod_kg, name="leg rod"), ball_mp]),
        )
    )
    return links


def _obj_text(mesh: trimesh.Trimesh) -> str:
    out = io.StringIO()
    out.write("# built-in self-righting robot part, metres, link frame (geometry/builtin.py)\n")
    for v in np.asarray(mesh.vertices):
        out.write(f"v {v[0]:.9f} {v[1]:.9f} {v[2]:.9f}\n")
    for f in np.asarray(mesh.faces) + 1:
        out.write(f"f {f[0]} {f[1]} {f[2]}\n")
    return out.getvalue()


def _fmt(v) -> str:
    return " ".join(f"{float(x):.9g}" for x in v)


def _urdf_text(p: BuiltinParameters, links: list[_Link]) -> str:
    lines = [
        '<?xml version="1.0"?>',
        "<!-- Built-in self-righting robot, written by geometry/builtin.py (version "
        f"{GENERATOR_VERSION}). Metres, kilograms, radians. -->",
        '<robot name="builtin_robot">',
    ]
    for link in links:
        lines.append(f'  <link name="{link.name}">')
        for fname in link.meshes:
            for kind in ("visual", "collision"):
                lines += [
                    f'    <{kind} name="{fname[:-4]}">',
                    '      <origin xyz="0 0 0" rpy="0 0 0"/>',
                    f'      <geometry><mesh filename="{fname}"/></geometry>',
                    f"    </{kind}>",
                ]
        inertia = link.inertial.inertia_kg_m2
        lines += [
            "    <inertial>",
            f'      <origin xyz="{_fmt(link.inertial.com_m)}" rpy="0 0 0"/>',
            f'      <mass value="{link.inertial.mass_kg:.9g}"/>',
            f'      <inertia ixx="{inertia[0, 0]:.9g}" ixy="{inertia[0, 1]:.9g}" ixz="{inertia[0, 2]:.9g}" '
            f'iyy="{inertia[1, 1]:.9g}" iyz="{inertia[1, 2]:.9g}" izz="{inertia[2, 2]:.9g}"/>',
            "    </inertial>",
            "  </link>",
        ]

    def joint(name, kind, parent, child, xyz, axis=None, limits=None):
        out = [
            f'  <joint name="{name}" type="{kind}">',
            f'    <parent link="{parent}"/>',
            f'    <child link="{child}"/>',
            f'    <origin xyz="{_fmt(xyz)}" rpy="0 0 0"/>',
        ]
        if axis is not None:
            out.append(f'    <axis xyz="{_fmt(axis)}"/>')
            out.append(
                f'    <limit lower="{limits[0]:.17g}" upper="{limits[1]:.17g}" '
                f'effort="{p.effort_n_m:g}" velocity="{p.velocity_rad_s:g}"/>'
            )
        return out + ["  </joint>"]

    lines += joint("head_mount", "fixed", "base_link", "head", p.head_origin_m)
    lines += joint("motor4_mount", "fixed", "base_link", "motor4", p.pitch_motor_origin_m)
    lines += joint("motor3_mount", "fixed", "base_link", "motor3", _mirror_y(p.pitch_motor_origin_m))
    lines += joint(
        "wing_pitch_left",
        "revolute",
        "motor4",
        "motor2",
        p.pitch_joint_origin_m,
        (0, -1, 0),
        p.wing_limits_rad,
    )
    lines += joint(
        "wing_pitch_right",
        "revolute",
        "motor3",
        "motor1",
        p.pitch_joint_origin_m,
        (0, -1, 0),
        p.wing_limits_rad,
    )
    lines += joint(
        "wing_roll_left", "revolute", "motor2", "wing2", p.roll_joint_origin_m, (-1, 0, 0), p.wing_limits_rad
    )
    lines += joint(
        "wing_roll_right",
        "revolute",
        "motor1",
        "wing1",
        _mirror_y(p.roll_joint_origin_m),
        (1, 0, 0),
        p.wing_limits_rad,
    )
    lines += joint("leg", "revolute", "base_link", "pendulum", p.leg_pivot_m, (0, 0, 1), p.leg_limits_rad)
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def builtin_description(params: BuiltinParameters | None = None) -> dict[str, bytes]:
    """The built-in robot's files: ``robot.urdf`` and one OBJ mesh per convex part. Pure and deterministic.

    Examples
    --------
    >>> files = builtin_description()
    >>> sorted(files)[:3], b'<joint name="wing_pitch_left"' in files["robot.urdf"]
    (['base_link.obj', 'head_left.obj', 'head_right.obj'], True)
    """
    return dict(_description(params or builtin_parameters()))


@lru_cache(maxsize=4)
def _description(p: BuiltinParameters) -> tuple[tuple[str, bytes], ...]:
    """Cached body of :func:`builtin_description` (every simulated trial asks for the built-in URDF's path)."""
    links = _links(p)
    files = {name: _obj_text(mesh).encode() for link in links for name, mesh in link.meshes.items()}
    files[URDF_NAME] = _urdf_text(p, links).encode()
    return tuple(sorted(files.items()))


def _cache_root() -> Path:
    env = os.environ.get("LANDSCAPE_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "selfrighting-landscape"


def _generator_key(p: BuiltinParameters) -> str:
    """What the generated files depend on: the parameters, this generator's source and version, and trimesh's
    version (its primitives); 16 hex digits of SHA-256."""
    from .cache import installed_version

    h = hashlib.sha256(f"{GENERATOR_VERSION}\0{p!r}\0trimesh={installed_version('trimesh')}\0".encode())
    for name in ("builtin.py", "mass.py", "frames.py"):
        h.update(name.encode() + b"\0" + (Path(__file__).parent / name).read_bytes())
    return h.hexdigest()[:16]


def _verified_from_index(root: Path, key: str) -> Path | None:
    """The URDF path recorded for ``key`` if every file it lists still has the SHA-256 recorded, else None."""
    try:
        index = json.loads((root / f"builtin-index-{key}.json").read_text())
        target = root / f"builtin-{index['digest']}"
        files = index["files"]
        if URDF_NAME not in files:
            return None
        for name, digest in files.items():
            if hashlib.sha256((target / name).read_bytes()).hexdigest() != digest:
                return None
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None
    return target / URDF_NAME


def builtin_urdf_path(cache_dir: str | Path | None = None, params: BuiltinParameters | None = None) -> Path:
    """Path of the built-in robot's URDF, in a content-addressed cache directory verified on every use.

    The directory is ``builtin-<hash of the files>`` under ``cache_dir`` (default ``$LANDSCAPE_CACHE`` or
    ``~/.cache/selfrighting-landscape``). It is written atomically, so concurrent processes agree; on every call
    each file is checked, and one that was edited, removed or damaged is rewritten (atomically, file by file),
    so the name never vouches for contents it no longer has. The check compares each file's SHA-256 with an index
    (``builtin-index-<key>.json``, key: the parameters, this generator's source and trimesh's version) written
    after the files were generated; without a valid index, or on any mismatch, the files are generated (which
    needs trimesh) and compared byte by byte.
    """
    p = params or builtin_parameters()
    root = Path(cache_dir) if cache_dir is not None else _cache_root()
    key = _generator_key(p)
    hit = _verified_from_index(root, key)
    if hit is not None:
        return hit
    files = builtin_description(p)
    digest = hashlib.sha256(b"".join(k.encode() + v for k, v in files.items())).hexdigest()[:16]
    target = root / f"builtin-{digest}"
    try:
        if not target.is_dir():
            root.mkdir(parents=True, exist_ok=True)
            tmp = root / f".tmp-{digest}-{os.getpid()}"
            tmp.mkdir(parents=True, exist_ok=True)
            for name, data in files.items():
                (tmp / name).write_bytes(data)
            try:
                os.replace(tmp, target)
            except OSError:  # another process won the race
                for f in tmp.iterdir():
                    f.unlink()
                tmp.rmdir()
        for name, data in files.items():
            path = target / name
            try:
                if path.read_bytes() == data:
                    continue
            except OSError:  # missing or unreadable: rewrite it
                pass
            tmp_file = target / f".{name}.tmp-{os.getpid()}"
            tmp_file.write_bytes(data)
            os.replace(tmp_file, path)
        index = {
            "digest": digest,
            "files": {name: hashlib.sha256(data).hexdigest() for name, data in files.items()},
        }
        tmp_index = root / f".builtin-index-{key}.json.tmp-{os.getpid()}"
        tmp_index.write_text(json.dumps(index, sort_keys=True))
        os.replace(tmp_index, root / f"builtin-index-{key}.json")
    except OSError as exc:
        raise RobotDescriptionError(
            f"cannot write the built-in robot's files under {root} ({exc.strerror or exc}); set LANDSCAPE_CACHE "
            "to a writable directory"
        ) from None
    return target / URDF_NAME


def load_builtin_robot():
    """The built-in robot as a :class:`geometry.Robot`."""
    from .robot import Robot

    return Robot.from_urdf(builtin_urdf_path())
