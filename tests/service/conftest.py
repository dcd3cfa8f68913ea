"""Fixtures of the service tests: an app over a temporary data directory, and upload files made here."""

from __future__ import annotations

import io
import zipfile
from dataclasses import replace
from pathlib import Path

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("httpx2")


@pytest.fixture
def make_app(tmp_path):
    from landscape.service.app import create_app
    from landscape.service.config import Limits, ServiceConfig

    def make(data: Path | None = None, **kw):
        limits = kw.pop("limits", None) or Limits()
        return create_app(ServiceConfig(data_dir=data or tmp_path / "data", workers=1, limits=limits, **kw))

    make.Limits = Limits
    make.replace = replace
    return make


@pytest.fixture
def client(make_app):
    from fastapi.testclient import TestClient

    with TestClient(make_app(), raise_server_exceptions=False) as c:
        yield c


def box_stl(extents=(2.0, 2.0, 2.0)) -> bytes:
    import trimesh

    return trimesh.creation.box(extents=extents).export(file_type="stl")


URDF = """<?xml version="1.0"?>
<robot name="{name}">
  <link name="base">
    <inertial><origin xyz="0 0 0"/><mass value="0.5"/>
      <inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
    <collision><geometry><mesh filename="{mesh}"/></geometry></collision>
  </link>
</robot>
"""


def zip_of(files: dict[str, bytes]) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for name, data in files.items():
            zf.writestr(name, data)
    return buf.getvalue()


def urdf_zip(name="boxbot", mesh="meshes/body.stl", extra: dict | None = None) -> bytes:
    files = {
        "boxbot/robot.urdf": URDF.format(name=name, mesh=mesh).encode(),
        "boxbot/meshes/body.stl": box_stl((0.1, 0.06, 0.04)),
    }
    files.update(extra or {})
    return zip_of(files)
