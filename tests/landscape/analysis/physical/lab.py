"""The lab's data directory for the tests (skipped without ../shared), and synthetic recordings."""

import os
from pathlib import Path

import numpy as np
import pytest

from landscape.analysis.physical.recording import Recording

DATA = (
    Path(os.environ.get("LANDSCAPE_SHARED", Path(__file__).resolve().parents[4].parent / "shared"))
    / "ref"
    / ("physical_robot")
)

needs_data = pytest.mark.skipif(
    not (DATA / "robot_attempts.mat").is_file(), reason="../shared/ref/physical_robot is absent"
)


def _quat_from_pitch_roll(pitch_deg, roll_deg):
    """Body-to-world quaternion (x, y, z, w) of R = Ry(p) Rx(r), built independently of the module."""
    p, r = np.deg2rad(pitch_deg) / 2, np.deg2rad(roll_deg) / 2
    qy = np.array([0.0, np.sin(p), 0.0, np.cos(p)])
    qx = np.array([np.sin(r), 0.0, 0.0, np.cos(r)])
    x1, y1, z1, w1 = qy
    x2, y2, z2, w2 = qx
    return np.array(
        [
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        ]
    )


def _recording(up_z, roll_deg, openings=(0.0, 2.0, 4.0), dt=0.02, t0=-1.0):
    n = len(up_z)
    t = t0 + dt * np.arange(n)
    return Recording(
        "x",
        60.0,
        15.0,
        1,
        t,
        np.zeros(n),
        np.asarray(roll_deg, float),
        np.asarray(up_z, float),
        np.asarray(openings, float),
    )
