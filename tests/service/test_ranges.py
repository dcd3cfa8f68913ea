"""Every number the service takes has a stated range: its OpenAPI description and schema state it, and a value
outside it answers 422 with the command line's words, the value named as the parameter. Walks the app's routes
(query parameters and form fields) and the sweep options, so a new numeric parameter that is not read through
``landscape.service.inputs.ranged`` fails here. Values that look like a slip of units are answered in
``warnings``."""

from __future__ import annotations

import typing

import pytest
from fastapi.routing import APIRoute

from landscape.service.jobs import SWEEP_BOUNDS, SWEEP_DEFAULTS, SWEEP_TEXT
from tests.conftest import outside

from .conftest import box_stl

QUERY_TEXT = {
    "robot": "a robot id",
    "method": "a barrier method's name",
    "format": "json, npz or csv",
    "model": "a shipped model set's name",
    "units": "mm, cm or m",
    "com": "X,Y,Z of a mesh, refused outside its convex hull",
    "file": "the uploaded file",
    "body": "a sweep's options, each walked below (SWEEP_BOUNDS)",
}
"""Parameters that take text, not a number, each with what it takes. A new text parameter is added here with why,
or holds numbers and is read through ``ranged``."""


def _range_of(field):
    """The (bounds, name, many) a ranged parameter is read with, or None."""
    for m in field.field_info.metadata:
        f = getattr(m, "func", None)
        if f is not None and hasattr(f, "bounds"):
            return f.bounds, f.name, f.many
    return None


def _params(app):
    for r in app.routes:
        if isinstance(r, APIRoute):
            for f in r.dependant.query_params + r.dependant.body_params:
                yield r, f


@pytest.fixture(scope="module")
def app(tmp_path_factory):
    from landscape.service.app import create_app
    from landscape.service.config import ServiceConfig

    return create_app(ServiceConfig(data_dir=tmp_path_factory.mktemp("data"), workers=1))


def test_every_numeric_parameter_is_ranged(app):
    ranged = 0
    for route, f in _params(app):
        where = f"{route.path} {f.name}"
        if _range_of(f) is not None:
            ranged += 1
            continue
        kinds = set(typing.get_args(f.field_info.annotation)) or {f.field_info.annotation}
        assert not kinds & {int, float}, (
            f"{where} is a bare number: read it through landscape.service.inputs.ranged"
        )
        if bool in kinds:
            continue
        assert f.name in QUERY_TEXT, (
            f"{where} reads text: add it to QUERY_TEXT saying what it takes, or range it"
        )
    assert ranged >= 11


def test_every_range_is_stated_and_refused_in_the_command_lines_words(app):
    from fastapi.testclient import TestClient

    with TestClient(app) as client:
        for route, f in _params(app):
            rng = _range_of(f)
            if rng is None:
                continue
            b, name, many = rng
            assert f.name == name and b.text in f.field_info.description, (
                route.path,
                f.field_info.description,
            )
            schema = f.field_info.json_schema_extra
            assert schema["x-range"] == b.text
            for text in outside(b):
                if "POST" in route.methods:  # a form field
                    r = client.post(route.path, files={"file": ("c.stl", box_stl())}, data={name: text})
                else:
                    r = client.get(route.path, params={name: text})
                assert r.status_code == 422, (route.path, name, text, r.text)
                assert r.json()["detail"] == b.outside_message(float(text), name), r.text


def test_every_sweep_option_is_ranged_or_text():
    assert set(SWEEP_DEFAULTS) == set(SWEEP_BOUNDS) | set(SWEEP_TEXT)
    assert not set(SWEEP_BOUNDS) & set(SWEEP_TEXT)


@pytest.mark.parametrize("key", sorted(SWEEP_BOUNDS))
def test_sweep_options_outside_their_range_are_refused(client, key):
    b, many = SWEEP_BOUNDS[key]
    for text in outside(b):
        r = client.post("/api/sweeps", json={key: text})
        assert r.status_code == 422, (key, text, r.text)
        assert r.json()["detail"] == b.outside_message(float(text), key)
    assert client.get("/api/sweeps").json() == []


def test_the_service_and_the_command_line_say_the_same(client, capsys):
    from landscape.cli import main

    assert main(["sweep", "--cv", "10", "--db", "unused.sqlite"]) == 2
    cli = capsys.readouterr().err.removeprefix("landscape: error: --cv")
    assert client.post("/api/sweeps", json={"cv": "10"}).json()["detail"] == "cv" + cli.rstrip("\n")
    assert main(["compute", "--theta-w", "400"]) == 2
    cli = capsys.readouterr().err.removeprefix("landscape: error: --theta-w")
    r = client.get("/api/landscape", params={"theta_w": 400})
    assert r.status_code == 422 and r.json()["detail"] == "theta_w" + cli.rstrip("\n")


def test_the_api_docs_state_the_ranges(client):
    spec = client.get("/openapi.json").json()
    q = {p["name"]: p for p in spec["paths"]["/api/landscape"]["get"]["parameters"]}
    assert q["step"]["schema"]["minimum"] == 0.05 and q["step"]["schema"]["maximum"] == 90
    assert q["step"]["schema"]["default"] == 1.0
    assert "in [0.05, 90] deg" in q["step"]["description"]
    sweeps = spec["paths"]["/api/sweeps"]["post"]["description"]
    assert "`cv` each in [0, 1], or a percentage written as '10%'" in sweeps


# ---------------------------------------------------------------------------------------------- unit slips
def test_an_angle_in_radians_is_answered_with_a_warning(client):
    got = client.get("/api/landscape", params={"theta_w": 1.3, "step": 30, "method": "grid"}).json()
    assert got["warnings"] == [
        "theta_w 1.3 is taken in degrees, as every angle is; if you meant 1.3 rad, give theta_w 74.48"
    ]
    assert got["theta_w_deg"] == 1.3
    plain = client.get("/api/landscape", params={"theta_w": 30, "step": 30, "method": "grid"}).json()
    assert "warnings" not in plain
    pose = client.get("/api/robot-pose", params={"theta_l": 0.5}).json()
    assert pose["warnings"] == [
        "theta_l 0.5 is taken in degrees, as every angle is; if you meant 0.5 rad, give theta_l 28.65"
    ]


def test_a_mass_in_grams_is_answered_with_a_warning(client):
    r = client.post("/api/robots", files={"file": ("c.stl", box_stl())}, data={"mass": "2600"})
    assert r.status_code == 201, r.text
    assert "mass 2600 kg is more than 1000 kg; if you meant grams, give mass 2.6" in r.json()["warnings"]


def test_a_sweep_in_radians_is_queued_with_a_warning(client):
    job = client.post(
        "/api/sweeps", json={"theta_w": "1.2", "theta_l": "30", "cv": "0", "trials": 1, "duration": 0.05}
    ).json()
    client.delete(f"/api/sweeps/{job['id']}")
    assert job["warnings"] == [
        "theta_w 1.2 is taken in degrees, as every angle is; if you meant 1.2 rad, give theta_w 68.75"
    ]
    assert client.get(f"/api/sweeps/{job['id']}").json()["warnings"] == job["warnings"]
