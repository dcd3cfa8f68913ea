"""benchmarks/studies/heading.py: pybullet's friction turns a pushed box's path unless it is pushed along a world
axis, and the study's tables run end to end on one trial."""

import pytest

from tests.conftest import load_script

pytest.importorskip("pybullet")


def test_a_box_pushed_off_a_world_axis_turns_and_the_study_prints_its_tables(capsys):
    bench = load_script("benchmarks/studies/heading.py")
    rows = {deg: (mm, turn) for deg, mm, turn in bench.friction_table()}
    assert abs(rows[0.0][1]) < 0.1 and rows[45.0][1] > 1.0  # isotropic friction would not turn it
    assert rows[0.0][0] == pytest.approx(1e3 / (2 * 9.81), rel=0.05)  # v^2 / (2 mu g)
    # pybullet's cone friction is on: off, the force is clamped per direction (a pyramid) and a diagonal push
    # stops sqrt(2) sooner; on, the box still turns (the two directions' own effective masses)
    pyramid = {deg: (mm, turn) for deg, mm, turn in bench.friction_table("pybullet", "pyramidal")}
    assert pyramid[45.0][0] == pytest.approx(rows[0.0][0] / 2**0.5, rel=0.05) and rows[45.0][0] > rows[0.0][0]
    args = ["--phases", "1", "--leg-periods", "0.8", "--wing-periods", "2.0", "--workers", "1"]
    assert bench.main(args) == 0
    out = capsys.readouterr().out
    assert "(1 single attempts, 1 trials)" in out
    for h in ("0.0001", "5", "45", "90"):
        assert f"\n{h:>12} " in out
    assert "fixed in the world" in out
    assert bench.main([*args, "--friction-axes", "body"]) == 0
    assert "fixed in the body" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        bench.main(["--phases", "0"])


def test_in_mujoco_the_elliptic_cone_stops_the_box_alike_in_every_direction_the_pyramidal_does_not(capsys):
    """The elliptic cone limits the friction force to a circle: the box slides v^2 / (2 mu g) whichever way it is
    pushed (its path turns by about a degree off its axes, as the load shifts to its leading corners). The pyramidal
    cone's square lets it slide further along a diagonal."""
    pytest.importorskip("mujoco")
    bench = load_script("benchmarks/studies/heading.py")
    elliptic = {deg: (mm, turn) for deg, mm, turn in bench.friction_table("mujoco", "elliptic")}
    pyramidal = {deg: (mm, turn) for deg, mm, turn in bench.friction_table("mujoco", "pyramidal")}
    for deg in (0.0, 30.0, 45.0):
        assert elliptic[deg][0] == pytest.approx(1e3 / (2 * 9.81), rel=0.01) and abs(elliptic[deg][1]) < 2.0
    assert pyramidal[0.0][0] == pytest.approx(elliptic[0.0][0], rel=0.01)
    assert pyramidal[45.0][0] > 1.2 * pyramidal[0.0][0]
    args = [
        "--phases",
        "1",
        "--leg-periods",
        "0.8",
        "--wing-periods",
        "2.0",
        "--workers",
        "1",
        "--engine",
        "mujoco",
    ]
    assert bench.main(args) == 0
    assert "mujoco, elliptic cone" in capsys.readouterr().out
