"""Where the lab's reference files are, and the robots the tests simulate.

The lab files live outside the repository, in ``../shared`` next to it; set the environment variable
``LANDSCAPE_SHARED`` to another directory (``LANDSCAPE_SHARED=/nonexistent pytest`` runs the suite as a fresh
clone sees it). Test modules import ``SHARED``, ``LAB_URDF`` and ``needs_lab`` from here (``from tests.conftest
import ...``) instead of building the path themselves.
"""

import os
from pathlib import Path
from typing import NamedTuple

import pytest

try:
    from hypothesis import settings as _hypothesis_settings
except ModuleNotFoundError:  # the test extra is not installed
    _hypothesis_settings = None

if _hypothesis_settings is not None:
    # The suite (and CI) draws the same property-test examples every run, so a red run can be rerun and is never
    # a new random draw; `HYPOTHESIS_PROFILE=explore pytest` draws new random examples every run (pin what it
    # finds with @example, as tests/landscape/barriers/test_exact.py does).
    _hypothesis_settings.register_profile("ci", derandomize=True, database=None)
    _hypothesis_settings.register_profile("explore", derandomize=False)
    _hypothesis_settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("LANDSCAPE_SHARED") or REPO.parent / "shared")
LAB_URDF = SHARED / "ref" / "lab_robot" / "lab_robot.urdf"
HAVE_LAB = LAB_URDF.is_file()
LAB_ABSENT = f"{LAB_URDF} is absent (set LANDSCAPE_SHARED to the directory holding ref/lab_robot)"

#: mark for a test that needs the lab files
needs_lab = pytest.mark.skipif(not HAVE_LAB, reason=LAB_ABSENT)


def run_cli(capsys, *argv):
    """Run ``landscape ARGV`` in this process (arguments as strings): (exit status, stdout, stderr)."""
    from landscape.cli import main

    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def outside(bounds) -> list[str]:
    """Values just outside a :class:`geometry.bounds.Bounds` at each finite end, and one that is not finite, as
    typed (whole numbers without a decimal point)."""
    import math

    vals = [math.nan]
    if not math.isinf(bounds.lo):
        vals.append(bounds.lo if bounds.lo_open else bounds.lo - 1)
    if not math.isinf(bounds.hi):
        vals.append(bounds.hi if bounds.hi_open else bounds.hi + 1)
    return ["nan" if math.isnan(v) else str(int(v)) if bounds.integer else repr(float(v)) for v in vals]


def csv_rows(path) -> list[dict]:
    """The rows of a CSV file with a header, as dicts of strings."""
    import csv

    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def set_with_table(directory: Path, table: str, text: str, base: str = "paper") -> Path:
    """A model-set file in ``directory``: the shipped set ``base`` with ``[table]`` and ``text`` appended."""
    from sim.model_set import load_model_set

    f = directory / f"{table}.toml"
    f.write_text(Path(load_model_set(base).source).read_text() + f"\n[{table}]\n" + text)
    return f


def load_script(relative: str):
    """A script of the repository that is no package module (``benchmarks/NAME.py``, ``figures/NAME.py``),
    imported as a module for its tests."""
    import importlib.util

    path = REPO / relative
    spec = importlib.util.spec_from_file_location(path.stem, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


class SimRobot(NamedTuple):
    """A robot to simulate: its URDF file and ``label``, ``"lab"`` or ``"builtin"``."""

    urdf: Path
    label: str


def builtin_robot() -> SimRobot:
    from geometry.robots import robot_urdf_path

    return SimRobot(robot_urdf_path(), "builtin")


def lab_sim_robot() -> SimRobot:
    if not HAVE_LAB:
        pytest.skip(LAB_ABSENT)
    return SimRobot(LAB_URDF, "lab")


@pytest.fixture(scope="session")
def lab_robot():
    """The lab robot as a :class:`geometry.Robot` (skips when the lab files are absent)."""
    from geometry import Robot

    return Robot.from_urdf(lab_sim_robot().urdf)


@pytest.fixture(scope="session")
def sim_robot() -> SimRobot:
    """The robot for tests whose assertions hold for any robot: the lab's when its files are here, else the
    built-in one, so a fresh clone still runs them."""
    return SimRobot(LAB_URDF, "lab") if HAVE_LAB else builtin_robot()


@pytest.fixture(scope="session", params=["lab", "builtin"])
def each_robot(request) -> SimRobot:
    """Both robots in turn, for tests with robot-specific numbers (the lab case skips without its files)."""
    return lab_sim_robot() if request.param == "lab" else builtin_robot()
