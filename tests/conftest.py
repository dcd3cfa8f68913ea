import os
from pathlib import Path

import pytest

SHARED = Path(os.environ.get("LANDSCAPE_SHARED", Path(__file__).resolve().parents[1].parent / "shared"))
LAB_URDF = SHARED / "ref" / "lab_robot" / "lab_robot.urdf"


@pytest.fixture(scope="session")
def lab_robot():
    if not LAB_URDF.is_file():
        pytest.skip("../shared/ref/lab_robot is absent")
    from geometry import Robot

    return Robot.from_urdf(LAB_URDF)
