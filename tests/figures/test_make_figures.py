"""figures/make_figures.py: a --quick mode that runs a reduced version of every step, numbered steps, and the
barrier map alone."""

from __future__ import annotations

import math
import shlex
from pathlib import Path

import click
import pytest

from landscape.cli.sim import sweep
from landscape.params import parse_values
from tests.conftest import load_script


@pytest.fixture(scope="module")
def mf():
    return load_script("figures/make_figures.py")


def _trials(args: str) -> tuple[int, int]:
    """Trials a `sweep ...` line runs (the command's own defaults for what it leaves out), and its --attempts."""
    words = shlex.split(args)
    assert words[0] == "sweep"
    given = dict(zip(words[1::2], words[2::2], strict=False))
    opts = {p.opts[0]: p.default for p in sweep.params if isinstance(p, click.Option)}
    n = math.prod(
        len(parse_values(str(given.get(f"--{k}", opts[f"--{k}"])), k))
        for k in ("theta-w", "theta-l", "cv", "phase", "wing-period", "leg-period")
    )
    return n * int(given.get("--trials", opts["--trials"])), int(given.get("--attempts", opts["--attempts"]))


def test_quick_is_a_reduced_version_of_every_step(mf, tmp_path):
    full = mf.plan(quick=False, db=tmp_path / "a.sqlite", out=tmp_path, workers=None, check=False)
    quick = mf.plan(quick=True, db=tmp_path / "a.sqlite", out=tmp_path, workers=None, check=False)
    assert [s.args.split()[0] for s in quick] == [s.args.split()[0] for s in full]
    assert len(full) == 6
    full_poses = [len(parse_values(v, "x")) for v in full[0].args.split()[2:5:2]]
    quick_poses = [len(parse_values(v, "x")) for v in quick[0].args.split()[2:5:2]]
    assert math.prod(full_poses) == 96 and math.prod(quick_poses) == 12
    total_quick = 0
    for f, q in zip(full[1:5], quick[1:5], strict=True):
        (nf, af), (nq, aq) = _trials(f.args), _trials(q.args)
        assert aq == af and nq < nf / 10, (f.args, q.args)
        assert f"({nf} trials)" in f.name and f"({nq} trials)" in q.name
        total_quick += nq
    assert total_quick <= 60  # minutes on two cores, not half an hour


def test_steps_are_numbered_and_quick_writes_elsewhere(mf, capsys):
    mf.main(["--quick", "--dry-run"])
    out = capsys.readouterr().out
    assert [line.split("]")[0] for line in out.splitlines() if line.startswith("[")] == [
        f"[{k}/6" for k in range(1, 7)
    ]
    assert f"--db {Path(mf.ROOT) / 'figures' / 'quick' / 'results.sqlite'}" in out
    assert "figures/analysis" not in out


def test_only_the_barrier_map_regenerates_the_committed_map(mf, capsys):
    mf.main(["--only", "barrier-map", "--dry-run"])
    out = capsys.readouterr().out
    assert [line for line in out.splitlines() if line.startswith("[")] == [
        "[1/1] barrier map, 96 poses (Fig. 5)"
    ]
    assert f"--out {Path(mf.ROOT) / 'figures' / 'barrier_map'}" in out and "sweep" not in out


def test_the_other_engine_sweeps_in_mujoco_into_its_own_folder(mf, capsys):
    """--engine mujoco: every sweep (and nothing else) gets --engine mujoco, and the database, report and copied
    figures go to figures/mujoco/, leaving pybullet's committed figures alone."""
    mf.main(["--engine", "mujoco", "--dry-run"])
    out = capsys.readouterr().out
    commands = [line for line in out.splitlines() if line.startswith("$ landscape")]
    assert len(commands) == 6
    assert all(("--engine mujoco" in c) == (" sweep " in c) for c in commands)
    assert f"--db {Path(mf.ROOT) / 'figures' / 'mujoco' / 'results.sqlite'}" in out
    assert f"--out {Path(mf.ROOT) / 'figures' / 'mujoco' / 'report'}" in out
