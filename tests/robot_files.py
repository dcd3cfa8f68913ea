"""Copies of the built-in robot's files to edit, for tests that need a URDF of their own (no ../shared needed).

Test modules import these helpers (``from tests.robot_files import export, rename_joints``).
"""

from pathlib import Path

from geometry.builtin import URDF_NAME, builtin_description

DEFAULT_JOINTS = ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right", "leg")


def export(directory: Path, edit=None) -> Path:
    """Write the built-in robot's files into ``directory`` (as ``landscape robot export`` does); ``edit`` maps
    the URDF text to a new one."""
    directory.mkdir(parents=True, exist_ok=True)
    for name, data in builtin_description().items():
        (directory / name).write_bytes(data)
    urdf = directory / URDF_NAME
    if edit is not None:
        urdf.write_text(edit(urdf.read_text()))
    return urdf


def rename_joints(text: str, names=DEFAULT_JOINTS, prefix="j_") -> str:
    """The URDF text with each joint of ``names`` renamed ``prefix + name``."""
    for n in names:
        text = text.replace(f'joint name="{n}"', f'joint name="{prefix}{n}"')
    return text
