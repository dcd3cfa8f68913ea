import hashlib
import os
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
import yourdfpy

from geometry import Robot
from geometry.builtin import builtin_description, builtin_parameters, builtin_urdf_path, load_builtin_robot
from landscape import compute

# the paper's Table 1, kg
PAPER_KG = {
    "head": 0.0134,
    "wing1": 0.0287,
    "wing2": 0.0287,
    "base_link": 0.0286,
    "motor3": 0.028,
    "motor4": 0.028,
    "motor1": 0.0244,
    "motor2": 0.0244,
    "pendulum": 0.0043 + 0.0515,
}


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    return Robot.from_urdf(builtin_urdf_path(tmp_path_factory.mktemp("cache")))


def test_masses(robot):
    assert {p.link: pytest.approx(p.mass.mass_kg, abs=1e-12) for p in robot.parts} == PAPER_KG
    assert robot.pose(0, 0).mass_kg == pytest.approx(0.260, abs=1e-12)
    assert builtin_parameters().total_mass_kg == pytest.approx(0.260, abs=1e-12)


def _digest(files):
    return hashlib.sha256(b"".join(k.encode() + v for k, v in sorted(files.items()))).hexdigest()


def test_deterministic_across_processes_and_cached(tmp_path):
    """A fresh process (another hash seed, no cache) generates byte-identical files; the cache directory is
    named by their content and is written once."""
    code = (
        "import hashlib; from geometry.builtin import builtin_description as d; "
        "f = d(); print(hashlib.sha256(b''.join(k.encode() + v for k, v in sorted(f.items()))).hexdigest())"
    )
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout
    files = builtin_description()
    assert out.strip() == _digest(files)
    a = builtin_urdf_path(tmp_path)
    assert a.parent.name == f"builtin-{_digest(files)[:16]}" and a.read_bytes() == files["robot.urdf"]
    assert {f.name for f in a.parent.iterdir()} == set(files)
    written_ns = a.stat().st_mtime_ns
    assert builtin_urdf_path(tmp_path) == a and a.stat().st_mtime_ns == written_ns  # cached: not rewritten
    other = builtin_urdf_path(tmp_path, params=replace(builtin_parameters(), head_kg=0.02))
    assert other.parent != a.parent  # other parameters, other files, another directory


def test_urdf_valid_and_joints(robot):
    u = yourdfpy.URDF.load(str(robot.source))
    assert u.validate()
    assert set(u.actuated_joint_names) == {
        "wing_pitch_left",
        "wing_pitch_right",
        "wing_roll_left",
        "wing_roll_right",
        "leg",
    }
    assert robot.theta_limits_deg() == {
        "theta_w": pytest.approx((-10, 95)),
        "theta_l": pytest.approx((-90, 90)),
    }


def test_closed_form_inertias(robot):
    parts = {p.link: p.mass for p in robot.parts}
    # leg motor: solid box 30 x 20 x 23 mm (link axes)
    m, (a, b, c) = 0.0286, (0.030, 0.020, 0.023)
    assert np.diag(parts["base_link"].inertia_kg_m2) == pytest.approx(
        [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12], rel=1e-6
    )
    # pendulum: rod (70 x 8 x 1.6 mm at x = -35 mm) + solid sphere r = 14 mm at x = -64.5 mm
    pend = parts["pendulum"]
    x = (0.0043 * -0.035 + 0.0515 * -0.0645) / 0.0558
    assert pend.com_m == pytest.approx([x, 0, 0], abs=1e-9)
    i_xx = 0.0043 * (0.008**2 + 0.0016**2) / 12 + 0.4 * 0.0515 * 0.014**2
    assert pend.inertia_kg_m2[0, 0] == pytest.approx(i_xx, rel=1e-3)
    # shells: physically sized, positive definite
    for link in ("head", "wing1", "wing2"):
        ev = np.linalg.eigvalsh(parts[link].inertia_kg_m2)
        assert ev.min() > 1e-6


def test_mirror_symmetry(robot):
    pose = robot.pose(74, 0)
    assert pose.com_m[1] == pytest.approx(0.0, abs=1e-12)
    v = pose.hull.vertices_m
    mirrored = v * [1, -1, 1]
    d = np.linalg.norm(mirrored[:, None, :] - v[None, :, :], axis=-1).min(axis=1)
    assert d.max() < 1e-9


def test_pybullet_loads_it(robot):
    pb = pytest.importorskip("sim.world").pb
    cid = pb.connect(pb.DIRECT)
    try:
        body = pb.loadURDF(str(robot.source), flags=pb.URDF_USE_INERTIA_FROM_FILE, physicsClientId=cid)
        total = sum(
            pb.getDynamicsInfo(body, k, physicsClientId=cid)[0]
            for k in range(-1, pb.getNumJoints(body, physicsClientId=cid))
        )
    finally:
        pb.disconnect(cid)
    assert total == pytest.approx(0.260, abs=1e-9)


def test_trends(robot):
    by_w = [compute(robot, theta_w_deg=w, theta_l_deg=0).barrier.righting.barrier_j for w in (60, 70, 80, 90)]
    by_l = [
        compute(robot, theta_w_deg=74, theta_l_deg=tl).barrier.righting.barrier_j for tl in (20, 30, 40, 50)
    ]
    assert np.all(np.diff(by_w) < 0) and np.all(np.diff(by_l) < 0)
    c = compute(robot, theta_w_deg=74, theta_l_deg=30)
    assert c.barrier.righting.direction == "roll"


# agreement with the lab URDF reached by this model (figures/builtin_vs_lab.py); tolerances are what it achieves
@pytest.mark.parametrize(
    "tw, tl, pitch_tol, barrier_rtol",
    [
        (30, 0, 1.0, 0.05),
        (60, 0, 1.0, 0.03),
        (70, 0, 1.0, 0.02),
        (74, 0, 1.0, 0.02),
        (80, 0, 1.0, 0.25),
        (74, 20, 1.0, 0.07),
        (74, 50, 1.0, 0.25),
    ],
)
def test_close_to_lab_robot(robot, lab_robot, tw, tl, pitch_tol, barrier_rtol):
    a = compute(robot, theta_w_deg=tw, theta_l_deg=tl)
    b = compute(lab_robot, theta_w_deg=tw, theta_l_deg=tl)
    assert a.minimum.pitch_deg == pytest.approx(b.minimum.pitch_deg, abs=pitch_tol)
    assert a.minimum.energy_j == pytest.approx(b.minimum.energy_j, rel=0.025)
    assert a.barrier.righting.barrier_j == pytest.approx(b.barrier.righting.barrier_j, rel=barrier_rtol)


def test_load_builtin_robot_default_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("LANDSCAPE_CACHE", str(tmp_path))
    r = load_builtin_robot()
    assert str(r.source).startswith(str(tmp_path)) and r.name == "builtin_robot"
