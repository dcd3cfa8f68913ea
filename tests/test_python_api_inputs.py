"""The Python API's answers to inputs that once gave a silent wrong answer or a CLI message: a mesh file given
as the robot, implausible units, mesh-only arguments with a URDF, angles no joint takes, mirror saddles that
tie, the kernels' cache location."""

from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

import landscape
from geometry import Robot
from geometry.errors import UnknownJointError, UsageError
from geometry.robots import ImplausibleUnitsWarning, load_robot

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture()
def box_stl(tmp_path):
    f = tmp_path / "box.stl"
    trimesh.creation.box(extents=(100.0, 60.0, 40.0)).export(f)  # a 100 mm box, saved in millimetres
    return f


def test_a_mesh_file_as_robot_is_read_as_a_mesh(box_stl):
    body = load_robot(str(box_stl), units="mm", mass_kg=0.2)
    assert body.name == "box" and body.total_mass_kg == 0.2 and not body.has_joints
    assert np.ptp(body.parts[0].hull_link_m, axis=0).max() == pytest.approx(0.1)


def test_implausible_units_warn_with_the_python_fix(box_stl):
    with pytest.warns(ImplausibleUnitsWarning, match=r"100 m across, read in metres; .* give units='mm'"):
        load_robot(str(box_stl))


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(robot="builtin", mesh="x.stl"), r"give either robot .* or mesh= \(a mesh file\), not both"),
        (dict(mass_kg=2.0), r"^mass_kg applies only to a single mesh body \(mesh= or a mesh file\)"),
        (dict(units="mm", com=(0, 0, 0)), r"^com, units apply only to a single mesh body"),
    ],
)
def test_python_errors_name_python_arguments(kwargs, match):
    with pytest.raises(UsageError, match=match):
        load_robot(**kwargs)


def test_joints_with_a_mesh_names_the_argument(box_stl):
    with pytest.raises(UsageError, match="^joints= applies to a URDF robot"):
        load_robot(mesh=box_stl, joints="wing=a")


def test_angles_no_joint_takes_are_refused_in_python(box_stl):
    body = load_robot(mesh=box_stl, units="mm")
    with pytest.raises(
        UnknownJointError, match="box is a single rigid body without joints: nothing takes theta_w_deg"
    ):
        landscape.compute(body, theta_w_deg=74.0)
    with pytest.raises(UnknownJointError, match="nothing takes wing_joints_deg"):
        landscape.compute(body, wing_joints_deg={"wing_pitch_left": 70.0})  # an AttributeError before


# ---------------------------------------------------------------------------------------------- mirror ties
def _box(com):
    return Robot.from_trimesh(trimesh.creation.box(extents=(0.2, 0.2, 0.1)), mass_kg=1.0, com=com, name="box")


def test_mirror_twins_are_reported_at_positive_roll():
    # a box symmetric in y with its CoM on the plane: the grid's roll-wise search met the -65 deg twin first
    c = landscape.compute(_box((0.03, 0.0, 0.0)), step_deg=5.0)
    assert c.barrier.roll_wise.saddle_roll_deg == 65.0
    assert (c.barrier.roll_wise.path_deg[:, 1] >= 0).all()


def test_an_asymmetric_body_keeps_its_own_saddle():
    c = landscape.compute(_box((0.03, 0.02, 0.0)), step_deg=5.0)  # CoM off the plane: no twin
    assert c.barrier.roll_wise.saddle_roll_deg < 0


def test_the_committed_barrier_map_follows_the_tie_rule():
    with open(REPO / "figures" / "barrier_map" / "barrier_map.csv") as f:
        rows = [r for r in csv.DictReader(f) if float(r["theta_l_deg"]) == 0.0]  # the symmetric poses
    assert len(rows) == 16
    for r in rows:
        for key in ("saddle_roll_deg", "escape_saddle_roll_deg"):
            assert r[key] == "" or float(r[key]) >= 0 or float(r[key]) == -180.0, (r["theta_w_deg"], key)


# ---------------------------------------------------------------------------------------------- numba cache
@pytest.mark.parametrize("numba_first", [False, True])
def test_kernels_are_cached_per_user_not_beside_the_sources(tmp_path, numba_first):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["LANDSCAPE_CACHE"] = str(tmp_path)
    code = ("import numba; " if numba_first else "") + (
        "import landscape._energy_kernels, numba.core.config as c; print(c.CACHE_DIR)"
    )
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == str(tmp_path / "numba")
