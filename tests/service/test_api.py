"""Every endpoint of the service and every bad input it must refuse (Starlette's TestClient, no socket)."""

from __future__ import annotations

import io
import json
import math
import threading
import zipfile

import numpy as np
import pytest

from .conftest import box_stl, urdf_zip, zip_of

G = 9.81


def _strip(d: dict) -> dict:
    d = dict(d)
    for k in ("paths", "timing_s", "grid"):
        d.pop(k, None)
    d["robot"] = {k: v for k, v in d["robot"].items() if k != "source"}
    return d


# ---------------------------------------------------------------------------------------------- robots
def test_builtin_robot_is_listed_with_its_hash(client):
    from geometry.robots import load_robot

    robots = client.get("/api/robots").json()
    assert robots[0]["id"] == "builtin"
    h = load_robot().description_hash
    assert robots[0]["description_hash"] == h
    by_hash = client.get(f"/api/robots/{h}").json()
    assert by_hash["id"] == "builtin" and by_hash["theta_limits_deg"]["theta_w"] == [-10.0, 95.0]


def test_unknown_robot_is_404_everywhere(client):
    for url in (
        "/api/robots/deadbeef00",
        "/api/landscape?robot=deadbeef00",
        "/api/barrier-map?robot=nope",
        "/api/landscape?robot=..%2F..%2Fetc",
    ):
        r = client.get(url)
        assert r.status_code == 404, url
        assert "unknown robot" in r.json()["detail"]
    assert client.get("/api/robots/..%2F..%2Fetc").status_code == 404


# ---------------------------------------------------------------------------------------------- landscape
def test_landscape_is_the_compute_json_of_the_command_line(client, capsys):
    from landscape.cli import main

    assert main(["compute", "--theta-w", "74", "--theta-l", "10", "--step", "3", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    got = client.get("/api/landscape", params={"theta_w": 74, "theta_l": 10, "step": 3}).json()
    assert "paths" in got and got["paths"]["righting"]["barrier_j"] == got["barrier"]["righting_j"]
    assert _strip(got) == _strip(cli)
    assert got["robot"]["source"] == "builtin"


def test_memo_of_the_continuation_gives_the_metastable_start():
    """The service's start memo walks the same continuation as metastable_orientation, in any request order."""
    from geometry.robots import load_robot
    from landscape.minima import metastable_orientation
    from landscape.service.landscapes import StartMemo

    robot = load_robot()
    memo = StartMemo(robot)
    for tw, tl in [(74.0, 0.0), (20.0, 30.0), (75.0, 0.0), (74.0, 30.0), (74.5, 12.5), (3.0, 0.0)]:
        assert memo.start_deg(tw, tl) == metastable_orientation(robot, tw, tl), (tw, tl)


def test_grid_is_the_library_landscape_in_mj(client):
    from geometry.robots import load_robot
    from landscape.computation import compute

    body = client.get("/api/landscape", params={"theta_w": 60, "step": 5, "grid": 1}).json()
    c = compute(load_robot(), theta_w_deg=60, theta_l_deg=0, step_deg=5)
    angles, energy = c.landscape.inclusive()
    assert body["grid"]["pitch_deg"] == angles.tolist()
    np.testing.assert_allclose(np.array(body["grid"]["energy_mj"]), energy * 1e3, atol=1e-6)
    assert body["grid"]["g_m_s2"] == pytest.approx(G)


def test_cache_in_memory_and_on_disk(make_app, tmp_path):
    from fastapi.testclient import TestClient

    q = {"theta_w": 70, "theta_l": 0, "step": 5}
    with TestClient(make_app()) as c:
        first = c.get("/api/landscape", params=q).json()
        assert c.get("/api/health").json()["cache"]["miss"] >= 1
        again = c.get("/api/landscape", params=q).json()
        assert c.get("/api/health").json()["cache"]["memory"] == 1
        assert again == first
    with TestClient(make_app()) as c:  # a restarted server: the answer comes from disk, not recomputed
        third = c.get("/api/landscape", params=q).json()
        assert c.get("/api/health").json()["cache"] == {"memory": 0, "disk": 1, "miss": 0}
        assert third == first
    assert list((tmp_path / "data" / "cache").rglob("energy_j.npy"))


def test_memory_cache_is_bounded(make_app):
    from fastapi.testclient import TestClient

    app = make_app(limits=make_app.Limits(memory_cache_bytes=150_000))  # one step-5 answer is ~100 kB
    with TestClient(app) as c:
        for tw in (60, 61, 62):
            assert c.get("/api/landscape", params={"theta_w": tw, "step": 5}).status_code == 200
        cache = app.state.landscapes.cache
        assert [k[1] for k in cache._mem] == [62.0] and 0 < cache._bytes <= 150_000


def test_downloads_npz_and_csv(client):
    q = {"theta_w": 74, "step": 10}
    z = client.get("/api/landscape", params={**q, "format": "npz"})
    assert z.status_code == 200
    npz = np.load(io.BytesIO(z.content))
    assert npz["energy_j"].shape == (37, 37) and float(npz["theta_w_deg"]) == 74.0
    csv = client.get("/api/landscape", params={**q, "format": "csv"})
    lines = csv.text.splitlines()
    assert lines[0] == "pitch_deg,roll_deg,energy_j" and len(lines) == 37 * 37 + 1
    assert client.get("/api/landscape", params={**q, "format": "xml"}).status_code == 422


@pytest.mark.parametrize(
    "params, status, match",
    [
        ({"theta_w": "nan"}, 422, "theta_w must be a finite number"),
        ({"theta_l": "inf"}, 422, "theta_l must be a finite number"),
        ({"theta_w": "-Infinity"}, 422, "theta_w must be a finite number"),
        ({"theta_w": "abc"}, 422, "theta_w must be a number in [-360, 360] deg; got 'abc'"),
        ({"step": "two"}, 422, "step must be a number in [0.05, 90] deg; got 'two'"),
        ({"theta_w": 200}, 422, "outside joint 'wing_pitch_left' limits [-10, 95]"),
        ({"theta_l": -120}, 422, "theta_l = -120 deg is outside joint 'leg' limits"),
        ({"step": 7}, 422, "step 7 deg does not divide 360"),
        ({"step": 0}, 422, "step 0 deg is outside [0.05, 90] deg: the grid step, which divides 360"),
        ({"step": 0.1}, 422, "12,960,000 grid cells"),
        ({"method": "magic"}, 422, "unknown barrier method 'magic'"),
        ({"robot": "0123456789abcdef"}, 404, "unknown robot"),
    ],
)
def test_bad_landscape_requests(client, params, status, match):
    r = client.get("/api/landscape", params=params)
    assert r.status_code == status
    detail = r.json()["detail"]
    assert isinstance(detail, str) and "\n" not in detail and match in detail


def test_a_request_over_the_time_estimate_is_refused_with_the_estimate(make_app):
    from fastapi.testclient import TestClient

    app = make_app(limits=make_app.Limits(max_request_s=0.5))
    with TestClient(app) as c:
        r = c.get("/api/landscape", params={"step": 0.25})  # 2,073,600 cells at the default 1 us per cell
        assert r.status_code == 422 and "would take about 2 s" in r.json()["detail"]


def test_a_slow_answer_times_out_without_blocking_others(make_app):
    """A computation still running at the time limit answers 503; meanwhile other requests are served."""
    from fastapi.testclient import TestClient

    app = make_app(limits=make_app.Limits(request_timeout_s=0.05))
    with TestClient(app) as c:
        entry = app.state.registry.builtin()
        with entry.lock:  # the robot is busy: its computation cannot start
            r = c.get("/api/landscape", params={"theta_w": 33, "step": 10})
            assert r.status_code == 503 and "retry later" in r.json()["detail"]
            assert c.get("/api/robots").status_code == 200
        fut = app.state.landscapes._inflight.get(app.state.landscapes.check(entry, 33.0, 0.0, "exact", 10.0))
        if fut is not None:
            fut.result(timeout=60)
        ok = c.get("/api/landscape", params={"theta_w": 33, "step": 10})
        assert ok.status_code == 200


def test_an_unexpected_error_is_a_generic_500(client, monkeypatch):
    import landscape.computation

    def boom(*a, **k):
        raise RuntimeError("/secret/server/path/file.py exploded")

    monkeypatch.setattr(landscape.computation, "compute", boom)
    r = client.get("/api/landscape", params={"theta_w": 41, "step": 10})
    assert r.status_code == 500
    assert "secret" not in r.text and "Traceback" not in r.text and "bug" in r.json()["detail"]


# ---------------------------------------------------------------------------------------------- barrier map
def test_barrier_map_rows_match_the_library(client):
    from geometry.robots import load_robot
    from landscape.computation import barrier_map
    from landscape.viz.files import barrier_map_rows

    r = client.get("/api/barrier-map", params={"theta_w": "70:74:2", "theta_l": "0,30", "step": 5})
    assert r.status_code == 200
    want = barrier_map_rows(barrier_map(load_robot(), [70, 72, 74], [0, 30], step_deg=5))
    assert r.json() == json.loads(json.dumps(want))
    csv = client.get(
        "/api/barrier-map", params={"theta_w": "70:74:2", "theta_l": "0,30", "step": 5, "format": "csv"}
    )
    assert csv.text.splitlines()[0].startswith("theta_w_deg,theta_l_deg,") and len(csv.text.splitlines()) == 7


def test_large_barrier_map_runs_as_a_job_with_progress(make_app):
    import time

    from fastapi.testclient import TestClient

    app = make_app(limits=make_app.Limits(sync_map_s=0.0))
    with TestClient(app) as c:
        r = c.get("/api/barrier-map", params={"theta_w": "70,72", "theta_l": "0", "step": 10})
        assert r.status_code == 202
        url = r.json()["status_url"]
        for _ in range(600):
            job = c.get(url).json()
            if job["status"] in ("done", "failed", "cancelled"):
                break
            time.sleep(0.1)
        assert job["status"] == "done" and job["done"] == job["total"] == 2 and len(job["rows"]) == 2
        assert c.get(url, params={"format": "csv"}).status_code == 200
        assert c.get("/api/barrier-map/jobs/nope").status_code == 404


@pytest.mark.parametrize(
    "params, match",
    [
        ({"theta_w": "60:90:0"}, "must be START:STOP:STEP with STEP > 0"),
        ({"theta_w": "a,b"}, "is not a list of numbers"),
        ({"theta_w": "nan"}, "theta_w must be a finite number; got nan"),
        ({"theta_w": "0:90:0.01", "theta_l": "0:80:0.01"}, "poses is over the limit"),
        ({"theta_w": "0:100:0.001"}, "more than the 100000 allowed"),
        ({"theta_w": "70,120"}, "outside joint"),
        ({"step": 7}, "does not divide 360"),
    ],
)
def test_bad_barrier_maps(client, params, match):
    r = client.get("/api/barrier-map", params={"theta_w": "70", "theta_l": "0", **params})
    assert r.status_code == 422 and match in r.json()["detail"]


def test_a_huge_barrier_map_is_refused_with_its_estimate(make_app):
    from fastapi.testclient import TestClient

    with TestClient(make_app(limits=make_app.Limits(max_map_s=10))) as c:
        r = c.get("/api/barrier-map", params={"theta_w": "0:90:1", "theta_l": "0:90:1", "step": 1})
        assert r.status_code == 422 and "would take about" in r.json()["detail"]


# ---------------------------------------------------------------------------------------------- uploads
def test_mesh_upload_closed_form_barrier(client):
    """A 2 m cube of 1 kg: righting barrier m g a (sqrt 2 - 1) with a = 1 m (STYLE.md's closed form)."""
    r = client.post("/api/robots", files={"file": ("cube.stl", box_stl(), "model/stl")}, data={"mass": "1"})
    assert r.status_code == 201, r.text
    info = r.json()
    assert info["kind"] == "mesh" and not info["has_joints"] and info["mass_kg"] == 1.0
    rid = info["id"]
    assert any(x["id"] == rid for x in client.get("/api/robots").json())
    body = client.get("/api/landscape", params={"robot": rid, "step": 5}).json()
    assert body["theta_w_deg"] is None
    assert body["barrier"]["righting_j"] == pytest.approx(G * (math.sqrt(2) - 1), rel=1e-6)
    again = client.post(
        "/api/robots", files={"file": ("other-name.stl", box_stl(), "model/stl")}, data={"mass": "1"}
    )
    assert again.status_code == 200 and again.json()["id"] == rid


def test_mesh_upload_with_units_and_com(client):
    r = client.post(
        "/api/robots",
        files={"file": ("c.stl", box_stl((200.0, 200.0, 200.0)), "model/stl")},
        data={"units": "cm", "mass": "2", "com": "0,0,0"},
    )
    assert r.status_code == 201, r.text
    body = client.get("/api/landscape", params={"robot": r.json()["id"], "step": 5}).json()
    assert body["barrier"]["righting_j"] == pytest.approx(2 * G * (math.sqrt(2) - 1), rel=1e-6)


def test_urdf_zip_upload_survives_a_restart(make_app):
    from fastapi.testclient import TestClient

    with TestClient(make_app()) as c:
        r = c.post("/api/robots", files={"file": ("boxbot.zip", urdf_zip(), "application/zip")})
        assert r.status_code == 201, r.text
        rid = r.json()["id"]
        assert r.json()["kind"] == "urdf" and r.json()["name"] == "boxbot"
    with TestClient(make_app()) as c:
        assert c.get(f"/api/robots/{rid}").json()["name"] == "boxbot"
        body = c.get("/api/landscape", params={"robot": rid, "step": 10})
        assert body.status_code == 200 and body.json()["mass_kg"] == 0.5


def test_two_simultaneous_uploads_of_one_robot_leave_one_copy(client, tmp_path):
    data = urdf_zip(name="twin")
    out = []

    def go():
        out.append(client.post("/api/robots", files={"file": ("twin.zip", data, "application/zip")}))

    threads = [threading.Thread(target=go) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(r.status_code for r in out) == [200, 200, 200, 201]
    assert len({r.json()["id"] for r in out}) == 1
    stored = [d for d in (tmp_path / "data" / "robots").iterdir()]
    assert len(stored) == 1 and not list((tmp_path / "data" / "tmp").iterdir())


def test_same_urdf_with_other_meshes_is_another_robot(client):
    """The robot id covers the meshes' bytes (#9): the same URDF text with another mesh is a second robot, never
    a cache hit on the first one's answers."""
    a = urdf_zip(name="same")
    b = urdf_zip(name="same", extra={"boxbot/meshes/body.stl": box_stl((0.2, 0.06, 0.04))})
    ra = client.post("/api/robots", files={"file": ("a.zip", a)})
    rb = client.post("/api/robots", files={"file": ("b.zip", b)})
    assert (ra.status_code, rb.status_code) == (201, 201) and ra.json()["id"] != rb.json()["id"]


def _nan_stl() -> bytes:
    import struct

    tri = struct.pack("<12fH", 0, 0, 1, float("nan"), 0, 0, 1, 0, 0, 0, 1, 0, 0)
    return b"\0" * 80 + struct.pack("<I", 1) + tri


def _evil_zip(name: str, data: bytes = b"x", symlink: bool = False) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        info = zipfile.ZipInfo(name)
        if symlink:
            info.external_attr = 0o120777 << 16
        zf.writestr(info, data)
        zf.writestr("robot.urdf", "<robot name='x'/>")
    return buf.getvalue()


XXE = b"""<?xml version="1.0"?>
<!DOCTYPE robot [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>
<robot name="&xxe;"><link name="a"/></robot>"""

LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">]>
<robot name="&lol2;"/>"""


@pytest.mark.parametrize(
    "name, data, status, match",
    [
        ("evil.zip", _evil_zip("../outside.stl"), 422, "climbs out of the archive"),
        ("evil.zip", _evil_zip("/etc/cron.d/x"), 422, "absolute path"),
        ("evil.zip", _evil_zip("C:/x.stl"), 422, "absolute path"),
        ("evil.zip", _evil_zip("link.stl", b"/etc/passwd", symlink=True), 422, "symbolic link"),
        ("xxe.zip", zip_of({"robot.urdf": XXE}), 422, "DTDs and XML entities are not accepted"),
        ("laughs.zip", zip_of({"robot.urdf": LAUGHS}), 422, "DTDs and XML entities are not accepted"),
        ("bad.zip", urdf_zip(mesh="/etc/passwd.stl"), 422, "is not a file inside the upload"),
        ("bad.zip", urdf_zip(mesh="../../../../etc/hosts.stl"), 422, "is not a file inside the upload"),
        ("bad.zip", urdf_zip(mesh="meshes/missing.stl"), 422, "is not a file inside the upload"),
        ("bad.zip", urdf_zip(mesh="meshes/body.dae"), 422, "is not one of .stl"),
        ("two.zip", zip_of({"a.urdf": b"<robot/>", "b.urdf": b"<robot/>"}), 422, "several URDF files"),
        ("none.zip", zip_of({"readme.txt": b"hi"}), 422, "holds no .urdf file"),
        ("broken.zip", b"PK\x03\x04 not really", 422, "not a readable zip"),
        ("xml.zip", zip_of({"robot.urdf": b"<robot><link"}), 422, "not well-formed XML"),
        ("empty.stl", b"", 422, "is empty"),
        ("junk.stl", b"this is not a mesh at all" * 10, 422, "holds no triangle mesh"),
        ("nan.stl", _nan_stl(), 422, "not finite"),
        ("robot.exe", b"MZ", 422, "neither a .zip"),
    ],
)
def test_bad_uploads(client, tmp_path, name, data, status, match):
    r = client.post("/api/robots", files={"file": (name, data)})
    assert r.status_code == status, r.text
    detail = r.json()["detail"]
    assert match in detail and str(tmp_path) not in detail and "/tmp" not in detail
    assert not list((tmp_path / "data" / "robots").iterdir())
    assert not (tmp_path / "outside.stl").exists() and not (tmp_path / "data" / "outside.stl").exists()


@pytest.mark.parametrize(
    "form, match",
    [
        ({"units": "inch"}, "units must be mm, cm or m"),
        ({"mass": "nan"}, "mass must be a finite number; got nan"),
        ({"mass": "-1"}, "mass must be > 0 kg, a body's mass; got -1"),
        ({"com": "1,2"}, "three finite numbers"),
        ({"com": "a,b,c"}, "com must be X,Y,Z"),
    ],
)
def test_bad_upload_options(client, form, match):
    r = client.post("/api/robots", files={"file": ("c.stl", box_stl())}, data=form)
    assert r.status_code == 422 and match in r.json()["detail"]


def test_upload_limits(make_app):
    import trimesh
    from fastapi.testclient import TestClient

    limits = make_app.Limits(max_upload_bytes=4000, max_vertices=100)
    with TestClient(make_app(limits=limits)) as c:
        big = c.post("/api/robots", files={"file": ("big.stl", b"\0" * 2_000_000)})
        assert big.status_code == 413 and "over the limit" in big.json()["detail"]
        sphere = trimesh.creation.icosphere(subdivisions=2).export(file_type="stl")  # 162 vertices, ~16 kB
        r = c.post("/api/robots", files={"file": ("s.stl", sphere)})
        assert r.status_code == 413
    with TestClient(make_app(limits=make_app.Limits(max_vertices=100))) as c:
        r = c.post("/api/robots", files={"file": ("s.stl", sphere)})
        assert r.status_code == 422 and "at most 100" in r.json()["detail"]
    with TestClient(make_app(limits=make_app.Limits(max_unzipped_bytes=10_000))) as c:
        bomb = zip_of({"robot.urdf": b"<robot/>", "pad.bin": b"\0" * 1_000_000})  # compresses to ~1 kB
        r = c.post("/api/robots", files={"file": ("bomb.zip", bomb)})
        assert r.status_code == 413 and "unpacks to more than" in r.json()["detail"]


# ---------------------------------------------------------------------------------------------- security
def test_token_is_required_when_set(make_app):
    from fastapi.testclient import TestClient

    with TestClient(make_app(token="s3cret")) as c:
        assert c.get("/api/robots").status_code == 401
        assert c.get("/api/robots", headers={"Authorization": "Bearer wrong"}).status_code == 401
        assert c.get("/api/robots", headers={"Authorization": "Bearer s3cret"}).status_code == 200
        assert c.get("/").status_code == 200  # the page itself holds no data


def test_host_header_is_checked_on_a_local_server(make_app):
    from fastapi.testclient import TestClient

    with TestClient(make_app(allowed_hosts=("127.0.0.1", "localhost"))) as c:
        assert c.get("/api/health", headers={"Host": "evil.example"}).status_code == 400
        assert c.get("/api/health", headers={"Host": "localhost:8000"}).status_code == 200


def test_page_and_offline_plotly(client):
    page = client.get("/")
    assert page.status_code == 200 and 'src="/static/plotly.min.js"' in page.text
    assert "cdn" not in page.text.lower()
    js = client.get("/static/plotly.min.js")
    assert js.status_code == 200 and len(js.content) > 1_000_000
    assert client.get("/static/app.js").status_code == 200
    assert client.get("/docs").status_code == 200 and "/api/landscape" in client.get("/openapi.json").text


def test_serve_refuses_a_public_address_without_a_token(monkeypatch):
    from landscape.cli import main

    monkeypatch.delenv("LANDSCAPE_TOKEN", raising=False)
    assert main(["serve", "--host", "0.0.0.0", "--port", "0"]) == 2
    assert main(["serve", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"]) == 2


def test_a_streamed_upload_without_length_is_cut_at_the_limit(make_app):
    """No Content-Length to refuse up front: the body is counted as it streams and answered 413 (was a 400 from
    the multipart parser before the middleware rewrote the answer)."""
    from fastapi.testclient import TestClient

    def body():
        yield (
            b'--b\r\nContent-Disposition: form-data; name="file"; filename="a.stl"\r\n'
            b"Content-Type: application/octet-stream\r\n\r\n"
        )
        for _ in range(100):
            yield b"\0" * 100_000
        yield b"\r\n--b--\r\n"

    with TestClient(
        make_app(limits=make_app.Limits(max_upload_bytes=4000)), raise_server_exceptions=False
    ) as c:
        r = c.post("/api/robots", content=body(), headers={"Content-Type": "multipart/form-data; boundary=b"})
    assert r.status_code == 413 and "over the limit" in r.json()["detail"]


def test_a_computation_already_done_when_submitted_does_not_deadlock():
    """A computation that fails (or finishes) before its done-callback is registered runs the callback at once in
    the submitting thread; that callback takes the in-flight lock, which submit must no longer hold (this hung
    a fresh-clone CI run in test_an_unexpected_error_is_a_generic_500)."""
    import threading
    from concurrent.futures import Future

    from landscape.service.landscapes import Landscapes

    class DonePool:
        def submit(self, fn, *args):
            f = Future()
            f.set_exception(RuntimeError("failed at once"))
            return f

    ls = Landscapes.__new__(Landscapes)
    ls._lock = threading.Lock()
    ls._inflight = {}
    ls.pool = DonePool()
    out = []
    t = threading.Thread(
        target=lambda: out.append(ls.submit(None, ("h", 1.0, 0.0, "exact", 10.0))), daemon=True
    )
    t.start()
    t.join(timeout=10)
    assert not t.is_alive(), "submit deadlocked on its own lock"
    assert out[0].done() and ls._inflight == {}


def test_a_millimetre_mesh_upload_is_warned_of_and_its_default_mass_said(client, tmp_path):
    import trimesh

    f = tmp_path / "box100.stl"
    trimesh.creation.box(extents=(100.0, 60.0, 40.0)).export(f)  # saved in millimetres
    r = client.post("/api/robots", files={"file": ("box100.stl", f.read_bytes(), "model/stl")})
    assert r.status_code == 201, r.text
    info = r.json()
    assert info["mass_default"] is True and info["mass_kg"] == 1.0
    assert info["warnings"] == [
        "the mesh is 100 m across, read in metres; if it was saved in millimetres (CAD exports usually are), "
        "give units mm"
    ]
    assert client.get(f"/api/robots/{info['id']}").json()["warnings"] == info["warnings"]
    r = client.post(
        "/api/robots",
        files={"file": ("box100.stl", f.read_bytes(), "model/stl")},
        data={"units": "mm", "mass": "0.2"},
    )
    assert r.status_code == 201 and r.json()["warnings"] == [] and r.json()["mass_default"] is False


def test_the_service_takes_the_wing_joints_whole_range_as_the_cli(client):
    ok = client.get("/api/landscape", params={"robot": "builtin", "theta_w": -10, "theta_l": 0, "step": 10})
    assert ok.status_code == 200, ok.text
    bad = client.get("/api/landscape", params={"robot": "builtin", "theta_w": -12, "theta_l": 0, "step": 10})
    assert bad.status_code in (400, 422) and "outside joint" in bad.text
