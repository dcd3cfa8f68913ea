"""GET /api/robot-pose: the robot's part meshes posed and resting on the ground, checked against closed forms (a
cube) and against the landscape's own numbers (CoM height at the start minimum, CoM lift at the saddle)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from .conftest import box_stl


def _cube(client) -> str:
    r = client.post("/api/robots", files={"file": ("cube.stl", box_stl(), "model/stl")}, data={"mass": "1"})
    assert r.status_code == 201, r.text
    return r.json()["id"]


def test_a_cube_rests_on_a_face_and_on_an_edge(client):
    """A 2 m cube centred on its CoM: flat, its CoM is 1 m up and its corners at +-1 m; pitched 45 deg it stands
    on an edge with the CoM sqrt(2) m up and the top edge 2 sqrt(2) m up."""
    rid = _cube(client)
    flat = client.get("/api/robot-pose", params={"robot": rid}).json()
    assert flat["theta_w_deg"] is None and flat["theta_l_deg"] is None
    assert len(flat["parts"]) == 1
    v = np.array(flat["parts"][0]["vertices_m"])
    f = np.array(flat["parts"][0]["faces"])
    assert v.shape == (8, 3) and f.shape == (12, 3) and f.min() == 0 and f.max() == 7
    assert sorted(map(tuple, np.round(v, 9).tolist())) == sorted(
        (x, y, z) for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (0.0, 2.0)
    )
    assert flat["com_m"] == [0.0, 0.0, 1.0] and flat["com_height_m"] == 1.0

    edge = client.get("/api/robot-pose", params={"robot": rid, "pitch": 45}).json()
    v = np.array(edge["parts"][0]["vertices_m"])
    assert edge["pitch_deg"] == 45.0 and edge["com_height_m"] == pytest.approx(math.sqrt(2), abs=1e-6)
    assert v[:, 2].min() == pytest.approx(0.0, abs=1e-7) and v[:, 2].max() == pytest.approx(2 * math.sqrt(2))
    assert np.sum(np.isclose(v[:, 2], 0.0, atol=1e-6)) == 2  # two corners: one edge on the ground
    assert edge["com_m"][:2] == [0.0, 0.0]


def test_builtin_robot_at_the_start_and_at_the_saddle_matches_the_landscape(client):
    """The pose at the landscape's minimum has the CoM at the minimum's height; at the righting saddle the CoM
    is higher by the barrier over m g (the CoM lift)."""
    s = client.get("/api/landscape", params={"theta_w": 74, "theta_l": 10, "step": 3}).json()
    q = {"theta_w": 74, "theta_l": 10}
    start = client.get(
        "/api/robot-pose", params={**q, "pitch": s["minimum"]["pitch_deg"], "roll": s["minimum"]["roll_deg"]}
    )
    assert start.status_code == 200, start.text
    start = start.json()
    assert start["com_height_m"] == pytest.approx(s["minimum"]["height_m"], abs=1e-6)
    r = s["paths"]["righting"]
    saddle = client.get(
        "/api/robot-pose", params={**q, "pitch": r["saddle_pitch_deg"], "roll": r["saddle_roll_deg"]}
    ).json()
    mg = s["mass_kg"] * 9.81
    assert saddle["com_height_m"] - start["com_height_m"] == pytest.approx(r["barrier_j"] / mg, abs=1e-6)
    for pose in (start, saddle):
        assert pose["theta_w_deg"] == 74.0 and len(pose["parts"]) > 1
        z = np.concatenate([np.array(p["vertices_m"])[:, 2] for p in pose["parts"]])
        assert z.min() == pytest.approx(0.0, abs=1e-7)  # resting on the ground, not in it
        for p in pose["parts"]:
            assert np.array(p["faces"]).max() < len(p["vertices_m"])
        assert pose["com_m"][:2] == [0.0, 0.0]


def test_the_joint_angles_move_the_parts(client):
    """Opening the wings changes the posed meshes and the CoM height of the same body orientation."""
    closed = client.get("/api/robot-pose", params={"theta_w": 0, "pitch": 0, "roll": 180}).json()
    opened = client.get("/api/robot-pose", params={"theta_w": 80, "pitch": 0, "roll": 180}).json()
    assert closed["com_height_m"] != pytest.approx(opened["com_height_m"], abs=1e-4)
    assert closed["parts"] != opened["parts"]


@pytest.mark.parametrize(
    "params, status, match",
    [
        ({"pitch": "nan"}, 422, "pitch must be a finite number of degrees; got nan"),
        ({"roll": "inf"}, 422, "roll must be a finite number of degrees; got inf"),
        ({"theta_w": "-Infinity"}, 422, "theta_w must be a finite number"),
        ({"pitch": "abc"}, 422, "pitch: Input should be a valid number"),
        ({"roll": 361}, 422, "roll = 361 deg is outside [-360, 360]"),
        ({"pitch": -1e9}, 422, "pitch = -1e+09 deg is outside [-360, 360]"),
        ({"theta_w": 200}, 422, "outside joint 'wing_pitch_left' limits [-10, 95]"),
        ({"theta_l": -120}, 422, "theta_l = -120 deg is outside joint 'leg' limits"),
        ({"robot": "0123456789abcdef"}, 404, "unknown robot"),
        ({"robot": "..%2F..%2Fetc"}, 404, "unknown robot"),
    ],
)
def test_bad_pose_requests(client, params, status, match):
    r = client.get("/api/robot-pose", params=params)
    assert r.status_code == status
    detail = r.json()["detail"]
    assert isinstance(detail, str) and "\n" not in detail and match in detail


def test_a_rigid_robot_ignores_the_joint_angles_but_not_bad_numbers(client):
    rid = _cube(client)
    a = client.get("/api/robot-pose", params={"robot": rid, "theta_w": 500, "roll": 30}).json()
    b = client.get("/api/robot-pose", params={"robot": rid, "roll": 30}).json()
    assert a == b
    assert client.get("/api/robot-pose", params={"robot": rid, "theta_w": "nan"}).status_code == 422
