"""Angles that no joint takes are refused in one line; either joint group may be left out of the joint map; the
landscape commands take the wing joints' whole range, the trial commands 0 up; malformed URDFs and mesh files
given as robots are refused with the fix."""

from __future__ import annotations

import csv
import shutil

import pytest
import trimesh

from geometry.robots import robot_urdf_path
from landscape.cli.options import THETA_W_OUT_OF_JOINT_RANGE, THETA_W_OUT_OF_RANGE
from tests.conftest import run_cli as run

RENAMES = {
    "wing_pitch_left": "wpl",
    "wing_pitch_right": "wpr",
    "wing_roll_left": "wrl",
    "wing_roll_right": "wrr",
    "leg": "tail",
}
WINGS = "wing=wpl,wpr,wrl,wrr"


def one_line_error(code: int, err: str) -> str:
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    return err


def builtin_copy(tmp_path, edit):
    """The built-in robot's files copied into ``tmp_path``, its URDF's text passed through ``edit``."""
    src = robot_urdf_path()
    d = tmp_path / "robot"
    shutil.copytree(src.parent, d)
    (d / src.name).write_text(edit((d / src.name).read_text()))
    return d / src.name


def wing1_visual_mesh(element: str):
    """An ``edit`` for :func:`builtin_copy`: the mesh of link wing1's visual (not its collision) replaced."""

    def edit(text: str) -> str:
        visual = text.index("<visual", text.index('<link name="wing1"'))
        end = text.index("</visual>", visual)
        assert '<mesh filename="wing1.obj"/>' in text[visual:end]
        return text[:visual] + text[visual:end].replace('<mesh filename="wing1.obj"/>', element) + text[end:]

    return edit


@pytest.fixture()
def renamed(tmp_path):
    """The built-in robot with all five joints renamed (none has a default name)."""

    def edit(text: str) -> str:
        for old, new in RENAMES.items():
            text = text.replace(f'name="{old}"', f'name="{new}"').replace(f'joint="{old}"', f'joint="{new}"')
        return text

    return builtin_copy(tmp_path, edit)


@pytest.fixture()
def box_stl(tmp_path):
    f = tmp_path / "box.stl"
    trimesh.creation.box(extents=(40.0, 20.0, 10.0)).export(f)
    return f


def test_theta_w_on_renamed_joints_is_refused_with_the_map(capsys, renamed):
    # it used to answer the closed-wing robot's barrier (theta_w '-') with exit 0
    err = one_line_error(*run(capsys, "compute", "--robot", renamed, "--theta-w", "74")[::2])
    assert "--theta-w: no joint of builtin_robot is driven by the wing angle" in err
    assert "movable joints: wpl, wpr, wrl, wrr, tail" in err
    assert "--joints 'wing=wpl,wpr,wrl,wrr;leg=tail'" in err
    err = one_line_error(*run(capsys, "compute", "--robot", renamed, "--theta-l", "30")[::2])
    assert "--theta-l: no joint" in err and "--joints 'wing=wpl,wpr,wrl,wrr;leg=tail'" in err


def test_renamed_joints_with_the_map_give_the_built_in_answer(capsys, renamed):
    code, out, err = run(
        capsys, "compute", "--robot", renamed, "--joints", f"{WINGS};leg=tail", "--theta-w", "74", "--json"
    )
    assert code == 0, err
    import json

    assert round(json.loads(out)["barrier"]["righting_j"] * 1e3, 3) == 8.689  # the README's built-in answer


def test_theta_w_on_a_mesh_is_refused(capsys, box_stl):
    err = one_line_error(*run(capsys, "compute", "--mesh", box_stl, "--units", "mm", "--theta-w", "74")[::2])
    assert "box is a single rigid body without joints: nothing takes --theta-w; drop it" in err


def test_a_mesh_given_as_robot_suggests_mesh(capsys, box_stl):
    err = one_line_error(*run(capsys, "compute", "--robot", box_stl)[::2])
    assert f"is a mesh file, not a URDF; give a single rigid body with --mesh {box_stl}" in err


def test_legless_body_refuses_theta_l_and_trials_say_what_they_need(capsys, renamed, tmp_path):
    err = one_line_error(
        *run(capsys, "compute", "--robot", renamed, "--joints", WINGS, "--theta-l", "30")[::2]
    )
    assert "no joint of builtin_robot is driven by the leg angle (joint map 'wing=wpl,wpr,wrl,wrr'" in err
    assert "--joints 'wing=wpl,wpr,wrl,wrr;leg=tail'" in err
    for argv in (
        ["simulate", "--theta-w", "74", "--theta-l", "30", "--duration", "0.1"],
        ["sweep", "--db", tmp_path / "s.sqlite", "--trials", "1"],
    ):
        err = one_line_error(*run(capsys, *argv, "--robot", renamed, "--joints", WINGS)[::2])
        assert (
            "a trial opens the wings (theta_w) and swings the leg (theta_l), so it needs both joint groups"
            in err
        )
        assert "maps no leg joint" in err and "e.g. 'wing=wpl,wpr,wrl,wrr;leg=tail'" in err


def test_legless_body_computes_a_barrier_map(capsys, renamed, tmp_path):
    out = tmp_path / "bm"
    code, stdout, err = run(
        capsys, "barrier-map", "--robot", renamed, "--joints", WINGS, "--theta-w", "70,74", "--out", out
    )
    assert code == 0, err
    assert stdout.startswith("2 poses in ")
    with open(out / "barrier_map.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["theta_w_deg"] for r in rows] == ["70.0", "74.0"] and {r["theta_l_deg"] for r in rows} == {""}
    # the leg rests at 0: the built-in robot's barrier at theta_l 0 (the README's 8.689 mJ at 74 deg)
    assert round(float(rows[1]["righting_j"]) * 1e3, 3) == 8.689
    assert (out / "barrier_map.png").is_file()


@pytest.mark.parametrize(
    "cmd", [["compute", "--step", "30"], ["barrier-map", "--step", "30", "--theta-l", "0"]]
)
def test_landscape_commands_take_the_whole_wing_joint_range(capsys, cmd, tmp_path):
    extra = ["--out", tmp_path / "o"]
    code, _, err = run(capsys, *cmd, "--theta-w", "-10", *extra)
    assert code == 0, err  # refused as below the wing opening range before
    err = one_line_error(*run(capsys, *cmd, "--theta-w", "-12", *extra)[::2])
    expected = THETA_W_OUT_OF_JOINT_RANGE.format(got=-12.0, lo=-10.0, hi=95.0, robot="builtin_robot")
    assert err == f"landscape: error: {expected}\n"


def test_trials_keep_the_opening_range(capsys):
    err = one_line_error(
        *run(capsys, "simulate", "--theta-w", "-5", "--theta-l", "30", "--duration", "0.1")[::2]
    )
    expected = THETA_W_OUT_OF_RANGE.format(got=-5.0, lo=0.0, hi=95.0, robot="builtin_robot")
    assert err == f"landscape: error: {expected}\n"


@pytest.mark.parametrize(
    "cmd, says",
    [
        ("compute", "anywhere within the wing joints' limits"),
        ("barrier-map", "anywhere within the wing"),
        ("render", "anywhere within the wing joints' limits"),
        ("simulate", "from 0 (closed) to the wing joints' limit"),
        ("sweep", "from 0 (closed) to the wing joints' limit"),
    ],
)
def test_help_says_which_wing_range_applies(capsys, cmd, says):
    code, out, _ = run(capsys, cmd, "--help")
    assert code == 0 and says in " ".join(out.split())


def test_bad_scale_on_a_visual_mesh_is_refused(capsys, tmp_path):
    urdf = builtin_copy(tmp_path, wing1_visual_mesh('<mesh filename="wing1.obj" scale="nan nan nan"/>'))
    err = one_line_error(*run(capsys, "compute", "--robot", urdf)[::2])
    assert "link 'wing1': visual mesh 'wing1.obj' scale [nan, nan, nan] must be finite and non-zero" in err


def test_legless_body_renders_with_its_wing_angle_alone(capsys, renamed, tmp_path):
    from landscape.viz import render as rd

    if rd.off_screen_problem() is not None:
        pytest.skip(rd.off_screen_problem())
    out = tmp_path / "fig"
    code, _, err = run(
        capsys,
        "render",
        "--robot",
        renamed,
        "--joints",
        WINGS,
        "--theta-w",
        "74",
        "--step",
        "10",
        "--out",
        out,
    )
    assert code == 0, err  # the title's leg angle was None: an internal error
    assert "<!-- builtin_robot  wing 74°  righting barrier" in (out / "contour.svg").read_text()


def test_barrier_map_of_a_body_without_a_joint_map_says_what_would_map_it(capsys, renamed, box_stl, tmp_path):
    err = one_line_error(*run(capsys, "barrier-map", "--robot", renamed, "--out", tmp_path / "o")[::2])
    assert (
        "movable joints: wpl, wpr, wrl, wrr, tail); map them with --joints 'wing=wpl,wpr,wrl,wrr;leg=tail'"
        in err
    )
    err = one_line_error(
        *run(capsys, "barrier-map", "--mesh", box_stl, "--units", "mm", "--out", tmp_path / "o")[::2]
    )
    assert "barrier-map sweeps joint angles, and box is a single rigid body without joints" in err


def test_a_visual_mesh_without_a_filename_is_refused(capsys, tmp_path):
    urdf = builtin_copy(tmp_path, wing1_visual_mesh("<mesh/>"))
    err = one_line_error(*run(capsys, "compute", "--robot", urdf)[::2])
    assert "link 'wing1': visual: a <mesh> has no filename" in err
