"""Following the README's tour leaves the checkout as it was (``git status`` clean): every command's default output
directory, every ``--out``/``--db`` the README's ``$ landscape`` lines give and the service screenshot's default
file are ignored by git, and none of them is a committed figure. Regenerating a committed figure is a command of
its own, and a rerun writes the committed barrier map's CSV byte for byte."""

from __future__ import annotations

import shlex
import shutil
import subprocess
from pathlib import Path

import click
import pytest

from landscape.cli import cli
from tests.conftest import load_script, run_cli

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
                ("../", "/")
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
    assert not missing, (
        f"the tour writes where git sees it (use an ignored folder, see .gitignore): {missing}"
    )


@pytest.mark.skipif(
    shutil.which("git") is None or not (REPO / ".git").exists(), reason="needs a git checkout"
)
def test_the_service_screenshot_writes_an_ignored_file_unless_told_otherwise():
    """The README's `python figures/service_screenshot.py` writes into an ignored folder; `--out
    figures/service_page.png` regenerates the committed screenshot."""
    shot = load_script("figures/service_screenshot.py")
    default = shot.DEFAULT_OUT.relative_to(REPO).as_posix()
    assert default != "figures/service_page.png"
    assert _ignored([default.rsplit("/", 1)[0]]) == {default.rsplit("/", 1)[0]}
    assert "python figures/service_screenshot.py`" in (REPO / "README.md").read_text(encoding="utf-8")


def test_a_rerun_writes_the_committed_barrier_map_byte_for_byte(capsys, tmp_path):
    """figures/barrier_map/barrier_map.csv is what `python figures/make_figures.py --only barrier-map` writes: the
    same command (the README's grid) run again gives the same bytes, since the CSV keeps the digits every
    machine agrees on (1e-9 J, 1e-6 degrees)."""
    mf = load_script("figures/make_figures.py")
    step = mf.plan(quick=False, db=tmp_path / "r.sqlite", out=tmp_path, workers=None, check=False)[0]
    assert step.args.startswith(mf.BARRIER_MAP) and "--theta-w 60:90:2 --theta-l 0:50:10" in step.args
    code, out, err = run_cli(capsys, *shlex.split(step.args))
    assert code == 0, err
    committed = REPO / "figures" / "barrier_map" / "barrier_map.csv"
    assert (tmp_path / "barrier_map" / "barrier_map.csv").read_bytes() == committed.read_bytes()
