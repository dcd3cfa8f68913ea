"""A posed robot: its inertia is its parts' by the parallel-axis theorem."""

import numpy as np


def test_a_poses_inertia_is_its_parts_by_the_parallel_axis_theorem():
    """Pose.inertia_kg_m2 against the parts' own tensors, turned into the body frame and moved to the CoM here."""
    from geometry.robots import load_robot

    pose = load_robot("builtin").pose(74.0, 30.0)
    expected = np.zeros((3, 3))
    for part in pose.parts:
        tf = pose.link_transforms[part.link]
        rot = tf[:3, :3]
        r = rot @ part.mass.com_m + tf[:3, 3] - pose.com_m
        expected += rot @ part.mass.inertia_kg_m2 @ rot.T + part.mass.mass_kg * (
            r @ r * np.eye(3) - np.outer(r, r)
        )
    assert np.allclose(pose.inertia_kg_m2, expected, rtol=1e-12, atol=1e-15)
    assert (np.linalg.eigvalsh(pose.inertia_kg_m2) > 0).all()
