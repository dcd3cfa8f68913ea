"""``landscape robot export``: the built-in robot's files."""

from __future__ import annotations

from pathlib import Path

import click


@click.group()
def robot():
    """The built-in robot."""


@robot.command("export")
@click.option("--out", type=click.Path(file_okay=False), required=True, help="Directory for URDF + meshes.")
def robot_export(out):
    """Write the built-in robot's URDF and meshes (the same files the landscape and pybullet load)."""
    from geometry.builtin import builtin_description

    outd = Path(out)
    outd.mkdir(parents=True, exist_ok=True)
    files = builtin_description()
    for name, data in files.items():
        (outd / name).write_bytes(data)
    click.echo(f"wrote {len(files)} files to {outd} (URDF: {outd / 'robot.urdf'})")
