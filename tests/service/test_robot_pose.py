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
        ({"pitch": "nan"}, 422, "pitch must be a finite number; got nan"),
        ({"roll": "inf"}, 422, "roll must be a finite number; got inf"),
        ({"theta_w": "-Infinity"}, 422, "theta_w must be a finite number"),
        ({"pitch": "abc"}, 422, "pitch must be a number in [-360, 360] deg; got 'abc'"),
        ({"roll": 361}, 422, "roll 361 deg is outside [-360, 360] deg: a body orientation within one turn"),
        ({"pitch": -1e9}, 422, "pitch -1000000000 deg is outside [-360, 360] deg"),
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
    a = client.get("/api/robot-pose", params={"robot": rid, "theta_w": 300, "roll": 30}).json()
    b = client.get("/api/robot-pose", params={"robot": rid, "roll": 30}).json()
    assert a == b
    assert client.get("/api/robot-pose", params={"robot": rid, "theta_w": "nan"}).status_code == 422
    assert client.get("/api/robot-pose", params={"robot": rid, "theta_w": 500}).status_code == 422


# ---------------------------------------------------------------------------------------------- model sets
def _displacements(a: dict, b: dict) -> list[np.ndarray]:
    """Per part, how far each vertex of pose ``b`` lies from the same vertex of pose ``a``, m (the parts are
    hulls of the same link points in the same order, so their vertices pair up)."""
    pairs = zip(a["parts"], b["parts"], strict=True)
    return [np.array(q["vertices_m"]) - np.array(p["vertices_m"]) for p, q in pairs]


def test_a_set_poses_the_robot_as_its_landscape_does(client):
    """physical-offset at theta_w 75 (wings at its plateaus, CoM 2 mm off the midline): the pose at the set's
    start minimum has the CoM at the minimum's height and the saddle lifts it by the barrier over m g, as without
    a set; the robot without the set, at the same orientation, does not."""
    from geometry.robots import load_robot
    from sim.model_set import load_model_set

    ms = load_model_set("physical-offset")
    s = client.get("/api/landscape", params={"theta_w": 75, "step": 3, "model": "physical-offset"}).json()
    m, r = s["minimum"], s["paths"]["righting"]
    q = {"theta_w": 75, "model": "physical-offset"}
    plain = client.get(
        "/api/robot-pose", params={"theta_w": 75, "pitch": m["pitch_deg"], "roll": m["roll_deg"]}
    )
    start = client.get("/api/robot-pose", params={**q, "pitch": m["pitch_deg"], "roll": m["roll_deg"]})
    assert start.status_code == 200, start.text
    start, plain = start.json(), plain.json()
    saddle = client.get(
        "/api/robot-pose", params={**q, "pitch": r["saddle_pitch_deg"], "roll": r["saddle_roll_deg"]}
    ).json()
    assert start["com_height_m"] == pytest.approx(m["height_m"], abs=1e-6)
    mg = s["mass_kg"] * 9.81
    assert saddle["com_height_m"] - start["com_height_m"] == pytest.approx(r["barrier_j"] / mg, abs=1e-6)
    assert abs(plain["com_height_m"] - m["height_m"]) > 1e-4  # the pose cache kept the two apart
    assert start["model_set"] == "physical-offset" and start["model_set_hash"] == ms.model_set_hash
    joints = ms.wing_joints_deg(load_robot(None).joint_map.wing, 75.0)
    assert start["wing_joints_deg"] == pytest.approx(joints) and s["wing_joints_deg"] == pytest.approx(joints)
    assert plain["model_set"] is None and plain["model_set_hash"] is None and plain["wing_joints_deg"] is None


@pytest.mark.parametrize("pitch, roll", [(0.0, 0.0), (20.0, 150.0)])
def test_the_offset_set_moves_the_com_by_its_offset(client, pitch, roll):
    """At theta_w 60 physical-offset holds the wings where physical-posed does and moves the CoM by (0, -2, 0)
    mm in the body frame: the body-frame CoM differs by that; in the world every vertex moves by minus its
    horizontal part (the CoM stays above the origin, the lowest point on the ground) and the CoM rises by its
    vertical part."""
    from geometry.frames import body_to_world
    from sim.model_set import load_model_set

    offset_m = np.array(load_model_set("physical-offset").com_offset_m)
    assert offset_m.tolist() == [0.0, -2e-3, 0.0]
    q = {"theta_w": 60, "theta_l": 10, "pitch": pitch, "roll": roll}
    posed = client.get("/api/robot-pose", params={**q, "model": "physical-posed"}).json()
    moved = client.get("/api/robot-pose", params={**q, "model": "physical-offset"}).json()
    assert moved["wing_joints_deg"] == posed["wing_joints_deg"]
    assert np.subtract(moved["com_body_m"], posed["com_body_m"]) == pytest.approx(offset_m, abs=2e-7)
    world_m = body_to_world(np.deg2rad(pitch), np.deg2rad(roll)) @ offset_m
    shift = [-world_m[0], -world_m[1], 0.0]
    for d in _displacements(posed, moved):
        assert d == pytest.approx(np.broadcast_to(shift, d.shape), abs=2e-7)
    assert moved["com_height_m"] - posed["com_height_m"] == pytest.approx(world_m[2], abs=2e-7)


def test_a_measured_set_poses_the_wings(client):
    """physical at theta_w 75 holds each wing servo at its own plateau: against every wing joint at 75 the wing
    parts move relative to the rest, which moves as one; the parts that move are the ones the wing command
    moves (75 -> 76 without a set)."""
    q = {"theta_w": 75, "theta_l": 10, "pitch": 10, "roll": 170}
    plain = client.get("/api/robot-pose", params=q).json()
    measured = client.get("/api/robot-pose", params={**q, "model": "physical"}).json()
    wider = client.get("/api/robot-pose", params={**q, "theta_w": 76}).json()

    def moved(a, b) -> list[bool]:
        d = _displacements(a, b)
        rest = d[0][0]  # the first part is the body: the rest moves with it
        return [not np.allclose(x, rest, atol=1e-6) for x in d]

    wings = moved(plain, wider)
    assert 0 < sum(wings) < len(wings)
    assert moved(plain, measured) == wings
    assert measured["com_body_m"] != plain["com_body_m"]


def test_the_pose_cache_key_holds_the_set(client):
    from landscape.service.poses import check_pose_request
    from sim.model_set import load_model_set

    entry = client.app.state.registry.get("builtin")
    keys = {m: check_pose_request(entry, 75.0, 0.0, 0.0, 0.0, model=m) for m in (None, "paper", "physical")}
    assert keys[None][5:] == (None, None, None)
    assert keys["paper"][5:] == ("paper", load_model_set("paper").model_set_hash, None)
    name, set_hash, joints = keys["physical"][5:]
    assert (name, set_hash) == ("physical", load_model_set("physical").model_set_hash) and len(joints) == 4
    assert len(set(keys.values())) == 3
    paper = client.get("/api/robot-pose", params={"theta_w": 75, "model": "paper"}).json()
    plain = client.get("/api/robot-pose", params={"theta_w": 75}).json()
    assert (
        paper["parts"] == plain["parts"] and paper["com_m"] == plain["com_m"]
    )  # an idealised set, no offset
    assert paper["model_set_hash"] == load_model_set("paper").model_set_hash


@pytest.mark.parametrize(
    "params, match",
    [
        (
            {"model": "nosuch"},
            "model must be a shipped model set (paper, physical, physical-head, physical-offset, physical-posed)",
        ),
        ({"model": "../sim/models/physical.toml"}, "the service reads no model files"),
        (
            {"theta_w": 50, "model": "physical"},
            "theta_w = 50 deg is outside the measured wing commands [60, 90]",
        ),
    ],
)
def test_bad_model_in_a_pose_request(client, params, match):
    r = client.get("/api/robot-pose", params=params)
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert isinstance(detail, str) and "\n" not in detail and match in detail


def test_a_rigid_robot_takes_an_idealised_set_but_not_a_measured_one(client):
    rid = _cube(client)
    paper = client.get("/api/robot-pose", params={"robot": rid, "model": "paper"}).json()
    assert paper["com_height_m"] == 1.0 and paper["model_set"] == "paper"
    r = client.get("/api/robot-pose", params={"robot": rid, "theta_w": 75, "model": "physical"})
    assert (
        r.status_code == 422
        and "measures 4 wing servos, but the robot drives 0 wing joints" in r.json()["detail"]
    )


def test_the_head_set_moves_the_head_by_its_shift(client):
    """physical-head holds the wings where physical does and moves the head 17 mm back: against physical at the
    same orientation, the head's vertices move by that shift (turned into the world) more than the rest, which
    move as one (the body is placed on the ground with its CoM above the origin)."""
    from geometry.frames import body_to_world
    from geometry.robots import load_robot

    links = [p.link for p in load_robot(None).parts if len(p.hull_link_m)]
    q = {"theta_w": 60, "theta_l": 10, "pitch": 20, "roll": 150}
    plain = client.get("/api/robot-pose", params={**q, "model": "physical"}).json()
    moved = client.get("/api/robot-pose", params={**q, "model": "physical-head"}).json()
    assert moved["wing_joints_deg"] == plain["wing_joints_deg"] and moved["model_set"] == "physical-head"
    d = _displacements(plain, moved)
    rest = [x for link, x in zip(links, d, strict=True) if link != "head"]
    common = rest[0][0]
    for x in rest:
        assert x == pytest.approx(np.broadcast_to(common, x.shape), abs=2e-7)
    shift = body_to_world(np.deg2rad(20.0), np.deg2rad(150.0)) @ np.array([-0.017, 0.0, 0.0])
    head = d[links.index("head")]
    assert head - common == pytest.approx(np.broadcast_to(shift, head.shape), abs=2e-7)
