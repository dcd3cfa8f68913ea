"""The ``model`` parameter (issue #15): a shipped model set poses the wings of a landscape, a barrier map and a
sweep as ``landscape compute|barrier-map|sweep --model NAME`` does; anything but a shipped name is refused."""

from __future__ import annotations

import json
import sys

import pytest

from tests.conftest import run_cli

from .conftest import box_stl
from .test_api import _strip
from .test_sweeps import TINY, _wait

OUT_OF_RANGE = "theta_w = 50 deg is outside the measured wing commands [60, 90] deg"
BAD_NAMES = ["../../etc/passwd", "nosuch", "/etc/passwd", "sim/models/physical.toml", "physical.toml", ""]


def _physical_joints(robot, theta_w_deg: float) -> dict[str, float]:
    from sim.model_set import load_model_set

    return load_model_set("physical").wing_joints_deg(robot.joint_map.wing, theta_w_deg)


def _refused(r, match: str) -> None:
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert match in detail and "\n" not in detail and "Traceback" not in detail


# ---------------------------------------------------------------------------------------------- the list
def test_the_route_lists_the_shipped_sets_as_the_library_reads_them(client):
    from sim.model_set import load_model_set, shipped_model_sets

    r = client.get("/api/model-sets")
    assert r.status_code == 200, r.text
    got = r.json()
    assert (
        [m["name"] for m in got]
        == shipped_model_sets()
        == ["paper", "physical", "physical-head", "physical-offset", "physical-posed"]
    )
    for m in got:
        ms = load_model_set(m["name"])
        assert (m["version"], m["model_set_hash"], m["description"], m["profile"]) == (
            ms.version,
            ms.model_set_hash,
            ms.description,
            ms.profile,
        )
        assert m["label"] == ms.label == f"{ms.name} v{ms.version} ({ms.model_set_hash})"
        assert m["com_offset_y_mm"] == ms.com_offset_y_mm and m["moves_com"] == (ms.com_offset_y_mm != 0)
    by = {m["name"]: m for m in got}
    assert [n for n, m in by.items() if m["poses_wings"]] == [
        "physical",
        "physical-head",
        "physical-offset",
        "physical-posed",
    ]
    assert [n for n, m in by.items() if m["moves_com"]] == ["physical-offset"]
    assert by["physical-offset"]["com_offset_y_mm"] == -2.0
    assert [n for n, m in by.items() if m["joint_shift"]] == ["physical-head"]
    assert by["physical-head"]["joint_shift"] == {"joint": "head_mount", "shift_mm": [-17.0, 0.0, 0.0]}
    assert by["paper"]["wing_command_deg"] is None and by["physical"]["wing_command_deg"] == [
        60.0,
        75.0,
        90.0,
    ]
    assert by["physical"]["version"] == 2 and by["paper"]["version"] == 1


def test_every_listed_set_is_taken_and_its_commands_bound_theta_w(client):
    """Each name the list gives is a ``model`` the landscape takes; a measured set's listed commands are where
    theta_w is taken (the page bounds its slider by them)."""
    for m in client.get("/api/model-sets").json():
        cmds = m["wing_command_deg"] or (0.0, 90.0)
        lo, hi = cmds[0], cmds[-1]
        for theta_w, ok in ((lo, True), (hi, True), (lo - 1, m["wing_command_deg"] is None)):
            r = client.get("/api/landscape", params={"theta_w": theta_w, "step": 10, "model": m["name"]})
            assert (r.status_code == 200) == ok, (m["name"], theta_w, r.text)
            if ok:
                assert r.json()["model_set"] == m["name"]


# ---------------------------------------------------------------------------------------------- landscape
def test_physical_landscape_is_compute_with_the_sets_wing_joints(client, capsys):
    from geometry.robots import load_robot
    from landscape.cli import main
    from landscape.computation import compute

    robot = load_robot(None)
    joints = _physical_joints(robot, 75.0)
    assert len(set(joints.values())) > 1  # each servo at its own plateau
    want = compute(robot, theta_w_deg=75.0, theta_l_deg=0.0, wing_joints_deg=joints)
    r = client.get("/api/landscape", params={"theta_w": 75, "model": "physical"})
    assert r.status_code == 200, r.text
    got = r.json()
    assert got["model_set"] == "physical" and got["wing_joints_deg"] == pytest.approx(joints)
    assert got["barrier"]["righting_j"] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)
    assert (got["start_deg"]["pitch_deg"], got["start_deg"]["roll_deg"]) == pytest.approx(want.start_deg)
    assert main(["compute", "--theta-w", "75", "--model", "physical", "--json"]) == 0
    assert _strip(got) == _strip(json.loads(capsys.readouterr().out))
    # the set is part of the cache key: the plain landscape at the same command is another answer
    plain = client.get("/api/landscape", params={"theta_w": 75}).json()
    assert "model_set" not in plain and "wing_joints_deg" not in plain
    assert plain["barrier"]["righting_j"] != got["barrier"]["righting_j"]
    again = client.get("/api/landscape", params={"theta_w": 75, "model": "physical"}).json()
    assert again["barrier"] == got["barrier"] and again["model_set"] == "physical"


def test_a_set_that_moves_the_com_moves_it_in_the_service(client, capsys):
    """physical-offset moves the CoM 2 mm towards -y: the service's landscape and barrier map are those of the
    moved robot, as `landscape compute --model physical-offset` gives them."""
    from geometry.robots import load_robot
    from landscape.cli import main
    from landscape.computation import compute
    from sim.model_set import load_model_set

    ms = load_model_set("physical-offset")
    robot = load_robot(None)
    joints = ms.wing_joints_deg(robot.joint_map.wing, 75.0)
    want = compute(
        ms.robot_for(robot), theta_w_deg=75.0, theta_l_deg=0.0, wing_joints_deg=joints, step_deg=3.0
    )
    unmoved = compute(robot, theta_w_deg=75.0, theta_l_deg=0.0, wing_joints_deg=joints, step_deg=3.0)
    assert want.barrier.righting.barrier_j < unmoved.barrier.righting.barrier_j - 1e-4
    got = client.get("/api/landscape", params={"theta_w": 75, "step": 3, "model": "physical-offset"}).json()
    assert got["barrier"]["righting_j"] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)
    assert main(["compute", "--theta-w", "75", "--step", "3", "--model", "physical-offset", "--json"]) == 0
    assert _strip(got) == _strip(json.loads(capsys.readouterr().out))
    rows = client.get(
        "/api/barrier-map", params={"theta_w": "75", "theta_l": "0", "step": 3, "model": "physical-offset"}
    ).json()
    assert rows[0]["righting_j"] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)


def test_paper_landscape_equals_no_model(client, capsys):
    params = {"theta_w": 74, "theta_l": 20, "step": 3}
    paper = client.get("/api/landscape", params={**params, "model": "paper"}).json()
    plain = client.get("/api/landscape", params=params).json()
    assert paper["model_set"] == "paper" and paper["wing_joints_deg"] is None
    assert {k: v for k, v in paper.items() if k not in ("model_set", "wing_joints_deg", "timing_s")} == {
        k: v for k, v in plain.items() if k != "timing_s"
    }
    from landscape.cli import main

    assert (
        main(["compute", "--theta-w", "74", "--theta-l", "20", "--step", "3", "--model", "paper", "--json"])
        == 0
    )
    assert _strip(paper) == _strip(json.loads(capsys.readouterr().out))


@pytest.mark.parametrize("model", BAD_NAMES)
@pytest.mark.parametrize("url", ["/api/landscape", "/api/barrier-map", "/api/robot-pose"])
def test_only_a_shipped_set_name_is_taken(client, url, model):
    r = client.get(url, params={"theta_w": "75", "theta_l": "0", "model": model})
    _refused(
        r,
        "model must be a shipped model set (paper, physical, physical-head, physical-offset, physical-posed)",
    )


@pytest.mark.parametrize("url", ["/api/landscape", "/api/barrier-map", "/api/robot-pose"])
def test_a_wing_command_outside_the_measured_ones_is_refused(client, url):
    _refused(client.get(url, params={"theta_w": "50", "theta_l": "0", "model": "physical"}), OUT_OF_RANGE)
    assert client.get(url, params={"theta_w": "50", "theta_l": "0", "model": "paper"}).status_code == 200


def test_a_measured_set_needs_the_wing_joints_it_measures(client):
    rid = client.post("/api/robots", files={"file": ("c.stl", box_stl())}).json()["id"]
    r = client.get("/api/landscape", params={"robot": rid, "theta_w": 75, "model": "physical"})
    _refused(r, "measures 4 wing servos, but the robot drives 0 wing joints")
    assert client.get("/api/landscape", params={"robot": rid, "model": "paper"}).status_code == 200


# ---------------------------------------------------------------------------------------------- barrier map
def test_physical_barrier_map_job_names_the_set_and_matches_the_library(make_app):
    from fastapi.testclient import TestClient

    from geometry.robots import load_robot
    from landscape.computation import barrier_map

    robot = load_robot(None)
    joints = {w: _physical_joints(robot, w) for w in (60.0, 75.0)}
    want = barrier_map(robot, [60.0, 75.0], [0.0], step_deg=10, wing_joints_deg=joints, workers=1)
    with TestClient(make_app(limits=make_app.Limits(sync_map_s=0.0))) as c:
        params = {"theta_w": "60,75", "theta_l": "0", "step": 10}
        r = c.get("/api/barrier-map", params={**params, "model": "physical"})
        assert r.status_code == 202, r.text
        assert r.json()["job"]["model_set"] == "physical"
        url = r.json()["status_url"]
        job = _wait(lambda: c.get(url).json(), lambda j: j["status"] in ("done", "failed", "cancelled"))
        assert job["status"] == "done", job
        assert job["model_set"] == "physical"
        assert job["wing_joints_deg"] == [pytest.approx(joints[60.0]), pytest.approx(joints[75.0])]
        assert [row["righting_j"] for row in job["rows"]] == pytest.approx(want.righting_j[:, 0], abs=1e-12)
        plain = c.get("/api/barrier-map", params=params).json()["job"]  # 202 again: the job names no set
        assert plain["model_set"] is None and plain["wing_joints_deg"] is None


def test_paper_barrier_map_equals_no_model(client):
    params = {"theta_w": "70,74", "theta_l": "0,30", "step": 10}
    paper = client.get("/api/barrier-map", params={**params, "model": "paper"})
    assert paper.status_code == 200, paper.text
    assert paper.json() == client.get("/api/barrier-map", params=params).json()


# ---------------------------------------------------------------------------------------------- sweeps
def test_a_physical_sweep_stores_trials_of_the_set(client):
    from sim.store import read_rows

    r = client.post("/api/sweeps", json={**TINY, "trials": 1, "model": "physical"})
    assert r.status_code == 201, r.text
    job = r.json()
    assert job["model_set"] == "physical" and job["request"]["model"] == "physical"
    done = _wait(lambda: client.get(f"/api/sweeps/{job['id']}").json(), lambda j: j["status"] != "queued")
    done = _wait(lambda: client.get(f"/api/sweeps/{job['id']}").json(), lambda j: j["status"] != "running")
    assert done["status"] == "done" and done["done"] == 1 and done["model_set"] == "physical"
    rows = read_rows(client.app.state.sweeps.root / job["id"] / "trials.sqlite")
    assert [row["model_set"] for row in rows] == ["physical"]
    # the job names the set as it was when made: its label, with the hash its trials were stored with
    from sim.model_set import load_model_set

    ms = load_model_set("physical")
    assert done["model_set_label"] == ms.label and [row["model_set_hash"] for row in rows] == [
        ms.model_set_hash
    ]


@pytest.mark.parametrize("model", [*BAD_NAMES, None, 1])
def test_a_sweep_takes_only_a_shipped_set_name(client, model):
    r = client.post("/api/sweeps", json={**TINY, "model": model})
    _refused(
        r,
        "model must be a shipped model set (paper, physical, physical-head, physical-offset, physical-posed)",
    )
    assert client.get("/api/sweeps").json() == []


@pytest.mark.e2e  # a sweep job and a CLI sweep
def test_a_mujoco_sweep_stores_trials_of_that_engine(client, capsys, tmp_path):
    """The job runs in MuJoCo, stores its trials under the set's MuJoCo hash and gives what ``landscape sweep
    --engine mujoco`` gives for the same options."""
    pytest.importorskip("mujoco")
    from sim.model_set import load_model_set
    from sim.store import read_rows

    r = client.post("/api/sweeps", json={**TINY, "trials": 1, "engine": "mujoco"})
    assert r.status_code == 201, r.text
    job = r.json()
    mj = load_model_set("paper").with_engine("mujoco")
    assert job["engine"] == "mujoco" and job["model_set_label"] == mj.label and mj.label.endswith(" [mujoco]")
    done = _wait(
        lambda: client.get(f"/api/sweeps/{job['id']}").json(),
        lambda j: j["status"] not in ("queued", "running"),
    )
    assert done["status"] == "done", done
    rows = read_rows(client.app.state.sweeps.root / job["id"] / "trials.sqlite")
    assert [(row["engine"], row["model_set_hash"]) for row in rows] == [("mujoco", mj.model_set_hash)]
    db = tmp_path / "cli.sqlite"
    argv = ("--theta-w", 74, "--theta-l", 30, "--cv", 0, "--trials", 1, "--duration", 1.0, "--dt", 1e-3)
    code, _, err = run_cli(
        capsys, "sweep", *argv, "--engine", "mujoco", "--db", db, "--workers", 1, "--no-progress"
    )
    assert code == 0, err
    same = ("seed", "success", "time_to_right_s", "engine", "model_set_hash")
    assert [{k: r[k] for k in same} for r in read_rows(db)] == [{k: r[k] for k in same} for r in rows]


def test_a_sweep_job_stored_before_engines_is_pybullet(client):
    job = client.post("/api/sweeps", json={**TINY, "trials": 200}).json()
    client.delete(f"/api/sweeps/{job['id']}")
    assert job["engine"] == "pybullet" and job["request"]["engine"] == "pybullet"
    # a copy of the job as a server before engines stored it, under an id no runner holds (no race with the
    # runner's own writes of the cancelled job's file)
    root = client.app.state.sweeps.root
    old = json.loads((root / job["id"] / "job.json").read_text())
    del old["request"]["engine"]
    old["id"] = "0ld0ld0ld0ld"
    (root / old["id"]).mkdir()
    (root / old["id"] / "job.json").write_text(json.dumps(old))
    assert client.get(f"/api/sweeps/{old['id']}").json()["engine"] == "pybullet"


@pytest.mark.parametrize(
    "engine, match",
    [
        ("bullet", "unknown engine 'bullet'; choose one of pybullet, mujoco"),
        (None, "engine must be one of pybullet, mujoco; got None"),
        (3, "engine must be one of pybullet, mujoco; got 3"),
    ],
)
def test_a_sweep_takes_only_a_known_engine(client, engine, match):
    r = client.post("/api/sweeps", json={**TINY, "engine": engine})
    _refused(r, match)
    assert client.get("/api/sweeps").json() == []


def test_a_mujoco_sweep_without_the_extra_is_refused(client, monkeypatch):
    from sim.engine import MUJOCO_EXTRA

    monkeypatch.setitem(sys.modules, "mujoco", None)
    monkeypatch.delitem(sys.modules, "sim.mujoco_world", raising=False)
    r = client.post("/api/sweeps", json={**TINY, "engine": "mujoco"})
    _refused(r, MUJOCO_EXTRA)
    assert client.get("/api/sweeps").json() == []
