"""What the README's tour writes into the checkout is ignored by git: every command's default output directory,
and every ``--out``/``--db`` the README's ``$ landscape`` lines give outside ``figures/``."""

from __future__ import annotations

import shlex
import shutil
import subprocess
from pathlib import Path

import click
import pytest

from landscape.cli import cli

REPO = Path(__file__).resolve().parents[1]
OUTPUT_OPTIONS = ("--out", "--db")
OUTPUT_PARAMS = ("out", "db", "data_dir")
"""Options (and their click names) that say where a command writes: its output directory or database, the
service's data directory."""


def _default_outputs(group: click.Group, prefix: str = "") -> dict[str, str]:
    """Command name -> the default of its output option (directories or files written in the working directory)."""
    out = {}
    for name, cmd in group.commands.items():
        if isinstance(cmd, click.Group):
            out |= _default_outputs(cmd, f"{prefix}{name} ")
            continue
        for p in cmd.params:
            if isinstance(p, click.Option) and p.name in OUTPUT_PARAMS and isinstance(p.default, str):
                out[f"{prefix}{name}"] = p.default
    return out


def _readme_outputs() -> list[str]:
    outputs = []
    for line in (REPO / "README.md").read_text(encoding="utf-8").splitlines():
        if not line.startswith("$ landscape "):
            continue
        args = shlex.split(line[2:])
        for opt, value in zip(args[:-1], args[1:], strict=True):
            if (opt in OUTPUT_OPTIONS or (args[1] == "serve" and opt == "--data")) and not value.startswith(
                ("figures/", "../", "/")
            ):
                outputs.append(value)
    return outputs


def _ignored(paths: list[str]) -> set[str]:
    done = subprocess.run(
        ["git", "check-ignore", "--no-index", "--stdin"],
        input="\n".join(p.rstrip("/") + "/x" for p in paths),
        cwd=REPO,
        capture_output=True,
        text=True,
    )
    return {p[: -len("/x")] for p in done.stdout.splitlines()}


@pytest.mark.skipif(
    shutil.which("git") is None or not (REPO / ".git").exists(), reason="needs a git checkout"
)
def test_tour_output_is_ignored():
    defaults = _default_outputs(cli)
    assert {"analysis", "landscape-data", "report"} <= set(defaults.values())
    paths = sorted(set(defaults.values()) | set(_readme_outputs()))
    assert "render/" in paths and "report" in paths
    missing = [p for p in paths if p.rstrip("/") not in _ignored(paths)]
    assert not missing, f"add these to .gitignore: {missing}"
